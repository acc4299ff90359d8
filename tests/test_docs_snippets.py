"""Every code block of README.md and docs/*.md runs as pasted.

Python blocks of one page run in order in one fresh interpreter, as a reader
pasting them into one session would (a later block may use the names of an
earlier one); C blocks compile warning-free under strict flags; ``sh`` blocks'
``fusion-altitude`` lines are parsed by the real parser (and the ones that
need no input file are run). A missing compiler fails, never skips.
"""

import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from fusion_altitude.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", re.MULTILINE | re.DOTALL)


def blocks(page: Path, language: str):
    return [body for lang, body in FENCE.findall(page.read_text(encoding="utf-8")) if lang == language]


def _page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


PYTHON_PAGES = [page for page in PAGES if blocks(page, "python")]
C_BLOCKS = [(page, k, body) for page in PAGES for k, body in enumerate(blocks(page, "c"))]
SH_LINES = [(page, line) for page in PAGES for body in blocks(page, "sh")
            for line in body.replace("\\\n", " ").splitlines()  # a trailing backslash continues the line
            if line.strip().startswith("fusion-altitude ")]


def test_the_pages_have_snippets_to_test():
    assert PYTHON_PAGES and C_BLOCKS and SH_LINES


@pytest.mark.parametrize("page", PYTHON_PAGES, ids=_page_id)
def test_python_blocks_of_a_page_run_in_order(page, tmp_path):
    script = "\n\n".join(blocks(page, "python"))
    completed = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True,
                               timeout=600)
    assert completed.returncode == 0, f"{page.name}:\n{completed.stderr[-3000:]}"


@pytest.mark.parametrize("page,index,body", C_BLOCKS, ids=[f"{_page_id(p)}[{k}]" for p, k, _ in C_BLOCKS])
def test_c_block_compiles_without_warnings(page, index, body, tmp_path):
    compiler = shutil.which("gcc") or shutil.which("cc")
    assert compiler, "a C compiler is needed for this test"
    source = tmp_path / "snippet.c"
    source.write_text(body)
    completed = subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-Wshadow",
                                "-I", str(ROOT / "csrc"), "-c", str(source), "-o", str(tmp_path / "snippet.o")],
                               capture_output=True, text=True)
    assert completed.returncode == 0, f"{page.name} C block {index}:\n{completed.stderr}"


def _argv(line: str):
    command = line.split("#", 1)[0]
    return shlex.split(command)[1:]


@pytest.mark.parametrize("page,line", SH_LINES, ids=[f"{_page_id(p)}: {line[:60]}" for p, line in SH_LINES])
def test_shell_command_lines_parse(page, line):
    build_parser().parse_args(_argv(line))


@pytest.mark.parametrize("line", sorted({line for _, line in SH_LINES
                                         if _argv(line)[0] in ("demo", "tune") and "--plot" not in line}))
def test_shell_commands_that_need_no_file_run(line, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # --export writes into the working folder
    assert main(_argv(line)) in (0, 1)  # tune returns 1 for an unstable choice, by design
    assert "Traceback" not in capsys.readouterr().err
