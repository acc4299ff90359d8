"""Issue 12, "the command line keeps its promise": output file modes, SIGTERM cleanup, messages that name the
flag (also for ``fleet``), warnings on stderr, plot labels, ``fit``'s runners-up."""

import os
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest

from fusion_altitude import fleet_cli
from fusion_altitude.cli import main


def csv_log(path, n=300, reference=False, last_line_cut=False):
    # live sensors (a little noise): a constant channel is a dead sensor, and warned about
    rows = ["t,az,alt,ref"] + [f"{0.02 * i:.2f},{0.01 * ((i * 7) % 5 - 2):.2f},{5.0 + 0.01 * ((i * 7) % 5 - 2):.2f},"
                               f"{'5.1' if reference else ''}" for i in range(n)]
    text = "\n".join(rows) + "\n"
    if last_line_cut:
        text += "99.0,0."
    path.write_text(text)
    return str(path)


def mode(path):
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture
def umask_022():
    previous = os.umask(0o022)
    yield 0o644
    os.umask(previous)


# ----------------------------------------------------------------------------
# 1. modes


def test_every_run_output_gets_the_mode_open_would_give(tmp_path, capsys, umask_022):
    log = csv_log(tmp_path / "log.csv")
    outputs = {"-o": tmp_path / "o.csv", "--plot": tmp_path / "p.png", "--events-csv": tmp_path / "e.csv"}
    argv = ["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "--rocket"]
    for flag, path in outputs.items():
        argv += [flag, str(path)]
    assert main(argv) == 0, capsys.readouterr().err
    for flag, path in outputs.items():
        assert mode(path) == umask_022, (flag, oct(mode(path)))


def test_demo_export_follows_the_umask(tmp_path, capsys):
    previous = os.umask(0o027)
    try:
        assert main(["demo", "--scenario", "clean", "--export", str(tmp_path / "x.csv")]) == 0
    finally:
        os.umask(previous)
    assert mode(tmp_path / "x.csv") == 0o640


def test_an_overwritten_output_keeps_its_mode(tmp_path, capsys, umask_022):
    log = csv_log(tmp_path / "log.csv")
    out = tmp_path / "o.csv"
    out.write_text("old\n")
    os.chmod(out, 0o640)  # not what the umask would give (0o644), nor mkstemp's 0o600
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "-o", str(out)]) == 0
    assert mode(out) == 0o640 and out.read_text().startswith("time,")


# ----------------------------------------------------------------------------
# 2. SIGTERM


def test_sigterm_while_writing_removes_the_temporary_file(tmp_path):
    # 2,000,000 rows: the C-formatted writer (issue 25) writes 200,000 in about 0.1 s, less than a loaded
    # machine may take to see the temporary file and send the signal
    n = 2_000_000
    t = 1_700_000_000.0 + 0.01 * np.arange(n)
    with open(tmp_path / "big.csv", "w") as stream:
        stream.write("t,az,alt\n")
        stream.write("\n".join(f"{t[i]:.2f},0.01,{'12.5' if i % 10 == 0 else ''}" for i in range(n)) + "\n")
    out = tmp_path / "out" / "o.csv"
    out.parent.mkdir()
    for _ in range(3):  # a try whose signal came only after the output was in place says nothing: again
        process, in_time = _sigterm_while_writing(tmp_path / "big.csv", out)
        stderr = process.communicate(timeout=120)[1]
        if in_time or process.returncode == 143:
            break
        out.unlink()
    assert in_time or process.returncode == 143, "the signal came after the output was in place, three times"
    assert process.returncode == 143, stderr
    assert os.listdir(out.parent) == [], os.listdir(out.parent)  # neither the .part file nor a half output
    assert "Traceback" not in stderr and stderr.strip().splitlines()[-1] == "terminated"


def _sigterm_while_writing(log, out):
    """Start ``run LOG -o OUT`` and send it SIGTERM once its temporary output file is seen; the process, and
    whether the temporary file was still there and OUT not yet (the signal was sent while it wrote)."""
    process = subprocess.Popen([sys.executable, "-m", "fusion_altitude", "run", str(log), "--time",
                                "t", "--accel", "az", "--baro", "alt", "-o", str(out)],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while not [name for name in os.listdir(out.parent) if ".part" in name]:
        assert process.poll() is None, ("finished before its temporary file was seen", process.stderr.read())
        assert time.monotonic() < deadline, "no temporary file appeared"
        time.sleep(0.002)
    process.send_signal(signal.SIGTERM)
    names = os.listdir(out.parent)
    return process, out.name not in names and any(".part" in name for name in names)


def test_the_sigterm_handler_is_restored_after_main(capsys):
    before = signal.getsignal(signal.SIGTERM)
    assert main(["tune"]) == 0
    assert signal.getsignal(signal.SIGTERM) is before


# ----------------------------------------------------------------------------
# 6. messages


def one_line(capsys):
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    return lines[0]


@pytest.mark.parametrize("value", ["x", "0", "-3", "nan", "inf", "150%", "0%", "nan%"])
def test_fit_checks_train_until_before_reading_the_log(tmp_path, capsys, monkeypatch, value):
    from fusion_altitude import logs

    def unread(*args, **kwargs):
        raise AssertionError("the log was read before --train-until was checked")

    monkeypatch.setattr(logs, "load_log", unread)
    log = csv_log(tmp_path / "log.csv", reference=True)
    assert main(["fit", log, "--time", "t", "--accel", "az", "--baro", "alt", "--reference", "ref",
                 "--train-until", value]) == 2
    assert "--train-until" in one_line(capsys)


def test_fit_train_until_beyond_the_log_is_named_after_reading_it(tmp_path, capsys):
    log = csv_log(tmp_path / "log.csv", reference=True)  # 6 s
    assert main(["fit", log, "--time", "t", "--accel", "az", "--baro", "alt", "--reference", "ref",
                 "--train-until", "100"]) == 2
    assert "--train-until 100" in one_line(capsys)


def test_fit_with_a_file_and_a_scenario_is_refused_before_simulating(tmp_path, capsys, monkeypatch):
    from fusion_altitude import scenarios

    monkeypatch.setattr(scenarios, "run_scenario", lambda *a, **k: pytest.fail("simulated"))
    assert main(["fit", csv_log(tmp_path / "log.csv"), "--scenario", "clean"]) == 2
    assert "--scenario" in one_line(capsys)


def test_fit_scenario_skip_beyond_its_end_names_skip(capsys):
    assert main(["fit", "--scenario", "clean", "--skip", "1000"]) == 2
    line = one_line(capsys)
    assert "--skip 1000" in line and "scenario clean" in line


def test_fit_runners_up_print_no_row_twice_nor_the_winner(capsys):
    assert main(["fit", "--scenario", "clean"]) == 0
    out = capsys.readouterr().out
    best = out.split("best of ")[1].splitlines()[0]
    table = out.split("runners-up:")[1].strip().splitlines()[2:]
    cells = [tuple(line.split()[:3]) for line in table]
    assert len(cells) == 5 and len(set(cells)) == 5
    winner = tuple(best.split(f"{name} ")[1].split()[0].rstrip(",") for name in ("omega", "zeta", "omega_b"))
    assert winner not in cells, (winner, cells)


def test_runners_up_skip_candidates_that_print_alike():
    from fusion_altitude.cli.fit import _runners_up  # fit's own helper (cli/fit.py since the CLI split)
    from fusion_altitude.tuning import LANDSCAPE_DTYPE

    landscape = np.array([(1.0, 0.7, 0.2, 0.1), (1.0000001, 0.7, 0.2, 0.1), (1.2, 0.7, 0.0, 0.2),
                          (1.2, 0.7, 1e-9, 0.2), (2.0, 0.5, 0.1, 0.3)], dtype=LANDSCAPE_DTYPE)
    rows = _runners_up(landscape)
    assert [row[:3] for row in rows] == [["1.2", "0.7", "0"], ["1.2", "0.7", "1e-09"], ["2", "0.5", "0.1"]]


def test_run_prints_the_readers_warnings_on_stderr(tmp_path, capsys):
    log = csv_log(tmp_path / "log.csv", last_line_cut=True)
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt"]) == 0
    captured = capsys.readouterr()
    assert "warning: " in captured.err and "cut short" in captured.err
    assert "warning" not in captured.out and "cut short" not in captured.out


def test_epoch_time_axis_label_gives_its_unit_once():
    from fusion_altitude.plotting import relative_time

    _, label = relative_time(1_700_000_000.0 + np.arange(3.0))
    assert "s (s)" not in label and label.startswith("time (s)") and "1700000000.000" in label


# ----------------------------------------------------------------------------
# fleet: checks before any cluster, in the command line's names


@pytest.fixture
def no_cluster(monkeypatch):
    from fusion_altitude import fleet

    monkeypatch.setattr(fleet, "open_client", lambda *a, **k: pytest.fail("a cluster was started"))


@pytest.mark.parametrize("argv,expected", [
    (["fleet", "run", "{tmp}/no-such-dir", "-o", "{tmp}/out"], "DIR_OR_GLOB {tmp}/no-such-dir: no such file"),
    (["fleet", "run", "{tmp}/*.none", "-o", "{tmp}/out"], "DIR_OR_GLOB: '{tmp}/*.none' matches no file"),
    (["fleet", "run", "{tmp}/empty", "-o", "{tmp}/out"], "DIR_OR_GLOB: directory '{tmp}/empty' holds no"),
    (["fleet", "run", "{tmp}/logs", "-o", "{tmp}/logs/a.csv"], "-o {tmp}/logs/a.csv is a file"),
    (["fleet", "run", "{tmp}/logs", "-o", "{tmp}/out", "--estimator", "x"], "--estimator must be one of"),
    (["fleet", "run", "{tmp}/logs", "-o", "{tmp}/out", "--estimator", "kalman", "--preset", "vtol"],
     "--preset: presets by name exist for the observer only"),
    (["fleet", "run", "{tmp}/logs", "-o", "{tmp}/out", "--worst", "-1"], "--worst must be >= 0"),
    (["fleet", "run", "{tmp}/logs", "-o", "{tmp}/out", "--time", "t"], "CSV logs need --accel"),
    (["fleet", "run", "{tmp}/logs", "-o", "{tmp}/out", "--time", "t", "--accel", "az", "--pressure", "alt",
      "--sea-level-pa", "-1"], "--sea-level-pa must be > 0"),
    (["fleet", "fit", "{tmp}/logs", "--holdout", "{tmp}/*.none"], "--holdout: '{tmp}/*.none' matches no file"),
    (["fleet", "fit", "{tmp}/logs", "--holdout", "{tmp}/gone"], "--holdout {tmp}/gone: no such file"),
    (["fleet", "fit", "{tmp}/logs", "--omega-max", "1e308"], "--omega-max must be <= 10000"),
    (["fleet", "fit", "{tmp}/logs", "--skip", "nan"], "--skip must be a finite number"),
    (["fleet", "fit", "{tmp}/logs", "-o", "{tmp}/no/fit.json"], "-o {tmp}/no/fit.json: folder"),
    (["fleet", "summary", "{tmp}/no-such-dir"], "OUT/ {tmp}/no-such-dir: no such directory"),
    (["fleet", "summary", "{tmp}/empty"], "OUT/: '{tmp}/empty' holds no summary.parquet"),
])
def test_fleet_input_problems_are_named_by_their_flags_before_any_cluster(tmp_path, capsys, no_cluster, argv,
                                                                           expected):
    (tmp_path / "logs").mkdir()
    (tmp_path / "empty").mkdir()
    csv_log(tmp_path / "logs" / "a.csv")
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv) == 2
    line = one_line(capsys)
    assert line.startswith("fusion-altitude fleet: error: ") and expected.replace("{tmp}", str(tmp_path)) in line
    for python_name in ("paths_or_globs", "output_dir", "omega_range", "_column"):
        assert python_name not in line


def test_fleet_names_the_readers_keywords_by_their_flags():
    from fusion_altitude import logs

    with pytest.raises(logs.LogError) as error:
        logs.load_log(__file__)  # a CSV-like file without column options
    message = fleet_cli._flag_message(error.value)
    assert "time_column" in str(error.value)
    assert "--time" in message and "--accel" in message and "_column" not in message
    assert fleet_cli._flag_message("holdout: 'x' is also a training log") == "--holdout: 'x' is also a training log"
    assert fleet_cli._flag_message("skip must be finite") == "--skip must be finite"
