"""The INS header's C unit tests (csrc/tests/test_ins.c), built the ways
firmware engineers build them: gcc and clang, C99, GNU modes (FMA contraction
on by default, turned off inside the header) and as C++, strict warnings as
errors, and under ASan + UBSan; the header's sqrtf-only / no-double /
no-malloc rules; and the 10^7-step covariance robustness run."""

import re
import subprocess
from pathlib import Path

import pytest

from tests.test_c_core import CSRC, SANITIZE, STRICT, compiler

BUILDS = {
    "gcc-c99": ["gcc", "-std=c99", "-O2"],
    "gcc-gnu11-O2": ["gcc", "-std=gnu11", "-O2"],
    "clang-c99": ["clang", "-std=c99", "-O2"],
    "clang-gnu11-O2": ["clang", "-std=gnu11", "-O2"],
    "g++-c++11": ["g++", "-x", "c++", "-std=c++11", "-O2"],
    "clang++-c++17": ["clang++", "-x", "c++", "-std=c++17", "-O2"],
    "clang-asan-ubsan": ["clang", "-std=c99", "-O1", *SANITIZE],
    "gcc-asan-ubsan": ["gcc", "-std=c99", "-O1", *SANITIZE],
}
HEADER = CSRC / "fusion_altitude_ins.h"
TEST = CSRC / "tests" / "test_ins.c"


def build(command, source: Path, binary: Path) -> None:
    result = subprocess.run([compiler(command[0]), *command[1:], *STRICT, f"-I{CSRC}", str(source), "-o", str(binary), "-lm"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stderr == "", result.stderr


@pytest.mark.parametrize("build_name", sorted(BUILDS))
def test_ins_c_unit_tests_pass_warning_free(build_name, tmp_path):
    binary = tmp_path / "test_ins"
    build(BUILDS[build_name], TEST, binary)
    run = subprocess.run([str(binary)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    summary = re.search(r"^(\d+) passed, (\d+) failed$", run.stdout, re.MULTILINE)
    assert summary is not None, run.stdout
    assert int(summary.group(1)) >= 11 and summary.group(2) == "0"
    assert "runtime error" not in run.stderr and "Sanitizer" not in run.stderr


def test_ins_covariance_stays_symmetric_psd_over_ten_million_steps_at_1khz(tmp_path):
    """2 x 10^7 float32 steps of a vehicle resting 60 s then tumbling and
    climbing 240 s, with accel rejections and gaps; with baro and without
    (height unobservable). Every 1000 steps: P finite, bit-symmetric,
    diagonal >= 0, Cholesky (double) of its correlation matrix without a
    negative pivot."""
    binary = tmp_path / "test_ins_long"
    build(["gcc", "-std=c99", "-O2"], TEST, binary)
    run = subprocess.run([str(binary), "long"], capture_output=True, text=True, timeout=600)
    print(run.stdout)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "2 of 2 configurations kept P symmetric PSD" in run.stdout
    assert run.stdout.count("10000000 steps") == 2


def test_ins_header_uses_sqrtf_only_no_double_no_malloc_no_globals():
    code = re.sub(r"/\*.*?\*/|//[^\n]*", "", HEADER.read_text(), flags=re.DOTALL)
    calls = set(re.findall(r"\b(sqrtf?|sinf?|cosf?|tanf?|asinf?|acosf?|atan2?f?|expf?|logf?|powf?|fabsf?)\s*\(", code))
    assert calls == {"sqrtf"}
    assert "double" not in code
    assert "malloc" not in code
    assert not re.search(r"^static (?!inline)", code, re.MULTILINE), "a file-scope static variable is a global"


def test_ins_gives_the_same_bits_under_gnu_modes_with_default_fma_contraction(tmp_path):
    """A tumbling run printed as hex floats, built -std=c99 (no contraction)
    and -std=gnu11 -O2 -march=native (gcc contracts a*b + c into FMA unless
    the header's pragma stops it): identical output."""
    source = tmp_path / "run.c"
    source.write_text(r'''
#include "fusion_altitude_ins.h"
#include <stdio.h>
int main(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    for (int i = 0; i < 20000; i++) {
        const float t = (float) i / 200.0f;  /* inputs built without a*b + c, so only the header could contract */
        const FusionAltitudeInsVector gyro = {0.3f * (float) (i % 97) / 97.0f, -0.2f, 0.01f * (float) (i % 13)};
        const FusionAltitudeInsVector accel = {0.5f + (float) (i % 31) / 1000.0f, -0.3f, 9.7f + (float) (i % 7) / 50.0f};
        const FusionAltitudeInsVector mag = {0.4f, t / 10.0f, -0.3f};
        (void) FusionAltitudeInsUpdate(&ins, gyro, accel, mag, (i % 7 == 0) ? 100.0f + t / 1000.0f : FUSION_ALTITUDE_NO_BARO, 0.005f);
    }
    const unsigned char *bytes = (const unsigned char *) &ins;
    for (size_t i = 0; i < sizeof(ins); i++) printf("%02x", bytes[i]);
    printf("\n");
    return 0;
}
''')
    outputs = []
    for flags in (["-std=c99", "-O2"], ["-std=gnu11", "-O2", "-march=native"], ["-std=gnu11", "-O3", "-march=native"]):
        binary = tmp_path / ("run" + "".join(flags).replace("=", "").replace("-", ""))
        result = subprocess.run([compiler("gcc"), *flags, f"-I{CSRC}", str(source), "-o", str(binary), "-lm"],
                                capture_output=True, text=True)
        assert result.returncode == 0, result.stderr
        outputs.append(subprocess.run([str(binary)], capture_output=True, text=True).stdout)
    assert outputs[0] == outputs[1] == outputs[2]


def test_ins_m4f_imu_step_costs_under_12000_cycles(tmp_path):
    """csrc/firmware/ins_cycles.py on QEMU (Cortex-M4F, -Os): the common IMU
    step (predict + accel correction) and the step with a baro sample each
    under 12 000 estimated cycles (71 µs at 168 MHz), a rejected input under 200."""
    import sys

    sys.path.insert(0, str(CSRC / "firmware"))
    import ins_cycles

    rows = {name: cycles for name, _, cycles in ins_cycles.estimate(tmp_path)}
    assert rows["predict + accel (no baro, no mag)"] < 12000
    assert rows["predict + accel + baro"] < 12000
    assert rows["rejected input (gyro NaN)"] < 200


def test_ins_fuzzer_finds_nothing_in_30000_inputs(tmp_path):
    """csrc/fuzz/fuzz_ins.c under ASan + UBSan + libFuzzer, 30 000 generated
    inputs from a fixed seed: rejected calls leave the INS bit-identical, P
    stays bit-symmetric, and sane runs stay finite with P's diagonal >= 0."""
    binary = tmp_path / "fuzz_ins"
    result = subprocess.run([compiler("clang"), "-std=c99", "-O1", "-g", "-fsanitize=fuzzer,address,undefined",
                             "-fno-sanitize-recover=all", *STRICT, f"-I{CSRC}", str(CSRC / "fuzz" / "fuzz_ins.c"),
                             "-o", str(binary), "-lm"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    run = subprocess.run([str(binary), "-runs=30000", "-seed=1", "-max_len=4096", f"-artifact_prefix={tmp_path}/"],
                         capture_output=True, text=True, timeout=900, cwd=tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "Done 30000 runs" in run.stderr
