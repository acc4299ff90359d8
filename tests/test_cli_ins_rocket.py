"""The INS and the rocket estimator where they are used: ``run --estimator ins``,
``compare`` INS rows, ``run`` on rocket logs with ``--events-csv`` and the events next to the flight
computer's own, the plot's event marks."""

import csv
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from fusion_altitude import comparison, logs, rocket, runner
from fusion_altitude._ins import InsEstimator
from fusion_altitude.cli import main
from fusion_altitude.logs import LogData
from fusion_altitude.rocket_sim import simulate_rocket_flight

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
from logfixtures import write_altos_csv  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
INS_COLUMNS = ["height", "roll", "pitch", "yaw", "quaternion_w", "quaternion_x", "quaternion_y", "quaternion_z",
               "gyro_bias_x", "gyro_bias_y", "gyro_bias_z", "accel_z_bias", "baro_bias", "is_stationary"]


@pytest.fixture(scope="module")
def shared_data():
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


@pytest.fixture(scope="module")
def px4(shared_data):
    return str(shared_data / "px4_sample_log_small.ulg")


@pytest.fixture(scope="module")
def hedy(shared_data):
    return str(shared_data / "hedy_baro.csv")


def read_csv(path):
    with open(path, newline="") as handle:
        return list(csv.reader(handle))


def vertical_only_log(n=2000, dt=0.01):
    time = dt * np.arange(n)
    baro = np.full(n, 100.0)
    return LogData("vertical only", time, np.zeros(n), baro, reference_altitude=baro.copy(), reference_name="flat")


@pytest.fixture(scope="module")
def simulated_rocket_csv(tmp_path_factory):
    flight = simulate_rocket_flight(seed=3)
    path = tmp_path_factory.mktemp("rocket") / "rocket.csv"
    baro = ["" if not np.isfinite(b) else repr(float(b)) for b in flight.baro_altitude]
    with open(path, "w") as handle:
        handle.write("time,accel,baro\n")
        for t, a, b in zip(flight.time, flight.accel, baro):
            handle.write(f"{float(t)!r},{float(a)!r},{b}\n")
    return str(path), flight


# ----------------------------------------------------------------------------
# the INS


def test_run_estimator_ins_writes_altitude_velocity_attitude_and_biases(px4, tmp_path, capsys):
    out = tmp_path / "ins.csv"
    assert main(["run", px4, "--estimator", "ins", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "estimator ins" in text and "final INS state" in text
    header = read_csv(out)[0]
    assert header[:3] == ["time", "altitude", "vertical_velocity"]
    assert header[3:3 + len(INS_COLUMNS)] == INS_COLUMNS


def test_run_ins_altitude_is_the_ins_height_plus_its_baro_bias(px4, tmp_path, capsys):
    out = tmp_path / "ins.csv"
    assert main(["run", px4, "--estimator", "ins", "-o", str(out)]) == 0
    table = np.genfromtxt(out, delimiter=",", names=True)
    expected = table["height"].astype(np.float32) + table["baro_bias"].astype(np.float32)
    assert np.array_equal(table["altitude"].astype(np.float32), expected)


def test_run_ins_output_is_the_binding_on_the_logs_raw_imu(px4):
    data = logs.load_log(px4)
    run = runner.run_log(data, estimator="ins")
    flu = np.array([1.0, -1.0, -1.0])  # the log's FRD axes as FLU
    direct = InsEstimator().update_batch(data.gyro * flu, data.accel * flu, runner.sample_periods(data.time),
                                         data.baro_altitude)
    assert np.array_equal(run.estimate.height, direct.height_above_start)
    assert np.array_equal(run.estimate.gyro_bias_z, direct.gyro_bias[:, 2])


def test_run_ins_on_a_log_without_raw_gyro_is_refused_by_name(tmp_path, capsys):
    path = tmp_path / "flat.csv"
    path.write_text("time,accel,baro\n" + "".join(f"{0.01 * k!r},0.0,100.0\n" for k in range(300)))
    assert main(["run", str(path), "--time", "time", "--accel", "accel", "--baro", "baro",
                 "--estimator", "ins"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--estimator ins needs raw gyro and accel" in err[0]


def test_run_ins_on_a_level_frd_log_reads_roll_and_pitch_near_zero(px4, tmp_path, capsys):
    out = tmp_path / "ins.csv"
    assert main(["run", px4, "--estimator", "ins", "-o", str(out)]) == 0
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert np.abs(table["roll"]).max() < 10 and np.abs(table["pitch"]).max() < 10


def test_run_without_estimator_picks_the_ins_on_a_log_with_raw_imu(px4, capsys):
    assert main(["run", px4]) == 0
    assert "estimator ins (raw gyro and accelerometer in the log)" in capsys.readouterr().out


def test_run_ins_says_it_uses_the_raw_imu_and_not_the_logs_attitude(px4, capsys):
    main(["run", str(px4)])
    out = capsys.readouterr().out
    assert "INS inputs: the raw gyro and accelerometer, body FRD and the baro" in out
    assert "not used (the INS estimates its own)" in out


def test_run_with_a_preset_and_no_estimator_runs_the_observer_on_a_log_with_raw_imu(px4, capsys):
    assert main(["run", px4, "--preset", "fixed_wing"]) == 0
    assert "estimator observer, preset fixed_wing" in capsys.readouterr().out


def test_run_without_estimator_keeps_the_observer_on_a_log_without_raw_imu(tmp_path, capsys):
    path = tmp_path / "flat.csv"
    path.write_text("time,accel,baro\n" + "".join(f"{0.01 * k!r},0.0,100.0\n" for k in range(300)))
    assert main(["run", str(path), "--time", "time", "--accel", "accel", "--baro", "baro"]) == 0
    assert "estimator observer" in capsys.readouterr().out


def test_compare_log_has_an_ins_row_when_the_log_has_raw_imu(px4):
    rows = comparison.compare_log(logs.load_log(px4), repeat=0)
    ins = [r for r in rows if r.estimator == "ins"]
    assert len(ins) == 1 and np.isfinite(ins[0].altitude_rms) and np.isfinite(ins[0].velocity_rms)


def test_compare_log_leaves_the_ins_out_without_raw_imu():
    rows = comparison.compare_log(vertical_only_log(), repeat=0)
    assert "ins" not in [r.estimator for r in rows] and "observer" in [r.estimator for r in rows]


def test_compare_scenario_ins_row_is_the_ins_on_the_scenarios_raw_imu():
    from fusion_altitude.scenarios import run_scenario

    (row,) = comparison.compare_scenario("terrain-step", repeat=0, estimators=("INS",))
    result = run_scenario("terrain-step", seed=0)
    batch = InsEstimator(gyro_units="deg/s", accel_units="g").update_batch(
        result.imu.gyro, result.imu.accel, np.float32(result.trajectory.dt),
        np.asarray(result.baro_altitude, np.float32), result.imu.mag)
    assert np.array_equal(row.altitude, batch.altitude.astype(float))


def test_compare_scenario_ins_row_beats_the_raw_baro_on_the_clean_scenario():
    (ins, baro) = comparison.compare_scenario("clean", repeat=0, estimators=("INS", "raw baro"))
    assert ins.altitude_rms < baro.altitude_rms / 2 and ins.velocity_rms < 0.05


# ----------------------------------------------------------------------------
# the rocket estimator


def test_rocket_long_axis_is_the_axis_carrying_gravity_signed_nose_up():
    accel = np.tile([0.3, -9.8, 0.1], (200, 1))
    assert runner.rocket_long_axis(accel) == (1, -1.0)
    assert runner.rocket_long_axis(-accel[:, [2, 0, 1]]) == (2, 1.0)


def test_run_on_a_rocket_log_runs_the_rocket_estimator_without_being_asked(hedy, capsys):
    assert main(["run", hedy]) == 0
    text = capsys.readouterr().out
    assert "estimator rocket (rocket log)" in text and "long axis -Y" in text and "flight events" in text
    # the rocket estimator uses the long axis, not the CATS reader's gyro-integrated attitude: the header says so
    assert "attitude by gyro integration" not in text
    assert "rocket estimator: accelerometer along the long axis (-Y) minus g, not rotated by an attitude" in text


def test_run_on_hedy_writes_the_events_csv_one_row_per_event(hedy, tmp_path, capsys):
    events = tmp_path / "events.csv"
    assert main(["run", hedy, "--events-csv", str(events)]) == 0
    rows = read_csv(events)
    assert rows[0] == ["event", "time", "height"]
    assert [r[0] for r in rows[1:]] == ["launch", "burnout", "apogee", "main"]  # the log ends before landing
    apogee = dict((r[0], (float(r[1]), float(r[2]))) for r in rows[1:])["apogee"]
    assert 33.0 < apogee[0] < 34.0 and 5200.0 < apogee[1] < 5260.0  # CATS: 33.42 s, 5230 m above the pad


def test_run_on_hedy_prints_the_flight_computers_events_next_to_ours(hedy, capsys):
    assert main(["run", hedy]) == 0
    text = capsys.readouterr().out
    assert "FC time (s)" in text and "read off its height and velocity" in text
    apogee = next(line for line in text.splitlines() if line.startswith("apogee"))
    ours_time, ours_height, fc_time, fc_height = (float(x) for x in apogee.split()[1:5])
    assert abs(ours_time - fc_time) < 0.5 and abs(ours_height - fc_height) < 10.0


def test_run_on_an_altos_log_prints_its_logged_states_as_events(tmp_path, capsys):
    path = tmp_path / "altos.csv"
    write_altos_csv(path)
    assert main(["run", str(path)]) == 0
    text = capsys.readouterr().out
    assert "flight computer's: its logged flight states" in text
    lines = {line.split()[0]: line.split() for line in text.splitlines() if line.split()
             and line.split()[0] in ("launch", "burnout", "apogee", "main")}
    # the fixture's states: boost at 0 s, coast at 2 s, drogue at 8 s, main at 20 s (FC columns: last two)
    assert [float(lines[name][-2]) for name in ("launch", "burnout", "apogee", "main")] == [0.0, 2.0, 8.0, 20.0]


def test_rocket_flag_runs_the_rocket_estimator_on_a_generic_csv(simulated_rocket_csv, tmp_path, capsys):
    path, flight = simulated_rocket_csv
    events = tmp_path / "events.csv"
    assert main(["run", path, "--time", "time", "--accel", "accel", "--baro", "baro", "--rocket",
                 "--events-csv", str(events)]) == 0
    found = {r[0]: (float(r[1]), float(r[2])) for r in read_csv(events)[1:]}
    assert set(found) == {"launch", "burnout", "apogee", "main", "landed"}
    assert 0.0 <= found["apogee"][0] - flight.apogee_time <= 0.5
    assert abs(found["apogee"][1] / flight.apogee_height - 1) < 0.01


def test_rocket_output_csv_has_height_phase_and_baro_fate(simulated_rocket_csv, tmp_path, capsys):
    path, _ = simulated_rocket_csv
    out = tmp_path / "out.csv"
    assert main(["run", path, "--time", "time", "--accel", "accel", "--baro", "baro", "--rocket", "-o", str(out)]) == 0
    header = read_csv(out)[0]
    assert header[:8] == ["time", "altitude", "vertical_velocity", "height", "accel_bias", "phase", "baro_fate",
                          "baro_altitude"]


def test_events_csv_without_the_rocket_layer_is_refused(px4, tmp_path, capsys):
    assert main(["run", px4, "--events-csv", str(tmp_path / "e.csv")]) == 2
    assert "--events-csv needs the rocket estimator" in capsys.readouterr().err
    assert not (tmp_path / "e.csv").exists()


def test_rocket_flag_with_another_estimator_is_refused(hedy, capsys):
    assert main(["run", hedy, "--rocket", "--estimator", "kalman"]) == 2
    assert "--rocket" in capsys.readouterr().err


def test_events_csv_and_output_naming_one_file_is_refused(hedy, tmp_path, capsys):
    same = str(tmp_path / "same.csv")
    assert main(["run", hedy, "-o", same, "--events-csv", same]) == 2
    assert "-o and --events-csv name the same file" in capsys.readouterr().err


def test_long_axis_flag_that_agrees_with_gravity_on_the_pad_is_used(hedy, capsys):
    assert main(["run", hedy, "--long-axis=-Y"]) == 0
    assert "long axis -Y" in capsys.readouterr().out


def test_long_axis_flag_that_contradicts_gravity_on_the_pad_is_refused_in_one_line(hedy, capsys):
    """Hedy's +Z reads about -0.8 m/s² on the pad while -Y carries g: integrating +Z would make a runaway."""
    assert main(["run", hedy, "--long-axis", "+Z"]) == 2
    errors = [line for line in capsys.readouterr().err.splitlines() if "error" in line]  # not the progress lines
    assert len(errors) == 1 and "long axis +Z reads" in errors[0] and "not about +9.81" in errors[0]


def test_compare_log_runs_the_rocket_layer_on_rocket_logs_only(hedy, px4):
    assert "rocket" in runner.applicable_estimators(logs.load_log(hedy))
    assert "rocket" not in runner.applicable_estimators(logs.load_log(px4))


def test_events_from_states_dates_each_event_at_the_first_sample_of_its_state():
    time = np.arange(8.0)
    states = ["pad", "pad", "boost", "fast", "coast", "drogue", "main", "landed"]
    events = rocket.events_from_states(time, states, np.arange(8.0) * 10)
    assert [(e.name, e.time, e.height) for e in events.occurred()] == [
        ("launch", 2.0, 20.0), ("burnout", 3.0, 30.0), ("apogee", 5.0, 50.0), ("main", 6.0, 60.0),
        ("landed", 7.0, 70.0)]


def test_plot_marks_every_declared_event(simulated_rocket_csv):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from fusion_altitude.plotting import mark_events

    _, flight = simulated_rocket_csv
    _, events = rocket.run_rocket(flight.time, flight.accel, flight.baro_altitude)
    figure, axis = plt.subplots()
    drawn = mark_events(axis, events)
    plt.close(figure)
    assert [name for name, _ in drawn] == [e.name for e in events.occurred()]
    assert [x for _, x in drawn] == [e.time for e in events.occurred()]


def test_event_labels_close_in_time_are_put_on_separate_rows():
    """Hedy: launch −0.11 s, max_speed 7.95 s, burnout 7.96 s on a 250 s axis: three rows, apogee back on the top."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from fusion_altitude.plotting import event_label_rows

    figure, axis = plt.subplots(figsize=(10, 3))
    axis.set_xlim(-10.0, 255.0)
    rows = event_label_rows(axis, [-0.106, 7.954, 7.964, 33.484, 233.734],
                            ["launch", "max_speed", "burnout", "apogee", "main"])
    plt.close(figure)
    assert rows == [0, 1, 2, 0, 0]


def test_run_rocket_plot_is_written(simulated_rocket_csv, tmp_path, capsys):
    path, _ = simulated_rocket_csv
    plot = tmp_path / "rocket.png"
    assert main(["run", path, "--time", "time", "--accel", "accel", "--baro", "baro", "--rocket",
                 "--plot", str(plot)]) == 0
    assert plot.stat().st_size > 10_000


# ----------------------------------------------------------------------------
# the rocket scenario


def test_rocket_scenario_is_the_rocket_simulators_flight_on_the_baro_datum():
    from fusion_altitude.scenarios import run_scenario

    result = run_scenario("rocket", seed=2)
    flight = simulate_rocket_flight(seed=2)
    assert np.array_equal(result.baro_altitude, flight.baro_altitude)
    assert np.array_equal(result.vertical_acceleration, flight.accel)
    assert np.array_equal(result.trajectory.altitude, flight.trajectory.altitude + flight.model.pad_altitude)


def test_rocket_scenario_clips_the_thrust_peak():
    from fusion_altitude.scenarios import run_scenario

    assert run_scenario("rocket", seed=0).imu.clipped.any()


def test_compare_rocket_scenario_rocket_layer_row_beats_the_observer_row():
    rows = {r.estimator: r for r in comparison.compare_scenario("rocket", repeat=0,
                                                                 estimators=("observer", "rocket"))}
    assert rows["rocket"].altitude_rms < rows["observer"].altitude_rms / 3


def test_compare_has_a_rocket_layer_row_on_the_rocket_scenario_only():
    assert "rocket" in comparison.estimators_for("rocket")
    assert "rocket" not in comparison.estimators_for("realistic")
    assert "INS" in comparison.estimators_for("realistic")


def test_compare_accepts_the_old_rocket_layer_label_with_a_deprecation_warning():
    with pytest.warns(DeprecationWarning, match="'rocket layer' is now 'rocket'"):
        assert comparison.estimators_for("rocket", ("observer", "rocket layer")) == ["observer", "rocket"]


def test_kalman_on_a_rocket_log_runs_with_the_rocket_settings(hedy):
    data = logs.load_log(hedy)
    run = runner.run_log(data, estimator="kalman")
    error = run.estimate.altitude - data.reference_altitude
    rms = float(np.sqrt(np.nanmean(error ** 2)))
    assert rms < 30.0, rms  # the general defaults: 476.6 m on this flight


def write_raw_imu_csv(path: Path, every: int = 1, degrees: bool = False, glitch: float = 0.0) -> "imu_sim.RawImuFlight":
    """The simulator's `realistic` flight from a raw IMU (5 s at rest first), body FLU = the NWU frame of the CSV
    flags, gyro in rad/s (or deg/s), baro empty between samples, every ``every``-th IMU row; ``glitch`` m added
    to the baro readings from 12 to 12.5 s (a glitch burst)."""
    from fusion_altitude import imu_sim

    flight = imu_sim.simulate_raw_imu("realistic", seed=2, rest_duration=5.0)
    rows = range(0, int(round(20.0 / flight.dt)), every)
    scale = 180.0 / np.pi if degrees else 1.0
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["t", "gx", "gy", "gz", "ax", "ay", "az", "qw", "qx", "qy", "qz", "alt"])
        for k in rows:
            baro = flight.baro_altitude[k] + (glitch if 12.0 <= flight.time[k] < 12.5 else 0.0)
            writer.writerow([repr(float(flight.time[k])), *(repr(float(v) * scale) for v in flight.gyro[k]),
                             *(repr(float(v)) for v in flight.accel[k]), "1", "0", "0", "0",
                             "" if np.isnan(baro) else repr(float(baro))])
    return flight


RAW_IMU_FLAGS = ["--time", "t", "--accel-body", "ax,ay,az", "--gyro-body", "gx,gy,gz", "--attitude-columns",
                 "qw,qx,qy,qz", "--frame", "NWU", "--baro", "alt"]


def test_run_picks_the_ins_on_a_csv_with_gyro_and_accelerometer_columns(tmp_path, capsys):
    path = tmp_path / "raw.csv"
    write_raw_imu_csv(path)
    assert main(["run", str(path), *RAW_IMU_FLAGS]) == 0
    assert "estimator ins (raw gyro and accelerometer in the log)" in capsys.readouterr().out


@pytest.mark.parametrize("degrees", [False, True])
def test_run_ins_on_a_raw_imu_csv_is_the_binding_on_its_columns(tmp_path, degrees):
    path = tmp_path / "raw.csv"
    write_raw_imu_csv(path, degrees=degrees)
    data = logs.read_csv_log(str(path), "t", baro_column="alt", accel_body_columns=("ax", "ay", "az"),
                             attitude_columns=("qw", "qx", "qy", "qz"), frame="NWU",
                             gyro_body_columns=("gx", "gy", "gz"), gyro_units="deg/s" if degrees else "rad/s")
    assert data.imu_frame == "FLU" and data.gyro.shape == data.accel.shape
    run = runner.run_log(data, estimator="ins")
    direct = InsEstimator().update_batch(data.gyro, data.accel, runner.sample_periods(data.time), data.baro_altitude)
    assert np.array_equal(run.estimate.height, direct.height_above_start)
    assert run.gap_count == 0


def test_run_ins_reports_the_baro_readings_its_gate_rejected(tmp_path, capsys):
    path = tmp_path / "glitch.csv"
    flight = write_raw_imu_csv(path, glitch=80.0)
    burst = int(np.count_nonzero(~np.isnan(flight.baro_altitude) & (flight.time >= 12.0) & (flight.time < 12.5)))
    assert main(["run", str(path), *RAW_IMU_FLAGS]) == 0
    line = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("baro innovation gate"))
    rejected = int(line.split(": ")[1].split(" of ")[0])
    assert burst <= rejected <= burst + 2 and "0 height resets" in line, line
    data = logs.read_csv_log(str(path), "t", baro_column="alt", accel_body_columns=("ax", "ay", "az"),
                             attitude_columns=("qw", "qx", "qy", "qz"), frame="NWU", gyro_body_columns=("gx", "gy", "gz"))
    run = runner.run_log(data, estimator="ins")
    assert (run.baro_rejections, run.baro_resets) == (rejected, 0)
    truth = flight.trajectory.altitude[:data.time.size] + flight.baro_offset
    assert np.max(np.abs(run.estimate.altitude - truth)[(data.time > 11.0) & (data.time < 16.0)]) < 0.3


def test_a_raw_imu_csv_in_degrees_reads_the_same_rates(tmp_path):
    radians, degrees = tmp_path / "rad.csv", tmp_path / "deg.csv"
    write_raw_imu_csv(radians)
    write_raw_imu_csv(degrees, degrees=True)
    common = dict(baro_column="alt", accel_body_columns=("ax", "ay", "az"), attitude_columns=("qw", "qx", "qy", "qz"),
                  frame="NWU", gyro_body_columns=("gx", "gy", "gz"))
    a = logs.read_csv_log(str(radians), "t", **common)
    b = logs.read_csv_log(str(degrees), "t", gyro_units="deg/s", **common)
    assert np.allclose(a.gyro, b.gyro, rtol=1e-12, atol=1e-15)


def test_the_ins_integrates_a_slow_raw_imu_log_instead_of_calling_every_step_a_gap(tmp_path):
    """5 Hz rows (dt 0.2 s, above the INS's 0.1 s default gap period): the gap period of every estimator is raised
    to ten nominal periods on a slow log (tuning.gap_period_for), so no step is a gap."""
    path = tmp_path / "slow.csv"
    write_raw_imu_csv(path, every=20)  # the simulator's 100 Hz → 5 Hz
    data = logs.read_csv_log(str(path), "t", baro_column="alt", accel_body_columns=("ax", "ay", "az"),
                             attitude_columns=("qw", "qx", "qy", "qz"), frame="NWU", gyro_body_columns=("gx", "gy", "gz"))
    run = runner.run_log(data, estimator="ins")
    assert run.gap_count == 0 and run.gap_period > 0.2


def test_gyro_columns_without_accelerometer_columns_are_one_line_exit_2(tmp_path, capsys):
    path = tmp_path / "raw.csv"
    write_raw_imu_csv(path)
    flags = ["--time", "t", "--accel", "az", "--gyro-body", "gx,gy,gz", "--baro", "alt", "--remove-gravity"]
    assert main(["run", str(path), *flags]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "gyroscope columns need body accelerometer columns" in err[0], err
