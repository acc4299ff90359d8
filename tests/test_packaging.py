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


def test_type_stubs_and_marker_are_installed():
    package = importlib.resources.files("fusion_altitude")
    assert (package / "py.typed").is_file()
    assert (package / "_observer.pyi").is_file()


def test_version_matches_the_c_header():
    major, minor, patch = (int(part) for part in fusion_altitude.__version__.split("."))
    assert _observer.C_VERSION == major * 10000 + minor * 100 + patch
