#!/usr/bin/env python3
"""Generate the C API reference (``docs/api/c.rst``) from the public headers ``csrc/fusion_altitude*.h``.

A declaration is public when a doc comment (``/** ... */``) stands right before it and does not open with
Doxygen's ``@internal`` tag (``/** @internal ...``: the headers' helpers, which ``tools/make_harnesses.py`` also
leaves out of the sized functions). Internal helpers are left out rather than shown marked: a user cannot rely on
them (they are not in the bindings' ``c<e>.pxd`` either, and may change in any release), and Doxygen, whose tag
this is, hides them too unless ``INTERNAL_DOCS`` is set. From
each header this writes its file comment, then every public ``#define`` (``.. c:macro::`` with its value),
``typedef enum`` (``.. c:enum::`` with its enumerators), ``typedef struct`` (``.. c:struct::`` with its
members) and function (``.. c:function::`` with its full prototype), each with its comment. Multi-line
comments are shown as written (a literal block: they hold ASCII formulas); one-line comments as text.

Usage::

    python tools/c_api_reference.py           # write docs/api/c.rst
    python tools/c_api_reference.py --check   # exit 1 if docs/api/c.rst is stale (tests/test_api_reference.py)
"""

from __future__ import annotations

import argparse
import difflib
import glob
import os
import re
import sys
from dataclasses import dataclass
from typing import List, Optional, Tuple

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUTPUT = os.path.join(ROOT, "docs", "api", "c.rst")
HEADERS = "csrc/fusion_altitude*.h"

_DOC_COMMENT = re.compile(r"/\*\*(?!/)(.*?)\*/", re.S)
_TYPEDEF = re.compile(r"typedef\s+(struct|enum)\s*\w*\s*\{(.*?)\}\s*(\w+)\s*;", re.S)
_FUNCTION = re.compile(r"(?:[A-Z_]+\s+)*(?:static\s+)?(?:inline\s+)?(.+?)\b(FusionAltitude\w+)\s*\((.*?)\)\s*\{", re.S)
_MEMBER_COMMENT = re.compile(r"/\*\*<(.*?)\*/", re.S)
_INTERNAL = re.compile(r"@internal\b")  # opening a doc comment: a helper, left out
_MACRO_WORD = re.compile(r"\b[A-Z][A-Z0-9_]+\b\s*")  # FUSION_ALTITUDE_INS_ONCE and the like, before the return type
_MACRO = re.compile(r"#define[ \t]+(\w+)(\([^)]*\))?[ \t]*([^\n]*)")
_ANY_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)


@dataclass
class Declaration:
    kind: str  # "enum", "struct", "function" or "macro"
    name: str
    signature: str  # the function's prototype; empty for types
    comment: List[str]  # the doc comment's lines, cleaned
    members: List[Tuple[str, List[str]]]  # (declaration, comment lines): enumerators, struct members; a macro's value


def comment_lines(text: str) -> List[str]:
    """The lines of a comment body without the leading `` * `` and ``@brief``; blank lines at the ends dropped."""
    lines = [re.sub(r"^\s*\*(?: |$)", "", line.rstrip()) if line.strip().startswith("*") else line.strip()
             for line in text.splitlines()]
    while lines and not lines[0].strip():
        lines.pop(0)
    while lines and not lines[-1].strip():
        lines.pop()
    return [re.sub(r"^@brief\s*", "", lines[0])] + lines[1:] if lines else []


def _members(kind: str, body: str) -> List[Tuple[str, List[str]]]:
    """Enumerators (``Name = value``) or struct members (``type name[n]``) with their ``/**< */`` comments."""
    members = []
    if kind == "enum":
        pieces = re.findall(r"(\w+(?:\s*=\s*[^,/]+?)?)\s*,?\s*(/\*\*<.*?\*/)?\s*(?=\n|$)", body)
    else:
        pieces = re.findall(r"([^;{}]+?);\s*(/\*\*<.*?\*/)?", _strip_plain_comments(body))
    for declaration, comment in pieces:
        declaration = " ".join(declaration.split())
        if not declaration:
            continue
        text = comment_lines(_MEMBER_COMMENT.match(comment).group(1)) if comment else []
        if kind == "struct" and "," in declaration:  # float a[n], b[n];
            first = declaration.split(",")[0]
            base = re.match(r"(.*?)(\w+\s*(?:\[[^\]]*\])*)$", first).group(1)
            members.extend((base + name.strip() if i else first, text) for i, name in
                           enumerate(declaration.split(",")))
        else:
            members.append((declaration, text))
    return members


def _strip_plain_comments(body: str) -> str:
    """Drops ``/* */`` and ``//`` comments that are not member doc comments (``/**< */``)."""
    return re.sub(r"/\*(?!\*<).*?\*/|//[^\n]*", "", body, flags=re.S)


def parse_header(text: str) -> Tuple[List[str], List[Declaration]]:
    """The file comment and the public declarations of one header, in order."""
    file_comment = comment_lines(_DOC_COMMENT.search(text).group(1))
    file_comment = [line for line in file_comment if not line.startswith("@file")]
    declarations = []
    for match in _DOC_COMMENT.finditer(text):
        comment = comment_lines(match.group(1))
        rest = text[match.end():]
        if not rest.startswith(("\n", " \n")) or not comment or comment[0].startswith("@file") or \
                _INTERNAL.match(comment[0]):
            continue
        rest = rest.lstrip()
        typedef = _TYPEDEF.match(rest)
        if typedef:
            kind, body, name = typedef.groups()
            declarations.append(Declaration(kind, name, "", comment, _members(kind, body)))
            continue
        macro = _MACRO.match(rest)
        if macro:
            name, parameters, value = macro.groups()
            value = " ".join(_ANY_COMMENT.sub("", value).split())
            declarations.append(Declaration("macro", name, name + (parameters or ""), comment,
                                            [(value, [])] if value else []))
            continue
        head = rest.split(";", 1)[0]
        if rest.startswith(("#", "typedef")) or "{" not in head:
            continue  # a preprocessor line, or a declaration without a body
        function = _FUNCTION.match(rest)
        if function:
            returns, name, parameters = function.groups()
            parameters = " ".join(_ANY_COMMENT.sub("", parameters).split())
            returns = " ".join(_MACRO_WORD.sub("", returns).split())
            signature = f"{returns} {name}({parameters})".replace("* ", "*")
            declarations.append(Declaration("function", name, signature, comment, []))
    return file_comment, declarations


def public_functions(text: str) -> List[str]:
    """The names of one header's public functions (for the tests)."""
    return [d.name for d in parse_header(text)[1] if d.kind == "function"]


_RST_SPECIAL = re.compile(r"([\\`*_|\[\]<>])")


def _text(lines: List[str], indent: str) -> str:
    """One line as escaped text; several as a literal block (they hold formulas aligned with spaces)."""
    if not lines:
        return ""
    if len(lines) == 1:
        return indent + _RST_SPECIAL.sub(r"\\\1", lines[0]) + "\n\n"
    body = "".join(f"{indent}   {line}".rstrip() + "\n" for line in lines)
    return f"{indent}.. code-block:: text\n\n{body}\n"


def render(headers: List[Tuple[str, str]]) -> str:
    """The reST of the C reference from (file name, text) pairs."""
    title = "C API"
    out = [".. Generated by tools/c_api_reference.py from csrc/fusion_altitude*.h; do not edit.\n\n",
           f"{title}\n{'=' * len(title)}\n\n",
           "The header-only C99 core: every public function, struct, enum and macro of the headers in ``csrc/``, with "
           "the headers' own comments (units as they state them).\n\n"]
    for file_name, text in headers:
        file_comment, declarations = parse_header(text)
        out.append(f"``{file_name}``\n{'-' * (len(file_name) + 4)}\n\n")
        out.append(_text(file_comment, ""))
        for declaration in declarations:
            if declaration.kind == "function":
                out.append(f".. c:function:: {declaration.signature}\n\n")
                out.append(_text(declaration.comment, "   "))
                continue
            if declaration.kind == "macro":
                out.append(f".. c:macro:: {declaration.signature}\n\n")
                out.append(_text(declaration.comment, "   "))
                out.extend(f"   Defined as ``{value}``.\n\n" for value, _ in declaration.members)
                continue
            out.append(f".. c:{declaration.kind}:: {declaration.name}\n\n")
            out.append(_text(declaration.comment, "   "))
            role = "enumerator" if declaration.kind == "enum" else "member"
            for member, comment in declaration.members:
                out.append(f"   .. c:{role}:: {member}\n\n")
                out.append(_text(comment, "      "))
    return "".join(out).rstrip("\n") + "\n"


def read_headers(root: str = ROOT) -> List[Tuple[str, str]]:
    paths = sorted(glob.glob(os.path.join(root, HEADERS)))
    return [(os.path.basename(path), open(path, encoding="utf-8").read()) for path in paths]


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if docs/api/c.rst differs from the headers")
    args = parser.parse_args(argv)
    text = render(read_headers())
    old = open(OUTPUT, encoding="utf-8").read() if os.path.exists(OUTPUT) else ""
    if old == text:
        return 0
    if args.check:
        sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), text.splitlines(True), OUTPUT, "new"))
        print("stale: docs/api/c.rst; run python tools/c_api_reference.py", file=sys.stderr)
        return 1
    with open(OUTPUT, "w", encoding="utf-8") as handle:
        handle.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
