"""Assembles the Arduino library archive: library.properties, src/ with the headers, examples/ with a sketch per
estimator, library.json (PlatformIO), LICENSE; as a folder and as a zip for the Library Manager or "Add .ZIP
Library".

    python tools/make_arduino.py OUT_DIR   # writes OUT_DIR/FusionAltitude/ and OUT_DIR/FusionAltitude-<version>.zip

Run by ``make -C csrc/firmware arduino``; tests/test_arduino.py compiles the sketches of the folder.
"""

import argparse
import json
import shutil
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGING = ROOT / "packaging" / "arduino"
NAME = "FusionAltitude"


def library_version() -> str:
    """The version stated by library.properties (tools/sync_version.py keeps it equal to the package's)."""
    for line in (PACKAGING / "library.properties").read_text().splitlines():
        if line.startswith("version="):
            return line.split("=", 1)[1]
    raise ValueError("packaging/arduino/library.properties has no version= line")


def library_json() -> dict:
    """PlatformIO's manifest for the archive's layout (src/, examples/), from the repository's library.json."""
    manifest = json.loads((ROOT / "library.json").read_text())
    manifest.pop("build", None)
    manifest.pop("export", None)
    manifest["build"] = {"flags": ["-ffp-contract=off"]}
    manifest["examples"] = [{"name": entry["name"], "base": f"examples/{entry['name']}", "files": entry["files"]}
                            for entry in manifest["examples"]]
    return manifest


def assemble(out_dir: Path) -> Path:
    """Writes the library folder OUT_DIR/FusionAltitude (replacing it) and its zip; returns the zip's path."""
    library = out_dir / NAME
    if library.exists():
        shutil.rmtree(library)
    (library / "src").mkdir(parents=True)
    shutil.copy2(PACKAGING / "library.properties", library / "library.properties")
    shutil.copy2(ROOT / "LICENSE", library / "LICENSE")
    (library / "library.json").write_text(json.dumps(library_json(), indent=2) + "\n")
    for header in sorted((ROOT / "csrc").glob("fusion_altitude*.h")):
        shutil.copy2(header, library / "src" / header.name)
    shutil.copytree(PACKAGING / "examples", library / "examples")
    archive = out_dir / f"{NAME}-{library_version()}.zip"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as zipped:
        for path in sorted(library.rglob("*")):
            if path.is_file():
                zipped.write(path, path.relative_to(out_dir).as_posix())
    return archive


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", type=Path)
    args = parser.parse_args(argv)
    args.out_dir.mkdir(parents=True, exist_ok=True)
    print(assemble(args.out_dir))
    return 0


if __name__ == "__main__":
    sys.exit(main())
