"""The INS on the shared real logs (examples/ins_real_logs.py): it runs on raw
PX4 `sensor_combined` and on the Hedy rocket's IMU CSV, and lands where the
logs' own data say. Reads $FUSION_ALTITUDE_SHARED_DATA (else ../shared/data) and needs
pyulog; a missing one FAILS."""

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def example():
    spec = importlib.util.spec_from_file_location("ins_real_logs", ROOT / "examples" / "ins_real_logs.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def data() -> Path:
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert (path / "px4_sample_log_small.ulg").is_file() and (path / "hedy_imu.csv").is_file(), path
    return path


def test_px4_raw_imu_ins_follows_the_baro_closer_than_the_autopilot_and_agrees_on_tilt(example, data):
    row = example.px4(data)
    assert np.all(np.isfinite(row["_error"]))
    assert row["_baro_rms"] < 0.3  # m
    assert float(row["tilt RMS diff vs log attitude (°)"]) < 1.0


def test_hedy_rocket_ins_apogee_within_2_percent_of_the_flight_computer(example, data):
    row = example.hedy(data)
    assert np.all(np.isfinite(row["_error"]))
    log_apogee, ins_apogee = row["_apogee"]
    assert abs(ins_apogee - log_apogee) < 0.02 * log_apogee
