"""The estimator lines of ``fusion_altitude/__init__.py`` and ``fusion_altitude/reference/__init__.py``, written by
``tools/generate_bindings.py`` from its ``MODULES`` (so a new estimator is one row there, not three hand-edited
lists in each file).

Each estimator of ``MODULES`` exports four names: its estimator class (``ESTIMATORS``), its settings class
(``SETTINGS_CLASSES``, from ``fusion_altitude.reference.<module>``), its batch result (the settings class's name
with ``Batch`` for ``Settings``, from ``fusion_altitude._core._<module>_glue``) and its status enum (the Python name
of the C enum ``<prefix>Status``, from ``fusion_altitude._core._c_tables``). The lines are plain static imports and
``__all__`` entries, so IDEs, type checkers and the API reference follow them; they sit between marker comments::

    # generated: <block> -- written by tools/generate_bindings.py from its MODULES; do not edit
    ...
    # end generated: <block>

and everything outside the markers stays hand-written (the other public names, the fallback without the compiled
extension). ``python tools/generate_bindings.py --check`` fails when a block is stale or its markers are missing.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Mapping

_MARKER = "# generated: {block} -- written by tools/generate_bindings.py from its MODULES; do not edit"
_END = "# end generated: {block}"
_WIDTH = 120


@dataclass(frozen=True)
class Exports:
    """The public names of one estimator: estimator class, settings class, batch result and status enum."""

    module: str
    estimator: str
    settings: str
    batch: str
    status: str

    def names(self) -> List[str]:
        return [self.estimator, self.settings, self.batch, self.status]


def estimator_exports(modules: Mapping[str, tuple], estimators: Mapping[str, str],
                      settings_classes: Mapping[str, str], enum_names: Mapping[str, str]) -> List[Exports]:
    """The exports of every estimator of ``modules`` (module → (header, C prefix, ...)), in its order."""
    return [Exports(module, estimators[module], settings_classes[module],
                    settings_classes[module][:-len("Settings")] + "Batch", enum_names[f"{prefix}Status"])
            for module, (_, prefix, *_) in modules.items()]


def import_line(source: str, names: List[str]) -> str:
    """``from <source> import <names>``, wrapped in parentheses when it would pass :data:`_WIDTH` characters."""
    line = f"from {source} import {', '.join(names)}"
    if len(line) <= _WIDTH:
        return line
    out, current = [f"from {source} import ("], "    "
    for name in names:
        if len(current) + len(name) + 2 > _WIDTH:
            out.append(current.rstrip())
            current = "    "
        current += name + ", "
    return "\n".join(out + [current.rstrip(", ") + ")"])


def names_list(names: List[str], opening: str) -> str:
    """``opening`` (``_COMPILED += (``) and the quoted names, wrapped at :data:`_WIDTH`, then ``]``."""
    lines, current = [opening], "   "
    for name in names:
        item = f' "{name}",'
        if len(current) + len(item) > _WIDTH:
            lines.append(current)
            current = "   "
        current += item
    return "\n".join(lines + [current, "]"])


def package_blocks(exports: List[Exports]) -> Dict[str, str]:
    """The generated blocks of ``fusion_altitude/__init__.py``: the estimators' tables, settings and batch imports;
    their compiled classes (inside the ``try`` of the compiled extension); their ``__all__`` entries."""
    lines = [import_line("._core._c_tables", sorted(e.status for e in exports))]
    lines += [import_line(f"._core._{e.module}_glue", [e.batch]) for e in exports]
    lines += [import_line(f".reference.{e.module}", [e.settings]) for e in exports]
    lines.append(names_list([e.estimator for e in exports], "_COMPILED += (")[:-1] + ")")
    compiled = [import_line(f"._core._{e.module}", [e.estimator]) for e in exports]
    return {"estimator imports": "\n".join(lines), "compiled estimators": "\n".join(compiled),
            "estimator names": all_entries(exports)}


def all_entries(exports: List[Exports]) -> str:
    """``__all__ += [...]`` with the names of each estimator on a line of their own."""
    rows = ["    " + ", ".join(f'"{name}"' for name in e.names()) + "," for e in exports]
    return "\n".join(["__all__ += ["] + rows + ["]"])


def reference_blocks(exports: List[Exports]) -> Dict[str, str]:
    """The generated blocks of ``fusion_altitude/reference/__init__.py``: the reference estimators with their
    settings, the batch results and status enums they share with the bindings; their ``__all__`` entries."""
    lines = [import_line(".._core._c_tables", sorted(e.status for e in exports))]
    lines += [import_line(f".._core._{e.module}_glue", [e.batch]) for e in exports]
    lines += [import_line(f".{e.module}", [e.estimator, e.settings]) for e in exports]
    return {"estimator imports": "\n".join(lines), "estimator names": all_entries(exports)}


def fill_blocks(text: str, blocks: Mapping[str, str], path: Path) -> str:
    """``text`` with the lines between each block's markers replaced by the block (indented as its marker)."""
    for block, body in blocks.items():
        marker = re.escape(_MARKER.format(block=block))
        pattern = re.compile(rf"^([ \t]*){marker}\n.*?^[ \t]*{re.escape(_END.format(block=block))}\n", re.M | re.S)
        match = pattern.search(text)
        if match is None:
            raise SystemExit(f"{path}: the markers of the generated block {block!r} are missing:\n"
                             f"{_MARKER.format(block=block)}\n{_END.format(block=block)}")
        indent = match.group(1)
        body = "\n".join(indent + line if line else line for line in body.split("\n"))
        replacement = f"{indent}{_MARKER.format(block=block)}\n{body}\n{indent}{_END.format(block=block)}\n"
        text = text[:match.start()] + replacement + text[match.end():]
    return text


def generate(package: Path, exports: List[Exports]) -> Dict[Path, str]:
    """The two ``__init__.py`` files of ``package`` (the ``fusion_altitude`` folder) with their blocks filled."""
    files = {package / "__init__.py": package_blocks(exports),
             package / "reference" / "__init__.py": reference_blocks(exports)}
    return {path: fill_blocks(path.read_text(), blocks, path) for path, blocks in files.items()}
