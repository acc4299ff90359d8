"""The health report: what a log's sensors and an estimator's run can stand behind (fusion_altitude.health, `run`)."""


import numpy as np
import pytest

from fusion_altitude import health, sim
from fusion_altitude.cli import main
from fusion_altitude.logs import LogData


@pytest.fixture
def shared_data(shared_logs):
    return shared_logs


def climb_log(duration=60.0, rate=50.0, baro_every=5, stop=None, gps=False, climb=2.0):
    """A 2 m/s climb on a `rate` Hz grid, baro on every `baro_every`-th step (NaN after `stop` s), GPS at 5 Hz."""
    time = np.arange(0.0, duration, 1.0 / rate)
    altitude = 100.0 + climb * time
    baro = np.full(time.size, np.nan)
    baro[::baro_every] = altitude[::baro_every]
    if stop is not None:
        baro[time >= stop] = np.nan
    gps_altitude = None
    if gps:
        gps_altitude = np.full(time.size, np.nan)
        step = int(rate / 5)
        gps_altitude[::step] = altitude[::step] + 30.0  # GPS above the baro's datum, as MSL often is
    accel = np.random.default_rng(1).normal(0.0, 0.02, time.size)  # a live accelerometer: a little noise
    return LogData("climb.csv (CSV)", time, accel, baro, gps_altitude=gps_altitude)


def write_csv(path, data):
    columns = {"az": data.vertical_acceleration, "alt": data.baro_altitude}
    if data.gps_altitude is not None:
        columns["gps"] = data.gps_altitude
    sim.write_log_csv(str(path), data.time, columns, time_column="t")
    return str(path)


def stream(report, name):
    return next(s for s in report if s.name == name)


def test_each_stream_has_its_rate_first_and_last_sample():
    baro = stream(health.sensor_health(climb_log()), "baro")
    assert baro.samples == 600 and baro.rate == pytest.approx(10.0)
    assert baro.first == 0.0 and baro.last == pytest.approx(59.9)
    assert not baro.stopped and not baro.dead


def test_a_baro_that_stops_is_stopped_and_its_silence_to_the_end_is_the_longest_outage():
    baro = stream(health.sensor_health(climb_log(stop=14.4)), "baro")
    assert baro.stopped and baro.last < 14.4
    assert baro.longest_outage == pytest.approx(60.0 - 0.02 - baro.last)
    assert baro.outage_start == baro.last


def test_a_one_packet_silence_of_a_2hz_baro_is_not_a_stop():
    baro = stream(health.sensor_health(climb_log(baro_every=25, duration=60.3)), "baro")
    assert baro.rate == pytest.approx(2.0) and not baro.stopped


def test_a_constant_channel_is_dead():
    data = climb_log()
    data.baro_altitude[np.isfinite(data.baro_altitude)] = 0.0
    assert stream(health.sensor_health(data), "baro").dead


def test_the_timeout_is_ten_periods_and_never_under_one_second():
    assert health.baro_timeout_for(100.0) == 1.0
    assert health.baro_timeout_for(2.0) == 5.0
    assert health.baro_timeout_for(np.nan) == 1.0


def test_rows_are_not_baro_aided_only_once_the_latest_baro_sample_is_older_than_the_timeout():
    data = climb_log(stop=20.0)
    unaided = health.not_baro_aided(data.time, data.baro_altitude)
    last = data.time[np.flatnonzero(np.isfinite(data.baro_altitude))[-1]]
    assert not unaided[data.time <= last + 1.0].any()
    assert unaided[data.time > last + 1.0 + 1e-9].all()


def test_row_flags_mark_a_gap_a_clipped_sample_and_the_rows_after_the_baro_ends():
    data = climb_log(stop=50.0)
    data.time[300:] += 3.0  # a 3 s logging gap before row 300
    data.clipped = np.zeros(data.time.size, bool)
    data.clipped[100] = True
    flags = health.row_flags(data, gap_period=0.5)
    bits = health.FLAG_BITS
    assert flags[300] & bits["logging_gap"] and not flags[299] & bits["logging_gap"]
    assert flags[100] & bits["accel_clipped"] and not flags[101] & bits["accel_clipped"]
    end = np.flatnonzero(np.isfinite(data.baro_altitude))[-1]
    assert (flags[end + 1:] & bits["baro_stopped"]).all() and not (flags[:end + 1] & bits["baro_stopped"]).any()


def test_a_finite_estimate_within_the_height_sources_passes_the_check():
    data = climb_log()
    assert health.check_estimate(data, 100.0 + 2.0 * data.time, np.full(data.time.size, 2.0)) is None


def test_a_non_finite_estimate_is_refused_from_its_first_bad_sample():
    data = climb_log()
    altitude = 100.0 + 2.0 * data.time
    altitude[1000:] = np.inf
    problem = health.check_estimate(data, altitude)
    assert problem.time == pytest.approx(data.time[1000]) and problem.count == data.time.size - 1000
    assert "non-finite" in str(problem)


def test_an_estimate_more_than_a_kilometre_outside_every_height_source_has_run_away():
    data = climb_log()
    altitude = 100.0 + 2.0 * data.time
    altitude[-1] = 100.0 + 120.0 + 1001.0
    problem = health.check_estimate(data, altitude)
    assert problem is not None and "outside every height source" in str(problem)


def test_the_gps_on_the_baro_datum_widens_the_plausible_range():
    data = climb_log(stop=10.0, gps=True)
    altitude = 100.0 + 2.0 * data.time + 0.0  # follows the GPS after the baro stops at 120 m: up to 220 m
    altitude[-1] = 100.0 + 2.0 * 60.0 + 900.0  # 900 m above the GPS's highest: not yet a runaway
    assert health.check_estimate(data, altitude) is None


def test_the_log_faults_stop_a_stream_and_kill_a_channel():
    time = np.arange(0.0, 10.0, 0.1)
    written, columns, _ = sim.apply_log_faults(time, {"alt": np.ones(time.size), "ax": np.ones(time.size)},
                                               sim.LogFaultModel(stops={"alt": 4.0}, dead_columns=("ax",)))
    assert np.isnan(columns["alt"][written >= 4.0]).all() and np.isfinite(columns["alt"][written < 4.0]).all()
    assert (columns["ax"] == 0.0).all()


def test_the_log_faults_name_a_column_the_log_does_not_have():
    with pytest.raises(ValueError, match="'baro'"):
        sim.apply_log_faults(np.arange(3.0), {"alt": np.ones(3)}, sim.LogFaultModel(stops={"baro": 1.0}))


def test_run_prints_the_sensor_table(tmp_path, capsys):
    log = write_csv(tmp_path / "log.csv", climb_log())
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt"]) == 0
    out = capsys.readouterr().out
    assert "longest outage (s)" in out
    row = next(line for line in out.splitlines() if line.strip().startswith("baro ") and "Hz" not in line
               and "'" not in line)
    assert "10.0" in row and "59.90" in row


def test_run_warns_when_the_baro_stops_and_flags_the_rows_that_are_not_baro_aided(tmp_path, capsys):
    log = write_csv(tmp_path / "log.csv", climb_log(stop=14.4))
    out = tmp_path / "out.csv"
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "warning: the baro stops at 14.30 s" in err and "no other height source" in err
    table = np.genfromtxt(out, delimiter=",", names=True)
    unaided = (table["flags"].astype(int) & health.FLAG_BITS["not_baro_aided"]) != 0
    assert unaided[table["time"] > 15.4].all() and not unaided[table["time"] < 15.2].any()


def test_run_picks_the_kalman_filter_when_the_baro_stops_and_the_log_has_gps(tmp_path, capsys):
    log = write_csv(tmp_path / "log.csv", climb_log(stop=14.4, gps=True))
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "--gps", "gps"]) == 0
    captured = capsys.readouterr()
    assert "estimator kalman" in captured.out and "carries on with the GPS altitude" in captured.err


def test_run_keeps_the_estimator_asked_for_and_says_it_has_no_other_height_source(tmp_path, capsys):
    log = write_csv(tmp_path / "log.csv", climb_log(stop=14.4, gps=True))
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "--gps", "gps",
                 "--estimator", "observer"]) == 0
    err = capsys.readouterr().err
    assert "estimator observer has no other height source" in err and "--estimator kalman" in err


def test_run_warns_that_a_non_rocket_estimator_has_no_baro_lockout_on_a_rocket_log(shared_data, capsys):
    assert main(["run", str(shared_data / "hedy_baro.csv"), "--estimator", "kalman"]) == 0
    assert "has no baro lockout" in capsys.readouterr().err


@pytest.fixture
def diverging_estimator():
    """A registered estimator whose altitude is inf from mid-log (removed afterwards)."""
    from typing import NamedTuple

    from fusion_altitude import runner

    class Batch(NamedTuple):
        altitude: np.ndarray
        vertical_velocity: np.ndarray

    def diverging(data, dt, options):
        altitude = np.asarray(data.baro_altitude, np.float32).copy()
        altitude[:] = 100.0
        altitude[data.time.size // 2:] = np.inf
        return Batch(altitude, np.zeros(data.time.size, np.float32))

    runner.register_estimator(runner.EstimatorEntry("diverging_test", "returns inf from mid-log", diverging))
    yield "diverging_test"
    del runner.ESTIMATORS["diverging_test"]


def test_run_refuses_a_non_finite_estimate_with_exit_3_and_writes_nothing(tmp_path, capsys, diverging_estimator):
    log = write_csv(tmp_path / "log.csv", climb_log())
    out = tmp_path / "out.csv"
    status = main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "--estimator", diverging_estimator,
                   "-o", str(out)])
    captured = capsys.readouterr()
    assert status == 3 and not out.exists() and "final altitude" not in captured.out
    assert "non-finite altitude or vertical velocity from 30.000 s on" in captured.err
    assert len(captured.err.strip().splitlines()) == 1


def test_compare_leaves_the_row_of_a_refused_estimate_blank_and_exits_3(capsys, diverging_estimator):
    from fusion_altitude import comparison

    data = climb_log()
    data.reference_altitude = 100.0 + 2.0 * data.time
    rows = comparison.compare_log(data, estimators=["observer", diverging_estimator], repeat=0)
    refused = next(row for row in rows if row.estimator == diverging_estimator)
    assert np.isnan(refused.altitude_rms) and "non-finite" in refused.problem
    assert next(row for row in rows if row.estimator == "observer").problem is None
