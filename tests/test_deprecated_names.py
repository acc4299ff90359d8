"""The rocket estimator's former ``flight`` names work for one release (issue 22, item 5; CHANGELOG,
"Deprecated"): each old module name is the new module and warns, pickles that name an old module load, and
``#include "fusion_altitude_flight.h"`` compiles warning-free and gives the same API as the new header."""

import importlib
import pickle
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import fusion_altitude as fa
import fusion_altitude.reference as ref

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"

#: old name → new name (fusion_altitude/_aliases.py, DEPRECATED_MODULES)
OLD_MODULES = {
    "fusion_altitude.reference.flight": "fusion_altitude.reference.rocket",
    "fusion_altitude._core._flight": "fusion_altitude._core._rocket",
    "fusion_altitude._core._flight_glue": "fusion_altitude._core._rocket_glue",
    "fusion_altitude._flight": "fusion_altitude._core._rocket",
    "fusion_altitude._flight_glue": "fusion_altitude._core._rocket_glue",
}

STRICT = ["-Wall", "-Wextra", "-Wpedantic", "-Wconversion", "-Wdouble-promotion", "-Wshadow", "-Werror"]
COMPILERS = {"gcc-c99": ["gcc", "-std=c99"], "g++-c++11": ["g++", "-x", "c++", "-std=c++11"],
             "clang-c99": ["clang", "-std=c99"]}

#: a rocket on the pad, then 3 s of boost: prints the height and velocity after each second
PROGRAM = """#include <stdio.h>
#include INCLUDES
int main(void) {
    FusionAltitudeRocket rocket;
    const FusionAltitudeRocketSettings settings = FusionAltitudeRocketSettingsDefault();
    if (FusionAltitudeRocketInitialise(&rocket, &settings) != FusionAltitudeRocketStatusOk) return 1;
    for (int i = 0; i < 1300; i++) {
        const float t = 0.01f * (float) (i - 1000);
        const float accel = i < 1000 ? 0.0f : 50.0f;
        const float baro = i < 1000 ? 100.0f : 100.0f + 25.0f * t * t;
        if (FusionAltitudeRocketUpdate(&rocket, accel, baro, 0.01f) != FusionAltitudeRocketStatusOk) return 2;
        if (i % 100 == 99) {
            printf("%.9g %.9g\\n", (double) FusionAltitudeRocketGetHeight(&rocket),
                   (double) FusionAltitudeRocketGetVerticalVelocity(&rocket));
        }
    }
    return 0;
}
"""


def _import_fresh(name, monkeypatch):
    monkeypatch.delitem(sys.modules, name, raising=False)
    return importlib.import_module(name)


@pytest.mark.parametrize("old", sorted(OLD_MODULES))
def test_an_old_flight_module_name_warns_and_is_the_new_module(old, monkeypatch):
    with pytest.warns(DeprecationWarning, match=rf"{old} is deprecated.*import {OLD_MODULES[old]}"):
        module = _import_fresh(old, monkeypatch)
    assert module is importlib.import_module(OLD_MODULES[old])


def test_the_old_reference_module_gives_the_same_classes_as_the_package(monkeypatch):
    monkeypatch.delitem(sys.modules, "fusion_altitude.reference.flight", raising=False)
    with pytest.warns(DeprecationWarning):
        import fusion_altitude.reference.flight as flight  # noqa: F401 (the deprecated name)
    assert flight.RocketEstimator is ref.RocketEstimator and flight.RocketSettings is fa.RocketSettings


def test_the_deprecation_warning_points_at_the_importing_line(monkeypatch):
    monkeypatch.delitem(sys.modules, "fusion_altitude.reference.flight", raising=False)
    with pytest.warns(DeprecationWarning) as record:
        import fusion_altitude.reference.flight  # noqa: F401 (the deprecated name)
    assert record[0].filename == __file__


def test_the_new_names_import_without_a_deprecation_warning():
    code = ("import numpy, warnings\n"
            "warnings.simplefilter('error', DeprecationWarning)\n"
            "import fusion_altitude, fusion_altitude.reference.rocket, fusion_altitude._core._rocket\n"
            "import fusion_altitude._core._rocket_glue, fusion_altitude.rocket\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stderr


def test_a_pickle_naming_the_old_reference_module_loads_with_a_warning(monkeypatch):
    settings = ref.RocketSettings(launch_accel=30.0)
    new = pickle.dumps(settings)
    old = new.replace(b"fusion_altitude.reference.rocket", b"fusion_altitude.reference.flight")
    assert old != new
    monkeypatch.delitem(sys.modules, "fusion_altitude.reference.flight", raising=False)
    with pytest.warns(DeprecationWarning):
        assert pickle.loads(old) == settings


def test_a_pickle_naming_the_old_binding_module_loads_with_a_warning_and_resumes_identically(monkeypatch):
    rocket = fa.RocketEstimator()
    for _ in range(300):
        rocket.update(0.0, 100.0, 0.01)
    new = pickle.dumps(rocket)
    old = new.replace(b"fusion_altitude._core._rocket", b"fusion_altitude._core._flight")
    assert old != new
    for name in ("fusion_altitude._core._flight", "fusion_altitude._core._flight_glue"):
        monkeypatch.delitem(sys.modules, name, raising=False)
    with pytest.warns(DeprecationWarning):
        resumed = pickle.loads(old)
    assert type(resumed) is fa.RocketEstimator
    for step in range(100):
        rocket.update(40.0, 100.0 + 0.2 * step, 0.01)
        resumed.update(40.0, 100.0 + 0.2 * step, 0.01)
    assert (resumed.height, resumed.vertical_velocity) == (rocket.height, rocket.vertical_velocity)


def _run_c(compiler, includes, tmp_path):
    path = shutil.which(compiler[0])
    assert path is not None, f"{compiler[0]} is not installed (.ci/run installs it with apt)"
    source, binary = tmp_path / "use.c", tmp_path / "use"
    source.write_text(PROGRAM.replace("#include INCLUDES", "\n".join(f'#include "{h}"' for h in includes)))
    build = subprocess.run([path, *compiler[1:], "-O2", *STRICT, f"-I{CSRC}", str(source), "-o", str(binary)],
                           capture_output=True, text=True)
    assert build.returncode == 0 and build.stderr == "", build.stderr
    run = subprocess.run([str(binary)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stdout + run.stderr
    return run.stdout


@pytest.mark.parametrize("compiler", sorted(COMPILERS))
def test_the_old_header_name_compiles_warning_free_and_gives_the_new_headers_api(compiler, tmp_path):
    old = _run_c(COMPILERS[compiler], ["fusion_altitude_flight.h"], tmp_path)
    assert old == _run_c(COMPILERS[compiler], ["fusion_altitude_rocket.h"], tmp_path)
    assert len(old.splitlines()) == 13


def test_the_old_and_the_new_header_together_compile_warning_free(tmp_path):
    _run_c(COMPILERS["gcc-c99"], ["fusion_altitude_flight.h", "fusion_altitude_rocket.h"], tmp_path)


def test_the_old_header_declares_nothing_of_its_own():
    text = (CSRC / "fusion_altitude_flight.h").read_text()
    code = [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith(("/*", "*"))]
    assert code == ['#include "fusion_altitude_rocket.h"']
