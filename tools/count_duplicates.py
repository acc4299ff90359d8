"""Count the duplicate pairs of the hand-written library, as docs/architecture.md reports them (issue 22, item 7).

Copies the tracked files of ``fusion_altitude/`` and ``csrc/`` (generated files left out: ``_c_tables.py``,
``_*_fields.pxi``, ``*.pyi``, ``c*.pxd``, the Cython ``.c`` output, ``csrc/tests/``, fuzz corpora and findings)
into a temporary folder, runs the ``duplicates`` command of the tool library over it and sorts each pair:
a *library* pair has both sides in ``fusion_altitude/`` or ``csrc/*.h``; any other pair (a side in
``csrc/firmware/`` or ``csrc/fuzz/``) is a *firmware and fuzz* pair.

Usage: ``python tools/count_duplicates.py [--list] [--seconds 120]``.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GENERATED = re.compile(
    r"(^fusion_altitude/.*_c_tables\.py$|_fields\.pxi$|\.pyi$|/c[a-z_]*\.pxd$|^fusion_altitude/.*\.c$|"
    r"^csrc/tests/|/corpus|/findings|/crashes)")


def tracked_library_files() -> list:
    """The tracked, hand-written files of ``fusion_altitude/`` and ``csrc/`` (paths relative to the root)."""
    out = subprocess.run(["git", "ls-files", "fusion_altitude", "csrc"], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout.split()
    return [p for p in out if not GENERATED.search(p)]


def is_library(path: str) -> bool:
    """Whether a side of a pair is in the library proper (not a firmware or fuzz harness)."""
    return path.startswith("fusion_altitude/") or (path.startswith("csrc/") and path.count("/") == 1)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", action="store_true", help="print every pair, not only the counts")
    parser.add_argument("--seconds", type=int, default=120)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        for rel in tracked_library_files():
            dest = Path(tmp) / rel
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(ROOT / rel, dest)
        out = subprocess.run(["duplicates", "--most", "200", "--seconds", str(args.seconds)], cwd=tmp,
                             check=True, capture_output=True, text=True).stdout
    rows = [line for line in out.splitlines() if re.match(r"^D\d+ ", line)]
    library = [r for r in rows if all(is_library(side.split(":")[0]) for side in r.split()[1:4:2])]
    other = [r for r in rows if r not in library]
    def thin(rs):
        return sum("boilerplate" in r for r in rs)
    print(f"library pairs: {len(library)} ({len(library) - thin(library)} not boilerplate)")
    print(f"firmware and fuzz pairs: {len(other)} ({len(other) - thin(other)} not boilerplate)")
    if args.list:
        print("\n".join(["", "# library"] + library + ["", "# firmware and fuzz"] + other))
    tail = [line for line in out.splitlines() if not re.match(r"^D\d+ ", line)]
    print("\n".join(tail), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
