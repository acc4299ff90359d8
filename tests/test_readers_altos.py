"""Specification of the AltOS reader on exports of every version (tests/logfixtures.py writes them as AltosUI does):
telemetry recordings, AltOS 1.4's comment preamble and header defect, TeleMega / EasyMega with a live, dead or
saturating IMU, TeleMetrum without IMU columns and EasyMini without an accelerometer."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude.logs import LogWarning  # noqa: E402

G = 9.80665


def read(path):
    """load_log with its LogWarnings recorded: (LogData, [warning texts])."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LogWarning)
        data = logs.load_log(str(path))
    return data, [str(w.message) for w in caught if issubclass(w.category, LogWarning)]


# --- telemetry recordings --------------------------------------------------------

def test_telemetry_export_is_recognised_as_altos(tmp_path):
    assert logs.sniff_format(fx.altos_telemetry_csv(tmp_path)) == "altos"


def test_telemetry_export_keeps_its_irregular_packet_times(tmp_path):
    data, _ = read(fx.altos_telemetry_csv(tmp_path))
    steps = np.diff(data.time)
    assert np.median(steps) == pytest.approx(0.1)
    assert steps.max() == pytest.approx(4.0) and np.any((steps >= 0.5) & (steps < 1.0))


def test_telemetry_losses_longer_than_ten_median_steps_are_one_gap_warning(tmp_path):
    data, caught = read(fx.altos_telemetry_csv(tmp_path))
    assert [round(length, 6) for _, length in data.gaps] == [1.2, 4.0, 2.0]
    assert len([w for w in caught if "logging gap" in w]) == 1


def test_telemetry_export_is_noted_as_a_ground_station_recording(tmp_path):
    data, _ = read(fx.altos_telemetry_csv(tmp_path))
    assert any("ground-station telemetry" in note for note in data.notes)


def test_accel_speed_is_the_reference_velocity_without_a_speed_column(tmp_path):
    path = fx.altos_telemetry_csv(tmp_path)
    data, _ = read(path)
    _, velocity, _ = fx.rocket_profile(data.time)
    np.testing.assert_allclose(data.reference_velocity, velocity, atol=0.006)


# --- AltOS 1.4 ------------------------------------------------------------------------

def test_altos_14_export_with_comment_lines_before_the_header_is_recognised(tmp_path):
    assert logs.sniff_format(fx.altos_14_csv(tmp_path)) == "altos"


def test_altos_14_software_version_from_the_preamble_is_noted(tmp_path):
    data, _ = read(fx.altos_14_csv(tmp_path))
    assert "AltOS 1.4.1" in data.notes


def test_altos_14_header_defect_is_repaired_with_one_warning(tmp_path):
    _, caught = read(fx.altos_14_csv(tmp_path))
    said = [w for w in caught if "header defect" in w]
    assert len(said) == 1
    assert "25 names for 26 cells" in said[0] and "'main_voltageaccel_x' → 'main_voltage', 'accel_x'" in said[0]


def test_altos_14_columns_after_the_repaired_name_are_read_in_place(tmp_path):
    path = fx.altos_14_csv(tmp_path)
    truth = fx.write_altos_rocket_csv(tmp_path / "again.csv", style="1.4")
    data, _ = read(path)
    np.testing.assert_allclose(data.accel[:, 0], truth["imu_x"], atol=0.006)


def test_flight_computer_download_with_zero_rssi_is_not_called_telemetry(tmp_path):
    data, _ = read(fx.altos_14_csv(tmp_path))
    assert not any("telemetry" in note for note in data.notes)


# --- along-axis acceleration ----------------------------------------------------

def test_acceleration_column_plus_g_is_the_axial_acceleration(tmp_path):
    truth = fx.write_altos_rocket_csv(tmp_path / "telemega.csv")
    data, _ = read(tmp_path / "telemega.csv")
    np.testing.assert_allclose(data.axial_acceleration, truth["accel"] + G, atol=0.006)
    assert np.median(data.axial_acceleration[data.time < 0]) == pytest.approx(G, abs=0.01)


def test_acceleration_column_is_the_vertical_acceleration_of_a_rocket_in_preference_to_the_imu(tmp_path):
    truth = fx.write_altos_rocket_csv(tmp_path / "telemega.csv", boost=fx.BOOST_HIGH)
    data, _ = read(tmp_path / "telemega.csv")
    boost = (data.time >= 0) & (data.time < fx.BURN_TIME)
    np.testing.assert_allclose(data.vertical_acceleration[boost], fx.BOOST_HIGH, atol=0.006)
    assert data.accel[boost, 0].max() < truth["specific"][boost].max()


# --- IMU: dead, saturating, absent ------------------------------------------------

def test_dead_imu_is_not_used(tmp_path):
    data, _ = read(fx.telemega_dead_imu_csv(tmp_path))
    assert data.accel is None and data.gyro is None and data.imu_frame == ""


def test_dead_imu_gets_one_warning_naming_the_fallback(tmp_path):
    _, caught = read(fx.telemega_dead_imu_csv(tmp_path))
    said = [w for w in caught if "IMU" in w]
    assert len(said) == 1
    assert "all zero on every sample: a dead sensor, not used; the along-axis 'acceleration' is used" in said[0]


def test_dead_imu_leaves_the_along_axis_acceleration_alive(tmp_path):
    data, _ = read(fx.telemega_dead_imu_csv(tmp_path))
    assert not data.baro_only and np.ptp(data.vertical_acceleration) > 100.0


def test_saturating_imu_samples_are_flagged_clipped(tmp_path):
    truth = fx.write_altos_rocket_csv(tmp_path / "telemega.csv", boost=fx.BOOST_HIGH)
    data, _ = read(tmp_path / "telemega.csv")
    np.testing.assert_array_equal(data.clipped, truth["specific"] >= 0.97 * fx.IMU_FULL_SCALE)


def test_saturating_imu_gets_one_warning(tmp_path):
    _, caught = read(fx.telemega_saturating_imu_csv(tmp_path))
    said = [w for w in caught if "saturates" in w]
    assert len(said) == 1 and "(±16 g) on 20 samples (0–0.95 s): marked clipped" in said[0]


def test_imu_within_range_is_not_clipped(tmp_path):
    fx.write_altos_rocket_csv(tmp_path / "telemega.csv", boost=fx.BOOST)
    data, caught = read(tmp_path / "telemega.csv")
    assert not data.clipped.any() and not any("saturates" in w for w in caught)


def test_imu_not_reading_one_g_on_the_pad_is_not_used_with_a_warning(tmp_path):
    path = tmp_path / "telemega.csv"
    fx.write_altos_rocket_csv(path)
    lines = path.read_text().split("\n")
    header = lines[0].lstrip("#").split(",")
    x = header.index("accel_x")
    for i in range(1, len(lines) - 1):  # raw counts: 2048 per g
        cells = lines[i].split(",")
        cells[x] = str(round(float(cells[x]) / G * 2048))
        lines[i] = ",".join(cells)
    path.write_text("\n".join(lines))
    data, caught = read(path)
    assert data.accel is None
    assert any("not about 9.81 m/s² (raw counts or another unit?): not used" in w for w in caught)


def test_telemetrum_without_imu_columns_has_no_raw_imu(tmp_path):
    fx.write_altos_rocket_csv(tmp_path / "telemetrum.csv", imu="none")
    data, _ = read(tmp_path / "telemetrum.csv")
    assert data.accel is None and data.clipped is None and data.axial_acceleration is not None


def test_easymini_without_an_accelerometer_is_baro_only_with_one_warning(tmp_path):
    data, caught = read(fx.easymini_csv(tmp_path))
    assert data.baro_only and data.axial_acceleration is None and np.all(data.vertical_acceleration == 0.0)
    assert len([w for w in caught if "no accelerometer, as on an EasyMini" in w]) == 1


def test_export_without_an_acceleration_column_is_baro_only_with_one_warning(tmp_path):
    path = tmp_path / "easymini.csv"
    fx.write_altos_rocket_csv(path, imu="none", acceleration=False)
    lines = path.read_text().split("\n")
    drop = lines[0].lstrip("#").split(",").index("acceleration")
    path.write_text("\n".join(",".join(c for j, c in enumerate(line.split(",")) if j != drop) if line else line
                              for line in lines))
    data, caught = read(path)
    assert data.baro_only and np.all(data.vertical_acceleration == 0.0)
    assert len([w for w in caught if "no 'acceleration' column" in w]) == 1


def test_easymini_baro_is_read(tmp_path):
    truth = fx.write_altos_rocket_csv(tmp_path / "easymini.csv", imu="none", acceleration=False)
    data, _ = read(tmp_path / "easymini.csv")
    np.testing.assert_allclose(data.baro_altitude, truth["altitude"], atol=0.006)


# --- plausibility ------------------------------------------------------------------

def test_altos_absurd_altitude_is_dropped_with_a_warning_naming_its_line(tmp_path):
    path = tmp_path / "telemega.csv"
    fx.write_altos_rocket_csv(path)
    lines = path.read_text().split("\n")
    altitude = lines[0].lstrip("#").split(",").index("altitude")
    cells = lines[40].split(",")
    cells[altitude] = "1e30"
    lines[40] = ",".join(cells)
    path.write_text("\n".join(lines))
    data, caught = read(path)
    assert any("line 41, column 'altitude': 1e+30 m is not a plausible baro altitude" in w for w in caught)
    assert np.isnan(data.baro_altitude[39])
