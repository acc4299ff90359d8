"""Specification of the plausibility checks every reader runs before an estimator sees a log
(fusion_altitude/logs/_checks.py): absurd cells dropped naming their line, dead channels never used, a time column
that is not in seconds refused naming the fix. Each check is one line, none silent."""

import re
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude.cli import main  # noqa: E402
from fusion_altitude.logs import LogData, LogError, LogWarning  # noqa: E402
from fusion_altitude.logs._checks import is_dead, is_dead_imu  # noqa: E402
from fusion_altitude.logs._data import finish  # noqa: E402

G = 9.80665
CSV = dict(time_column="time", accel_column="accel", baro_column="baro")


def caught_warnings(function, *args, **kwargs):
    """(result, [LogWarning texts]) of a call."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LogWarning)
        result = function(*args, **kwargs)
    return result, [str(w.message) for w in caught if issubclass(w.category, LogWarning)]


def write_csv(path, rows, header="time,accel,baro"):
    Path(path).write_text(header + "\n" + "".join(",".join(str(c) for c in row) + "\n" for row in rows))
    return str(path)


def live_rows(n, step=0.1, baro=lambda i: 10.0 + 0.01 * (i % 7)):
    return [[round(i * step, 6), 0.01 * ((i * 37) % 11 - 5), baro(i)] for i in range(n)]


# --- absurd cells --------------------------------------------------------------------

def test_csv_1e30_baro_cell_is_dropped_with_a_warning_naming_its_line(tmp_path):
    data, caught = caught_warnings(logs.load_log, fx.csv_with_absurd_baro(tmp_path), **CSV)
    line = fx.ABSURD_BARO_ROW + 2
    said = [w for w in caught if "not a plausible baro altitude" in w]
    assert len(said) == 1 and f"line {line}, column 'baro': 1e+30 m" in said[0] and "dropped" in said[0]
    assert np.isnan(data.baro_altitude[fx.ABSURD_BARO_ROW])


def test_csv_1e30_baro_cell_no_longer_reaches_the_printed_altitude(tmp_path, capsys):
    path = fx.csv_with_absurd_baro(tmp_path)
    assert main(["run", path, "--time", "time", "--accel", "accel", "--baro", "baro", "--estimator", "observer",
                 "-o", str(tmp_path / "out.csv")]) == 0
    printed = capsys.readouterr()
    final = re.search(r"final altitude \(m\)\s+(\S+)", printed.out)
    assert final is not None and abs(float(final.group(1)) - 30.0) < 1.0
    assert "line 702, column 'baro'" in printed.out + printed.err


def test_infinite_baro_cell_is_dropped(tmp_path):
    rows = live_rows(40)
    rows[7][2] = "inf"
    data, caught = caught_warnings(logs.load_log, write_csv(tmp_path / "log.csv", rows), **CSV)
    assert np.isnan(data.baro_altitude[7]) and any("line 9, column 'baro': inf m" in w for w in caught)


def test_baro_below_minus_one_kilometre_is_dropped(tmp_path):
    rows = live_rows(40)
    rows[3][2] = -2500.0
    data, caught = caught_warnings(logs.load_log, write_csv(tmp_path / "log.csv", rows), **CSV)
    assert np.isnan(data.baro_altitude[3]) and any("line 5, column 'baro': -2500 m" in w for w in caught)


def test_several_absurd_cells_are_one_warning_with_a_count(tmp_path):
    rows = live_rows(40)
    for i in (3, 9, 20):
        rows[i][2] = 1e30
    _, caught = caught_warnings(logs.load_log, write_csv(tmp_path / "log.csv", rows), **CSV)
    said = [w for w in caught if "not a plausible" in w]
    assert len(said) == 1 and "and 2 more lines (the last line 22)" in said[0]


def test_pressure_of_zero_and_above_120_kpa_is_dropped(tmp_path):
    rows = [[round(i * 0.1, 6), 0.01 * (i % 3), 95000.0 + i] for i in range(40)]
    rows[5][2], rows[6][2] = 0.0, 130000.0
    data, caught = caught_warnings(logs.load_log, write_csv(tmp_path / "log.csv", rows, "time,accel,p"),
                                   time_column="time", accel_column="accel", pressure_column="p")
    assert np.isnan(data.pressure[[5, 6]]).all() and np.isfinite(data.pressure[[4, 7]]).all()
    assert any("line 7, column 'p': 0 Pa is not a plausible pressure" in w for w in caught)


def test_absurd_baro_on_a_grid_without_lines_names_the_sample_and_its_time():
    baro = np.linspace(0.0, 10.0, 50)
    baro[12] = 1e30
    data = LogData("x.ulg (PX4 ULog)", np.arange(50) * 0.1, np.sin(np.arange(50.0)), baro)
    _, caught = caught_warnings(finish, data)
    assert any("sample 12 (1.2 s), column 'baro_altitude': 1e+30 m" in w for w in caught)
    assert np.isnan(data.baro_altitude[12])


def test_cats_absurd_pressure_row_is_dropped_naming_its_line(tmp_path):
    fx.write_cats_set(tmp_path)
    path = tmp_path / "flight_baro.csv"
    lines = path.read_text().split("\n")
    cells = lines[150].split(",")
    cells[3] = "-5"
    lines[150] = ",".join(cells)
    path.write_text("\n".join(lines))
    _, caught = caught_warnings(logs.load_log, str(path))
    assert any("line 151, column 'P': -5 Pa is not a plausible pressure" in w for w in caught)


# --- dead channels --------------------------------------------------------------------

def test_constant_channel_is_dead():
    assert is_dead(np.full(50, 3.0)) and is_dead(np.zeros(50))


def test_short_constant_channel_is_not_called_dead():
    assert not is_dead(np.zeros(10))


def test_channel_with_one_changed_sample_is_alive():
    values = np.zeros(50)
    values[20] = 0.01
    assert not is_dead(values)


def test_constant_channel_with_infinite_and_missing_samples_is_dead():
    values = np.full(50, 3.0)
    values[[5, 9, 30]] = [np.inf, -np.inf, np.nan]
    assert is_dead(values)


def test_channel_of_two_finite_values_beside_infinities_is_alive():
    values = np.full(50, 3.0)
    values[[5, 9, 30]] = [np.inf, 4.0, -np.inf]
    assert not is_dead(values)


def test_raw_accelerometer_steady_at_one_g_is_a_vehicle_at_rest_not_a_dead_one():
    assert not is_dead_imu(np.tile([0.0, 0.0, -G], (50, 1))) and is_dead_imu(np.zeros((50, 3)))


def test_csv_all_zero_accel_column_is_dead_and_the_log_runs_baro_only(tmp_path):
    rows = [[r[0], 0.0, r[2]] for r in live_rows(40)]
    data, caught = caught_warnings(logs.load_log, write_csv(tmp_path / "log.csv", rows), **CSV)
    assert data.baro_only
    said = [w for w in caught if "dead sensor" in w]
    assert len(said) == 1 and "column 'accel' is all zero" in said[0] and "baro alone" in said[0]


def test_csv_constant_nonzero_accel_column_is_dead_and_not_integrated(tmp_path):
    rows = [[r[0], 0.7, r[2]] for r in live_rows(40)]
    data, _ = caught_warnings(logs.load_log, write_csv(tmp_path / "log.csv", rows), **CSV)
    assert data.baro_only and np.all(data.vertical_acceleration == 0.0)


def test_dead_raw_accelerometer_on_any_reader_is_dropped_with_one_warning():
    data = LogData("x.bin (ArduPilot DataFlash)", np.arange(50) * 0.1, np.sin(np.arange(50.0)),
                   np.linspace(0, 5, 50), accel=np.zeros((50, 3)), gyro=np.ones((50, 3)) * 0.01, imu_frame="FRD")
    _, caught = caught_warnings(finish, data)
    assert data.accel is None and data.gyro is None and data.imu_frame == ""
    assert len([w for w in caught if "raw accelerometer (every axis) is all zero" in w]) == 1


def test_constant_baro_gets_a_warning():
    data = LogData("x.csv (CSV)", np.arange(50) * 0.1, np.sin(np.arange(50.0)), np.full(50, 12.0))
    _, caught = caught_warnings(finish, data)
    assert any("the baro altitude is constant (12 m) on every sample" in w for w in caught)


# --- time units -------------------------------------------------------------------------

def test_csv_millisecond_time_is_refused_naming_the_time_units_option(tmp_path):
    with pytest.raises(LogError, match=r"does not look like seconds \(median step 10, .*probably milliseconds; "
                                       r"column 'time': set time_units to 'ms' or 'us'"):
        logs.load_log(fx.csv_with_millisecond_time(tmp_path), **CSV)


def test_csv_millisecond_time_is_refused_by_run_with_a_one_line_error_naming_the_flag(tmp_path, capsys):
    code = main(["run", fx.csv_with_millisecond_time(tmp_path), "--time", "time", "--accel", "accel",
                 "--baro", "baro"])
    error = capsys.readouterr().err.strip()
    assert code != 0 and "\n" not in error and "set --time-units to 'ms' or 'us'" in error


def test_csv_millisecond_time_is_read_with_time_units_ms(tmp_path):
    data = logs.load_log(fx.csv_with_millisecond_time(tmp_path), time_units="ms", **CSV)
    assert np.median(np.diff(data.time)) == pytest.approx(0.01) and data.time[-1] == pytest.approx(19.99)


def test_csv_millisecond_time_is_read_by_run_with_the_time_units_flag(tmp_path):
    assert main(["run", fx.csv_with_millisecond_time(tmp_path), "--time", "time", "--accel", "accel",
                 "--baro", "baro", "--time-units", "ms", "--estimator", "observer",
                 "-o", str(tmp_path / "out.csv")]) == 0


def test_csv_microsecond_time_is_refused_as_microseconds(tmp_path):
    path = tmp_path / "us.csv"
    fx.write_generic_csv(path, time_scale=1e6)
    with pytest.raises(LogError, match="probably microseconds"):
        logs.load_log(str(path), **CSV)


def test_slow_one_hertz_log_in_seconds_is_not_refused(tmp_path):
    data = logs.load_log(write_csv(tmp_path / "log.csv", live_rows(120, step=1.0)), **CSV)
    assert np.median(np.diff(data.time)) == 1.0


def test_kilohertz_log_in_milliseconds_spanning_more_than_a_day_is_refused(tmp_path):
    rows = live_rows(90_000, step=1.0)
    with pytest.raises(LogError, match="does not look like seconds"):
        logs.load_log(write_csv(tmp_path / "log.csv", rows), **CSV)


def test_unknown_time_units_are_refused():
    with pytest.raises(LogError, match="time units must be 's', 'ms' or 'us', got 'min'"):
        logs.read_csv_log("whatever.csv", time_units="min", **CSV)


def test_fixed_format_with_time_not_in_seconds_is_refused():
    data = LogData("x.ulg (PX4 ULog)", np.arange(50) * 10.0, np.sin(np.arange(50.0)), np.linspace(0, 5, 50))
    with pytest.raises(LogError, match="this format's time is in seconds"):
        finish(data)


@pytest.mark.parametrize("size", [1, 2, 3, 4, 11, 610, 611, 1000])
def test_the_median_of_the_checks_is_numpys_bit_for_bit(size):
    from fusion_altitude.logs._data import median

    rng = np.random.default_rng(size)
    for values in (rng.random(size) * 10.0, rng.choice([0.01, 0.02, 0.0025, 1e-9, 3.0], size),
                   np.full(size, 0.1) + rng.integers(0, 2, size) * 1e-17):
        assert np.float64(median(values)).tobytes() == np.float64(np.median(values)).tobytes()


@pytest.mark.parametrize("values, absurd", [([1.0, np.nan, 1.5], False), ([np.nan, np.nan], False), ([], False),
                                            ([1.0, np.inf], True), ([-np.inf, 2.0], True), ([0.0, 3.0], True)])
def test_drop_absurd_without_an_absurd_cell_returns_its_input_and_no_message(values, absurd):
    from fusion_altitude.logs._checks import drop_absurd

    values = np.array(values, dtype=float)
    cleaned, message = drop_absurd("f.csv", "p", values, None, 0.0, 2.0, "Pa", "pressure", low_inclusive=False)
    assert (message is not None) == absurd
    assert (cleaned is values) == (not absurd)
