"""The estimator lines of ``fusion_altitude/__init__.py`` and ``fusion_altitude/reference/__init__.py`` are written
by ``tools/generate_bindings.py`` from its ``MODULES`` (``tools/package_init.py``), between marker comments, as
plain imports and ``__all__`` entries; the rest of both files is hand-written."""

import re
import sys
from pathlib import Path

import pytest

import fusion_altitude
import fusion_altitude.reference

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import generate_bindings  # noqa: E402  (tools/)
import package_init  # noqa: E402  (tools/)

EXPORTS = package_init.estimator_exports(generate_bindings.MODULES, generate_bindings.ESTIMATORS,
                                         generate_bindings.SETTINGS_CLASSES, generate_bindings.ENUM_NAMES)


def test_every_estimator_of_the_generator_exports_its_estimator_settings_batch_and_status():
    assert [e.module for e in EXPORTS] == list(generate_bindings.MODULES)
    kalman = next(e for e in EXPORTS if e.module == "kalman")
    assert kalman.names() == ["KalmanEstimator", "KalmanSettings", "KalmanBatch", "KalmanStatus"]
    observer = next(e for e in EXPORTS if e.module == "observer")
    assert observer.names() == ["AltitudeEstimator", "AltitudeSettings", "AltitudeBatch", "Status"]


@pytest.mark.parametrize("package", [fusion_altitude, fusion_altitude.reference], ids=["package", "reference"])
def test_the_generated_names_are_public_and_importable(package):
    for exports in EXPORTS:
        for name in exports.names():
            assert name in package.__all__, (package.__name__, name)
            assert getattr(package, name).__name__ == name


def test_the_package_and_the_reference_export_the_same_estimator_settings_batch_and_status_objects():
    for exports in EXPORTS:
        for name in (exports.settings, exports.batch, exports.status):
            assert getattr(fusion_altitude, name) is getattr(fusion_altitude.reference, name), name
        assert getattr(fusion_altitude.reference, exports.estimator).__module__ == \
            f"fusion_altitude.reference.{exports.module}"


def test_the_committed_init_files_are_what_the_generator_writes():
    for path, text in package_init.generate(ROOT / "fusion_altitude", EXPORTS).items():
        assert path.read_text() == text, f"run python tools/generate_bindings.py ({path.relative_to(ROOT)})"


def test_the_generated_lines_are_static_imports_and_all_entries():
    text = (ROOT / "fusion_altitude" / "__init__.py").read_text()
    assert "from ._core._kalman import KalmanEstimator\n" in text
    assert "from .reference.kalman import KalmanSettings\n" in text
    assert re.search(r'^__all__ \+= \[\n    "AltitudeEstimator", "AltitudeSettings", "AltitudeBatch", "Status",$',
                     text, re.M)


def test_filling_a_block_replaces_only_the_lines_between_its_markers():
    marker = package_init._MARKER.format(block="names")
    end = package_init._END.format(block="names")
    text = f"x = 1\ntry:\n    {marker}\n    stale = 0\n    {end}\nexcept ImportError:\n    pass\n"
    filled = package_init.fill_blocks(text, {"names": "a = 1\n\nb = 2"}, Path("demo.py"))
    assert filled == f"x = 1\ntry:\n    {marker}\n    a = 1\n\n    b = 2\n    {end}\nexcept ImportError:\n    pass\n"


def test_a_file_without_the_markers_of_a_block_stops_the_generator_naming_the_block():
    with pytest.raises(SystemExit, match="'estimator names'"):
        package_init.fill_blocks("__all__ = []\n", {"estimator names": "__all__ += []"}, Path("demo.py"))


def test_a_long_import_is_wrapped_in_parentheses_under_120_characters():
    names = [f"Name{i:02d}Status" for i in range(12)]
    line = package_init.import_line("._core._c_tables", names)
    assert line.startswith("from ._core._c_tables import (\n") and line.endswith(")")
    assert max(len(row) for row in line.splitlines()) <= 120
    assert re.findall(r"Name\d\dStatus", line) == names
