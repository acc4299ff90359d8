"""``run --estimator``, ``--agl`` and ``compare LOG``: every estimator on real logs, through one registry."""

import os
from pathlib import Path

import numpy as np
import pytest

from fusion_altitude import comparison, logs, runner
from fusion_altitude.cli import main
from fusion_altitude.estimators import ESTIMATORS as REGISTRY
from fusion_altitude.logs import LogData

ROOT = Path(__file__).resolve().parents[1]
#: The estimators that run on any baro + accel log (no raw IMU needed, no vehicle of their own), from the registry.
ESTIMATORS = [entry.name for entry in REGISTRY.values() if not entry.needs and not entry.vehicle]


@pytest.fixture(scope="module")
def shared_data():
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


def simulated_log(n=4000, dt=0.02, seed=0, gps=False):
    rng = np.random.default_rng(seed)
    time = dt * np.arange(n)
    truth = 300 + 10 * np.sin(2 * np.pi * 0.02 * time)
    accel = -10 * (2 * np.pi * 0.02) ** 2 * np.sin(2 * np.pi * 0.02 * time) + rng.normal(0, 0.05, n)
    baro = truth + rng.normal(0, 0.5, n)
    baro[1::2] = np.nan
    gps_altitude = None
    if gps:
        gps_altitude = np.full(n, np.nan)
        gps_altitude[::10] = truth[::10] + 40 + rng.normal(0, 0.3, n)[::10]
    return LogData("simulated", time, accel, baro, reference_altitude=truth, reference_velocity=None,
                   reference_name="truth", gps_altitude=gps_altitude)


def test_the_registry_holds_the_four_estimators_in_table_order():
    assert runner.estimator_names()[:4] == ESTIMATORS


@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_every_estimator_tracks_a_simulated_log(estimator):
    run = runner.run_log(simulated_log(), estimator=estimator)
    assert run.comparison(transient=20.0).rms < 1.0


def test_the_kalman_filter_uses_the_logs_gps_altitude():
    with_gps = runner.run_log(simulated_log(gps=True), estimator="kalman").estimate
    without = runner.run_log(simulated_log(gps=False), estimator="kalman").estimate
    assert not np.array_equal(with_gps.gps_offset, without.gps_offset)
    # the GPS datum is 40 m above the baro's
    assert abs(float(with_gps.gps_offset[-1]) - float(with_gps.baro_offset[-1]) - 40.0) < 3.0


def test_the_alpha_beta_fusion_gets_the_gps_on_the_baro_datum():
    # the GPS reads 40 m above the baro; the fusion has no offset state, so an unshifted GPS would pull it up
    run = runner.run_log(simulated_log(gps=True), estimator="alphabeta")
    assert abs(run.comparison(transient=20.0).mean) < 2.0


def test_a_new_estimator_joins_run_and_the_output_csv_by_one_registration(tmp_path):
    from typing import NamedTuple

    class Batch(NamedTuple):
        altitude: np.ndarray
        vertical_velocity: np.ndarray
        confidence: np.ndarray
        phase: np.ndarray

    def hold_baro(data, dt, options):
        held = np.asarray(data.baro_altitude, float).copy()
        for i in range(1, held.size):
            if np.isnan(held[i]):
                held[i] = held[i - 1]
        return Batch(held.astype(np.float32), np.zeros(held.size, np.float32), np.ones(held.size, np.float32),
                     (np.arange(held.size) // 1000).astype(np.uint8))

    runner.register_estimator(runner.EstimatorEntry("hold", "sample-and-hold baro", hold_baro))
    try:
        run = runner.run_log(simulated_log(), estimator="hold")
        runner.write_csv(run, str(tmp_path / "out.csv"))
        lines = (tmp_path / "out.csv").read_text().splitlines()
        assert lines[0].split(",")[:5] == ["time", "altitude", "vertical_velocity", "confidence", "phase"]
        assert lines[1500].split(",")[4] == "1"  # an integer column stays an integer
    finally:
        del runner.ESTIMATORS["hold"]


def test_an_unknown_estimator_name_lists_the_known_ones():
    with pytest.raises(ValueError, match="observer, kalman"):
        runner.run_log(simulated_log(), estimator="magic")


def test_agl_starts_every_altitude_at_zero_and_keeps_the_reference_aligned():
    data = simulated_log()
    plain = runner.run_log(data)
    agl = runner.run_log(data, agl=True)
    assert abs(agl.datum - 300.0) < 1.0
    assert abs(float(np.nanmedian(agl.baro_altitude[:50]))) < 1.0
    np.testing.assert_allclose(agl.reference_altitude, plain.reference_altitude - agl.datum)
    # one datum for estimate and reference: their difference does not move
    assert abs(agl.comparison(20.0).rms - plain.comparison(20.0).rms) < 0.05


def test_agl_uses_the_pad_altitude_the_log_states():
    data = simulated_log()
    data.ground_altitude = 295.0
    assert runner.run_log(data, agl=True).datum == 295.0


@pytest.mark.parametrize("estimator", ESTIMATORS)
@pytest.mark.parametrize("name", ["px4_sample_log_small.ulg", "ardupilot_test.BIN", "hedy_baro.csv"])
def test_run_runs_every_estimator_on_the_shared_logs(shared_data, tmp_path, capsys, estimator, name):
    out = tmp_path / "out.csv"
    assert main(["run", str(shared_data / name), "--estimator", estimator, "--agl", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "against the log's own estimate" in text and f"estimator {estimator}" in text
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert table.dtype.names[:3] == ("time", "altitude", "vertical_velocity")
    assert table.dtype.names[-2:] == ("reference_altitude", "flags") and np.isfinite(table["altitude"]).all()


def test_compare_log_has_a_row_per_estimator_and_the_raw_baro(shared_data):
    data = logs.load_log(str(shared_data / "px4_sample_log_small.ulg"))
    rows = comparison.compare_log(data, repeat=0)
    assert [r.estimator for r in rows] == runner.applicable_estimators(data) + ["raw baro"]
    for row in rows:
        assert np.isfinite(row.altitude_rms) and row.recovery is None and row.ns_per_sample is None


def test_compare_log_on_the_command_line_prints_the_table_and_a_plot(shared_data, tmp_path, capsys):
    plot = tmp_path / "compare.png"
    assert main(["compare", str(shared_data / "px4_sample_log_small.ulg"), "--repeat", "1", "--markdown",
                 "--plot", str(plot)]) == 0
    text = capsys.readouterr().out
    assert "| px4_sample_log_small.ulg | kalman |" in text and "| px4_sample_log_small.ulg | raw baro |" in text
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_compare_log_without_a_reference_says_so(tmp_path, capsys):
    log = tmp_path / "log.csv"
    log.write_text("t,az,alt\n" + "".join(f"{0.01 * i:.2f},0,5\n" for i in range(300)))
    assert main(["compare", str(log), "--time", "t", "--accel", "az", "--baro", "alt", "--repeat", "0"]) == 2
    assert "no reference altitude" in capsys.readouterr().err


def test_demo_export_writes_a_csv_that_run_reads_back_to_the_same_estimate(tmp_path, capsys):
    from fusion_altitude.scenarios import run_scenario

    flight, out = tmp_path / "flight.csv", tmp_path / "out.csv"
    assert main(["demo", "--scenario", "clean", "--attitude", "truth", "--export", str(flight)]) == 0
    assert main(["run", str(flight), "--time", "time", "--accel", "vertical_acceleration", "--baro",
                 "baro_altitude", "--reference", "true_altitude", "-o", str(out)]) == 0
    table = np.genfromtxt(out, delimiter=",", names=True)
    demo = run_scenario("clean", attitude="truth")
    assert np.array_equal(table["time"], demo.time)
    assert np.array_equal(table["altitude"].astype(np.float32), demo.estimate.altitude)


def test_reader_keywords_in_messages_are_given_as_flags(shared_data, capsys):
    assert main(["run", str(shared_data / "px4_sample_log_small.ulg"), "--ground-temperature", "20"]) == 2
    err = capsys.readouterr().err
    assert "--ground-temperature" in err and "ground_temperature_k" not in err


def test_run_turns_body_accelerometer_columns_and_a_quaternion_into_vertical_acceleration(tmp_path, capsys):
    n = 1000
    time = 0.01 * np.arange(n)
    up = 0.5 * np.sin(time)  # m/s², +up
    rows = ["t,ax,ay,az,qw,qx,qy,qz,alt"] + [f"{time[i]:.2f},0,0,{-(9.80665 + up[i]):.6f},1,0,0,0,10"
                                             for i in range(n)]  # NED body: level, z down
    (tmp_path / "log.csv").write_text("\n".join(rows) + "\n")
    out = tmp_path / "out.csv"
    assert main(["run", str(tmp_path / "log.csv"), "--time", "t", "--accel-body", "ax,ay,az",
                 "--attitude-columns", "qw,qx,qy,qz", "--baro", "alt", "-o", str(out)]) == 0
    table = np.genfromtxt(out, delimiter=",", names=True)
    np.testing.assert_allclose(table["vertical_acceleration"], up, atol=1e-4)


@pytest.mark.parametrize("command", ["run", "fit", "compare"])
def test_ground_temperature_log_on_cats_is_refused_in_one_line(shared_data, command, capsys):
    argv = [command, str(shared_data / "hedy_baro.csv"), "--ground-temperature", "log"]
    assert main(argv + (["--repeat", "0"] if command == "compare" else [])) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert "board temperature" in err and "column 'T'" in err



def slow_log(gap_at=None, gap=30.0):
    """A 1 Hz log (a slow CSV): baro and accel every second, optionally a ``gap`` s hole after sample ``gap_at``."""
    rng = np.random.default_rng(4)
    time = np.arange(300.0)
    if gap_at is not None:
        time[gap_at:] += gap
    truth = 50 + 20 * np.sin(2 * np.pi * time / 120)
    accel = -20 * (2 * np.pi / 120) ** 2 * np.sin(2 * np.pi * time / 120) + rng.normal(0, 0.02, time.size)
    return LogData("slow", time, accel, truth + rng.normal(0, 0.3, time.size), reference_altitude=truth,
                   reference_name="truth")


@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_a_1hz_log_is_integrated_not_one_gap_per_step(estimator):
    run = runner.run_log(slow_log(), estimator=estimator)
    assert run.gap_count == 0
    assert run.gap_period == pytest.approx(10.0)  # ten nominal periods, above every default
    assert not np.array_equal(np.asarray(run.estimate.altitude, float), run.baro_altitude)  # not the raw baro
    assert run.comparison(transient=30.0).max < 5.0


@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_a_real_gap_in_a_1hz_log_is_still_counted(estimator):
    assert runner.run_log(slow_log(gap_at=150), estimator=estimator).gap_count == 1


def test_the_fast_log_keeps_the_default_gap_period():
    assert runner.run_log(simulated_log(dt=0.02), estimator="observer").gap_period == pytest.approx(0.5)
    assert runner.run_log(simulated_log(dt=0.02), estimator="alphabeta").gap_period == pytest.approx(1.5)


def test_the_fit_sweep_uses_the_same_gap_period_as_run():
    from fusion_altitude import AltitudeSettings, tuning

    data = slow_log(gap_at=150)
    settings = AltitudeSettings.preset("balloon").replace(gap_period=0.5)
    ran = runner.run_observer(data.time, data.vertical_acceleration, data.baro_altitude, settings)
    swept = tuning.sweep(data.vertical_acceleration, data.baro_altitude, runner.sample_periods(data.time),
                         [settings], outputs=True)
    assert np.array_equal(swept.outputs.altitude[:, 0], ran.altitude)


def test_run_on_a_1hz_csv_prints_the_gap_count_and_a_stable_default_preset(tmp_path, capsys):
    data = slow_log()
    rows = ["t,az,alt"] + [f"{t:g},{a:.5f},{b:.3f}" for t, a, b in zip(data.time, data.vertical_acceleration,
                                                                         data.baro_altitude)]
    (tmp_path / "slow.csv").write_text("\n".join(rows) + "\n")
    argv = ["run", str(tmp_path / "slow.csv"), "--time", "t", "--accel", "az", "--baro", "alt"]
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert "gaps met by the estimator (dt > 10 s, or a step its gains cannot integrate stably): 0" in captured.out
    assert "preset fixed_wing" in captured.out and "vtol is unstable" in captured.err
    assert main(argv + ["--preset", "vtol"]) == 0  # unstable there: every step is a stability gap, not a divergence
    captured = capsys.readouterr()
    assert "such steps are gaps, where the estimate is the raw baro" in captured.err and "fixed_wing" in captured.err
    assert "gaps met by the estimator (dt > 10 s, or a step its gains cannot integrate stably): 299" in captured.out
