"""The C cores' own unit tests (csrc/tests/test_*.c), built the ways firmware
engineers build them: gcc and clang, C99/C11 and as C++, strict warnings as
errors, and under AddressSanitizer + UndefinedBehaviorSanitizer; plus the
headers' no-libm / no-double / no-malloc rules and the Kalman filter's
10^7-step covariance robustness run."""

import importlib.util
import re
import shutil
import subprocess
import sys
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
#: every C test program but the INS's (tests/test_ins_c.py builds test_ins.c) -> the tests it must report passed:
#: one per RUN(...) line of its main
PROGRAMS = {path.name: len(re.findall(r"^    RUN\(", path.read_text(), re.MULTILINE))
            for path in sorted((CSRC / "tests").glob("test_*.c")) if path.name != "test_ins.c"}
#: public headers: copied into firmware, so no libm, no double, no malloc
#: every header, new ones included, except the INS: it needs sqrtf, and tests/test_ins_c.py holds it to that one call
HEADERS = sorted(path.name for path in CSRC.glob("fusion_altitude*.h") if path.name != "fusion_altitude_ins.h")


def compiler(name: str) -> str:
    path = shutil.which(name)
    assert path is not None, f"{name} is not installed (.ci/run installs it with apt)"
    return path


def build(command, source: Path, binary: Path) -> None:
    """Compile one test program warning-free (the tests themselves may use libm; the headers do not)."""
    result = subprocess.run([compiler(command[0]), *command[1:], *STRICT, f"-I{CSRC}", str(source), "-o", str(binary),
                             "-lm"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stderr == "", result.stderr


@pytest.mark.parametrize("program", sorted(PROGRAMS))
@pytest.mark.parametrize("build_name", sorted(BUILDS))
def test_c_unit_tests_pass_warning_free(build_name, program, tmp_path):
    binary = tmp_path / "test_program"
    build(BUILDS[build_name], CSRC / "tests" / program, binary)
    run = subprocess.run([str(binary)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    summary = re.search(r"^(\d+) passed, (\d+) failed$", run.stdout, re.MULTILINE)
    assert summary is not None, run.stdout
    assert int(summary.group(1)) == PROGRAMS[program] and summary.group(2) == "0"
    assert "runtime error" not in run.stderr and "Sanitizer" not in run.stderr


def test_every_c_test_program_runs_tests():
    assert PROGRAMS and all(count > 0 for count in PROGRAMS.values()), PROGRAMS


def test_kalman_covariance_stays_symmetric_psd_over_ten_million_steps_at_1khz(tmp_path):
    """3 x 10^7 float32 steps: all sensors with outages, GPS jumps and ground
    effect; baro only (h and the baro offset unobservable apart, strongly
    correlated, variances growing); baro + GPS with the bias state off. Every
    1000 steps: P finite, bit-symmetric, diagonal >= 0, and the Cholesky
    factorisation (double) of its correlation matrix has no negative pivot."""
    binary = tmp_path / "test_kalman_long"
    build(["gcc", "-std=c99", "-O2"], CSRC / "tests" / "test_kalman.c", binary)
    run = subprocess.run([str(binary), "long"], capture_output=True, text=True, timeout=300)
    print(run.stdout)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "3 of 3 configurations kept P symmetric PSD" in run.stdout
    assert run.stdout.count("10000000 steps") == 3


@pytest.mark.parametrize("header", HEADERS)
def test_header_uses_no_libm_no_double_no_malloc_no_globals(header):
    code = re.sub(r"/\*.*?\*/|//[^\n]*", "", (CSRC / header).read_text(), flags=re.DOTALL)
    assert "#include <math.h>" not in code
    assert "double" not in code
    assert "malloc" not in code
    assert "sqrt" not in code
    assert not re.search(r"^static (?!inline)", code, re.MULTILINE), "a file-scope static variable is a global"


USES = {
    "fusion_altitude.h": (
        "    FusionAltitude a; FusionAltitudeInitialise(&a);\n"
        "    FusionAltitudeSettings s = FusionAltitudeSettingsDefault();\n"
        "    if (FusionAltitudeSettingsFromBandwidth(&s, 1.5f, 0.7f, 0.3f) != FusionAltitudeStatusOk) return 1;\n"
        "    if (FusionAltitudeSettingsValidate(&s, 0.01f) != FusionAltitudeStatusOk) return 1;\n"
        "    (void) FusionAltitudeSetSettings(&a, &s);\n"
        "    (void) FusionAltitudeUpdate(&a, 0.1f, 1.0f, 0.01f);\n"
        "    (void) FusionAltitudeUpdate(&a, 0.1f, FUSION_ALTITUDE_NO_BARO, 0.01f);\n"
        "    return (FusionAltitudeIsReferenceSet(&a) && FusionAltitudeGetAltitude(&a) > 1.0f) ? 0 : 2;\n"),
    "fusion_altitude_kalman.h": (
        "    FusionAltitudeKalman k; FusionAltitudeKalmanInitialise(&k);\n"
        "    FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();\n"
        "    m.baroAltitude = 100.0f; m.rangeDistance = 1.0f; m.gpsAltitude = 150.0f; m.gpsSatellites = 9;\n"
        "    for (int i = 0; i < 10; i++) (void) FusionAltitudeKalmanUpdate(&k, 0.1f, 0.01f, &m);\n"
        "    return FusionAltitudeKalmanGetAltitude(&k) > 99.0f ? 0 : 2;\n"),
}


USES.update({
    "fusion_altitude_complementary.h": (
        "    FusionAltitudeComplementary f; FusionAltitudeComplementaryInitialise(&f);\n"
        "    for (int i = 0; i < 10; i++) (void) FusionAltitudeComplementaryUpdate(&f, 0.1f, 100.0f, 0.01f);\n"
        "    return FusionAltitudeComplementaryGetAltitude(&f) > 99.0f ? 0 : 2;\n"),
    "fusion_altitude_alphabeta.h": (
        "    FusionAltitudeAlphaBeta a; FusionAltitudeAlphaBetaInitialise(&a);\n"
        "    FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();\n"
        "    m.baroAltitude = 100.0f; m.gpsAltitude = 100.5f;\n"
        "    for (int i = 0; i < 10; i++) (void) FusionAltitudeAlphaBetaUpdate(&a, 0.1f, 0.01f, &m);\n"
        "    return FusionAltitudeAlphaBetaGetAltitude(&a) > 99.0f ? 0 : 2;\n"),
    "fusion_altitude_sweep.h": (
        "    const float kh[2] = {2.4f, 0.8f}, kv[2] = {2.88f, 0.32f}, kb[2] = {0.675f, 0.025f};\n"
        "    float h[2], v[2], b[2], r[2], accel[8] = {0}, baro[8] = {100, 100, 100, 100, 100, 100, 100, 100};\n"
        "    const float dt = 0.01f; size_t bad = 0;\n"
        "    FusionAltitudeSweep s = {2, kh, kv, kb, h, v, b, r, 0.5f, 2.0f, 0.0f, -1.0f, 0.0f, 0, 0, false, false, 0, 0};\n"
        "    FusionAltitudeSweepInitialise(&s);\n"
        "    s.gapPeriod = 0.5f;\n"
        "    if (FusionAltitudeSweepUpdate(&s, accel, baro, &dt, 0, 8, NULL, NULL, &bad) != FusionAltitudeStatusOk) return 1;\n"
        "    return h[0] > 99.0f && h[1] > 99.0f ? 0 : 2;\n"),
    "fusion_altitude_rocket.h": (
        "    FusionAltitudeRocket r;\n"
        "    const FusionAltitudeRocketSettings s = FusionAltitudeRocketSettingsDefault();\n"
        "    if (FusionAltitudeRocketInitialise(&r, &s) != FusionAltitudeRocketStatusOk) return 1;\n"
        "    for (int i = 0; i < 10; i++) (void) FusionAltitudeRocketUpdate(&r, 0.0f, 100.0f, 0.01f);\n"
        "    return FusionAltitudeRocketGetHeight(&r) > -1.0f ? 0 : 2;\n"),
})
#: the deprecated header name (one release) includes fusion_altitude_rocket.h: the same program
USES["fusion_altitude_flight.h"] = USES["fusion_altitude_rocket.h"]


def _estimator_modules() -> dict:
    """The generator's MODULES (tools/generate_bindings.py): estimator name → (header, C prefix, structs)."""
    if "generate_bindings" not in sys.modules:  # registered before it runs: its dataclasses look themselves up
        spec = importlib.util.spec_from_file_location("generate_bindings", ROOT / "tools" / "generate_bindings.py")
        sys.modules["generate_bindings"] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules["generate_bindings"])
    return sys.modules["generate_bindings"].MODULES


#: estimator → its header, for the estimators held to no libm (all but the INS): csrc/firmware/sized_<name>.c
#: holds an out-of-line copy of every public function of the header, so linking it without libm checks them all
FIRMWARE_HEADERS = {name: header for name, (header, *_) in _estimator_modules().items() if header in HEADERS}


def test_every_header_has_a_no_libm_link_program():
    assert sorted(set(USES) | set(FIRMWARE_HEADERS.values())) == HEADERS


@pytest.mark.parametrize("name", sorted(FIRMWARE_HEADERS))
def test_every_public_function_of_an_estimator_links_without_libm(name, tmp_path):
    (tmp_path / "main.c").write_text("int main(void) { return 0; }\n")
    result = subprocess.run([compiler("gcc"), "-std=c99", "-O0", *STRICT, f"-I{CSRC}",
                             str(CSRC / "firmware" / f"sized_{name}.c"), str(tmp_path / "main.c"),
                             "-o", str(tmp_path / "firmware"), "-nodefaultlibs", "-lc"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


@pytest.mark.parametrize("header", sorted(USES))
def test_header_links_without_libm(header, tmp_path):
    source = tmp_path / "use.c"
    source.write_text(f'#include "{header}"\nint main(void) {{\n{USES[header]}}}\n')
    binary = tmp_path / "use"
    result = subprocess.run([compiler("gcc"), "-std=c99", "-O0", *STRICT, f"-I{CSRC}", str(source), "-o", str(binary),
                             "-nodefaultlibs", "-lc"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert subprocess.run([str(binary)]).returncode == 0


#: every header, the INS included: each turns contraction off for its own functions under gcc's GNU modes
ALL_HEADERS = sorted(path.name for path in CSRC.glob("fusion_altitude*.h"))
#: x86 fused multiply-add mnemonics (vfmadd132ss, vfnmsub231ps, vfmaddsub..., and the FMA4 forms vfmaddss)
FMA = re.compile(r"\bvfn?m(?:add|sub)\w*")


def fma_functions(source: str, tmp_path: Path) -> tuple:
    """Compile source as vendor IDEs do (gcc -std=gnu11 -O2, FMA contraction on by default) with -mfma, keeping every
    static inline function, and return (functions emitted, {function: FMA mnemonics found in it})."""
    (tmp_path / "fma.c").write_text(source)
    subprocess.run([compiler("gcc"), "-std=gnu11", "-O2", "-mfma", "-fkeep-inline-functions", f"-I{CSRC}", "-c",
                    str(tmp_path / "fma.c"), "-o", str(tmp_path / "fma.o")], check=True)
    listing = subprocess.run(["objdump", "-d", "--no-show-raw-insn", str(tmp_path / "fma.o")], check=True,
                             capture_output=True, text=True).stdout
    functions, found, name = [], {}, None
    for line in listing.splitlines():
        header = re.match(r"^[0-9a-f]+ <(.+)>:$", line)
        if header:
            name = header.group(1)
            functions.append(name)
        elif name is not None and FMA.search(line):
            found.setdefault(name, []).append(FMA.search(line).group(0))
    return functions, found


def test_fma_check_finds_a_contracted_multiply_add(tmp_path):
    """The check below can fail: a plain a * b + c outside the headers' pragmas is contracted under these flags."""
    functions, found = fma_functions("float madd(float a, float b, float c);\n"
                                     "float madd(float a, float b, float c) { return a * b + c; }\n", tmp_path)
    assert functions == ["madd"] and list(found) == ["madd"], (functions, found)


@pytest.mark.parametrize("header", ALL_HEADERS)
def test_header_functions_have_no_fma_under_gcc_gnu11_mfma(header, tmp_path):
    """gcc -std=gnu11 -O2 -mfma on x86: no function of the header contains a fused multiply-add instruction (the
    header's #pragma GCC optimize("fp-contract=off") block), so the bits do not depend on the caller's -std. A
    function defined after the header must still be contracted: the pragma does not leak into user code."""
    functions, found = fma_functions(f'#include "{header}"\n'
                                     "float user_madd(float a, float b, float c);\n"
                                     "float user_madd(float a, float b, float c) { return a * b + c; }\n", tmp_path)
    ours = [name for name in functions if name.startswith("FusionAltitude")]
    assert len(ours) >= 5, functions
    assert list(found) == ["user_madd"], f"{header}: FMA in {found}"
