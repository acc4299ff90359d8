"""Function lengths in the hand-written library: no Python function over 60 lines, no C function over 80.

Python functions are measured with :mod:`ast` (first line of the ``def``, decorators excluded, to the last
line of the body), less the lines of the docstring: documentation is not code, and a reader function's numpydoc
entry for each of its 23 options must not push it to be split (as pylint and ruff count statements, not
docstrings); C functions by a brace scan of the hand-written C (a line that opens a
function at column 0 to the matching closing brace). Generated files (``_c_tables.py``, the ``.pxi``/``.pyi``/
``.pxd`` of ``tools/generate_bindings.py``, the test vectors) and the tests are not measured.

``LONG_PYTHON`` and ``LONG_C`` list the functions that were over the limit when the test was written, with
their length then: a listed function must not grow, and one that has been shortened below the limit must be
taken off its list (the test fails until it is), so the lists only shrink.

Run ``python tests/test_code_shape.py`` for the longest functions of each language.
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path
from typing import Dict, List, Tuple

import pytest

ROOT = Path(__file__).resolve().parents[1]
PYTHON_LIMIT = 60
C_LIMIT = 80

#: Generated Python (tools/generate_bindings.py) and folders that are not the library.
GENERATED_PYTHON = {"fusion_altitude/_c_tables.py"}

#: Functions over the limit when this test was written: "path:qualified name" → lines then.
LONG_PYTHON: Dict[str, int] = {
}
LONG_C: Dict[str, int] = {}


def python_files() -> List[Path]:
    files = sorted((ROOT / "fusion_altitude").rglob("*.py")) + sorted((ROOT / "tools").glob("*.py"))
    return [f for f in files if f.relative_to(ROOT).as_posix() not in GENERATED_PYTHON]


def c_files() -> List[Path]:
    return (sorted((ROOT / "csrc").glob("*.h")) + sorted((ROOT / "csrc" / "firmware").glob("*.[ch]"))
            + sorted((ROOT / "csrc" / "fuzz").glob("*.[ch]")))


def _docstring_lines(function: ast.AST) -> int:
    """The lines a function's docstring spans (0 without one)."""
    first = function.body[0] if function.body else None
    if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
            and isinstance(first.value.value, str)):
        return first.end_lineno - first.lineno + 1
    return 0


def python_function_lengths(path: Path) -> Dict[str, int]:
    """{"path:Class.function": lines} of every function and method of one file."""
    tree = ast.parse(path.read_text(), filename=str(path))
    lengths = {}

    def visit(node, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                name = f"{prefix}{child.name}"
                lengths[f"{path.relative_to(ROOT).as_posix()}:{name}"] = (child.end_lineno - child.lineno + 1
                                                                          - _docstring_lines(child))
                visit(child, name + ".")
            elif isinstance(child, ast.ClassDef):
                visit(child, f"{prefix}{child.name}.")
            else:
                visit(child, prefix)

    visit(tree, "")
    return lengths


#: A function definition's first line: at column 0, a type and a name followed by "(", not a declaration.
_C_FUNCTION = re.compile(r"^(?:static\s+|inline\s+|const\s+)*[A-Za-z_][\w\s\*]*?\b([A-Za-z_]\w*)\s*\(")


def c_function_lengths(path: Path) -> Dict[str, int]:
    """{"path:function": lines} of every function defined in one C file: from the line naming it to the line
    of the closing brace that balances the first opening brace after it (comments and strings removed)."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), path.read_text(), flags=re.S)
    text = re.sub(r"//[^\n]*|\"(?:\\.|[^\"\\\n])*\"|'(?:\\.|[^'\\\n])*'", "\"\"", text)
    lines = text.splitlines()
    lengths = {}
    i = 0
    while i < len(lines):
        match = _C_FUNCTION.match(lines[i])
        if not match or lines[i].startswith(("typedef", "#", "struct", "enum", "union", "return")):
            i += 1
            continue
        j, depth, opened = i, 0, False
        while j < len(lines):
            if not opened and ";" in lines[j] and "{" not in lines[j]:
                break  # a declaration (prototype), not a definition
            depth += lines[j].count("{") - lines[j].count("}")
            opened = opened or "{" in lines[j]
            if opened and depth == 0:
                lengths[f"{path.relative_to(ROOT).as_posix()}:{match.group(1)}"] = j - i + 1
                break
            j += 1
        i = j + 1 if opened else i + 1
    return lengths


def all_lengths(kind: str) -> Dict[str, int]:
    lengths: Dict[str, int] = {}
    for path in (python_files() if kind == "python" else c_files()):
        lengths.update(python_function_lengths(path) if kind == "python" else c_function_lengths(path))
    return lengths


CASES = {"python": (PYTHON_LIMIT, LONG_PYTHON), "c": (C_LIMIT, LONG_C)}


@pytest.mark.parametrize("kind", sorted(CASES))
def test_no_new_function_is_over_the_limit(kind):
    limit, known = CASES[kind]
    over = {name: n for name, n in all_lengths(kind).items() if n > limit and name not in known}
    assert not over, f"{kind} functions over {limit} lines (split them): {over}"


@pytest.mark.parametrize("kind", sorted(CASES))
def test_a_listed_long_function_does_not_grow(kind):
    limit, known = CASES[kind]
    lengths = all_lengths(kind)
    grown = {name: (lengths[name], was) for name, was in known.items() if lengths.get(name, 0) > was}
    assert not grown, f"listed {kind} functions grew (now, then): {grown}"


@pytest.mark.parametrize("kind", sorted(CASES))
def test_a_shortened_long_function_leaves_the_list(kind):
    limit, known = CASES[kind]
    lengths = all_lengths(kind)
    done = sorted(name for name in known if lengths.get(name, 0) <= limit)
    assert not done, f"now within {limit} lines (or gone): take them off LONG_{kind.upper()}: {done}"


def test_the_c_scan_measures_a_known_function():
    """The brace scan finds a function of the observer header and measures it as its lines (a scan that
    found nothing would pass every other test)."""
    lengths = c_function_lengths(ROOT / "csrc" / "fusion_altitude.h")
    name = "csrc/fusion_altitude.h:FusionAltitudeSettingsFromPreset"
    source = (ROOT / "csrc" / "fusion_altitude.h").read_text().splitlines()
    first = next(i for i, line in enumerate(source) if "FusionAltitudeSettingsFromPreset(FusionAltitudeSettings" in line
                 and line.startswith("static"))
    last = next(i for i in range(first, len(source)) if source[i] == "}")
    assert lengths[name] == last - first + 1


def longest(kind: str, count: int = 10) -> List[Tuple[str, int]]:
    return sorted(all_lengths(kind).items(), key=lambda item: -item[1])[:count]


if __name__ == "__main__":
    for kind in ("python", "c"):
        print(f"{kind}: {len(all_lengths(kind))} functions, over {CASES[kind][0]}: "
              f"{sum(n > CASES[kind][0] for n in all_lengths(kind).values())}")
        for name, n in longest(kind, int(sys.argv[1]) if len(sys.argv) > 1 else 10):
            print(f"  {n:5d}  {name}")
