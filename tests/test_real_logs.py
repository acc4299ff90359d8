"""Real logs end to end: the Hedy rocket flight, the PX4 ULog and the ArduPilot DataFlash fixtures.

The logs live in ../shared/data (never committed); the path comes from
FUSION_ALTITUDE_SHARED_DATA, else ../shared/data relative to the repository
root. A missing directory fails the tests: they are never skipped.
"""

import importlib.util
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from fusion_altitude import logs, runner

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def data_dir():
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


@pytest.fixture(scope="module")
def hedy(data_dir):
    spec = importlib.util.spec_from_file_location("hedy_rocket", ROOT / "examples" / "hedy_rocket.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses in the example look their module up here
    spec.loader.exec_module(module)
    run = module.run_hedy(str(data_dir))
    return module.summary(run)


def test_hedy_estimate_tracks_the_flight_computer_height_within_20_m_rms(hedy):
    assert hedy["rms_difference"] < 20.0


def test_hedy_apogee_agrees_with_the_flight_computer_within_one_percent(hedy):
    assert abs(hedy["apogee_error"]) < 0.01 * hedy["apogee_reference"]


def test_hedy_apogee_time_agrees_with_the_flight_computer_within_half_a_second(hedy):
    assert abs(hedy["apogee_time_estimate"] - hedy["apogee_time_reference"]) < 0.5


def test_px4_ulog_yields_baro_accel_and_ekf_reference(data_dir):
    data = logs.read_ulog(str(data_dir / "px4_sample_log_small.ulg"))
    assert np.sum(np.isfinite(data.baro_altitude)) > 100
    assert np.isfinite(data.reference_altitude).mean() > 0.9
    # On the ground and level, gravity must be removed: |mean vertical accel| well below 1 m/s².
    assert abs(np.mean(data.vertical_acceleration)) < 0.5


def test_px4_fused_estimate_is_closer_to_the_ekf_than_raw_baro_is(data_dir):
    run = runner.run_log(logs.read_ulog(str(data_dir / "px4_sample_log_small.ulg")))
    assert run.comparison().rms <= run.baro_comparison().rms


def test_ardupilot_dataflash_yields_baro_accel_and_ekf_reference(data_dir):
    data = logs.read_dataflash(str(data_dir / "ardupilot_test.BIN"))
    assert np.sum(np.isfinite(data.baro_altitude)) >= 5
    assert data.reference_name.startswith("ArduPilot EKF")
    assert abs(np.mean(data.vertical_acceleration)) < 1.0


def test_clipped_samples_freeze_the_bias_estimate():
    n = 1000
    time = np.arange(n) * 0.01
    clipped = (time > 5) & (time < 6)
    accel = np.where(clipped, 30.0, 0.2)
    out = runner.run_observer(time, accel, np.zeros(n), clipped=clipped)
    inside = np.flatnonzero(clipped)
    assert out.accel_bias[inside[-1]] == out.accel_bias[inside[0] - 1]


def test_clipping_handling_reduces_error_on_the_simulated_rocket():
    from fusion_altitude.scenarios import run_scenario
    result = run_scenario("rocket", 0, attitude="truth")
    assert result.imu.clipped.any()
    handled = runner.run_observer(result.time, result.vertical_acceleration, result.baro_altitude,
                                clipped=result.imu.clipped)
    ignored = runner.run_observer(result.time, result.vertical_acceleration, result.baro_altitude)
    truth = result.trajectory.altitude
    assert np.sqrt(np.mean((handled.altitude - truth) ** 2)) < np.sqrt(np.mean((ignored.altitude - truth) ** 2))


# --- the readers on the shared logs: what each real log yields -------------------------------

def test_hedy_split_files_are_read_as_a_cats_rocket_log_from_the_baro_file(data_dir):
    data = logs.load_log(str(data_dir / "hedy_baro.csv"))
    assert (data.vehicle, data.altitude_reference, data.ground_altitude) == ("rocket", "pad", 0.0)
    assert data.reference_name.startswith("CATS")


def test_hedy_baro_apogee_is_about_5230_m_above_the_pad(data_dir):
    data = logs.load_log(str(data_dir))
    assert np.nanmax(data.baro_altitude) == pytest.approx(5230.0, rel=0.03)


def test_hedy_through_the_reader_tracks_the_flight_computer_within_20_m_rms(data_dir):
    from fusion_altitude import AltitudeSettings
    data = logs.load_log(str(data_dir / "hedy_baro.csv"))
    estimate = runner.run_observer(data.time, data.vertical_acceleration, data.baro_altitude,
                                   AltitudeSettings.from_bandwidth(0.5), clipped=data.clipped)
    flight = (data.time >= 0) & np.isfinite(data.reference_altitude)
    difference = estimate.altitude[flight] - data.reference_altitude[flight]
    assert np.sqrt(np.mean(difference ** 2)) < 20.0


def test_px4_ulog_yields_gps_with_fix_pressure_temperature_and_arming(data_dir):
    data = logs.load_log(str(data_dir / "px4_sample_log_small.ulg"))
    assert np.isfinite(data.gps_altitude).sum() >= 30
    assert np.nanmedian(data.pressure) == pytest.approx(100300.0, rel=0.01)
    assert 250.0 < np.nanmedian(data.temperature) < 330.0
    assert data.vehicle == "copter" and "armed" in set(data.flight_state)


def test_px4_ulog_second_baro_instance_reads_sensor_baro(data_dir):
    data = logs.load_log(str(data_dir / "px4_sample_log_small.ulg"), instance=1)
    assert np.isfinite(data.baro_altitude).sum() >= 5
    assert "sensor_baro instance 1" in " ".join(data.notes)


def test_ardupilot_log_yields_gps_pressure_and_plane_hint(data_dir):
    data = logs.load_log(str(data_dir / "ardupilot_test.BIN"))
    assert data.vehicle == "plane"
    assert np.isfinite(data.gps_altitude).sum() >= 4
    assert np.nanmedian(data.pressure) == pytest.approx(94144.0, rel=0.01)
