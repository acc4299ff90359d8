"""Writes the one version string (fusion_altitude/_version.py) into every other place that states it.

The places: the version macros of csrc/fusion_altitude.h, the Arduino library.properties, PlatformIO's
library.json and ESP-IDF's idf_component.yml. CMake reads the macros from the header, Python packaging reads
_version.py, so nothing else carries a copy. Run after changing _version.py; ``--check`` (used by
tests/test_distribution.py) only reports the places that disagree and exits 1 if any does.

    python tools/sync_version.py          # rewrite
    python tools/sync_version.py --check  # verify
"""

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def read_version() -> str:
    """The version string of fusion_altitude/_version.py ("major.minor.patch")."""
    text = (ROOT / "fusion_altitude" / "_version.py").read_text()
    match = re.search(r'^__version__ = "(\d+)\.(\d+)\.(\d+)"$', text, flags=re.M)
    if match is None:
        raise ValueError("fusion_altitude/_version.py: no __version__ = \"major.minor.patch\"")
    return ".".join(match.groups())


def rewrites(version: str) -> dict:
    """Per file (relative to the repository root), the (pattern, replacement) pairs that state the version."""
    major, minor, patch = (int(part) for part in version.split("."))
    return {
        "csrc/fusion_altitude.h": [
            (r"^#define FUSION_ALTITUDE_VERSION_MAJOR \(\d+\)$", f"#define FUSION_ALTITUDE_VERSION_MAJOR ({major})"),
            (r"^#define FUSION_ALTITUDE_VERSION_MINOR \(\d+\)$", f"#define FUSION_ALTITUDE_VERSION_MINOR ({minor})"),
            (r"^#define FUSION_ALTITUDE_VERSION_PATCH \(\d+\)$", f"#define FUSION_ALTITUDE_VERSION_PATCH ({patch})"),
            (r'^#define FUSION_ALTITUDE_VERSION_STRING "[\d.]+"$', f'#define FUSION_ALTITUDE_VERSION_STRING "{version}"'),
            (r"^#define FUSION_ALTITUDE_VERSION \(\d+\)$",
             f"#define FUSION_ALTITUDE_VERSION ({major * 10000 + minor * 100 + patch})"),
        ],
        "packaging/arduino/library.properties": [(r"^version=[\d.]+$", f"version={version}")],
        "library.json": [(r'^  "version": "[\d.]+",$', f'  "version": "{version}",')],
        "idf_component.yml": [(r'^version: "[\d.]+"$', f'version: "{version}"')],
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only report the files that disagree")
    args = parser.parse_args(argv)
    version = read_version()
    stale = []
    for name, pairs in rewrites(version).items():
        path = ROOT / name
        text = path.read_text()
        new = text
        for pattern, replacement in pairs:
            new, count = re.subn(pattern, replacement, new, flags=re.M)
            if count != 1:
                raise ValueError(f"{name}: {count} lines match {pattern!r}, expected 1")
        if new != text:
            stale.append(name)
            if not args.check:
                path.write_text(new)
    for name in stale:
        print(f"{name}: {'differs from' if args.check else 'set to'} version {version}")
    return 1 if (args.check and stale) else 0


if __name__ == "__main__":
    sys.exit(main())
