"""The C core's own unit tests (csrc/tests/test_observer.c, test_sweep.c), built the ways
firmware engineers build it: gcc and clang, C99 and as C++, strict warnings as
errors, and once under AddressSanitizer + UndefinedBehaviorSanitizer."""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"
STRICT = ["-Wall", "-Wextra", "-Wpedantic", "-Wconversion", "-Wdouble-promotion", "-Wshadow", "-Werror"]
SANITIZE = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer", "-g"]

BUILDS = {
    "gcc-c99": ["gcc", "-std=c99", "-O2"],
    "gcc-c11": ["gcc", "-std=c11", "-O2"],
    "clang-c99": ["clang", "-std=c99", "-O2"],
    "g++-c++11": ["g++", "-x", "c++", "-std=c++11", "-O2"],
    "clang++-c++17": ["clang++", "-x", "c++", "-std=c++17", "-O2"],
    "clang-asan-ubsan": ["clang", "-std=c99", "-O1", *SANITIZE],
    "gcc-asan-ubsan": ["gcc", "-std=c99", "-O1", *SANITIZE],
    "gcc-multiversion": ["gcc", "-std=c99", "-O2", "-DFUSION_ALTITUDE_SWEEP_MULTIVERSION"],
}
#: test program -> the least number of tests it must report passed
PROGRAMS = {"test_observer.c": 16, "test_sweep.c": 4}


def compiler(name: str) -> str:
    path = shutil.which(name)
    assert path is not None, f"{name} is not installed (.ci/run installs it with apt)"
    return path


@pytest.mark.parametrize("program", sorted(PROGRAMS))
@pytest.mark.parametrize("build", sorted(BUILDS))
def test_c_unit_tests_pass_warning_free(build, program, tmp_path):
    command = BUILDS[build]
    binary = tmp_path / "test_program"
    compile_result = subprocess.run(
        [compiler(command[0]), *command[1:], *STRICT, f"-I{CSRC}", str(CSRC / "tests" / program),
         "-o", str(binary)],
        capture_output=True, text=True)
    assert compile_result.returncode == 0, compile_result.stderr
    assert compile_result.stderr == "", compile_result.stderr
    run = subprocess.run([str(binary)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    summary = re.search(r"^(\d+) passed, (\d+) failed$", run.stdout, re.MULTILINE)
    assert summary is not None, run.stdout
    assert int(summary.group(1)) >= PROGRAMS[program] and summary.group(2) == "0"
    assert "runtime error" not in run.stderr and "Sanitizer" not in run.stderr


def test_header_uses_no_libm_and_no_double():
    header = (CSRC / "fusion_altitude.h").read_text()
    code = re.sub(r"/\*.*?\*/|//[^\n]*", "", header, flags=re.DOTALL)
    assert "#include <math.h>" not in code
    assert "double" not in code
    assert "malloc" not in code


def test_header_links_without_libm(tmp_path):
    source = tmp_path / "use.c"
    source.write_text(
        '#include "fusion_altitude.h"\n'
        "int main(void) {\n"
        "    FusionAltitude a; FusionAltitudeInitialise(&a);\n"
        "    FusionAltitudeSettings s;\n"
        "    if (FusionAltitudeSettingsFromBandwidth(&s, 1.5f, 0.7f, 0.3f) != FusionAltitudeStatusOk) return 1;\n"
        "    if (FusionAltitudeSettingsValidate(&s, 0.01f) != FusionAltitudeStatusOk) return 1;\n"
        "    (void) FusionAltitudeSetSettings(&a, &s);\n"
        "    (void) FusionAltitudeUpdate(&a, 0.1f, 1.0f, 0.01f);\n"
        "    (void) FusionAltitudeUpdate(&a, 0.1f, FUSION_ALTITUDE_NO_BARO, 0.01f);\n"
        "    return (FusionAltitudeIsReferenceSet(&a) && FusionAltitudeGetAltitude(&a) > 1.0f) ? 0 : 2;\n"
        "}\n")
    binary = tmp_path / "use"
    result = subprocess.run([compiler("gcc"), "-std=c99", "-O0", *STRICT, f"-I{CSRC}", str(source), "-o", str(binary),
                             "-nodefaultlibs", "-lc"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert subprocess.run([str(binary)]).returncode == 0
