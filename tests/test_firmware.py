"""Firmware fitness of csrc/fusion_altitude.h (issue 3), through csrc/firmware/Makefile:

- cross builds (Cortex-M0+/M4F/M7, rv32imac/rv32imafc; C99/C11; -Os/-O2) with
  warnings as errors, and no double instruction or libm call in the objects;
- the shared vectors (csrc/tests/vectors, from the pure-Python reference)
  replayed bit for bit on the host (gcc, clang) and on QEMU's Cortex-M4F;
- the size/stack/cycle table of docs/embedded.md, the firmware example on
  QEMU, cppcheck, and a libFuzzer run (FUSION_ALTITUDE_FUZZ_SECONDS, default 60).

A missing tool fails the test (never a skip): .ci/run installs them with apt.
"""

import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"
FIRMWARE = CSRC / "firmware"
VECTORS = CSRC / "tests" / "vectors"
DOC = ROOT / "docs" / "embedded.md"
TOOLS = ("make", "gcc", "clang", "cppcheck", "arm-none-eabi-gcc", "arm-none-eabi-objdump", "arm-none-eabi-nm",
         "riscv64-unknown-elf-gcc", "qemu-system-arm", "timeout")
FUZZ_SECONDS = max(1, int(os.environ.get("FUSION_ALTITUDE_FUZZ_SECONDS", "60")))  # libFuzzer: 0 = forever


def make(build: Path, *targets: str, timeout: float = 600, **variables: str) -> subprocess.CompletedProcess:
    missing = [tool for tool in TOOLS if shutil.which(tool) is None]
    assert not missing, f"missing tools {missing} (.ci/run installs them with apt)"
    settings = [f"{name}={value}" for name, value in {"BUILD": str(build), "PYTHON": sys.executable,
                                                      **variables}.items()]
    return subprocess.run(["make", "-C", str(FIRMWARE), "-j2", *settings, *targets],
                          capture_output=True, text=True, timeout=timeout)


def assert_ok(result: subprocess.CompletedProcess) -> str:
    assert result.returncode == 0, result.stdout[-6000:] + result.stderr[-6000:]
    return result.stdout


@pytest.fixture(scope="session")
def build(tmp_path_factory) -> Path:
    """One build directory shared by the tests (the cross objects are built once)."""
    return tmp_path_factory.mktemp("firmware")


def vector_count() -> int:
    return int(re.search(r"#define FUSION_ALTITUDE_VECTOR_COUNT \((\d+)\)", (VECTORS / "vectors.h").read_text()).group(1))


def test_vectors_are_up_to_date():
    spec = importlib.util.spec_from_file_location("generate_vectors", VECTORS / "generate.py")
    generator = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(generator)
    assert generator.render() == (VECTORS / "vectors.h").read_text(), \
        "csrc/tests/vectors/vectors.h is stale: run python csrc/tests/vectors/generate.py"
    assert vector_count() > 3000


def test_every_public_function_is_built_and_sized():
    header = (CSRC / "fusion_altitude.h").read_text()
    public = set(re.findall(r"^static inline [^(]*?\b(FusionAltitude\w+)\(", header, re.MULTILINE))
    assert "FusionAltitudeUpdate" in public
    sized = set(re.findall(r"\bSized(FusionAltitude\w+)\(", (FIRMWARE / "sized.c").read_text()))
    called = set(re.findall(r"\b(FusionAltitude\w+)\(", (FIRMWARE / "firmware.c").read_text()))
    spec = importlib.util.spec_from_file_location("size_table", FIRMWARE / "size_table.py")
    table = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(table)
    assert public - sized == set(), "add these to csrc/firmware/sized.c"
    assert public - called - {"FusionAltitudeNaN"} == set(), "call these from csrc/firmware/firmware.c"
    assert public - set(table.FUNCTIONS) == set(), "add these to FUNCTIONS in csrc/firmware/size_table.py"


def test_cross_builds_are_warning_free_without_double_or_libm(build):
    output = assert_ok(make(build, "check-objects"))
    assert re.search(r"^40 objects checked, 0 with double or libm$", output, re.MULTILINE), output
    for target in ("cortex-m0plus", "cortex-m4f", "cortex-m7", "rv32imac", "rv32imafc"):
        for variant in ("c99-Os", "c99-O2", "c11-Os", "c11-O2"):
            assert (build / "cross" / target / variant / "sized.o").exists()


def test_object_check_catches_double(tmp_path):
    """The checker itself: a float promoted to double is found on each target."""
    source = tmp_path / "promote.c"
    source.write_text("float tenth(float x);\nfloat tenth(float x) { return (float) (x * 0.1); }\n")
    compilers = {"cortex-m7": ["arm-none-eabi-gcc", "-mcpu=cortex-m7", "-mthumb", "-mfpu=fpv5-d16",
                               "-mfloat-abi=hard"],
                 "cortex-m0plus": ["arm-none-eabi-gcc", "-mcpu=cortex-m0plus", "-mthumb"],
                 "rv32imac": ["riscv64-unknown-elf-gcc", "-march=rv32imac", "-mabi=ilp32"]}
    for target, command in compilers.items():
        variant = tmp_path / "cross" / target / "c99-O2"
        variant.mkdir(parents=True)
        prefix = command[0][:-len("gcc")]
        subprocess.run([*command, "-O2", "-c", str(source), "-o", str(variant / "promote.o")], check=True)
        for tool, suffix in (("objdump", ["-d"]), ("nm", ["-u"])):
            listing = subprocess.run([prefix + tool, *suffix, str(variant / "promote.o")], check=True,
                                     capture_output=True, text=True).stdout
            (variant / ("promote.lst" if tool == "objdump" else "promote.undefined")).write_text(listing)
    result = subprocess.run([sys.executable, str(FIRMWARE / "check_objects.py"), str(tmp_path / "cross")],
                            capture_output=True, text=True)
    assert result.returncode == 1, result.stdout
    assert re.search(r"cortex-m7/c99-O2/promote: FAIL .*vcvt\.f64", result.stdout), result.stdout
    assert re.search(r"cortex-m0plus/c99-O2/promote: FAIL .*__aeabi_d", result.stdout), result.stdout
    assert re.search(r"rv32imac/c99-O2/promote: FAIL .*df", result.stdout), result.stdout


def replay_lines(output: str) -> list:
    return re.findall(r"^replay: (\d+) records, (\d+) mismatches$", output, re.MULTILINE)


def test_replay_on_host_is_bit_exact(build):
    output = assert_ok(make(build, "replay-host"))
    assert replay_lines(output) == [(str(vector_count()), "0")] * 2, output


def test_replay_on_qemu_cortex_m4f_is_bit_exact(build):
    output = assert_ok(make(build, "replay-qemu"))
    assert replay_lines(output) == [(str(vector_count()), "0")] * 2, output


def test_replay_reports_a_mismatch(tmp_path):
    """One flipped expected bit fails the run, on the host and through QEMU's semihosting exit."""
    defines = "-DREPLAY_CORRUPT_RECORD=1000"
    for target in ("replay-host", "replay-qemu"):
        result = make(tmp_path / target, target, REPLAY_DEFINES=defines)
        assert result.returncode != 0, result.stdout
        assert replay_lines(result.stdout)[0] == (str(vector_count()), "1"), result.stdout
        assert "record 1000 " in result.stdout


def test_sizes_meet_the_firmware_budget_and_match_the_doc(build):
    assert_ok(make(build, "cross", f"{build}/cycles/trace.log"))
    measured = json.loads(subprocess.run([sys.executable, str(FIRMWARE / "size_table.py"), str(build), "--json"],
                                         check=True, capture_output=True, text=True).stdout)
    assert set(measured["ram"].values()) == {32}, measured["ram"]
    assert measured["stack"]["FusionAltitudeUpdate/cortex-m4f/Os"] == [0, "static"]
    # Goal 200 bytes (see docs/embedded.md); this bound only catches regressions.
    assert measured["size"]["FusionAltitudeUpdate/cortex-m4f/Os"] <= 256
    full, missing, rejected = measured["cycles"]
    assert 20 < full["instructions"] < 80 and missing["instructions"] < full["instructions"]
    assert rejected["instructions"] < 12
    table = subprocess.run([sys.executable, str(FIRMWARE / "size_table.py"), str(build)], check=True,
                           capture_output=True, text=True).stdout.strip()
    assert table in DOC.read_text(), "docs/embedded.md is stale: paste the output of make -C csrc/firmware sizes"


def test_example_runs_on_qemu_and_detects_the_baro_fault(build):
    output = assert_ok(make(build, "example-run"))
    assert "done: 0 rejected updates, baro fault detected" in output, output
    fault = re.search(r"^baro fault at (\d+) ms", output, re.MULTILINE)
    assert fault and 40000 <= int(fault.group(1)) <= 40500, output
    hover = re.search(r"^t 35000 ms: height (-?\d+) cm", output, re.MULTILINE)
    assert hover and abs(int(hover.group(1)) - 2400) < 100, output  # 24 m climb
    coast = re.search(r"^t 60000 ms: height (-?\d+) cm", output, re.MULTILINE)
    assert coast and abs(int(coast.group(1)) - 2400) < 500, output  # 20 s on the accelerometer alone


def test_cppcheck_is_clean(build):
    assert_ok(make(build, "cppcheck"))


def test_fuzzer_finds_nothing(build):
    result = make(build, "fuzz-run", timeout=FUZZ_SECONDS + 300, FUZZ_SECONDS=str(FUZZ_SECONDS))
    log = result.stdout + result.stderr
    assert result.returncode == 0, log[-6000:]
    runs = re.search(r"^Done (\d+) runs in", log, re.MULTILINE)
    assert runs and int(runs.group(1)) > 0, log[-6000:]
    assert "runtime error" not in log and "ERROR: " not in log and "CHECK(" not in log
