"""Shared fixtures: most behaviour tests run against both implementations."""

import os
from pathlib import Path

import numpy as np
import pytest

import fusion_altitude
import fusion_altitude.reference


@pytest.fixture(scope="session")
def shared_logs() -> Path:
    """The shared real logs (``../shared/data``, or FUSION_ALTITUDE_SHARED_DATA as .ci/run sets it); missing: fail."""
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", Path(__file__).parents[1] / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


@pytest.fixture(params=["c", "reference"])
def impl(request):
    """The C binding (``fusion_altitude``) or the pure-Python reference."""
    return fusion_altitude if request.param == "c" else fusion_altitude.reference


def float_bits(value) -> int:
    """The float32 bit pattern of a number, so NaNs and signed zeros compare exactly."""
    return int(np.array(value, dtype=np.float32).view(np.uint32))


def estimator_state_bits(estimator) -> tuple:
    """Every state variable of an estimator, floats as float32 bit patterns."""
    return (float_bits(estimator.altitude), float_bits(estimator.vertical_velocity),
            float_bits(estimator.accel_bias), float_bits(estimator.baro_residual),
            estimator.reference_set, estimator.settings.as_tuple())


@pytest.fixture
def state_bits():
    """``state_bits(estimator)``: the full state as comparable bit patterns."""
    return estimator_state_bits


#: What takes minutes: cross builds and QEMU, fuzzing and cppcheck (test_firmware.py), the compiler and
#: sanitizer matrix and the 10^7-step runs (test_c_core.py, test_ins_c.py), the INS M4F cycle count (cross build +
#: QEMU) and fuzzer (test_ins_c.py), the Kalman Monte Carlo. ``pytest -m "not slow"``
#: leaves them out for a quick run; CI (``pytest``) runs everything. A whole file, or ``file::test``.
SLOW = {
    "test_firmware.py",
    "test_c_core.py::test_c_unit_tests_pass_warning_free",
    "test_c_core.py::test_kalman_covariance_stays_symmetric_psd_over_ten_million_steps_at_1khz",
    "test_kalman_consistency.py",
    "test_ins_c.py::test_ins_c_unit_tests_pass_warning_free",
    "test_ins_c.py::test_ins_covariance_stays_symmetric_psd_over_ten_million_steps_at_1khz",
    "test_ins_c.py::test_ins_m4f_imu_step_costs_under_12000_cycles",
    "test_ins_c.py::test_ins_fuzzer_finds_nothing_in_30000_inputs",
    # tens of seconds each: 60 random tune runs, 96 bad-baro flights through the pure-Python rocket estimator
    "test_cli_fuzz.py::test_tune_anywhere_in_its_bounds_prints_no_warning",
    "test_rocket_reference.py::test_the_height_does_not_drop_more_than_1_m_in_the_ascent_with_bad_baro",
}


def pytest_collection_modifyitems(items):
    for item in items:
        file = item.path.name
        if file in SLOW or f"{file}::{getattr(item, 'originalname', item.name)}" in SLOW:
            item.add_marker(pytest.mark.slow)
