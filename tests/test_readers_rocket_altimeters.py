"""Specification of the Featherweight Raven and Missile Works RRC3 readers.

Fixtures are written by tests/logfixtures.py the way the real exports are; the
real shared logs (``raven_ndrt2020.csv``, ``rrc3_juno3.csv``, read through
FUSION_ALTITUDE_SHARED_DATA) are checked for the quirks the README lists.
"""

import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude.cli import main  # noqa: E402
from fusion_altitude.logs import LogError, LogWarning  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = os.environ.get("FUSION_ALTITUDE_SHARED_DATA", str(ROOT / ".." / "shared" / "data"))
G = 9.80665


def read(path, **options):
    """load_log with its LogWarnings recorded: (LogData, [warning texts])."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LogWarning)
        data = logs.load_log(str(path), **options)
    return data, [str(w.message) for w in caught if issubclass(w.category, LogWarning)]


def shared(name):
    path = os.path.join(DATA, name)
    assert os.path.exists(path), f"shared data not found at {path}"
    return path


# --- Featherweight Raven -------------------------------------------------------

def test_raven_export_is_recognised_by_its_header(tmp_path):
    assert logs.sniff_format(fx.raven_csv(tmp_path)) == "raven"


def test_raven_grid_is_the_union_of_both_time_columns(tmp_path):
    data, _ = read(fx.raven_csv(tmp_path, duration=10.0, accel_seconds=4.5))
    accel_time = np.round(np.arange(0.0, 4.5, 0.0025), 6)
    alt_time = np.round(np.arange(0.04375, 10.0, 0.05), 6)
    np.testing.assert_allclose(data.time, np.union1d(accel_time, alt_time))


def test_raven_altitude_is_converted_from_feet_on_its_own_time_steps(tmp_path):
    data, _ = read(fx.raven_csv(tmp_path))
    sampled = np.isfinite(data.baro_altitude)
    height, _, _ = fx.rocket_profile(data.time[sampled] - 0.5)
    np.testing.assert_allclose(data.baro_altitude[sampled], height, atol=0.3048 * 1e-5 + 1e-9)
    assert data.altitude_reference == "pad" and data.ground_altitude == 0.0


def test_raven_axial_accel_is_converted_from_g_where_sampled_and_nan_elsewhere(tmp_path):
    data, _ = read(fx.raven_csv(tmp_path, accel_seconds=4.5))
    sampled = np.isfinite(data.axial_acceleration)
    _, _, accel = fx.rocket_profile(data.time[sampled] - 0.5)
    np.testing.assert_allclose(data.axial_acceleration[sampled], accel + G, atol=0.005 * G)
    assert data.time[sampled][-1] < 4.5 and not sampled[data.time > 4.5].any()


def test_raven_vertical_acceleration_is_axial_minus_g_while_the_accelerometer_runs(tmp_path):
    data, _ = read(fx.raven_csv(tmp_path, accel_seconds=4.5))
    sampled = np.isfinite(data.axial_acceleration)
    np.testing.assert_allclose(data.vertical_acceleration[sampled], data.axial_acceleration[sampled] - G)


def test_raven_vertical_acceleration_is_zero_after_the_accelerometer_ends_and_one_warning_says_so(tmp_path):
    data, caught = read(fx.raven_csv(tmp_path, accel_seconds=4.5))
    assert np.all(data.vertical_acceleration[data.time > 4.5] == 0.0)
    said = [w for w in caught if "accelerometer ends at 4.4975 s" in w]
    assert len(said) == 1 and "0 m/s² after" in said[0] and "baro alone" in said[0]


def test_raven_log_is_a_rocket_with_an_accelerometer(tmp_path):
    data, _ = read(fx.raven_csv(tmp_path))
    assert data.vehicle == "rocket" and not data.baro_only


def test_raven_absurd_altitude_cell_is_dropped_with_a_warning_naming_its_line(tmp_path):
    path = fx.raven_csv(tmp_path)
    lines = Path(path).read_text().split("\n")
    cells = lines[100].split(",")
    cells[4] = "1e30"
    lines[100] = ",".join(cells)
    Path(path).write_text("\n".join(lines))
    data, caught = read(path)
    assert any("line 101, column 'Altitude (Ft-AGL)'" in w and "dropped" in w for w in caught)
    assert np.nanmax(data.baro_altitude) < 2000.0


def test_raven_takes_no_options(tmp_path):
    with pytest.raises(LogError, match="takes no ground_temperature_k option"):
        logs.load_log(fx.raven_csv(tmp_path), ground_temperature_k=288.0)


def test_real_raven_export_reads_both_time_bases():
    data, _ = read(shared("raven_ndrt2020.csv"))
    assert data.time[-1] == pytest.approx(90.945)
    assert int(np.isfinite(data.axial_acceleration).sum()) == 1819  # every data line holds both channels
    assert int(np.isfinite(data.baro_altitude).sum()) == 1819
    assert np.nanmedian(data.axial_acceleration[data.time < 0.1]) == pytest.approx(G, abs=0.15 * G)


def test_real_raven_export_is_no_longer_refused_by_run(tmp_path, capsys):
    assert main(["run", shared("raven_ndrt2020.csv"), "--estimator", "observer", "-o",
                 str(tmp_path / "out.csv")]) == 0
    assert "Featherweight Raven CSV" in capsys.readouterr().out


# --- Missile Works RRC3 --------------------------------------------------------

def test_rrc3_export_is_recognised_by_its_header(tmp_path):
    assert logs.sniff_format(fx.rrc3_csv(tmp_path)) == "rrc3"


def test_rrc3_is_baro_only_with_zero_vertical_acceleration(tmp_path):
    data, _ = read(fx.rrc3_csv(tmp_path))
    assert data.baro_only and data.accel is None and data.axial_acceleration is None
    assert np.all(data.vertical_acceleration == 0.0)


def test_rrc3_altitude_is_above_the_pad_and_its_velocity_the_reference(tmp_path):
    data, _ = read(fx.rrc3_csv(tmp_path))
    height, velocity, _ = fx.rocket_profile(data.time - 1.0)
    keep = np.isfinite(data.baro_altitude)
    keep[fx.RRC3_SPIKE_ROW] = False
    np.testing.assert_allclose(data.baro_altitude[keep], height[keep], rtol=1e-5, atol=1e-3)
    np.testing.assert_allclose(data.reference_velocity[keep], velocity[keep], rtol=1e-5, atol=1e-3)
    assert data.altitude_reference == "pad" and data.vehicle == "rocket"


def test_rrc3_pressure_is_converted_from_hpa_to_pa(tmp_path):
    path = fx.rrc3_csv(tmp_path)
    data, _ = read(path)
    first_cell = float(Path(path).read_text().split("\n")[1].split(",")[2])
    assert data.pressure[0] == pytest.approx(first_cell * 100.0)


def test_rrc3_one_sample_spike_is_kept_as_baro_noise(tmp_path):
    data, _ = read(fx.rrc3_csv(tmp_path))
    height, _, _ = fx.rocket_profile(data.time[fx.RRC3_SPIKE_ROW] - 1.0)
    assert data.baro_altitude[fx.RRC3_SPIKE_ROW] == pytest.approx(height + 54.0, abs=0.01)


def test_rrc3_garbage_rows_are_dropped_with_a_warning_naming_their_lines(tmp_path):
    data, caught = read(fx.rrc3_csv(tmp_path))
    lines = [row + 2 for row in fx.RRC3_GARBAGE_ROWS]
    assert any(f"lines {lines[0]}, {lines[1]}: garbage rows" in w for w in caught)
    assert not np.isfinite(data.baro_altitude[list(fx.RRC3_GARBAGE_ROWS)]).any()


def test_rrc3_event_of_a_garbage_row_is_kept_in_the_flight_state(tmp_path):
    data, _ = read(fx.rrc3_csv(tmp_path))
    first = fx.RRC3_GARBAGE_ROWS[0]
    assert list(data.flight_state[first - 1:first + 1]) == ["pad", "drogue"]
    assert any("Drogue at" in note for note in data.notes)


def test_rrc3_rows_without_a_temperature_cell_read_the_event_from_the_shifted_column(tmp_path):
    data, _ = read(fx.rrc3_csv(tmp_path))
    assert np.isnan(data.temperature[fx.RRC3_SHIFT_FROM_ROW:]).all()
    assert data.temperature[0] == pytest.approx(31.9 + 273.15)
    assert set(data.flight_state[fx.RRC3_SHIFT_FROM_ROW:fx.RRC3_GARBAGE_ROWS[0]]) == {"pad"}


def test_rrc3_bad_number_names_file_line_and_column(tmp_path):
    path = fx.rrc3_csv(tmp_path)
    lines = Path(path).read_text().split("\n")
    cells = lines[10].split(",")
    lines[10] = ",".join([cells[0], "oops"] + cells[2:])
    Path(path).write_text("\n".join(lines))
    with pytest.raises(LogError, match=r"line 11, column 'altitude': 'oops' is not a number"):
        logs.load_log(path)


def test_real_rrc3_export_drops_its_two_garbage_rows_and_keeps_the_drogue_event():
    data, caught = read(shared("rrc3_juno3.csv"))
    assert any("lines 611, 612: garbage rows" in w for w in caught)
    assert np.nanmax(data.baro_altitude) < 3300.0 and np.nanmin(data.baro_altitude) > -20.0
    assert data.flight_state[-1] == "drogue"


def test_real_rrc3_export_reads_the_shifted_rows_from_29_5_s():
    data, _ = read(shared("rrc3_juno3.csv"))
    after = data.time >= 29.5
    assert np.isnan(data.temperature[after]).all() and np.isfinite(data.temperature[~after]).all()
    assert any("21 rows without a temperature cell" in note for note in data.notes)


def test_real_rrc3_export_is_read_by_run(tmp_path, capsys):
    assert main(["run", shared("rrc3_juno3.csv"), "--estimator", "observer", "-o", str(tmp_path / "out.csv")]) == 0
    assert "RRC3 CSV" in capsys.readouterr().out
