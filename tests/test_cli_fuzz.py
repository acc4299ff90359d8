"""CLI fuzz: every subcommand with randomised bad flags and files never prints a traceback.

Each example builds an argument list from a vocabulary of real flags with
odd values (NaN, inf, negative, huge, text, empty) and a file that is
empty, binary garbage, truncated, header-only, a folder, missing or a valid
log. ``main`` must return 0, 1 or 2 (or argparse's usage exit 2) and never
raise; stderr never holds a traceback.
"""

import os
import sys
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fusion_altitude.cli import main

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402

NUMBERS = ["0", "-1", "-5", "1e308", "nan", "inf", "-inf", "0.5", "3", "abc", "", "1e-30", "100000"]
COMMON_LOG_FLAGS = ["--time", "--accel", "--baro", "--pressure", "--reference", "--accel-units", "--altitude-units",
                    "--sea-level-pa", "--remove-gravity", "--instance", "--ground-temperature", "--gps",
                    "--rangefinder", "--accel-body", "--attitude-columns", "--attitude-convention", "--frame",
                    "--temperature", "--temperature-units"]
FLAGS = {
    "demo": ["--seed", "--scenario", "--attitude", "--plot", "--export"],
    "tune": ["--omega", "--zeta", "--omega-b", "--rate"],
    "run": COMMON_LOG_FLAGS + ["--estimator", "--preset", "-o", "--plot", "--agl"],
    "fit": COMMON_LOG_FLAGS + ["--skip", "--train-until", "--omega-min", "--omega-max", "--plot"],
    "compare": COMMON_LOG_FLAGS + ["--skip", "--repeat", "--markdown", "--plot", "--agl"],
}
SWITCHES = {"--remove-gravity", "--agl", "--markdown"}
COLUMNS = ["t", "az", "alt", "ref", "nope"]


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


def value_for(flag, draw, folder):
    if flag in ("-o", "--plot", "--export"):
        return draw(st.sampled_from([os.path.join(folder, "out.csv"), os.path.join(folder, "p.png"),
                                     os.path.join(folder, "p.xyz"), os.path.join(folder, "no", "p.png"), folder,
                                     ""]))
    if flag in ("--time", "--accel", "--baro", "--pressure", "--reference", "--gps", "--rangefinder", "--temperature"):
        return draw(st.sampled_from(COLUMNS))
    if flag in ("--accel-body", "--attitude-columns"):
        return draw(st.sampled_from(["az,az,az", "az,alt", "t,az,alt,ref", ",,", "nope,nope,nope"]))
    if flag in ("--attitude-convention", "--frame", "--temperature-units"):
        return draw(st.sampled_from(["quaternion", "euler_deg", "NED", "ENU", "C", "K", "bogus"]))
    if flag == "--ground-temperature":
        return draw(st.sampled_from(NUMBERS + ["log", "LOG"]))
    if flag in ("--scenario",):
        return draw(st.sampled_from(["clean", "terrain-step", "submarine"]))
    if flag == "--estimator":
        return draw(st.sampled_from(["observer", "kalman", "complementary", "alphabeta", "x"]))
    if flag in ("--accel-units",):
        return draw(st.sampled_from(["g", "m/s^2", "furlongs"]))
    if flag in ("--altitude-units",):
        return draw(st.sampled_from(["m", "ft", "km"]))
    if flag == "--train-until":
        return draw(st.sampled_from(NUMBERS + ["50%", "0%", "150%", "x%"]))
    return draw(st.sampled_from(NUMBERS))


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
    for flag in draw(st.lists(st.sampled_from(FLAGS[command]), max_size=4)):
        argv.append(flag)
        if flag not in SWITCHES:
            argv.append(value_for(flag, draw, folder))
    return argv


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_no_input_makes_the_cli_print_a_traceback(data, tmp_path_factory, capsys):
    folder = str(tmp_path_factory.mktemp("fuzz"))
    argv = data.draw(argv_and_file(folder))
    try:
        status = main(argv)
    except SystemExit as exit_:  # argparse: usage error (2) or --help (0)
        status = exit_.code
    captured = capsys.readouterr()
    assert status in (0, 1, 2), (argv, status, captured.err)
    assert "Traceback" not in captured.err, (argv, captured.err)
    if status == 2:
        assert captured.err.strip(), argv


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
    try:
        status = main(argv)
    except SystemExit as exit_:
        status = exit_.code
    captured = capsys.readouterr()
    assert status in (0, 1, 2), (argv, status, captured.err)
    assert "Traceback" not in captured.err, (argv, captured.err)
