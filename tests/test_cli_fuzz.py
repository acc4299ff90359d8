"""CLI fuzz: every subcommand with randomised bad flags and files never prints a traceback or a warning.

Each example builds an argument list from a vocabulary of real flags with
odd values (NaN, inf, negative, huge, text, empty) and a file that is
empty, binary garbage, truncated, header-only, a folder, missing or a valid
log. ``main`` must return 0, 1 or 2 (or argparse's usage exit 2) and never
raise; stderr never holds a traceback or a Python warning (``RuntimeWarning:
overflow…``), and an error (status 2) is one line: nothing but stage times
and the CLI's own ``warning: …`` lines may come before it.

``compare`` also runs without a FILE on the cheapest scenario. ``fleet`` is fuzzed on its checks only: a combination that passes them would
start a Dask cluster, which the test replaces by an exception that counts as
"the checks passed".
"""

import os
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fusion_altitude.cli import main

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402

NUMBERS = ["0", "-1", "-5", "1e308", "nan", "inf", "-inf", "0.5", "3", "abc", "", "1e-30", "100000", "1e30",
           "1000"]
COMMON_LOG_FLAGS = ["--time", "--accel", "--baro", "--pressure", "--reference", "--accel-units", "--altitude-units",
                    "--sea-level-pa", "--remove-gravity", "--instance", "--ground-temperature", "--gps",
                    "--rangefinder", "--accel-body", "--attitude-columns", "--attitude-convention", "--frame",
                    "--temperature", "--temperature-units"]
FLAGS = {
    "demo": ["--seed", "--scenario", "--attitude", "--plot", "--export"],
    "tune": ["--omega", "--zeta", "--omega-b", "--rate"],
    "run": COMMON_LOG_FLAGS + ["--estimator", "--preset", "-o", "--plot", "--agl", "--rocket", "--events-csv",
                               "--long-axis"],
    "fit": COMMON_LOG_FLAGS + ["--skip", "--train-until", "--omega-min", "--omega-max", "--plot", "--scenario",
                               "--seed"],
    "compare": COMMON_LOG_FLAGS + ["--skip", "--repeat", "--markdown", "--plot", "--agl", "--scenario",
                                   "--plot-scenario", "--seed", "--fit-seed"],
}
CLUSTER_FLAGS = ["--workers", "--scheduler"]
FLEET_CSV_FLAGS = ["--time", "--accel", "--baro", "--pressure", "--sea-level-pa", "--accel-units"]
FLEET_FLAGS = {
    "run": FLEET_CSV_FLAGS + CLUSTER_FLAGS + ["--estimator", "--preset", "--csv", "--retry-failed", "--worst"],
    "fit": FLEET_CSV_FLAGS + CLUSTER_FLAGS + ["--reference", "--holdout", "--holdout-every", "--skip", "--omega-min",
                                              "--omega-max", "-o"],
    "summary": ["--worst", "--all"],
}
SWITCHES = {"--remove-gravity", "--agl", "--markdown", "--rocket", "--csv", "--retry-failed", "--all"}
COLUMNS = ["t", "az", "alt", "ref", "nope"]
#: What stderr may hold besides the error line: stage times and the CLI's own warnings.
ALLOWED_EXTRA = re.compile(r"^(\w+: \d+\.\d\d s|warning: .*)$")


class ClusterWouldStart(Exception):
    """Raised instead of starting a Dask cluster: every check of the fleet command passed."""


def make_file(folder, kind, seed):
    rng = np.random.default_rng(seed)
    path = os.path.join(folder, f"log{seed}.csv")
    if kind == "missing":
        return os.path.join(folder, "missing.csv")
    if kind == "folder":
        return folder
    if kind == "altos":  # sniffed formats: the option combinations must fail (or run) in one line too
        fx.write_altos_csv(os.path.join(folder, f"altos{seed}.csv"), duration=3.0, rate=10.0, pad_time=1.0)
        return os.path.join(folder, f"altos{seed}.csv")
    if kind == "cats":
        fx.write_cats_set(folder, prefix=f"c{seed}_", duration=2.0, rate=20.0, pad_time=1.0)
        return os.path.join(folder, f"c{seed}_baro.csv")
    if kind == "dataflash":
        fx.write_dataflash(os.path.join(folder, f"df{seed}.bin"), duration=3.0)
        return os.path.join(folder, f"df{seed}.bin")
    if kind == "empty":
        open(path, "w").close()
    elif kind == "garbage":
        with open(path, "wb") as stream:
            stream.write(rng.integers(0, 256, 2000, dtype=np.uint8).tobytes())
    elif kind == "header":
        with open(path, "w") as stream:
            stream.write("t,az,alt,ref\n")
    else:
        n = int(rng.integers(2, 400))
        rows = ["t,az,alt,ref"] + [f"{0.01 * i:.2f},{rng.normal():.3f},{'' if i % 3 else f'{rng.normal(10):.2f}'},"
                                   f"{10 + rng.normal():.2f}" for i in range(n)]
        text = "\n".join(rows) + "\n"
        if kind == "truncated":
            text = text[: int(rng.integers(1, len(text)))]
        elif kind == "ulg":
            path = os.path.join(folder, f"log{seed}.ulg")
        elif kind == "bin":
            path = os.path.join(folder, f"log{seed}.bin")
        with open(path, "w") as stream:
            stream.write(text)
    return path


def fleet_path(folder, kind, seed):
    """A DIR_OR_GLOB argument of ``fleet``: a folder with one log, an empty folder, a missing folder, a glob
    matching nothing or something, a single log."""
    if kind == "logs":
        logs = os.path.join(folder, "logs")
        os.makedirs(logs, exist_ok=True)
        make_file(logs, "valid", seed)
        return logs
    if kind == "empty-dir":
        empty = os.path.join(folder, "empty")
        os.makedirs(empty, exist_ok=True)
        return empty
    if kind == "missing-dir":
        return os.path.join(folder, "no-such-dir")
    if kind == "glob-nothing":
        return os.path.join(folder, "*.nothing")
    if kind == "glob":
        make_file(folder, "valid", seed)
        return os.path.join(folder, "*.csv")
    return make_file(folder, kind, seed)


def output_target(draw, folder):
    """An output path: ordinary names, and the ones that must never be replaced: every file already in the folder
    (the input and the siblings its reader opens), a symlink and a hard link to one of them, a device, ``-``."""
    existing = sorted(os.path.join(folder, name) for name in os.listdir(folder)
                      if os.path.isfile(os.path.join(folder, name)))
    choices = [os.path.join(folder, "out.csv"), os.path.join(folder, "p.png"), os.path.join(folder, "p.xyz"),
               os.path.join(folder, "no", "p.png"), folder, os.path.join(folder, "fit.json"), "", os.devnull, "-"]
    if existing:
        target = draw(st.sampled_from(existing))
        kind = draw(st.sampled_from(["same", "symlink", "hardlink"]))
        if kind == "same":
            return target
        link = os.path.join(folder, "links", f"{kind}-{os.path.basename(target)}")
        os.makedirs(os.path.dirname(link), exist_ok=True)
        if not os.path.lexists(link):
            (os.symlink if kind == "symlink" else os.link)(target, link)
        return link
    return draw(st.sampled_from(choices))


def value_for(flag, draw, folder):
    if flag in ("-o", "--plot", "--export", "--events-csv"):
        return output_target(draw, folder)
    if flag in ("--time", "--accel", "--baro", "--pressure", "--reference", "--gps", "--rangefinder", "--temperature"):
        return draw(st.sampled_from(COLUMNS))
    if flag in ("--accel-body", "--attitude-columns"):
        return draw(st.sampled_from(["az,az,az", "az,alt", "t,az,alt,ref", ",,", "nope,nope,nope"]))
    if flag in ("--attitude-convention", "--frame", "--temperature-units"):
        return draw(st.sampled_from(["quaternion", "euler_deg", "NED", "ENU", "C", "K", "bogus"]))
    if flag == "--ground-temperature":
        return draw(st.sampled_from(NUMBERS + ["log", "LOG"]))
    if flag in ("--scenario", "--plot-scenario"):
        return draw(st.sampled_from(["clean", "terrain-step", "submarine"]))
    if flag == "--estimator":
        return draw(st.sampled_from(["observer", "kalman", "complementary", "alphabeta", "ins", "rocket", "x"]))
    if flag == "--preset":
        return draw(st.sampled_from(["vtol", "balloon", "rocket", "warp"]))
    if flag == "--long-axis":
        return draw(st.sampled_from(["+X", "-Z", "Z", "up"]))
    if flag in ("--accel-units",):
        return draw(st.sampled_from(["g", "m/s^2", "furlongs"]))
    if flag in ("--altitude-units",):
        return draw(st.sampled_from(["m", "ft", "km"]))
    if flag == "--train-until":
        return draw(st.sampled_from(NUMBERS + ["50%", "0%", "150%", "x%", "nan%"]))
    if flag == "--scheduler":
        return draw(st.sampled_from(["tcp://127.0.0.1:1", "", "nonsense"]))
    if flag == "--holdout":
        return fleet_path(folder, draw(st.sampled_from(["logs", "missing-dir", "glob-nothing", "empty-dir"])),
                          draw(st.integers(0, 10_000)))
    return draw(st.sampled_from(NUMBERS))


def draw_flags(draw, vocabulary, folder):
    argv = []
    for flag in draw(st.lists(st.sampled_from(vocabulary), max_size=4)):
        argv.append(flag)
        if flag not in SWITCHES:
            argv.append(value_for(flag, draw, folder))
    return argv


@st.composite
def argv_and_file(draw, folder):
    command = draw(st.sampled_from(sorted(FLAGS)))
    argv = [command]
    if command in ("run", "fit", "compare"):
        kind = draw(st.sampled_from(["missing", "folder", "empty", "garbage", "header", "truncated", "valid", "valid",
                                     "ulg", "bin", "altos", "cats", "dataflash"]))
        argv.append(make_file(folder, kind, draw(st.integers(0, 10_000))))
        if draw(st.booleans()):
            argv += ["--time", "t", "--accel", "az", "--baro", "alt"]
    if command == "compare":
        argv += ["--repeat", "0"]
    return argv + draw_flags(draw, FLAGS[command], folder)


@st.composite
def fleet_argv(draw, folder):
    command = draw(st.sampled_from(sorted(FLEET_FLAGS)))
    argv = ["fleet", command]
    kinds = ["logs", "empty-dir", "missing-dir", "glob-nothing", "glob", "valid", "garbage", "missing"]
    if command == "summary":
        argv.append(draw(st.sampled_from([folder, os.path.join(folder, "no-such-dir"),
                                          make_file(folder, "valid", 0)])))
    else:
        for _ in range(draw(st.integers(1, 2))):
            argv.append(fleet_path(folder, draw(st.sampled_from(kinds)), draw(st.integers(0, 10_000))))
        if command == "run" and draw(st.integers(0, 5)):
            argv += ["-o", draw(st.sampled_from([os.path.join(folder, "out"), make_file(folder, "valid", 1), ""]))]
        if draw(st.booleans()):
            argv += ["--time", "t", "--accel", "az", "--baro", "alt"]
    return argv + draw_flags(draw, FLEET_FLAGS[command], folder)


def snapshot(folder):
    """The bytes of every regular file under ``folder`` (symlinks not followed)."""
    files = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            if os.path.isfile(path) and not os.path.islink(path):
                with open(path, "rb") as stream:
                    files[path] = stream.read()
    return files


def check(argv, run, folder=None):
    """Run ``main(argv)`` via ``run``; the status and stderr obey the CLI's promises, and no file that was in
    ``folder`` before (inputs, the siblings their readers open, links to them) is changed."""
    before = snapshot(folder) if folder else {}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            status = main(argv)
        except SystemExit as exit_:  # argparse: usage error (2) or --help (0)
            status = exit_.code
            usage = True
        except ClusterWouldStart:
            status, usage = 0, False
        else:
            usage = False
    err = run()
    after = snapshot(folder) if folder else {}
    assert all(after.get(path) == data for path, data in before.items()), (argv, "an input was changed")
    assert not caught, (argv, [f"{w.category.__name__}: {w.message}" for w in caught])
    assert status in (0, 1, 2, 3), (argv, status, err)
    if status == 3:  # an estimate refused: one line says why
        assert err.strip().splitlines()[-1].startswith(f"fusion-altitude {argv[0]}: error: "), (argv, err)
    assert "Traceback" not in err, (argv, err)
    assert not re.search(r"\w+Warning\b", err), (argv, err)
    if status == 2 and not usage:
        lines = err.strip().splitlines()
        assert lines and lines[-1].startswith(f"fusion-altitude {argv[0]}: error: "), (argv, err)
        assert all(ALLOWED_EXTRA.match(line) for line in lines[:-1]), (argv, err)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_no_input_makes_the_cli_print_a_traceback(data, tmp_path_factory, capsys):
    folder = str(tmp_path_factory.mktemp("fuzz"))
    argv = data.draw(argv_and_file(folder))
    check(argv, lambda: capsys.readouterr().err, folder if argv[0] != "demo" else None)


@pytest.fixture
def no_cluster(monkeypatch):
    from fusion_altitude import fleet

    def refuse(*args, **kwargs):
        raise ClusterWouldStart()

    monkeypatch.setattr(fleet, "open_client", refuse)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_fleet_checks_never_print_a_traceback(data, tmp_path_factory, capsys, no_cluster):
    folder = str(tmp_path_factory.mktemp("fleetfuzz"))
    argv = data.draw(fleet_argv(folder))
    check(argv, lambda: capsys.readouterr().err)


@st.composite
def compare_scenario_argv(draw, folder):
    """``compare`` without a FILE on the cheapest scenario, with odd --plot-scenario, --plot, seeds, attitude."""
    argv = ["compare", "--scenario", "clean", "--repeat", "0"]
    vocabulary = ["--scenario", "--plot-scenario", "--plot", "--seed", "--fit-seed", "--attitude", "--markdown"]
    for flag in draw(st.lists(st.sampled_from(vocabulary), max_size=3, unique=True)):
        argv.append(flag)
        if flag == "--markdown":
            continue
        if flag in ("--seed", "--fit-seed"):
            argv.append(draw(st.sampled_from(["0", "2", "-1", "abc", "1e308"])))
        elif flag == "--attitude":
            argv.append(draw(st.sampled_from(["truth", "ahrs", "magic"])))
        else:
            argv.append(value_for(flag, draw, folder))
    return argv


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_compare_on_scenarios_never_prints_a_traceback(data, tmp_path_factory, capsys):
    folder = str(tmp_path_factory.mktemp("comparefuzz"))
    argv = data.draw(compare_scenario_argv(folder))
    check(argv, lambda: capsys.readouterr().err)


@pytest.mark.parametrize("argv,flag", [
    (["tune", "--omega", "1e308"], "--omega"),
    (["tune", "--omega", "1e30"], "--omega"),
    (["tune", "--omega-b", "1e308"], "--omega-b"),
    (["tune", "--zeta", "1e308"], "--zeta"),
    (["tune", "--rate", "1e-300"], "--rate"),
    (["fit", "--scenario", "clean", "--omega-max", "1e308"], "--omega-max"),
    (["fit", "--scenario", "clean", "--skip", "1000"], "--skip"),
])
def test_huge_and_tiny_values_are_one_line_errors_without_warnings(argv, flag, capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(argv) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and flag in lines[0], lines


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(omega=st.floats(1e-30, 1e4), zeta=st.floats(1e-30, 100), ratio=st.floats(0, 1e4),
       rate=st.floats(1e-3, 1e4))
def test_tune_anywhere_in_its_bounds_prints_no_warning(omega, zeta, ratio, rate, capsys):
    omega_b = min(omega * ratio, 1e4)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        status = main(["tune", "--omega", repr(omega), "--zeta", repr(zeta), "--omega-b", repr(omega_b),
                       "--rate", repr(rate)])
    err = capsys.readouterr().err
    assert not caught, [str(w.message) for w in caught]
    assert status in (0, 1) or (status == 2 and len(err.strip().splitlines()) == 1), err
    assert "Traceback" not in err and "Warning" not in err


SNIFFED_FLAGS = ["--ground-temperature", "--instance", "--estimator", "--agl", "--accel-units", "--sea-level-pa"]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_option_combinations_on_sniffed_formats_never_print_a_traceback(data, tmp_path_factory, capsys):
    """A recognised log (AltOS, CATS, DataFlash) with the reader options that apply to some formats only."""
    folder = str(tmp_path_factory.mktemp("sniffed"))
    command = data.draw(st.sampled_from(["run", "fit", "compare"]))
    kind = data.draw(st.sampled_from(["altos", "cats", "dataflash"]))
    argv = [command, make_file(folder, kind, data.draw(st.integers(0, 10_000)))]
    if command == "compare":
        argv += ["--repeat", "0"]
    for flag in data.draw(st.lists(st.sampled_from(SNIFFED_FLAGS), min_size=1, max_size=3, unique=True)):
        if command == "fit" and flag in ("--estimator", "--agl"):
            continue
        argv.append(flag)
        if flag == "--ground-temperature":
            argv.append(data.draw(st.sampled_from(["log", "Log", "20", "-300", "nan", "abc"])))
        elif flag == "--instance":
            argv.append(data.draw(st.sampled_from(["0", "1", "7", "-1"])))
        elif flag not in SWITCHES:
            argv.append(value_for(flag, data.draw, folder))
    check(argv, lambda: capsys.readouterr().err)
