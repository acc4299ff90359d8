"""The README and the docs show what their commands print: every block after a ``<!-- output: COMMAND -->``
line is COMMAND's output (stdout and stderr as a terminal shows them, stage times left out), run here.

``FUSION_ALTITUDE_UPDATE_README=1 pytest tests/test_readme.py`` rewrites the blocks from the commands.
"""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
BLOCK = re.compile(r"^<!-- output: (.*?) -->\n```\n(.*?)^```\n", re.MULTILINE | re.DOTALL)
#: Lines that vary from run to run (stage times on stderr) are left out of the comparison.
VARYING = re.compile(r"^\w+: \d+\.\d\d s$")


def shared_data() -> Path:
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


def output_of(command: str) -> str:
    """What ``command`` (a ``fusion-altitude`` line) prints, run from a folder where ``../shared/data`` is the
    shared data, as in the README."""
    argv = shlex.split(command)
    assert argv[0] == "fusion-altitude"
    argv = [str(shared_data() / arg[len("../shared/data/"):]) if arg.startswith("../shared/data/") else arg
            for arg in argv[1:]]
    environment = dict(os.environ, PYTHONUNBUFFERED="1", COLUMNS="120")
    completed = subprocess.run([sys.executable, "-m", "fusion_altitude", *argv], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=600, env=environment, cwd=ROOT)
    assert completed.returncode == 0, completed.stdout[-2000:]
    lines = [line.rstrip() for line in completed.stdout.splitlines() if not VARYING.match(line)]
    return "\n".join(lines).replace(str(shared_data()) + os.sep, "../shared/data/") + "\n"


PAGES = [README] + sorted((ROOT / "docs").glob("*.md"))
BLOCKS = [(page, command, shown) for page in PAGES for command, shown in BLOCK.findall(page.read_text(encoding="utf-8"))]


def test_the_readme_has_command_outputs_and_stays_short():
    assert len([page for page, _, _ in BLOCKS if page == README]) >= 2
    assert len(README.read_text(encoding="utf-8").splitlines()) <= 250


@pytest.mark.parametrize("page,command,shown", BLOCKS,
                         ids=[f"{page.name}: {command}" for page, command, _ in BLOCKS])
def test_a_block_is_what_its_command_prints(page, command, shown):
    printed = output_of(command)
    if os.environ.get("FUSION_ALTITUDE_UPDATE_README"):
        text = page.read_text(encoding="utf-8")
        page.write_text(text.replace(f"<!-- output: {command} -->\n```\n{shown}```\n",
                                     f"<!-- output: {command} -->\n```\n{printed}```\n"), encoding="utf-8")
        return
    assert printed == shown
