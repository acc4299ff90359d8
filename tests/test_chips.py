"""The headers on more chips, run and not only compiled (csrc/firmware/Makefile, docs/embedded.md):

- RISC-V 32 under qemu-system-riscv32 (-M virt, picolibc, semihosting): every estimator's replay of its shared
  vectors (the same as on the host and the Cortex-M4F) on rv32imac (soft float) and rv32imafc (hardware single
  precision), at -Os and -O2, bit for bit; and the retired instructions of each Update path (minstret under
  QEMU -icount);
- AVR under simavr (atmega1284p): the same replays at -Os and -O2, bit for bit, the records streamed from a
  libsimavr host over the UART (they fit no AVR's memory); the CPU cycles of each Update path (Timer1), every
  path taking its status;
- the Arduino library archive and its sketches, compiled warning-free for an ATmega328P and a Cortex-M4F.

A missing tool fails the test (never a skip): .ci/run installs them with apt.
"""

import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FIRMWARE = ROOT / "csrc" / "firmware"
ESTIMATORS = ["observer", "kalman", "complementary", "alphabeta", "rocket", "ins"]
SKETCHES = ["Observer", "Kalman", "Complementary", "AlphaBeta", "Rocket", "Ins"]
TOOLS = ("make", "gcc", "riscv64-unknown-elf-gcc", "qemu-system-riscv32", "avr-gcc", "avr-g++", "avr-size", "simavr",
         "arm-none-eabi-g++", "timeout")
#: Update paths of cycles_<name>.c, in call order (their comments list them)
PATHS = {"observer": 3, "kalman": 5, "complementary": 4, "alphabeta": 4, "rocket": 5, "ins": 6}


def make(build: Path, *targets: str, timeout: float = 1200) -> str:
    missing = [tool for tool in TOOLS if shutil.which(tool) is None]
    assert not missing, f"missing tools {missing} (.ci/run installs them with apt)"
    result = subprocess.run(["make", "-C", str(FIRMWARE), "-j2", f"BUILD={build}", f"PYTHON={sys.executable}",
                             *targets], capture_output=True, text=True, timeout=timeout)
    assert result.returncode == 0, result.stdout[-6000:] + result.stderr[-6000:]
    return result.stdout


@pytest.fixture(scope="module")
def build(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("chips")


def record_count(name: str) -> int:
    text = (ROOT / "csrc" / "tests" / "vectors" / f"{name}_vectors.h").read_text()
    return int(re.search(r"#define FUSION_ALTITUDE_\w*VECTOR_COUNT \((\d+)\)", text).group(1))


@pytest.mark.slow
def test_replays_on_riscv32_soft_and_hard_float_are_bit_exact(build):
    output = make(build, "replay-riscv")
    for target in ("rv32imac", "rv32imafc"):
        for name in ESTIMATORS:
            for optimisation in ("Os", "O2"):
                line = f"{target} replay_{name}-{optimisation}: replay: {record_count(name)} records, 0 mismatches"
                assert line in output.splitlines(), line


@pytest.mark.slow
def test_a_corrupted_record_fails_the_riscv_replay(tmp_path):
    """The check above can fail: one flipped expected bit is a mismatch and a non-zero exit on RV32 too."""
    missing = [tool for tool in TOOLS if shutil.which(tool) is None]
    assert not missing, missing
    result = subprocess.run(["make", "-C", str(FIRMWARE), f"BUILD={tmp_path}", "REPLAY_DEFINES=-DREPLAY_CORRUPT_RECORD=5",
                             "riscv-run/rv32imafc/replay_kalman-Os"], capture_output=True, text=True, timeout=600)
    assert result.returncode != 0
    assert f"replay: {record_count('kalman')} records, 1 mismatches" in result.stdout


@pytest.mark.slow
def test_replays_on_avr_under_simavr_are_bit_exact(build):
    assert Path("/usr/include/simavr/sim_avr.h").is_file(), "libsimavr-dev is not installed (.ci/run installs it)"
    output = make(build, "replay-avr")
    for name in ESTIMATORS:
        # the INS at -O2 needs more stack than its replay leaves on the atmega1284p (Makefile: AVR_NOT_REPLAYED)
        for optimisation in ("Os",) if name == "ins" else ("Os", "O2"):
            line = f"avr replay_{name}-{optimisation}: replay: {record_count(name)} records, 0 mismatches"
            assert line in output.splitlines(), line
            # every byte of the streams was asked for: the replay read all records and checkpoints
            sent = re.search(rf"^avr replay_{name}-{optimisation}: avr cycles \d+, records sent (\d+) of (\d+) B, "
                             rf"checkpoints (\d+) of (\d+) B$", output, re.M)
            assert sent is not None and sent.group(1) == sent.group(2) and sent.group(3) == sent.group(4), name


@pytest.mark.slow
def test_a_corrupted_record_fails_the_avr_replay(tmp_path):
    """The check above can fail: one flipped expected bit is a mismatch and a non-zero exit on the AVR too."""
    missing = [tool for tool in TOOLS if shutil.which(tool) is None]
    assert not missing, missing
    result = subprocess.run(["make", "-C", str(FIRMWARE), f"BUILD={tmp_path}", f"PYTHON={sys.executable}",
                             "REPLAY_DEFINES=-DREPLAY_CORRUPT_RECORD=5", "avr-run/replay_complementary-Os"],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode != 0
    assert f"replay: {record_count('complementary')} records, 1 mismatches" in result.stdout


def steps(output: str, prefix: str, unit: str) -> dict:
    counts = {}
    for name, step, count in re.findall(rf"^{prefix} steps_(\w+): step (\d+): (\d+) {unit}$", output, re.M):
        counts.setdefault(name, []).append(int(count))
    return counts


@pytest.mark.slow
def test_every_update_path_is_counted_on_riscv32_under_qemu_icount(build):
    output = make(build, "steps-riscv")
    for target in ("rv32imac", "rv32imafc"):
        counts = steps(output, target, "instructions")
        assert {name: len(values) for name, values in counts.items()} == PATHS, target
        for name, values in counts.items():
            assert all(value > 0 for value in values), (target, name, values)
    soft, hard = steps(output, "rv32imac", "instructions"), steps(output, "rv32imafc", "instructions")
    # software float costs more instructions than the F extension on every accepted full step
    assert all(soft[name][0] > hard[name][0] for name in ESTIMATORS)


@pytest.mark.slow
def test_every_update_path_takes_its_status_and_is_counted_on_avr_under_simavr(build):
    output = make(build, "steps-avr")
    counts = steps(output, "avr", "cycles")
    assert {name: len(values) for name, values in counts.items()} == PATHS
    for name in ESTIMATORS:
        assert f"avr steps_{name}: exit 0" in output.splitlines(), name
        # a rejected call (the last path) returns after its input check: far cheaper than the full step
        assert counts[name][-1] * 10 < counts[name][0], (name, counts[name])


def test_arduino_archive_holds_the_properties_the_headers_and_a_sketch_per_estimator(tmp_path):
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "make_arduino.py"), str(tmp_path)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    archive = Path(result.stdout.strip())
    with zipfile.ZipFile(archive) as zipped:
        names = set(zipped.namelist())
    headers = sorted(path.name for path in (ROOT / "csrc").glob("fusion_altitude*.h"))
    expected = {"FusionAltitude/library.properties", "FusionAltitude/library.json", "FusionAltitude/LICENSE"}
    expected |= {f"FusionAltitude/src/{header}" for header in headers}
    expected |= {f"FusionAltitude/examples/{sketch}/{sketch}.ino" for sketch in SKETCHES}
    assert names == expected


def test_arduino_sketches_are_written_from_one_template():
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "make_arduino.py"), "--sketches", "--check"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.slow
def test_arduino_sketches_compile_warning_free_for_atmega328p_and_cortex_m4f(build):
    output = make(build, "arduino-sketches")
    sizes = dict(re.findall(r"^(\w+ \w+)\s+(\d+\s+\d+\s+\d+)", output, re.M))
    for board in ("avr", "m4f"):
        for sketch in SKETCHES:
            assert f"{board} {sketch}" in sizes, (board, sketch)
    for sketch in SKETCHES:
        text, data, bss = (int(value) for value in sizes[f"avr {sketch}"].split())
        assert text + data <= 32 * 1024 - 512, (sketch, "flash of an ATmega328P (less a 512 B bootloader)")
        assert data + bss <= 2048 - 256, (sketch, "RAM of an ATmega328P, less 256 B of stack")


@pytest.mark.slow
def test_chips_tables_in_the_docs_match_a_fresh_measurement(build):
    """docs/embedded.md's RISC-V, AVR and sketch tables are what make doc-chips writes from this build."""
    output = make(build, "chips-table")
    doc = (ROOT / "docs" / "embedded.md").read_text()
    stated = re.search(r"<!-- chips:begin -->\n(.*?)<!-- chips:end -->", doc, re.S).group(1)
    fresh = output[output.index("RISC-V 32 under QEMU"):]
    fresh = "\n".join(line for line in fresh.splitlines() if not line.startswith("make")) + "\n"
    assert stated == fresh
