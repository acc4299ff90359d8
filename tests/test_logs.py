"""Specification of the log readers on fixtures written by tests/logfixtures.py (never copied real files).

Each test holds one reader behaviour: format detection, time stamps of every
DataFlash generation, sensor instances, GPS fix status, AltOS and CATS
layouts, repeated timestamps, gaps, units, BOM, damaged files and one-line
errors naming file, line and column.
"""

import re
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude.logs import LogData, LogError, LogWarning  # noqa: E402


@pytest.fixture(autouse=True)
def _quiet_log_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LogWarning)
        yield


def truth_at(truth, time, key="altitude"):
    return np.interp(time, truth["time"], truth[key])


# --- LogData ---------------------------------------------------------------------

def test_logdata_new_fields_default_to_absent():
    data = LogData("x", np.arange(3.0), np.zeros(3), np.zeros(3))
    assert (data.gps_altitude, data.accel, data.flight_state, data.ground_altitude) == (None, None, None, None)
    assert (data.repeated_timestamps, data.gaps, data.gap_count, data.vehicle) == (0, [], 0, "")


# --- format detection ------------------------------------------------------------

def test_dataflash_is_recognised_by_content_whatever_its_extension(tmp_path):
    fx.write_dataflash(tmp_path / "flight.dat")
    assert logs.sniff_format(str(tmp_path / "flight.dat")) == "dataflash"


def test_altos_csv_is_recognised_by_its_header(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv")
    assert logs.sniff_format(str(tmp_path / "telemega.csv")) == "altos"


def test_altos_csv_with_bom_is_recognised(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv", bom=True)
    assert logs.sniff_format(str(tmp_path / "telemega.csv")) == "altos"


def test_cats_baro_file_is_recognised(tmp_path):
    fx.write_cats_set(tmp_path)
    assert logs.sniff_format(str(tmp_path / "flight_baro.csv")) == "cats"


def test_a_directory_with_a_cats_set_is_recognised(tmp_path):
    fx.write_cats_set(tmp_path)
    assert logs.sniff_format(str(tmp_path)) == "cats"


def test_other_csv_is_generic(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv")
    assert logs.sniff_format(str(tmp_path / "log.csv")) == "csv"


def test_format_of_an_sniffed_log_refuses_column_options(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv")
    with pytest.raises(LogError, match="takes no time_column option"):
        logs.load_log(str(tmp_path / "telemega.csv"), time_column="time")


def test_a_text_log_is_opened_once_to_sniff_and_read_it(tmp_path, monkeypatch):
    import builtins

    path = fx.rrc3_csv(tmp_path)
    expected = logs.load_log(path)
    opened = []
    real_open = builtins.open
    monkeypatch.setattr(builtins, "open", lambda file, *args, **kw: opened.append(file) or real_open(file, *args, **kw))
    data = logs.load_log(path)
    assert opened == [path]
    assert np.array_equal(data.baro_altitude, expected.baro_altitude, equal_nan=True)


def test_the_bytes_read_to_sniff_a_log_are_forgotten_after_its_read(tmp_path):
    from fusion_altitude.logs import _table

    path = fx.rrc3_csv(tmp_path)
    logs.load_log(path)
    Path(path).write_text("time,altitude\n0,1\n")
    assert _table.read_text(path) == "time,altitude\n0,1\n"


def test_missing_file_is_one_log_error(tmp_path):
    with pytest.raises(LogError, match="no such file"):
        logs.load_log(str(tmp_path / "nothing.bin"))


# --- DataFlash -------------------------------------------------------------------

@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
def test_dataflash_of_either_generation_gives_the_baro_altitude(tmp_path, style):
    truth = fx.write_dataflash(tmp_path / "log.bin", style=style)
    data = logs.load_log(str(tmp_path / "log.bin"))
    baro = np.isfinite(data.baro_altitude)
    np.testing.assert_allclose(data.baro_altitude[baro], truth_at(truth, data.time[baro] - 0.019), atol=0.15)


def test_dataflash_timems_log_is_stamped_in_seconds(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", style="TimeMS", duration=20.0, imu_rate=50.0)
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert data.time[-1] == pytest.approx(19.98, abs=1e-6)


def test_dataflash_timems_vertical_acceleration_is_gravity_free(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", style="TimeMS")
    data = logs.load_log(str(tmp_path / "log.bin"))
    _, _, accel = fx.profile(data.time)
    np.testing.assert_allclose(data.vertical_acceleration, accel, atol=1e-4)


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
def test_dataflash_second_baro_instance_is_read_on_request(tmp_path, style):
    fx.write_dataflash(tmp_path / "log.bin", style=style, second_instance_offset=3.0)
    primary = logs.load_log(str(tmp_path / "log.bin"))
    second = logs.load_log(str(tmp_path / "log.bin"), instance=1)
    baro = np.isfinite(primary.baro_altitude)
    np.testing.assert_allclose(second.baro_altitude[baro] - primary.baro_altitude[baro], 3.0, atol=1e-4)


def test_dataflash_instance_absent_is_a_log_error(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", style="TimeUS")
    with pytest.raises(LogError, match="for instance 2"):
        logs.load_log(str(tmp_path / "log.bin"), instance=2)


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
def test_dataflash_gps_altitude_is_nan_without_a_3d_fix(tmp_path, style):
    fx.write_dataflash(tmp_path / "log.bin", style=style, gps_fix_from=2.0)
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert not np.isfinite(data.gps_altitude[data.time < 1.9]).any()
    assert np.isfinite(data.gps_altitude[data.time > 2.1]).sum() > 10


def test_dataflash_gps_altitude_is_above_sea_level_in_metres(tmp_path):
    truth = fx.write_dataflash(tmp_path / "log.bin", style="TimeMS")
    data = logs.load_log(str(tmp_path / "log.bin"))
    gps = np.isfinite(data.gps_altitude)
    np.testing.assert_allclose(data.gps_altitude[gps], truth_at(truth, data.time[gps] - 0.017) + 100.0, atol=0.01)


def test_dataflash_current_log_has_gps_accuracy_rangefinder_and_arming(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", style="TimeUS")
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert np.nanmedian(data.gps_accuracy) == pytest.approx(1.5)
    assert np.isfinite(data.rangefinder).sum() > 10
    assert set(data.flight_state) == {"armed"}


def test_dataflash_rangefinder_readings_flagged_bad_are_dropped(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", style="TimeUS")  # Stat 1 (not good) above 20 m
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert np.nanmax(data.rangefinder) < 20.2


def test_dataflash_firmware_gives_the_vehicle_hint(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", firmware="ArduCopter V3.2.1")
    assert logs.load_log(str(tmp_path / "log.bin")).vehicle == "copter"


def test_dataflash_reference_is_the_ekf_of_core_zero(tmp_path):
    truth = fx.write_dataflash(tmp_path / "log.bin", style="TimeUS")  # core 1 is 50 m off
    data = logs.load_log(str(tmp_path / "log.bin"))
    known = np.isfinite(data.reference_altitude)
    assert known.sum() > 990
    np.testing.assert_allclose(data.reference_altitude[known], truth_at(truth, data.time[known]), atol=0.01)


def test_dataflash_raw_imu_is_kept_in_frd(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin")
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert data.imu_frame == "FRD"
    assert data.accel[0, 2] == pytest.approx(-fx.G, abs=1e-4)


def test_dataflash_corrupt_tail_is_skipped_with_a_warning(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", style="TimeMS", corrupt_tail=True)
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert data.time[-1] < 20.0 and data.gaps == []
    assert any("damaged" in w for w in data.warnings)


def test_dataflash_gap_is_listed(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", gap=(8.0, 2.0))
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert data.gap_count == 1
    assert data.gaps[0][1] == pytest.approx(2.02, abs=0.01)


def test_dataflash_repeated_imu_timestamps_are_merged_and_counted(tmp_path):
    fx.write_dataflash(tmp_path / "log.bin", repeat_every=5)
    data = logs.load_log(str(tmp_path / "log.bin"))
    assert data.repeated_timestamps == 199
    assert np.all(np.diff(data.time) > 0)


def test_dataflash_reader_refuses_a_text_file(tmp_path):
    path = tmp_path / "notes.bin"
    path.write_text("hello\n")
    with pytest.raises(LogError, match="not an ArduPilot DataFlash log"):
        logs.read_dataflash(str(path))


# --- AltOS -----------------------------------------------------------------------

def test_altos_needs_no_column_options(tmp_path):
    truth = fx.write_altos_csv(tmp_path / "telemega.csv")
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    np.testing.assert_allclose(data.baro_altitude, truth_at(truth, data.time), atol=0.01)


def test_altos_time_is_negative_on_the_pad(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv", pad_time=3.0)
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    assert data.time[0] == pytest.approx(-3.0)


def test_altos_rows_sharing_a_time_stamp_are_merged_by_averaging(tmp_path):
    truth = fx.write_altos_csv(tmp_path / "telemega.csv", rows_per_stamp=2)  # copies at truth ± 0.2
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    assert data.repeated_timestamps == truth["time"].size
    _, _, accel = fx.profile(data.time, start=0.0)
    np.testing.assert_allclose(data.vertical_acceleration, accel, atol=1e-3)


def test_altos_repeated_timestamps_are_reported_in_a_warning(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv", rows_per_stamp=2)
    with pytest.warns(LogWarning, match="rows repeated the timestamp"):
        logs.load_log(str(tmp_path / "telemega.csv"))


def test_altos_height_column_is_the_reference_in_the_baro_datum(tmp_path):
    truth = fx.write_altos_csv(tmp_path / "telemega.csv")
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    assert data.ground_altitude == pytest.approx(fx.PAD_ALTITUDE, abs=0.01)
    np.testing.assert_allclose(data.reference_altitude - data.ground_altitude,
                               truth_at(truth, data.time, "height"), atol=0.01)


def test_altos_second_altitude_column_is_the_gps_altitude(tmp_path):
    truth = fx.write_altos_csv(tmp_path / "telemega.csv")
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    gps = np.isfinite(data.gps_altitude)
    assert gps.sum() > 10
    np.testing.assert_allclose(data.gps_altitude[gps], truth_at(truth, data.time[gps]) + 40.0, atol=0.1)


def test_altos_gps_altitude_is_nan_before_lock(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv")  # locked from 1 s
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    assert not np.isfinite(data.gps_altitude[data.time < 1.0]).any()


def test_altos_state_name_is_kept_as_flight_state(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv")
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    assert [data.flight_state[np.searchsorted(data.time, t)] for t in (-1.0, 1.0, 5.0, 25.0)] == \
        ["pad", "boost", "coast", "main"]


def test_altos_log_is_a_rocket_above_sea_level_with_temperature_in_kelvin(tmp_path):
    fx.write_altos_csv(tmp_path / "telemega.csv")
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    assert (data.vehicle, data.altitude_reference) == ("rocket", "sea level")
    assert data.temperature[0] == pytest.approx(288.15 - 0.0065 * fx.PAD_ALTITUDE, abs=1e-3)


def test_altos_hypsometric_height_from_the_pad_with_the_log_temperature(tmp_path):
    truth = fx.write_altos_csv(tmp_path / "telemega.csv")
    data = logs.read_altos_csv(str(tmp_path / "telemega.csv"), ground_temperature_k="log")
    assert data.altitude_reference == "pad"
    np.testing.assert_allclose(data.baro_altitude, truth_at(truth, data.time, "height"), atol=0.05)


def test_altos_bad_cell_names_line_and_column(tmp_path):
    path = tmp_path / "telemega.csv"
    fx.write_altos_csv(path)
    lines = path.read_text().split("\n")
    cells = lines[5].split(",")
    cells[8] = "12x"
    lines[5] = ",".join(cells)
    path.write_text("\n".join(lines))
    with pytest.raises(LogError, match=r"line 6, column 'pressure': '12x' is not a number"):
        logs.load_log(str(path))


# --- CATS --------------------------------------------------------------------------

@pytest.mark.parametrize("given", ["flight_baro.csv", "flight_imu.csv", "flight_flight_info.csv", "."])
def test_cats_set_is_read_from_any_of_its_files_or_its_directory(tmp_path, given):
    truth = fx.write_cats_set(tmp_path)
    data = logs.load_log(str(tmp_path / given))
    np.testing.assert_allclose(data.reference_altitude, truth_at(truth, data.time), atol=1e-3)


def test_cats_baro_altitude_is_height_above_the_pad(tmp_path):
    truth = fx.write_cats_set(tmp_path)
    data = logs.load_log(str(tmp_path))
    assert data.altitude_reference == "pad" and data.ground_altitude == 0.0
    np.testing.assert_allclose(data.baro_altitude, truth_at(truth, data.time), atol=0.1)


def test_cats_vertical_acceleration_comes_from_the_sensor_y_axis(tmp_path):
    fx.write_cats_set(tmp_path)
    data = logs.load_log(str(tmp_path))
    _, _, accel = fx.profile(data.time, start=0.0)
    np.testing.assert_allclose(data.vertical_acceleration, accel, atol=1e-3)


def test_cats_second_instance_is_read_on_request(tmp_path):
    fx.write_cats_set(tmp_path, second_instance=True)
    data = logs.load_log(str(tmp_path), instance=1)
    assert "IMU1" in data.notes[0] and "BARO1" in data.notes[1]


def test_cats_without_imu_file_names_the_missing_file(tmp_path):
    fx.write_cats_set(tmp_path)
    (tmp_path / "flight_imu.csv").unlink()
    with pytest.raises(LogError, match="flight_imu.csv"):
        logs.read_cats(str(tmp_path / "flight_baro.csv"))


def test_cats_camel_case_flight_info_is_found(tmp_path):
    fx.write_cats_set(tmp_path, info_name="flightInfo")
    data = logs.load_log(str(tmp_path / "flight_baro.csv"))
    assert data.reference_name.startswith("CATS")


# --- generic CSV -------------------------------------------------------------------

def read(path, **options):
    return logs.read_csv_log(str(path), "time", "accel", "baro", reference_column="reference", **options)


def test_csv_in_g_and_feet_reads_in_si_units(tmp_path):
    truth = fx.write_generic_csv(tmp_path / "log.csv", accel_units="g", altitude_units="ft")
    data = read(tmp_path / "log.csv", accel_units="g", altitude_units="ft")
    baro = np.isfinite(data.baro_altitude)
    np.testing.assert_allclose(data.baro_altitude[baro], truth["altitude"][baro], atol=1e-3)
    np.testing.assert_allclose(data.vertical_acceleration, truth["accel"], atol=1e-4)


def test_csv_reference_in_feet_is_converted_too(tmp_path):
    truth = fx.write_generic_csv(tmp_path / "log.csv", altitude_units="ft")
    data = read(tmp_path / "log.csv", altitude_units="ft")
    np.testing.assert_allclose(data.reference_altitude, truth["altitude"], atol=1e-3)


def test_csv_with_gravity_left_in_is_refused_with_the_remedy(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", gravity=fx.G)
    with pytest.raises(LogError, match="gravity is still in it.*remove_gravity=True"):
        read(tmp_path / "log.csv")


def test_csv_in_g_with_gravity_but_no_units_given_is_refused(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", gravity=fx.G, accel_units="g")
    with pytest.raises(LogError, match="probably in g with gravity"):
        read(tmp_path / "log.csv")


def test_csv_remove_gravity_subtracts_one_g(tmp_path):
    truth = fx.write_generic_csv(tmp_path / "log.csv", gravity=fx.G)
    data = read(tmp_path / "log.csv", remove_gravity=True)
    np.testing.assert_allclose(data.vertical_acceleration, truth["accel"], atol=1e-5)


def test_csv_remove_gravity_on_a_gravity_free_column_is_refused(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv")
    with pytest.raises(LogError, match="not about"):
        read(tmp_path / "log.csv", remove_gravity=True)


def test_csv_with_bom_reads_its_first_column_name(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", bom=True)
    assert read(tmp_path / "log.csv").time.size == 2000


def test_csv_repeated_timestamps_are_merged_not_refused(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", repeat_every=4)
    data = read(tmp_path / "log.csv")
    assert data.repeated_timestamps == 499
    assert np.all(np.diff(data.time) > 0)


def test_csv_time_going_backwards_names_the_line_in_plain_numbers(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", backwards_row=50)
    with pytest.raises(LogError) as error:
        read(tmp_path / "log.csv")
    message = str(error.value)
    assert "line 52, column 'time': time goes backwards (-0.51 s after 0.49 s on line 51)" in message
    assert "np." not in message and "float64" not in message


def test_csv_bad_cell_names_the_file_line_and_column(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", bad_cell_row=37)
    with pytest.raises(LogError, match=r"log\.csv: line 39, column 'accel': 'oops' is not a number"):
        read(tmp_path / "log.csv")


def test_csv_gap_is_listed_and_warned(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", gap=(8.0, 2.0))
    with pytest.warns(LogWarning, match="logging gap"):
        data = read(tmp_path / "log.csv")
    assert data.gaps == [(pytest.approx(7.99), pytest.approx(2.01))]


def test_csv_cut_short_last_line_is_dropped_with_a_warning(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", cut_tail=True)
    data = read(tmp_path / "log.csv")
    assert data.time.size == 2000
    assert any("cut short" in w for w in data.warnings)


def test_csv_short_row_in_the_middle_names_line_and_column(tmp_path):
    path = tmp_path / "log.csv"
    fx.write_generic_csv(path)
    lines = path.read_text().split("\n")
    lines[10] = lines[10].split(",")[0]
    path.write_text("\n".join(lines))
    with pytest.raises(LogError, match="line 11, column 'accel': missing"):
        read(path)


def test_csv_empty_baro_column_is_a_log_error(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("time,accel,baro\n0,0,\n0.1,0,\n0.2,0,\n")
    with pytest.raises(LogError, match="column 'baro': no usable value"):
        logs.read_csv_log(str(path), "time", "accel", "baro")


def test_csv_na_and_null_cells_mean_no_baro_sample(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("time,accel,baro\n0,0,1.5\n0.1,0,NA\n0.2,0,null\n0.3,0,2.0\n")
    data = logs.read_csv_log(str(path), "time", "accel", "baro")
    np.testing.assert_array_equal(np.isfinite(data.baro_altitude), [True, False, False, True])


def test_csv_pressure_column_far_outside_pascal_range_warns(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv")
    with pytest.warns(LogWarning, match="is it really a pressure in Pa"):
        logs.read_csv_log(str(tmp_path / "log.csv"), "time", "accel", pressure_column="reference")


def test_csv_pressure_with_ground_temperature_gives_height_above_start(tmp_path):
    time = np.arange(0, 10, 0.1)
    height = np.where(time > 2, 100.0, 0.0)
    pressure = 95000.0 * np.exp(-9.80665 * height / (287.05287 * 280.0))
    path = tmp_path / "log.csv"
    path.write_text("time,accel,p\n" + "".join(f"{t},0,{p}\n" for t, p in zip(time, pressure)))
    data = logs.read_csv_log(str(path), "time", "accel", pressure_column="p", ground_temperature_k=280.0)
    assert data.altitude_reference == "pad"
    assert data.baro_altitude[-1] == pytest.approx(100.0, abs=0.5)


def test_csv_zero_ground_pressure_with_ground_temperature_is_a_log_error(tmp_path):
    """A pressure column that reads 0 Pa over the first second cannot be a ground pressure: its 0 Pa cells are
    dropped as implausible, and then there is no ground pressure: a LogError naming the
    column (the CLI's one-line error), not the ValueError of sensors.height_above_ground."""
    time = np.arange(0, 4, 0.1)
    pressure = np.where(time < 1.5, 0.0, 95000.0)
    path = tmp_path / "log.csv"
    path.write_text("time,accel,p\n" + "".join(f"{t},0,{p}\n" for t, p in zip(time, pressure)))
    with pytest.raises(logs.LogError, match=r"column 'p': no pressure in the first 1 s"):
        logs.read_csv_log(str(path), "time", "accel", pressure_column="p", ground_temperature_k=280.0)


def test_csv_body_accelerometer_with_quaternion_gives_vertical_acceleration(tmp_path):
    time = np.arange(0, 4, 0.01)
    half = np.radians(30.0) / 2  # rolled 30°, climbing at 2 m/s² (earth frame)
    specific_force_earth = np.array([0.0, 0.0, -(fx.G + 2.0)])  # NED
    q = np.array([np.cos(half), np.sin(half), 0.0, 0.0])
    from fusion_altitude.sensors import quaternion_to_matrix
    body = quaternion_to_matrix(q).T @ specific_force_earth
    path = tmp_path / "log.csv"
    path.write_text("t,ax,ay,az,qw,qx,qy,qz,alt\n" + "".join(
        f"{t},{body[0]},{body[1]},{body[2]},{q[0]},{q[1]},{q[2]},{q[3]},1.0\n" for t in time))
    data = logs.read_csv_log(str(path), "t", baro_column="alt", accel_body_columns=("ax", "ay", "az"),
                             attitude_columns=("qw", "qx", "qy", "qz"), frame="NED")
    np.testing.assert_allclose(data.vertical_acceleration, 2.0, atol=1e-9)


def test_csv_body_accelerometer_with_euler_degrees_gives_vertical_acceleration(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("t,ax,ay,az,roll,pitch,yaw,alt\n" + "".join(
        f"{t / 100},0,0,{-fx.G},0,0,45,1.0\n" for t in range(200)))
    data = logs.read_csv_log(str(path), "t", baro_column="alt", accel_body_columns=("ax", "ay", "az"),
                             attitude_columns=("roll", "pitch", "yaw"), attitude_convention="euler_deg")
    np.testing.assert_allclose(data.vertical_acceleration, 0.0, atol=1e-9)


def test_csv_euler_convention_with_four_columns_is_refused(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv")
    with pytest.raises(LogError, match="needs 3 attitude columns"):
        logs.read_csv_log(str(tmp_path / "log.csv"), "time", baro_column="baro", accel_body_columns=("a", "b", "c"),
                          attitude_columns=("w", "x", "y", "z"), attitude_convention="euler_deg")


def test_csv_unknown_column_lists_the_columns(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv")
    with pytest.raises(LogError, match="column 'alt' not found; columns are time, accel, baro, reference"):
        logs.read_csv_log(str(tmp_path / "log.csv"), "time", "accel", "alt")


def test_csv_blank_lines_keep_line_numbers_right(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("time,accel,baro\n0,0,1\n\n0.1,0,1\n\n0.05,0,1\n")
    with pytest.raises(LogError, match="line 6, column 'time': time goes backwards"):
        logs.read_csv_log(str(path), "time", "accel", "baro")


def test_csv_reader_reports_progress_to_the_end(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv")
    calls = []
    read(tmp_path / "log.csv", progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1][0] == calls[-1][1]


def test_every_reader_error_is_a_single_line(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", bad_cell_row=3)
    with pytest.raises(LogError) as error:
        read(tmp_path / "log.csv")
    assert "\n" not in str(error.value)


def test_numbers_in_messages_are_plain(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("time,accel,baro\n1700000000.25,0,1\n1700000000.125,0,1\n")
    with pytest.raises(LogError) as error:
        logs.read_csv_log(str(path), "time", "accel", "baro")
    assert not re.search(r"np\.|float64|array\(", str(error.value))


def test_csv_gps_rangefinder_and_temperature_columns_are_read_in_si_units(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("t,a,alt,gps,range,temp\n0,0,10,,3.0,20\n0.1,0,10,1000,,21\n0.2,0,10,1001,3.5,22\n")
    data = logs.read_csv_log(str(path), "t", "a", "alt", gps_column="gps", rangefinder_column="range",
                             temperature_column="temp", altitude_units="ft")
    np.testing.assert_allclose(data.gps_altitude, [np.nan, 304.8, 305.1048])
    np.testing.assert_allclose(data.rangefinder, [0.9144, np.nan, 1.0668])
    np.testing.assert_allclose(data.temperature, [293.15, 294.15, 295.15])


def test_cats_flight_info_state_column_becomes_flight_state(tmp_path):
    fx.write_cats_set(tmp_path)
    info = tmp_path / "flight_flight_info.csv"
    lines = info.read_text().strip().split("\n")
    lines = [lines[0] + ",state"] + [line + ("," + ("READY" if float(line.split(",")[0]) < 0 else "THRUSTING"))
                                     for line in lines[1:]]
    info.write_text("\n".join(lines) + "\n")
    data = logs.load_log(str(tmp_path))
    assert data.flight_state[0] == "READY" and data.flight_state[-1] == "THRUSTING"


def test_log_error_message_is_folded_onto_one_line():
    assert str(LogError("a\nb  c")) == "a b c"


def test_altos_fixed_width_fields_are_read(tmp_path):
    truth = fx.write_altos_csv(tmp_path / "telemega.csv", padded=True)
    data = logs.load_log(str(tmp_path / "telemega.csv"))
    np.testing.assert_allclose(data.baro_altitude, truth_at(truth, data.time), atol=0.01)
    assert data.flight_state[0] == "pad"


# --- PX4 ULog ----------------------------------------------------------------------

@pytest.mark.parametrize("style", ["new", "old"])
def test_ulog_of_either_generation_gives_the_baro_altitude(tmp_path, style):
    truth = fx.write_ulog(tmp_path / "log.ulg", style=style)
    data = logs.load_log(str(tmp_path / "log.ulg"))
    baro = np.isfinite(data.baro_altitude)
    assert baro.sum() >= 199
    np.testing.assert_allclose(data.baro_altitude[baro], truth_at(truth, data.time[baro]), atol=1e-4)


@pytest.mark.parametrize("style", ["new", "old"])
def test_ulog_gps_altitude_in_metres_only_with_a_3d_fix(tmp_path, style):
    truth = fx.write_ulog(tmp_path / "log.ulg", style=style, gps_fix_from=2.0)
    data = logs.load_log(str(tmp_path / "log.ulg"))
    gps = np.isfinite(data.gps_altitude)
    assert not gps[data.time < 2.0].any() and gps.sum() == 40
    np.testing.assert_allclose(data.gps_altitude[gps], truth_at(truth, data.time[gps]) + 100.0, atol=1e-3)


def test_ulog_vertical_acceleration_is_gravity_free(tmp_path):
    fx.write_ulog(tmp_path / "log.ulg")
    data = logs.load_log(str(tmp_path / "log.ulg"))
    np.testing.assert_allclose(data.vertical_acceleration, fx.profile(data.time)[2], atol=1e-4)


def test_ulog_second_baro_instance_reads_its_pressure(tmp_path):
    fx.write_ulog(tmp_path / "log.ulg", second_baro_offset_pa=-24.0)
    primary = logs.load_log(str(tmp_path / "log.ulg"))
    second = logs.load_log(str(tmp_path / "log.ulg"), instance=1)
    baro = np.isfinite(primary.baro_altitude)
    np.testing.assert_allclose(second.baro_altitude[baro] - primary.baro_altitude[baro], 2.0, atol=0.05)


def test_ulog_missing_instance_is_a_log_error(tmp_path):
    fx.write_ulog(tmp_path / "log.ulg")
    with pytest.raises(LogError, match="instance 5"):
        logs.load_log(str(tmp_path / "log.ulg"), instance=5)


def test_ulog_gap_is_listed(tmp_path):
    fx.write_ulog(tmp_path / "log.ulg", gap=(4.0, 2.0))
    assert logs.load_log(str(tmp_path / "log.ulg")).gaps == [(pytest.approx(3.99), pytest.approx(2.01))]


def test_ulog_is_recognised_by_content(tmp_path):
    fx.write_ulog(tmp_path / "flight.dat")
    assert logs.sniff_format(str(tmp_path / "flight.dat")) == "ulog"


def test_csv_body_accelerometer_in_the_wrong_frame_is_refused(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("t,ax,ay,az,roll,pitch,yaw,alt\n" + "".join(
        f"{t / 100},0,0,{fx.G},0,0,0,1.0\n" for t in range(200)))  # z-up body (+1 g) declared NED
    with pytest.raises(LogError, match="frame 'NED' looks wrong"):
        logs.read_csv_log(str(path), "t", baro_column="alt", accel_body_columns=("ax", "ay", "az"),
                          attitude_columns=("roll", "pitch", "yaw"), attitude_convention="euler_deg", frame="NED")


def test_ulog_second_accelerometer_instance_reads_sensor_accel(tmp_path):
    fx.write_ulog(tmp_path / "log.ulg")  # instance 1 reads 0.3 m/s² more on body z (down)
    primary = logs.load_log(str(tmp_path / "log.ulg"))
    second = logs.load_log(str(tmp_path / "log.ulg"), instance=1)
    np.testing.assert_allclose(second.vertical_acceleration - primary.vertical_acceleration, -0.3, atol=1e-5)


def test_reader_warnings_point_at_the_callers_line(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", repeat_every=4)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LogWarning)
        read(tmp_path / "log.csv")
    assert caught and all(Path(w.filename).name == "test_logs.py" for w in caught)


def test_ground_temperature_in_celsius_on_cats_gives_a_hypsometric_height(tmp_path):
    fx.write_cats_set(tmp_path)
    warm = logs.load_log(str(tmp_path / "flight_baro.csv"), ground_temperature_k=308.15)
    isa = logs.load_log(str(tmp_path / "flight_baro.csv"))
    top = np.nanargmax(isa.baro_altitude)
    assert warm.baro_altitude[top] > isa.baro_altitude[top] * 1.02  # 35 °C air is thinner than ISA's 15 °C
    with pytest.raises(LogError, match="board temperature"):
        logs.read_cats(str(tmp_path / "flight_baro.csv"), ground_temperature_k="log")


def test_quiet_warnings_records_a_readers_warnings_without_issuing_them(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", duration=6.0, rate=50.0, repeat_every=7)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an issued warning would fail here
        with logs.quiet_warnings():
            log = logs.load_log(str(tmp_path / "log.csv"), time_column="time", accel_column="accel",
                                baro_column="baro")
    assert any("repeated" in message for message in log.warnings)


def test_quiet_warnings_keeps_its_old_private_path():
    from fusion_altitude.logs import _data

    assert _data.quiet_warnings is logs.quiet_warnings
