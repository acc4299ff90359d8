"""Every option is used or refused, and every suggested command runs as written."""

import re

import numpy as np

from fusion_altitude.cli import main


def write_csv(path, accel, baro):
    time = 0.01 * np.arange(accel.size)
    rng = np.random.default_rng(0)
    lines = ["t,az,alt"] + [f"{t:.2f},{a:.6f},{b:.4f}" for t, a, b in
                            zip(time, accel + rng.normal(0, 0.002, accel.size), baro + rng.normal(0, 0.05, baro.size))]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_a_preset_with_a_non_observer_estimator_is_refused(tmp_path, capsys):
    log = write_csv(tmp_path / "log.csv", np.zeros(500), np.full(500, 10.0))
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "--estimator", "kalman",
                 "--preset", "racing"]) == 2
    assert "--preset names observer gains; it does not apply to --estimator kalman" in capsys.readouterr().err


def test_tune_says_unstable_instead_of_printing_an_overflowed_noise_gain(capsys):
    assert main(["tune", "--omega", "50", "--rate", "50"]) == 1
    out = capsys.readouterr().out
    assert "baro noise gain: unstable" in out and "bandwidth of baro → altitude: unstable" in out
    assert not re.search(r"\d{20}", out)


def test_the_gravity_message_suggests_flags_that_run_as_written(tmp_path, capsys):
    log = write_csv(tmp_path / "log.csv", np.ones(500), np.full(500, 10.0))  # 1 g at rest, in g
    argv = ["run", log, "--time", "t", "--accel", "az", "--baro", "alt"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    suggested = re.search(r"say so with (.*) and (.*)$", err.strip())
    assert suggested, err
    flags = [word for part in suggested.groups() for word in part.split()]
    assert flags == ["--accel-units", "g", "--remove-gravity"]
    assert main(argv + flags) == 0


def test_the_demo_exports_a_log_and_its_suggested_run_command_runs_as_printed(tmp_path, capsys):
    import shlex

    assert main(["demo", "--seed", "0", "--export", str(tmp_path / "flight.csv")]) == 0
    out = capsys.readouterr().out
    line = out.splitlines()[out.splitlines().index(next(l for l in out.splitlines() if "run it with:" in l)) + 1]
    argv = shlex.split(line.strip())
    assert argv[:2] == ["fusion-altitude", "run"]
    assert main(argv[1:]) == 0
    assert "flight.csv" in capsys.readouterr().out  # the run's report names the exported log


def test_fit_without_a_reference_suggests_the_flag_that_makes_it_run(tmp_path, capsys):
    log = write_csv(tmp_path / "log.csv", np.zeros(2000), 10.0 + np.sin(0.01 * np.arange(2000)))
    base = ["fit", log, "--time", "t", "--accel", "az", "--baro", "alt"]
    assert main(base) == 2
    err = capsys.readouterr().err
    assert "give --reference COLUMN" in err
    assert main(base + ["--reference", "alt"]) == 0
