"""What pip installs: version, entry points, stubs, and constants that match the C header."""

import importlib.resources
import subprocess
import sys

import fusion_altitude
from fusion_altitude import _observer


def test_module_prints_its_version(tmp_path):
    # run outside the checkout, so that the installed package (with its extension) is imported
    result = subprocess.run([sys.executable, "-m", "fusion_altitude", "--version"], capture_output=True, text=True,
                            cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert fusion_altitude.__version__ in result.stdout


def test_status_enum_matches_the_c_header():
    assert {status.name: int(status) for status in fusion_altitude.Status} == _observer.C_STATUS_VALUES


def test_status_messages_come_from_the_c_header():
    assert _observer.status_message(fusion_altitude.Status.INVALID_DT) == "dt must be finite and > 0"


def test_gravity_is_standard_gravity_in_both_layers():
    assert fusion_altitude.GRAVITY == 9.80665
    assert _observer.C_GRAVITY == float.__new__(float, __import__("numpy").float32(9.80665))


def _binding_modules():
    """The compiled binding modules that pip installs in ``fusion_altitude/_core`` (not the shared ``_common`` and
    ``_estimator``): read from the installed package, so that the list cannot drift from the build."""
    import importlib.machinery

    import os

    import fusion_altitude._core

    suffixes = tuple(importlib.machinery.EXTENSION_SUFFIXES)
    names = {name.split(".")[0] for folder in fusion_altitude._core.__path__  # with the installed copy's, if added
             for name in os.listdir(folder) if name.endswith(suffixes)}
    return sorted(names - {"_common", "_estimator"})


BINDINGS = _binding_modules()


def test_every_binding_module_is_installed():
    assert {"_observer", "_kalman", "_complementary", "_alphabeta", "_ins", "_rocket", "_sweep"} <= set(BINDINGS)


def test_type_stubs_and_marker_are_installed():
    assert (importlib.resources.files("fusion_altitude") / "py.typed").is_file()
    package = importlib.resources.files("fusion_altitude._core")
    for binding in BINDINGS:
        assert (package / f"{binding}.pyi").is_file(), binding


def test_type_stubs_declare_every_public_name_and_method():
    import importlib
    import re
    package = importlib.resources.files("fusion_altitude._core")
    for binding in BINDINGS:
        module = importlib.import_module(f"fusion_altitude._core.{binding}")
        stub = (package / f"{binding}.pyi").read_text()
        for name in (n for n in dir(module) if not n.startswith("_")):
            value = getattr(module, name)
            defined_here = callable(value) and getattr(value, "__module__", None) == module.__name__
            if not (defined_here or name.startswith("C_") or name == "BLOCK"):
                continue  # imported from elsewhere
            assert re.search(rf"\b{name}\b", stub), f"{binding}.pyi lacks {name}"
            if isinstance(value, type):
                for member in (m for m in vars(value) if not m.startswith("_")):
                    assert re.search(rf"def {member}\b", stub), f"{binding}.pyi lacks {name}.{member}"


def test_version_matches_the_c_header():
    major, minor, patch = (int(part) for part in fusion_altitude.__version__.split("."))
    assert _observer.C_VERSION == major * 10000 + minor * 100 + patch


BLOCK_EXTENSIONS = """
import importlib.abc, sys
class NoExtension(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.startswith("fusion_altitude._") and name.split(".")[-1][1:] in {b[1:] for b in BINDINGS + ["_estimator"]}:
            raise ImportError(f"{name}: blocked, as if the extension were not built")
sys.meta_path.insert(0, NoExtension())
"""


def test_the_reference_imports_and_runs_without_the_compiled_extension():
    code = f"BINDINGS = {BINDINGS!r}\n" + BLOCK_EXTENSIONS + """
import fusion_altitude.reference as ref
estimator = ref.AltitudeEstimator(ref.AltitudeSettings.preset("fixed_wing"))
estimator.update(0.1, 10.0, 0.01)
ref.KalmanEstimator().update(0.1, 0.01, baro_altitude=5.0)
import fusion_altitude
try:
    fusion_altitude.AltitudeEstimator
except ImportError as error:
    print("binding:", error)
print("reference:", estimator.altitude)
"""
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "reference: 10.0" in result.stdout
    assert "binding: fusion_altitude.AltitudeEstimator needs the compiled extension" in result.stdout


def test_the_license_is_an_spdx_expression_not_a_deprecated_table():
    # setuptools >= 77 warns "`project.license` as a TOML table is deprecated" on every build of {text = "MIT"}
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "pyproject.toml").read_text()
    assert re.search(r'^license = "MIT"$', text, re.MULTILINE)
    assert re.search(r'^license-files = \["LICENSE"\]$', text, re.MULTILINE)
    assert '"setuptools>=77"' in text  # the first setuptools that reads an SPDX license and license-files
    assert "License ::" not in text  # setuptools refuses a license classifier next to an SPDX expression
