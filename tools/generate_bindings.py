#!/usr/bin/env python3
"""Generate the binding's tables from the C headers, so that each value exists once.

From every ``csrc/fusion_altitude*.h`` listed in :data:`MODULES` this writes

- ``fusion_altitude/_core/_c_tables.py`` (pure Python, used by the binding *and* the
  reference): every ``typedef enum`` as an ``enum.IntEnum``, every status
  message (``...StatusMessage``), and each settings struct as a table of
  ``(python_name, c_name, kind, default)`` with the defaults of
  ``...SettingsDefault()``;
- ``fusion_altitude/_core/_<module>_fields.pxi`` (Cython, included at module level
  of ``_<module>.pyx``): ``C_STATUS_VALUES`` and the other enum values as the
  compiler sees them, the conversions settings dict ⇄ C struct, and the
  estimator state ⇄ tuple (``_get_state``/``_set_state`` layout: the struct's
  fields in order; a settings struct as its dict, arrays flattened to lists,
  arrays of structs as lists of tuples).

The defaults and messages are read from C itself: the generator compiles and
runs a small program that calls ``...SettingsDefault()`` and
``...StatusMessage()`` (needs a C compiler, ``cc``). A field added to a
settings or state struct (e.g. ``float gapPeriod``) reaches Python by running
this script again; nothing else is edited by hand.

It also writes ``csrc/tests/vectors/<module>_settings_words.h`` (:mod:`settings_words`): the settings structs as
the 32-bit words of the test vectors, which the firmware replays and the fuzzers decode; and the estimator lines
of ``fusion_altitude/__init__.py`` and ``fusion_altitude/reference/__init__.py`` (:mod:`package_init`: each
estimator's class, settings, batch result and status enum, imported and in ``__all__``, between marker comments).

Usage::

    python tools/generate_bindings.py           # write the files
    python tools/generate_bindings.py --check   # exit 1 if a file is stale (CI, tests/test_contract.py)
"""

from __future__ import annotations

import argparse
import difflib
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent))
import package_init  # noqa: E402  (tools/package_init.py: the estimator lines of the package's __init__ files)
import settings_words  # noqa: E402  (tools/settings_words.py: the settings as words, for replays and fuzzers)

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"
PACKAGE = ROOT / "fusion_altitude" / "_core"  # the generated files sit beside the bindings
PACKAGE_NAME = "fusion_altitude._core"


def _relative_to_package(module_name: str) -> str:
    """``module_name`` as a relative import from the generated files' package (``fusion_altitude._core``)."""
    if module_name.startswith(PACKAGE_NAME + "."):
        return "." + module_name[len(PACKAGE_NAME) + 1:]
    return ".." + module_name[len("fusion_altitude."):]

#: module name → (header, C prefix, settings struct, state struct).
MODULES = {
    "observer": ("fusion_altitude.h", "FusionAltitude", "FusionAltitudeSettings", "FusionAltitude"),
    "kalman": ("fusion_altitude_kalman.h", "FusionAltitudeKalman", "FusionAltitudeKalmanSettings",
               "FusionAltitudeKalman"),
    "complementary": ("fusion_altitude_complementary.h", "FusionAltitudeComplementary",
                      "FusionAltitudeComplementarySettings", "FusionAltitudeComplementary"),
    "alphabeta": ("fusion_altitude_alphabeta.h", "FusionAltitudeAlphaBeta", "FusionAltitudeAlphaBetaSettings",
                  "FusionAltitudeAlphaBeta"),
    "ins": ("fusion_altitude_ins.h", "FusionAltitudeIns", "FusionAltitudeInsSettings", "FusionAltitudeIns"),
    "rocket": ("fusion_altitude_rocket.h", "FusionAltitudeRocket", "FusionAltitudeRocketSettings", "FusionAltitudeRocket"),
}

#: module name → the Python estimator class (binding and reference alike).
ESTIMATORS = {"observer": "AltitudeEstimator", "kalman": "KalmanEstimator", "complementary": "ComplementaryFilter",
              "alphabeta": "AlphaBetaFusion", "ins": "InsEstimator", "rocket": "RocketEstimator"}

#: Python enum name of each C enum, and the prefix its members drop.
ENUM_NAMES = {
    "FusionAltitudeStatus": "Status",
    "FusionAltitudePreset": "Preset",
    "FusionAltitudeKalmanStatus": "KalmanStatus",
    "FusionAltitudeKalmanResult": "KalmanResult",
    "FusionAltitudeKalmanState": "KalmanStateIndex",
    "FusionAltitudeKalmanSensorIndex": "KalmanSensorIndex",
    "FusionAltitudeComplementaryStatus": "ComplementaryStatus",
    "FusionAltitudeAlphaBetaStatus": "AlphaBetaStatus",
    "FusionAltitudeAlphaBetaSensorIndex": "AlphaBetaSensorIndex",
    "FusionAltitudeInsStatus": "InsStatus",
    "FusionAltitudeRocketStatus": "RocketStatus",
    "FusionAltitudeRocketPhase": "Phase",
    "FusionAltitudeRocketEventId": "RocketEventId",
    "FusionAltitudeRocketBaro": "BaroFate",
}

#: Python names that are not the snake_case of the C name (kept for compatibility).
PYTHON_NAMES = {
    "rangeMinimum": "range_min",
    "rangeMaximum": "range_max",
    "gpsMinimumSatellites": "gps_min_satellites",
}

#: Python property names of getters that are not the snake_case of the part after ``Get``/``Is``.
GETTER_NAMES = {
    "FusionAltitudeInsIsStationary": "is_stationary",
    "FusionAltitudeInsIsAccelRejected": "is_accel_rejected",
    "FusionAltitudeInsIsBaroRejecting": "is_baro_rejecting",
    "FusionAltitudeInsGetAccelZBias": "accel_z_bias",
    "FusionAltitudeInsGetAltitude": "height_above_start",  # the INS's `altitude` is the baro datum's (docs/ins.md)
}

#: C scalar type → kind: "f" float32, "b" bool, "i" signed int, "u" unsigned int, "e" enum (as int).
SCALAR_KINDS = {"float": "f", "bool": "b", "int32_t": "i", "uint32_t": "u", "int": "i", "uint8_t": "u",
                "size_t": "u"}

GENERATED = "# Generated by tools/generate_bindings.py from csrc/ -- do not edit; run the script instead.\n"


def snake(name: str) -> str:
    """camelCase → snake_case, with the exceptions of :data:`PYTHON_NAMES`."""
    if name in PYTHON_NAMES:
        return PYTHON_NAMES[name]
    return re.sub(r"(?<=[a-z0-9])([A-Z])", r"_\1", name).lower()


def upper_snake(name: str) -> str:
    return re.sub(r"(?<=[a-z0-9])([A-Z])", r"_\1", name).upper()


@dataclass
class Field:
    ctype: str
    name: str
    dims: Tuple[str, ...]
    comment: str
    rule: str = ""  # the ``[rule: ...]`` at the end of the comment (settings fields), without the brackets

    @property
    def python(self) -> str:
        return snake(self.name)


@dataclass
class Enum:
    cname: str
    members: List[Tuple[str, str]]  # (C name, comment)


@dataclass
class Getter:
    ctype: str
    cname: str
    python: str
    doc: str


@dataclass
class Header:
    path: Path
    getters: List[Getter] = field(default_factory=list)
    enums: Dict[str, Enum] = field(default_factory=dict)
    structs: Dict[str, List[Field]] = field(default_factory=dict)
    defines: Dict[str, str] = field(default_factory=dict)


def _strip_comments(text: str) -> str:
    return re.sub(r"/\*.*?\*/|//[^\n]*", "", text, flags=re.S)


def parse_header(path: Path, known: Optional[Header] = None) -> Header:
    """The enums, structs and integer #defines of one header (plus those of ``known``)."""
    text = path.read_text()
    header = Header(path)
    if known is not None:
        header.enums.update(known.enums)
        header.structs.update(known.structs)
        header.defines.update(known.defines)
    for name, value in re.findall(r"^#define\s+(FUSION_ALTITUDE_\w+)\s+\(?(\d+)\)?\s*$", text, flags=re.M):
        header.defines[name] = value
    for body, name in re.findall(r"typedef enum \{(.*?)\} (\w+);", text, flags=re.S):
        members = []
        for line in body.splitlines():
            match = re.match(r"\s*(\w+)\s*(?:=\s*\d+)?\s*,?\s*(?:/\*\*<\s*(.*?)\s*\*/)?\s*$", line)
            if match and match.group(1):
                members.append((match.group(1), match.group(2) or ""))
        header.enums[name] = Enum(name, members)
    for body, name in re.findall(r"typedef struct \{(.*?)\} (\w+);", text, flags=re.S):
        fields = []
        for line in body.splitlines():
            match = re.match(r"\s*((?:const\s+)?\w+(?:\s*\*)?)\s*(\w+)((?:\[\w+\])*);\s*(?:/\*\*<\s*(.*?)\s*\*/)?", line)
            if match:
                dims = tuple(re.findall(r"\[(\w+)\]", match.group(3)))
                comment, rule = re.match(r"(.*?)\s*(?:\[rule: ([^\]]*)\])?$", match.group(4) or "").groups()
                fields.append(Field(match.group(1).replace(" ", ""), match.group(2), dims, comment, rule or ""))
        header.structs[name] = fields
    getter = re.compile(r"(?:/\*\*((?:[^*]|\*(?!/))*)\*/\s*)?static inline (float|bool|int32_t|uint32_t) "
                        r"(FusionAltitude\w*?(?:Get|Is)(\w+))\(const (\w+) \*const \w+\) \{")
    for doc, ctype, cname, short, argument in getter.findall(text):
        if argument in header.structs:
            doc = " ".join(line.strip(" *") for line in doc.strip().splitlines()).strip()
            doc = re.sub(r"^@brief\s*|^@return\s*", "", doc).replace("^2", "²").replace("^3", "³")
            header.getters.append(Getter(ctype, cname, GETTER_NAMES.get(cname, snake(short)),
                                         (doc[:1].upper() + doc[1:]) or f"{cname}."))
    return header


# -- values read from C ---------------------------------------------------------------------------------------------

def _c_leaves(header: Header, struct: str, access: str, python: Tuple[str, ...] = ()):
    """(python path, C access expression, kind) of every scalar leaf of a struct, in order."""
    for f in header.structs[struct]:
        if f.ctype in header.structs:
            if f.dims:
                count = int(header.defines.get(f.dims[0], f.dims[0]))
                for i in range(count):
                    yield from _c_leaves(header, f.ctype, f"{access}.{f.name}[{i}]", python + (f.python, str(i)))
            else:
                yield from _c_leaves(header, f.ctype, f"{access}.{f.name}", python + (f.python,))
        else:
            yield python + (f.python,), f"{access}.{f.name}", SCALAR_KINDS.get(f.ctype, "i")


def read_from_c(headers: Dict[str, Header]) -> Tuple[Dict[str, Dict[Tuple[str, ...], str]], Dict[str, List[str]]]:
    """Compile and run a program printing every default setting and status message. Returns (defaults, messages)."""
    compiler = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if compiler is None:
        raise SystemExit("generate_bindings: needs a C compiler (cc, gcc or clang) to read the defaults from C")
    lines = ["#include <stdio.h>"]
    lines += [f'#include "{headers[m].path.name}"' for m in MODULES]
    lines.append("int main(void) {")
    for module, (_, prefix, settings, _) in MODULES.items():
        header = headers[module]
        lines.append(f"    {{ const {settings} s = {settings}Default();")
        for path, access, kind in _c_leaves(header, settings, "s"):
            fmt, cast = {"f": ('"%.9g"', "(double)"), "b": ('"%d"', "(int)"), "u": ('"%lu"', "(unsigned long)")}.get(
                kind, ('"%ld"', "(long)"))
            lines.append(f'      printf("D {module} {".".join(path)} "); printf({fmt}, {cast}{access}); printf("\\n");')
        lines.append("    }")
        if f"{prefix}Preset" in header.enums and f"{prefix}SettingsFromPreset" in header.path.read_text():
            for member, _ in header.enums[f"{prefix}Preset"].members:
                lines.append(f"    {{ {settings} s; {prefix}SettingsFromPreset(&s, {member});")
                for path, access, kind in _c_leaves(header, settings, "s"):
                    lines.append(f'      printf("P {module} {member}.{".".join(path)} %.9g\\n", (double){access});')
                lines.append("    }")
        status = f"{prefix}Status"
        for member, _ in header.enums[status].members:
            lines.append(f'    printf("M {module} %s\\n", {prefix}StatusMessage({member}));')
    lines += ["    return 0;", "}"]
    with tempfile.TemporaryDirectory() as tmp:
        source, program = Path(tmp) / "defaults.c", Path(tmp) / "defaults"
        source.write_text("\n".join(lines) + "\n")
        subprocess.run([compiler, "-std=c99", "-I", str(CSRC), str(source), "-o", str(program)], check=True)
        output = subprocess.run([str(program)], check=True, capture_output=True, text=True).stdout
    defaults: Dict[str, Dict[Tuple[str, ...], str]] = {m: {} for m in MODULES}
    messages: Dict[str, List[str]] = {m: [] for m in MODULES}
    for line in output.splitlines():
        tag, module, rest = line.split(" ", 2)
        if tag == "D":
            path, value = rest.split(" ", 1)
            defaults[module][tuple(path.split("."))] = value
        elif tag == "P":  # a preset's settings: stored as defaults under ("preset", member, field...)
            path, value = rest.split(" ", 1)
            defaults[module][("preset",) + tuple(path.split("."))] = value
        else:
            messages[module].append(rest)
    return defaults, messages


def _python_float(text: str) -> str:
    """The shortest decimal that rounds to the same float32 (as Python source)."""
    value = float(text)
    if value != value:
        return 'float("nan")'
    if value in (float("inf"), float("-inf")):
        return 'float("inf")' if value > 0 else '-float("inf")'
    import struct
    bits = struct.pack("<f", value)
    for digits in range(1, 10):
        candidate = f"{value:.{digits}g}"
        if struct.pack("<f", float(candidate)) == bits:
            return repr(float(candidate))
    return repr(value)


def _python_value(text: str, kind: str) -> str:
    if kind == "f":
        return _python_float(text)
    if kind == "b":
        return "True" if text != "0" else "False"
    return str(int(text))


# -- _c_tables.py -------------------------------------------------------------------------------------------------

def enum_prefix(enum: Enum) -> str:
    """What every member name starts with: the enum's name, else (``FusionAltitudeRocketEventId`` with members
    ``FusionAltitudeRocketEventLaunch`` …) the name without its last word."""
    if all(m.startswith(enum.cname) for m, _ in enum.members):
        return enum.cname
    shorter = re.sub(r"[A-Z][a-z0-9]*$", "", enum.cname)
    return shorter if all(m.startswith(shorter) for m, _ in enum.members) else enum.cname


def enum_python(header: Header, enum: Enum) -> List[str]:
    prefix = enum_prefix(enum)
    name = ENUM_NAMES[enum.cname]
    lines = [f"class {name}(enum.IntEnum):", f'    """C ``{enum.cname}`` ({header.path.name})."""', ""]
    for value, (member, comment) in enumerate(enum.members):
        short = member[len(prefix):] if member.startswith(prefix) else member
        lines.append(f"    {upper_snake(short)} = {value}" + (f"  #: {comment}" if comment else ""))
    return lines + ["", ""]


def settings_table(module: str, header: Header, struct: str, defaults: Dict[Tuple[str, ...], str]) -> List[str]:
    """``<MODULE>_SETTINGS``: (python name, C name, kind, default, comment) per field; nested structs as sub-tables."""
    upper = module.upper()
    lines = []
    fields = header.structs[struct]
    if fields[0].ctype in header.structs and fields[0].dims:  # an array of per-sensor structs, then scalar fields
        inner = fields[0]
        sensor_enum = [e for e in header.enums.values() if e.cname.endswith("SensorIndex")][0]
        names = [upper_snake(m[len(sensor_enum.cname.replace("Index", "")):]).lower() for m, _ in sensor_enum.members]
        lines.append(f"#: Sensors of ``{struct}.{inner.name}``, in the C index order.")
        lines.append(f"{upper}_SENSORS = {tuple(names)!r}")
        lines.append("")
        lines.append(f"#: ``{inner.ctype}``: (python name, C name, kind, comment); kind f float32, i int32, b bool.")
        lines.append(f"{upper}_SENSOR_FIELDS = (")
        for f in header.structs[inner.ctype]:
            lines.append(f"    ({f.python!r}, {f.name!r}, {SCALAR_KINDS[f.ctype]!r}, {f.comment!r}),")
        lines.append(")")
        lines.append("")
        lines.append(f"#: ``{struct}Default()``: {{sensor: {{field: default}}}}, read from C.")
        lines.append(f"{upper}_DEFAULTS = {{")
        for i, sensor in enumerate(names):
            values = ", ".join(
                f"{f.python!r}: {_python_value(defaults[(inner.python, str(i), f.python)], SCALAR_KINDS[f.ctype])}"
                for f in header.structs[inner.ctype])
            lines.append(f"    {sensor!r}: {{{values}}},")
        lines.append("}")
        lines.append("")
        lines.append(f"#: ``{struct}`` fields after the sensors: (python name, C name, kind, default, comment).")
        lines.append(f"{upper}_SETTINGS = (")
        for f in fields[1:]:
            kind = SCALAR_KINDS[f.ctype]
            lines.append(f"    ({f.python!r}, {f.name!r}, {kind!r}, {_python_value(defaults[(f.python,)], kind)}, "
                         f"{f.comment!r}),")
        lines.append(")")
        return lines + ["", ""]
    lines.append(f"#: ``{struct}``: (python name, C name, kind, default, comment) per field, in the struct's order;")
    lines.append(f"#: kind f float32, i int32, b bool, s a struct (its default: the tuple of its fields in order); the")
    lines.append(f"#: defaults are ``{struct}Default()``, read from C.")
    lines.append(f"{upper}_SETTINGS = (")
    for f in fields:
        if f.ctype in header.structs:
            default = "(" + "".join(f"{_python_value(defaults[(f.python, g.python)], SCALAR_KINDS[g.ctype])}, "
                                    for g in header.structs[f.ctype]).rstrip() + ")"
            lines.append(f"    ({f.python!r}, {f.name!r}, 's', {default}, {f.comment!r}),")
            continue
        kind = SCALAR_KINDS[f.ctype]
        lines.append(f"    ({f.python!r}, {f.name!r}, {kind!r}, {_python_value(defaults[(f.python,)], kind)}, "
                     f"{f.comment!r}),")
    lines.append(")")
    return lines + ["", ""]


def _rule_terms(header: Header, struct: str, f: Field) -> str:
    """The Python tuple of a field's rule terms: "finite", "any", "checked", or (operator, bound) with the bound a
    number, a numeric constant of ``_c_tables`` or another field's Python name."""
    terms = []
    names = {g.name: g.python for g in header.structs[struct]}
    for term in f.rule.split(";")[0].split(","):
        term = term.strip()
        match = re.fullmatch(r"(>=|<=|>|<) (\S+)", term)
        if term in ("finite", "any", "checked"):
            terms.append(repr(term))
        elif match and re.fullmatch(r"-?[\d.]+(?:e-?\d+)?", match.group(2)):
            terms.append(f"({match.group(1)!r}, {match.group(2)})")
        elif match and match.group(2).startswith("FUSION_ALTITUDE_"):
            terms.append(f"({match.group(1)!r}, {match.group(2)})")
        elif match and match.group(2) in names:
            terms.append(f"({match.group(1)!r}, {names[match.group(2)]!r})")
        else:
            raise SystemExit(f"generate_bindings: {struct}.{f.name}: cannot read the rule term {term!r}")
    return "(" + ", ".join(terms) + ("," if len(terms) == 1 else "") + ")"


def rules_table(module: str, header: Header, prefix: str, struct: str, table: str) -> List[str]:
    """``<table>``: the rule of every field of ``struct``, from the ``[rule: terms; else Status]`` at the end of its
    comment in the header; a field without one stops the generator (every setting says what it accepts)."""
    status = header.enums[f"{prefix}Status"]
    lines = [f"#: The rule of each field of ``{struct}`` (the ``[rule: ...; else Status]`` of its comment in the header):",
             "#: Python name → (status when broken, terms); a term is \"finite\", \"any\" (no rule), \"checked\" (a struct",
             "#: checked by its own check) or (operator, bound), the bound a number, a constant or another field's name.",
             f"{table} = {{"]
    for f in header.structs[struct]:
        if not f.rule:
            raise SystemExit(f"generate_bindings: {header.path.name}: {struct}.{f.name} has no [rule: ...] in its "
                             "comment (e.g. /**< s, ... [rule: finite, > 0; else InvalidGapPeriod] */)")
        name = f.rule.partition("; else ")[2].strip()
        if name and f"{prefix}Status{name}" not in [m for m, _ in status.members]:
            raise SystemExit(f"generate_bindings: {struct}.{f.name}: no status {prefix}Status{name}")
        python_status = f"{ENUM_NAMES[status.cname]}.{upper_snake(name)}" if name else "None"
        lines.append(f"    {f.python!r}: ({python_status}, {_rule_terms(header, struct, f)}),")
    return lines + ["}", "", ""]


def settings_rules(module: str, header: Header, prefix: str, struct: str) -> List[str]:
    """The rules tables of a settings struct: ``<MODULE>_RULES``, and ``<MODULE>_SENSOR_RULES`` for the per-sensor
    struct it holds."""
    lines = []
    for f in header.structs[struct]:
        if f.ctype in header.structs and f.dims:
            lines += rules_table(module, header, prefix, f.ctype, f"{module.upper()}_SENSOR_RULES")
    return lines + rules_table(module, header, prefix, struct, f"{module.upper()}_RULES")


def presets_table(module: str, header: Header, prefix: str, struct: str,
                  defaults: Dict[Tuple[str, ...], str]) -> List[str]:
    """``<MODULE>_PRESETS`` (``...SettingsFromPreset`` of each preset, read from C) and ``<MODULE>_PRESET_OMEGA``
    (the bandwidth ω, rad/s, that each preset's enum comment gives), keyed by the preset's Python name."""
    enum = header.enums.get(f"{prefix}Preset")
    if enum is None or not any(key[0] == "preset" for key in defaults):
        return []
    upper = module.upper()
    lines = [f"#: ``{prefix}SettingsFromPreset``: {{preset: {{setting: value}}}}, read from C.", f"{upper}_PRESETS = {{"]
    for member, _ in enum.members:
        name = upper_snake(member[len(enum_prefix(enum)):]).lower()
        values = ", ".join(f"{path[-1]!r}: {_python_value(defaults[('preset', member) + path], kind)}"
                           for path, _, kind in _c_leaves(header, struct, "s"))
        lines.append(f"    {name!r}: {{{values}}},")
    lines += ["}", "", f"#: The position-loop bandwidth ω of each preset, rad/s: the comments of ``{enum.cname}``.",
              f"{upper}_PRESET_OMEGA = {{"]
    for member, comment in enum.members:
        match = re.search(r"omega = ([\d.]+) rad/s", comment)
        if match is None:
            raise SystemExit(f"generate_bindings: {member} has no 'omega = <value> rad/s' in its comment")
        lines.append(f"    {upper_snake(member[len(enum_prefix(enum)):]).lower()!r}: {float(match.group(1))!r},")
    return lines + ["}", "", ""]


def generate_tables(headers: Dict[str, Header], defaults, messages) -> str:
    out = [GENERATED.rstrip(), '"""Enums, status messages and settings tables of the C headers, for the binding and the reference.',
           "", "Pure Python: :mod:`fusion_altitude.reference` imports it without the compiled extension.", '"""', "",
           "import enum", "", ""]
    seen = set()
    for module, (header_name, prefix, settings, _) in MODULES.items():
        header = headers[module]
        out.append(f"# -- {header_name} " + "-" * (100 - len(header_name)))
        out.append("")
        for enum in header.enums.values():
            if enum.cname in seen or enum.cname not in ENUM_NAMES:
                continue
            if not any(m.startswith(enum_prefix(enum)) for m, _ in enum.members):
                continue
            seen.add(enum.cname)
            out += enum_python(header, enum)
        constants = re.findall(r"^#define\s+(FUSION_ALTITUDE_\w+)\s+\(([-\d.e]+)f?\)\s*$", header.path.read_text(),
                               flags=re.M)
        if constants:
            out.append(f"#: The numeric ``#define`` constants of {header_name} (floats are float32 in C).")
            out += [f"{name} = {value}" for name, value in constants]
            out += ["", ""]
        out.append(f"#: ``{prefix}StatusMessage`` of each status, read from C.")
        out.append(f"{module.upper()}_STATUS_MESSAGES = (")
        out += [f"    {message!r}," for message in messages[module]]
        out += [")", "", ""]
        if settings:
            out += settings_table(module, header, settings, defaults[module])
            out += settings_rules(module, header, prefix, settings)
            out += presets_table(module, header, prefix, settings, defaults[module])
    out.append("#: Status messages of each estimator class, for ``Estimator.status_message``.")
    out.append("STATUS_MESSAGES = {")
    out += [f"    {ESTIMATORS[m]!r}: {m.upper()}_STATUS_MESSAGES," for m in MODULES]
    out.append("}")
    return "\n".join(out).rstrip() + "\n"


# -- _<module>_fields.pxi -----------------------------------------------------------------------------------------

def _py_of(kind: str, expr: str) -> str:
    return {"b": f"bool({expr})", "i": f"int({expr})", "u": f"int({expr})", "e": f"int(<int>{expr})"}.get(kind, expr)


#: The settings class of each binding: the reference's (``fusion_altitude.reference.<module>``).
SETTINGS_CLASSES = {"observer": "AltitudeSettings", "kalman": "KalmanSettings", "complementary": "ComplementarySettings",
                    "alphabeta": "AlphaBetaSettings", "ins": "InsSettings", "rocket": "RocketSettings"}


def binding_preamble(module: str) -> List[str]:
    """What every binding imports (one place, as PyWavelets' shared templates): the C declarations, the
    ``Estimator`` base, the glue and the reference's settings class and checkpoint ``restore``."""
    return ["from fusion_altitude._core._convert cimport as_double as _as_double",
            "from fusion_altitude._core._estimator cimport Estimator",
            f"from fusion_altitude._core.{PXD_NAMES[module][:-4]} cimport *", "",
            f"from fusion_altitude import _common, _{module}_glue  # (also sets fusion_altitude._{module}_glue)",
            "from fusion_altitude.reference._checkpoint import restore",
            f"from fusion_altitude.reference.{module} import {SETTINGS_CLASSES[module]}", "", ""]


def enum_values(module: str, header: Header) -> List[str]:
    """``C_<ENUM>_VALUES``: the binding's enums as the compiler sees them, and ``c_status_message``."""
    prefix = MODULES[module][1]
    out = []
    for enum in header.enums.values():
        suffix = enum.cname[len(prefix):]
        if enum.cname not in ENUM_NAMES or not enum.cname.startswith(prefix) \
                or not any(m.startswith(enum_prefix(enum)) for m, _ in enum.members) \
                or suffix not in ("Status", "Result", "Preset", "Phase", "Baro", "EventId"):
            continue
        variable = "C_STATUS_VALUES" if suffix == "Status" else f"C_{suffix.upper()}_VALUES"
        out.append(f"#: The C enum {enum.cname}, as the compiler sees it (the generated Python enum must equal it).")
        out.append(f"{variable} = {{")
        for member, _ in enum.members:
            out.append(f"    {upper_snake(member[len(enum_prefix(enum)):])!r}: {member},")
        out += ["}", "", ""]
    return out + [f"def c_status_message(int status):",
                  f'    """{prefix}StatusMessage(status), from C."""',
                  f"    return {prefix}StatusMessage(<{prefix}Status>status).decode(\"ascii\")", "", ""]


def nested_settings_conversions(header: Header, settings: str) -> List[str]:
    """``_settings_to_c``/``_settings_from_c`` of a settings struct that starts with an array of per-sensor structs."""
    fields = header.structs[settings]
    inner = fields[0]
    sub = header.structs[inner.ctype]
    count = header.defines[inner.dims[0]]
    out = [f"cdef {settings} _settings_to_c(object values) except *:",
           f'    """{{"{inner.python}": [{{field: value}} per sensor], other field: value}} (checked Python values)'
           f' → {settings}."""',
           f"    cdef {settings} c", "    cdef int i",
           f"    for i, sensor in enumerate(values[{inner.python!r}]):"]
    out += [f"        c.{inner.name}[i].{f.name} = sensor[{f.python!r}]" for f in sub]
    out += [f"    c.{f.name} = values[{f.python!r}]" for f in fields[1:]]
    out += ["    return c", "", ""]
    out += [f"cdef dict _settings_from_c(const {settings} *c):",
            f'    """{settings} → {{"{inner.python}": [{{field: value}} per sensor], other field: value}}."""',
            "    cdef int i", f"    return {{{inner.python!r}: [{{"]
    out += [f"        {f.python!r}: {_py_of(SCALAR_KINDS[f.ctype], f'c.{inner.name}[i].{f.name}')}," for f in sub]
    out += [f"    }} for i in range({count})],"]
    out += [f"        {f.python!r}: {_py_of(SCALAR_KINDS[f.ctype], 'c.' + f.name)}," for f in fields[1:]]
    return out + ["    }", "", ""]


def settings_conversions(header: Header, settings: str) -> List[str]:
    """``_settings_to_c``/``_settings_from_c``: the settings dict ⇄ the C struct."""
    fields = header.structs[settings]
    if fields[0].ctype in header.structs and bool(fields[0].dims):
        return nested_settings_conversions(header, settings)
    out = [f"cdef {settings} _settings_to_c(object values) except *:",
           f'    """{{name: value}} (checked Python values) → {settings}."""',
           f"    cdef {settings} c"]
    for f in fields:
        if f.ctype in header.structs:  # a struct: the tuple of its fields in order
            out += [f"    c.{f.name}.{g.name} = values[{f.python!r}][{k}]" for k, g in enumerate(header.structs[f.ctype])]
        else:
            out.append(f"    c.{f.name} = values[{f.python!r}]")
    out += ["    return c", "", ""]
    out += [f"cdef dict _settings_from_c(const {settings} *c):",
            f'    """{settings} → {{name: value}} in the struct\'s order."""', "    return {"]
    out += [f"        {f.python!r}: {_struct_get(header, f.ctype, 'c.' + f.name)}," for f in fields]
    return out + ["    }", "", ""]


def checkpoint_functions(module: str) -> List[str]:
    """``_checked_settings`` (a checkpoint's settings through the settings class) and ``_restore``."""
    estimator = ESTIMATORS[module]
    return ["", "", "#: The settings in ``_get_state()``: the dict of ``_settings_from_c`` (a binding may rebind it after its include).",
            "_settings_out = dict", "", "",
            "def _settings_error(status, values):",
            '    """The error of settings C rejected (a binding may rebind it to its glue\'s, naming the field)."""',
            '    raise ValueError(f"invalid settings: {c_status_message(status)}")', "", "",
            "def _checked_settings(values):",
            '    """A checkpoint\'s settings ``values`` checked by the settings class, as :func:`_state_set` takes them."""',
            f"    return {SETTINGS_CLASSES[module]}(**values).as_dict()", "", "",
            "def _restore(state):",
            '    """A new estimator holding ``state`` (a reference or binding ``_get_state()``)."""',
            f"    return restore({estimator}, state)", ""]


@dataclass(frozen=True)
class BatchLoop:
    """One estimator's batch loop, the part of ``update_batch`` that runs with the GIL released.

    ``inputs``: (name in the glue's arrays, C type, pointer name) in the loop's argument order; ``outputs``:
    (field of the batch result, C type, dimensions, lines that copy sample ``i`` out of ``local`` into the pointer
    ``{p}``); ``update``: the C call for sample ``i`` (``{accel}``… the inputs at ``i``); ``measure``: lines that fill
    a measurements struct ``m`` before it; ``flag``: a ``bint`` argument the update reads (the rocket layer's
    ``vertical``); ``raise_error``: the glue function that raises for the first bad sample (the scalar bindings; the
    multi-sensor bindings raise themselves, from the index ``_batch_into`` returns).
    """

    inputs: Tuple[Tuple[str, str, str], ...]
    outputs: Tuple[Tuple[str, str, int, Tuple[str, ...]], ...]
    update: str
    measure: Tuple[str, ...] = ()
    flag: str = ""
    raise_error: str = ""
    copy_by_memcpy: bool = False


_SCALAR_INPUTS = (("accel", "float", "accel"), ("baro_altitude", "float", "baro"), ("dt", "float", "dt"))


def _scalar_outputs(*fields: Tuple[str, str]) -> Tuple[Tuple[str, str, int, Tuple[str, ...]], ...]:
    """1-D float32 outputs, each one expression of the state ``local``."""
    return tuple((name, "float", 1, (f"{{p}}[i] = {expression}",)) for name, expression in fields)


def _sensor_inputs(*names: str) -> Tuple[Tuple[str, str, str], ...]:
    """accel, dt and per-sensor float32 inputs, each with its own step (0: one value for every sample)."""
    return tuple((name, "float", name) for name in ("accel", "dt") + names)


#: module → its batch loop (the outputs each copies out of the state; the inputs the glue prepares).
BATCH_LOOPS = {
    "observer": BatchLoop(
        _SCALAR_INPUTS, _scalar_outputs(("altitude", "local.altitude"), ("vertical_velocity", "local.verticalVelocity"),
                                        ("accel_bias", "local.accelBias"), ("baro_residual", "local.baroResidual")),
        "FusionAltitudeUpdate(&local, {accel}, {baro}, {dt})", raise_error="_observer_glue.raise_update_error"),
    "complementary": BatchLoop(
        _SCALAR_INPUTS, _scalar_outputs(("altitude", "local.altitude"), ("vertical_velocity", "local.verticalVelocity"),
                                        ("baro_filtered", "local.baroFiltered"), ("baro_velocity", "local.baroVelocity")),
        "FusionAltitudeComplementaryUpdate(&local, {accel}, {baro}, {dt})",
        raise_error="_complementary_glue.raise_complementary_update_error"),
    "rocket": BatchLoop(
        _SCALAR_INPUTS,
        _scalar_outputs(("height", "FusionAltitudeRocketGetHeight(&local)"),
                        ("vertical_velocity", "FusionAltitudeRocketGetVerticalVelocity(&local)"),
                        ("accel_bias", "FusionAltitudeRocketGetAccelBias(&local)"))
        + (("phase", "unsigned char", 1, ("{p}[i] = <unsigned char>FusionAltitudeRocketGetPhase(&local)",)),
           ("baro", "unsigned char", 1, ("{p}[i] = <unsigned char>FusionAltitudeRocketGetBaro(&local)",))),
        "(FusionAltitudeRocketUpdateWithVerticalAccel(&local, {accel}, {baro}, {dt}) if vertical\n"
        "                 else FusionAltitudeRocketUpdate(&local, {accel}, {baro}, {dt}))",
        flag="vertical", raise_error="_rocket_glue.raise_update_error", copy_by_memcpy=True),
    "kalman": BatchLoop(
        _sensor_inputs("baro_altitude", "range_distance", "gps_altitude", "gps_vertical_accuracy")
        + (("gps_satellites", "int32_t", "gps_satellites"), ("ground_effect", "uint8_t", "ground_effect")),
        _scalar_outputs(("height_above_ground", "local.x[<int>FusionAltitudeKalmanStateHeight]"),
                        ("altitude", "FusionAltitudeKalmanGetAltitude(&local)"),
                        ("vertical_velocity", "local.x[<int>FusionAltitudeKalmanStateVelocity]"),
                        ("accel_bias", "local.x[<int>FusionAltitudeKalmanStateAccelBias]"),
                        ("baro_offset", "local.x[<int>FusionAltitudeKalmanStateBaroOffset]"),
                        ("gps_offset", "local.x[<int>FusionAltitudeKalmanStateGpsOffset]"))
        + (("covariance_diagonal", "float", 2, ("for j in range(5):", "    {p}[i * 5 + j] = local.P[j][j]")),
           ("innovation", "float", 2, ("for j in range(3):", "    {p}[i * 3 + j] = local.sensors[j].innovation")),
           ("nis", "float", 2, ("for j in range(3):",
                                "    {p}[i * 3 + j] = FusionAltitudeKalmanGetNis(&local, <FusionAltitudeKalmanSensorIndex>j)")),
           ("result", "uint8_t", 2, ("for j in range(3):", "    {p}[i * 3 + j] = <uint8_t>local.sensors[j].result"))),
        "FusionAltitudeKalmanUpdate(&local, {accel}, {dt}, &m)",
        measure=("m.baroAltitude = {baro_altitude}", "m.rangeDistance = {range_distance}",
                 "m.gpsAltitude = {gps_altitude}", "m.gpsVerticalAccuracy = {gps_vertical_accuracy}",
                 "m.gpsSatellites = {gps_satellites}", "m.groundEffect = {ground_effect} != 0")),
    "alphabeta": BatchLoop(
        _sensor_inputs("baro_altitude", "lidar_altitude", "sonar_altitude", "gps_altitude"),
        _scalar_outputs(("altitude", "local.altitude"), ("vertical_velocity", "local.verticalVelocity"))
        + (("weight", "float", 2, ("for j in range(5):", "    {p}[i * 5 + j] = local.filters[j].weight")),
           ("quality", "int32_t", 2, ("for j in range(5):", "    {p}[i * 5 + j] = local.filters[j].quality"))),
        "FusionAltitudeAlphaBetaUpdate(&local, {accel}, {dt}, &m)",
        measure=("m.baroAltitude = {baro_altitude}", "m.lidarAltitude = {lidar_altitude}",
                 "m.sonarAltitude = {sonar_altitude}", "m.gpsAltitude = {gps_altitude}")),
}


def _batch_run(module: str, loop: BatchLoop) -> List[str]:
    """``_run``: the nogil loop over raw pointers, on a private copy of the state committed only if all succeed."""
    _, prefix, _, state = MODULES[module]
    scalar = bool(loop.raise_error)
    step = {pointer: ("dt_step" if pointer == "dt" else "") if scalar else f"s_{pointer}"
            for _, _, pointer in loop.inputs}
    at = {pointer: f"{pointer}[i * {step[pointer]}]" if step[pointer] else f"{pointer}[i]"
          for _, _, pointer in loop.inputs}
    params = [f"{state} *state", "Py_ssize_t n"]
    params += [f"const {ctype} *{pointer}" + (f", Py_ssize_t {step[pointer]}" if step[pointer] else "")
               for _, ctype, pointer in loop.inputs]
    params += [f"bint {loop.flag}"] if loop.flag else []
    params += [f"{ctype} *out_{name}" for name, ctype, _, _ in loop.outputs]
    out = [f"cdef Py_ssize_t _run({params[0]},"]
    out += [f"                     {param}," for param in params[1:-1]]
    out += [f"                     {params[-1]}) noexcept nogil:",
            '    """Run n updates on a private copy of *state; commit it only if all succeed.',
            "", "    Returns the index of the first rejected sample, or -1.", '    """',
            f"    cdef {state} local"]
    out += ["    memcpy(&local, state, sizeof(local))"] if loop.copy_by_memcpy else ["    local = state[0]"]
    out += ["    cdef Py_ssize_t i"]
    out += [f"    cdef {prefix}Measurements m"] if loop.measure else []
    out += ["    cdef int j"] if any(len(lines) > 1 for *_, lines in loop.outputs) else []
    out += ["    for i in range(n):"]
    out += [f"        {line.format(**at)}" for line in loop.measure]
    out += [f"        if {loop.update.format(**at)} != {prefix}StatusOk:", "            return i"]
    out += [f"        {line.format(p='out_' + name)}" for name, _, _, lines in loop.outputs for line in lines]
    out += ["    memcpy(state, &local, sizeof(local))" if loop.copy_by_memcpy else "    state[0] = local",
            "    return -1", "", ""]
    return out


def _memoryview(ctype: str, dims: int, const: bool = False) -> str:
    return f"{'const ' if const else ''}{ctype}[{':, ' * (dims - 1)}::1]"


def _batch_into(module: str, loop: BatchLoop) -> List[str]:
    """``_batch_into``: ``update_batch``'s typed views of the glue's arrays and the nogil call of ``_run``."""
    state = MODULES[module][3]
    first = (0,) * 2
    outputs = [f"&out_{name}[{', '.join(map(str, first[:dims]))}]" for name, _, dims, _ in loop.outputs]
    if loop.raise_error:
        out = [f"cdef int _batch_into({state} *state, {_memoryview('float', 1, True)} accel, "
               f"{_memoryview('float', 1, True)} baro,",
               f"                     {_memoryview('float', 1, True)} dt, bint dt_is_array, object result"
               + (f", bint {loop.flag}" if loop.flag else "") + ") except -1:",
               '    """update_batch over the prepared float32 arrays into ``result``\'s arrays, the GIL released;',
               "    raises for the first bad sample (naming it), with the state untouched.\"\"\"",
               "    cdef Py_ssize_t n = accel.shape[0]", "    cdef Py_ssize_t dt_step = 1 if dt_is_array else 0",
               "    cdef Py_ssize_t bad = -1"]
        out += [f"    cdef {_memoryview(ctype, dims)} out_{name} = result.{name}" for name, ctype, dims, _ in loop.outputs]
        call = ["state", "n", "&accel[0]", "&baro[0]", "&dt[0], dt_step"] + ([loop.flag] if loop.flag else [])
        out += ["    if n == 0:", "        return 0", "    with nogil:",
                f"        bad = _run({', '.join(call + outputs)})",
                "    if bad >= 0:",
                "        a, z, t = float(accel[bad]), float(baro[bad]), float(dt[bad * dt_step])",
                f"        {loop.raise_error}({MODULES[module][1]}CheckInputs(a, z, t), a, z, t, bad, dt_is_array)",
                "    return 0", "", ""]
        return out
    out = [f"cdef Py_ssize_t _batch_into({state} *state, Py_ssize_t n, dict inputs, dict steps, object result) "
           "except -2:",
           '    """update_batch over the glue\'s prepared ``inputs`` (each with its step in ``steps``) into ``result``\'s',
           '    arrays, the GIL released: the index of the first rejected sample (the state untouched), or -1."""']
    out += [f"    cdef {_memoryview(ctype, 1, True)} {pointer} = inputs[\"{name}\"]" for name, ctype, pointer in loop.inputs]
    out += [f"    cdef Py_ssize_t s_{pointer} = steps[\"{name}\"]" for name, _, pointer in loop.inputs]
    out += [f"    cdef {_memoryview(ctype, dims)} out_{name} = result.{name}" for name, ctype, dims, _ in loop.outputs]
    call = ["state", "n"] + [f"&{pointer}[0], s_{pointer}" for _, _, pointer in loop.inputs]
    out += ["    cdef Py_ssize_t bad = -1", "    if n == 0:", "        return -1", "    with nogil:",
            f"        bad = _run({', '.join(call + outputs)})", "    return bad", "", ""]
    return out


def batch_functions(module: str) -> List[str]:
    """The batch loop of ``module`` (:data:`BATCH_LOOPS`), or nothing (the INS writes its own)."""
    loop = BATCH_LOOPS.get(module)
    if loop is None:
        return []
    cimports = ["from libc.string cimport memcpy", "", ""] if loop.copy_by_memcpy else []
    return cimports + _batch_run(module, loop) + _batch_into(module, loop)


def generate_pxi(module: str, header: Header) -> str:
    """``_<module>_fields.pxi``: the imports, enums, settings conversions, state layout, getters, checkpoint
    functions and class docstring of one binding, included at the top of ``_<module>.pyx``."""
    _, prefix, settings, state = MODULES[module]
    out = [GENERATED.rstrip(), f"# Included at module level by fusion_altitude/_core/_{module}.pyx, after its own cimports.",
           ""]
    out += binding_preamble(module) + enum_values(module, header) + settings_conversions(header, settings)
    fields = header.structs[settings]
    nested = fields[0].ctype in header.structs and bool(fields[0].dims)  # per-sensor settings: a hand-written form
    out += [f"def {'_c_default_settings' if nested else 'c_default_settings'}():",
            f'    """{settings}Default(), from C, in the form :func:`_settings_from_c` gives."""',
            f"    cdef {settings} c = {settings}Default()",
            "    return _settings_from_c(&c)", "", "",
            f"def c_settings_check(values):",
            f'    """{settings}Check of the settings ``values`` (as :func:`_settings_to_c` takes them): the status, from C."""',
            f"    cdef {settings} c = _settings_to_c(values)",
            f"    return int({settings}Check(&c))", "", ""]
    out += state_functions(header, state, settings)
    out += getter_class(module, header, state) + checkpoint_functions(module)
    out += batch_functions(module)
    return "\n".join(out + class_doc(module)).rstrip() + "\n"


def _reference_module(module: str):
    """``fusion_altitude.reference.<module>``, imported from this checkout."""
    import importlib
    sys.path.insert(0, str(ROOT))
    try:
        return importlib.import_module(f"fusion_altitude.reference.{module}")
    finally:
        sys.path.pop(0)


def class_doc(module: str) -> List[str]:
    """``DOC_<Estimator>``: the reference class's docstring, written once there; the binding's class takes it as its
    ``__doc__`` (``__doc__ = DOC_<Estimator>`` in the ``cdef class`` body: an extension type's docstring cannot be
    set after the class is made)."""
    name = ESTIMATORS[module]
    doc = getattr(_reference_module(module), name).__doc__
    if not doc:
        raise SystemExit(f"fusion_altitude/reference/{module}.py: {name} has no docstring")
    literal = f'"""{doc}"""' if '"""' not in doc and "\\" not in doc and not doc.endswith('"') else repr(doc)
    return ["", "", f"#: The docstring of {name} (binding and reference), from fusion_altitude/reference/{module}.py.",
            f"DOC_{name} = {literal}", ""]


def _struct_get(header: Header, ctype: str, access: str) -> str:
    """Python expression of a C value: a scalar, or a struct as the tuple of its fields in order (recursively)."""
    if ctype in header.structs:
        return "(" + "".join(f"{_struct_get(header, g.ctype, f'{access}.{g.name}')}, "
                             for g in header.structs[ctype]).rstrip() + ")"
    return _py_of(_kind(header, ctype), access)


def _struct_set(header: Header, ctype: str, access: str, value: str) -> List[str]:
    """Statements assigning the Python value (a tuple for a struct, recursively) to the C lvalue ``access``."""
    if ctype in header.structs:
        lines = []
        for k, g in enumerate(header.structs[ctype]):
            lines += _struct_set(header, g.ctype, f"{access}.{g.name}", f"{value}[{k}]")
        return lines
    cast = f"<{ctype}><int>" if ctype in header.enums else ""
    return [f"    {access} = {cast}{value}"]


def _kind(header: Header, ctype: str) -> str:
    if ctype in header.enums:
        return "e"
    return SCALAR_KINDS[ctype]


def state_functions(header: Header, state: str, settings: str) -> List[str]:
    """``_state_get``/``_state_set``: the state struct as a tuple of its fields, in order."""
    get = [f"cdef tuple _state_get(const {state} *c, object settings_out):",
           f'    """{state} → tuple of its fields in order; settings as ``settings_out(_settings_from_c(...))``,',
           '    arrays as lists, arrays of structs as tuples of tuples."""',
           "    cdef int i, j", "    return ("]
    put = [f"cdef void _state_set({state} *c, tuple state, object settings_in) except *:",
           f'    """tuple from :func:`_state_get` → {state}; ``settings_in`` checks the settings entry and returns',
           '    what :func:`_settings_to_c` takes."""',
           "    cdef int i, j", "    cdef tuple row",
           f"    ({', '.join('_' + f.python for f in header.structs[state])},) = state"]
    for f in header.structs[state]:
        var = "_" + f.python
        if f.ctype == settings:
            get.append(f"        settings_out(_settings_from_c(&c.{f.name})),")
            put.append(f"    c.{f.name} = _settings_to_c(settings_in({var}))")
        elif f.ctype in header.structs and not f.dims:  # a struct: the tuple of its fields, recursively
            get.append(f"        {_struct_get(header, f.ctype, 'c.' + f.name)},")
            put += _struct_set(header, f.ctype, "c." + f.name, var)
        elif f.ctype in header.structs:
            sub = header.structs[f.ctype]
            count = header.defines.get(f.dims[0], f.dims[0])
            items = ", ".join(_py_of(_kind(header, s.ctype), f"c.{f.name}[i].{s.name}") for s in sub)
            get.append(f"        tuple([({items},) for i in range({count})]),")
            put.append(f"    for i in range({count}):")
            put.append(f"        row = tuple({var}[i])")
            for k, s in enumerate(sub):
                cast = f"<{s.ctype}><int>" if s.ctype in header.enums else ""
                put.append(f"        c.{f.name}[i].{s.name} = {cast}row[{k}]")
        elif len(f.dims) == 1:
            count = header.defines.get(f.dims[0], f.dims[0])
            get.append(f"        [{_py_of(_kind(header, f.ctype), f'c.{f.name}[i]')} for i in range({count})],")
            put += [f"    for i in range({count}):", f"        c.{f.name}[i] = {var}[i]"]
        elif len(f.dims) == 2:
            rows = header.defines.get(f.dims[0], f.dims[0])
            cols = header.defines.get(f.dims[1], f.dims[1])
            get.append(f"        [c.{f.name}[i][j] for i in range({rows}) for j in range({cols})],")
            put += [f"    for i in range({rows}):", f"        for j in range({cols}):",
                    f"            c.{f.name}[i][j] = {var}[i * {cols} + j]"]
        else:
            get.append(f"        {_py_of(_kind(header, f.ctype), 'c.' + f.name)},")
            cast = f"<{f.ctype}><int>" if f.ctype in header.enums else ""
            put.append(f"    c.{f.name} = {cast}{var}")
    get.append("    )")
    return get + ["", ""] + put + [""]


# -- c<module>.pxd -----------------------------------------------------------------------------------------------

#: The .pxd of each module's header.
PXD_NAMES = {"observer": "cobserver.pxd", "kalman": "ckalman.pxd", "complementary": "ccomplementary.pxd",
             "alphabeta": "calphabeta.pxd", "ins": "cins.pxd", "rocket": "crocket.pxd"}


def _cython_type(ctype: str) -> str:
    ctype = re.sub(r"\*\s*const\b", "*", ctype.strip())
    ctype = re.sub(r"\bbool\b", "bint", ctype)
    return re.sub(r"\s+", " ", ctype).replace(" *", " *").strip()


def generate_pxd(module: str, header: Header, pxi: str) -> str:
    """Cython declarations of one header: its numeric #defines, enums, structs, and the functions the binding
    calls (``_<module>.pyx`` and its generated ``.pxi``; internal helpers stay undeclared), in header order."""
    used = set(re.findall(r"\b(FusionAltitude\w+)\(", (PACKAGE / f"_{module}.pyx").read_text() + pxi))
    text = header.path.read_text()
    own = parse_header(header.path)
    code = _strip_comments(text)
    out = [GENERATED.rstrip(), "# cython: language_level=3",
           f'"""Declarations of csrc/{header.path.name}, and nothing else."""', "",
           "from libc.stdint cimport int32_t, uint8_t, uint32_t", ""]
    foreign = sorted({f.ctype for fields in own.structs.values() for f in fields
                      if f.ctype in header.structs and f.ctype not in own.structs})
    if foreign:  # structs of fusion_altitude.h that this header's structs hold
        out += [f"from {PACKAGE_NAME}.cobserver cimport {', '.join(foreign)}", ""]
    out += ["", f'cdef extern from "{header.path.name}" nogil:']
    for name, value in re.findall(r"^#define\s+(FUSION_ALTITUDE_\w+)\s+\(([-\d.e]+f?)\)\s*$", text, flags=re.M):
        out.append(f"    {'float' if value.endswith('f') else 'int'} {name}")
    for match in re.finditer(r"typedef (enum|struct) \{(.*?)\} (\w+);", code, flags=re.S):
        kind, name = match.group(1), match.group(3)
        out += ["", f"    ctypedef {kind} {name}:"]
        if kind == "enum":
            out += [f"        {member}" for member, _ in own.enums[name].members]
        else:
            for f in own.structs[name]:
                dims = "".join(f"[{header.defines.get(d, d)}]" for d in f.dims)
                out.append(f"        {_cython_type(f.ctype)} {f.name}{dims}")
    out.append("")
    for ret, name, params in re.findall(r"static inline\s+((?:const\s+)?\w+(?:\s*\*)?)\s*(FusionAltitude\w+)\(([^)]*)\)\s*\{",
                                        code):
        if name not in used:
            continue
        args = [] if params.strip() == "void" else [_cython_type(re.sub(r"(\w+)\s*\[\w*\]$", r"*\1", p.strip()))
                                                    for p in params.split(",")]
        out.append(f"    {_cython_type(ret)} {name}({', '.join(args)})")
    return "\n".join(out) + "\n"


#: The bindings whose ``settings`` property has the plain form (read the struct, assign a checked settings object).
SETTINGS_PROPERTY = ("kalman", "complementary", "ins")


def settings_property(module: str, header: Header, state: str) -> List[str]:
    """The ``settings`` property: the settings class from the struct; assigning one sets the struct (the settings
    class checked it with the same C check; a rejection raises ``_settings_error(status, values)``)."""
    _, prefix, settings, _ = MODULES[module]
    name = SETTINGS_CLASSES[module]
    return ["", "    @property", "    def settings(self):",
            f'        """The settings (:class:`{name}`); assign new ones to retune, keeping the state."""',
            f"        return {name}(**_settings_from_c(&self._c.settings))", "",
            "    @settings.setter", "    def settings(self, settings):",
            f"        cdef {settings} c = _settings_to_c({name}.coerce(settings).as_dict())",
            f"        cdef int status = <int>{prefix}SetSettings(&self._c, &c)",
            "        if status != 0:",
            "            _settings_error(status, _settings_from_c(&c))"]


#: The bindings whose ``__init__`` is ``…Initialise`` and then ``self.settings = settings`` (given one): ``_initialise``.
PLAIN_INIT = ("observer", "complementary")


def getter_class(module: str, header: Header, state: str) -> List[str]:
    """``cdef class _<Estimator>Getters(Estimator)``: the state struct and one property per scalar getter of the
    header (``...Get<Name>(const State *)``, ``...Is<Name>(const State *)``); the estimator derives from it."""
    getters = [g for g in header.getters if g.cname.startswith(MODULES[module][1]) and _takes(header, g, state)]
    out = ["", "", f"cdef class _{ESTIMATORS[module]}Getters(Estimator):",
            f'    """The state (``{state}``) and a property per getter of {header.path.name}."""', "",
            f"    cdef {state} _c"]
    for g in getters:
        doc = g.doc.replace('"', "'").replace("\\", "\\\\")
        out += ["", "    @property", f"    def {g.python}(self):", f'        """{doc}"""',
                f"        return {g.cname}(&self._c)"]
    if module in SETTINGS_PROPERTY:
        out += settings_property(module, header, state)
    if module in PLAIN_INIT:  # what the estimator's __init__ does: the header's start state, then the settings
        out += ["", "    cdef int _initialise(self, settings) except -1:",
                f'        """{MODULES[module][1]}Initialise, then ``settings`` if given (the ``settings`` setter checks them)."""',
                f"        {MODULES[module][1]}Initialise(&self._c)",
                "        if settings is not None:", "            self.settings = settings", "        return 0"]
    return out + ["", "    def _get_state(self):",
                  f'        """The fields of {state} in order (the settings as ``as_dict()``)."""',
                  "        return _state_get(&self._c, _settings_out)", "",
                  "    def _set_state(self, state):",
                  f'        """A ``_get_state()`` (binding or reference) into {state}, the settings checked."""',
                  "        _state_set(&self._c, tuple(state), _checked_settings)", ""]


def _takes(header: Header, getter: Getter, state: str) -> bool:
    text = header.path.read_text()
    return re.search(rf"{getter.cname}\(const {state} \*const", text) is not None


# -- _<module>.pyi -----------------------------------------------------------------------------------------------

#: Module-level functions each ``_<module>.pyx`` writes by hand (beyond the generated ones), as stub lines.
EXTRA_STUBS = {
    "observer": ["GRAVITY: float", "C_GRAVITY: float", "C_VERSION: int",
                 "def status_message(status: int) -> str: ...",
                 "def c_settings_from_bandwidth(omega: float, zeta: float, omega_b: float)"
                 " -> Tuple[int, Optional[Dict[str, float]]]: ...",
                 "def c_settings_from_preset(preset: int) -> Dict[str, float]: ...",
                 "def c_settings_validate(values: Mapping[str, float], dt: float) -> int: ...",
                 "def c_gains_check(position_gain: float, velocity_gain: float, bias_gain: float) -> int: ..."],
    "kalman": ["def kalman_status_message(status: int) -> str: ..."],
    "complementary": ["def status_message(status: int) -> str: ..."],
    "alphabeta": ["C_SENSOR_COUNT: int", "C_MAX_QUALITY: int", "def status_message(status: int) -> str: ...",
                  "def gains(quality: int) -> Tuple[float, float]: ...",
                  "def c_default_settings() -> Dict[str, AlphaBetaSensorSettings]: ...",
                  "def c_sensor_settings_check(sensor: AlphaBetaSensorSettings) -> int: ...",
                  "def c_gap_period_check(gap_period: float) -> int: ..."],
    "ins": [],
    "rocket": ["C_MACH_LOCKOUT: float", "C_NUMBER_OF_EVENTS: int", "def status_message(status: int) -> str: ..."],
}


def _stub_signature(name: str, function, indent: str = "    ") -> List[str]:
    import inspect
    signature = inspect.signature(function)
    parts = []
    star = False
    for parameter in signature.parameters.values():
        text = parameter.name
        if parameter.kind is parameter.VAR_POSITIONAL:
            text, star = "*" + text, True
        elif parameter.kind is parameter.VAR_KEYWORD:
            text = "**" + text
        elif parameter.kind is parameter.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        if parameter.annotation is not parameter.empty:
            text += f": {parameter.annotation}"
        if parameter.default is not parameter.empty:
            text += " = ..."
        parts.append(text)
    returns = "" if signature.return_annotation is signature.empty else f" -> {signature.return_annotation}"
    return [f"{indent}def {name}({', '.join(parts)}){returns}: ..."]


def generate_stub(module: str, header: Header) -> str:
    """The stub of ``_<module>``: generated names, the hand-written extras, and the estimator class with the
    reference class's public signatures (the contract tests hold the binding to the same parameters)."""
    import inspect
    reference = _reference_module(module)
    estimator = getattr(reference, ESTIMATORS[module])
    settings_name = f"{ESTIMATORS[module].replace('Estimator', '').replace('Filter', '').replace('Fusion', '')}Settings"
    settings_name = "AltitudeSettings" if module == "observer" else settings_name
    body = []
    for name in sorted(n for n in dir(estimator) if not n.startswith("_")):
        member = inspect.getattr_static(estimator, name)
        if isinstance(member, property):
            body.append("    @property")
            body += _stub_signature(name, member.fget)
            if member.fset is not None:
                body.append(f"    @{name}.setter")
                body += _stub_signature(name, member.fset)
        elif isinstance(member, classmethod):
            body.append("    @classmethod")
            body += _stub_signature(name, member.__func__)
        elif callable(member):
            body += _stub_signature(name, member)
    body += _stub_signature("__init__", estimator.__init__)
    text = "\n".join(body)
    local = {n: v for n, v in vars(reference).items() if isinstance(v, type)}
    used = sorted(n for n in set(re.findall(r"\b([A-Z]\w*)\b", text + " ".join(EXTRA_STUBS[module])))
                  if n in local and n != estimator.__name__)
    lines = [GENERATED.rstrip(),
             f'"""Type stubs for the Cython binding of csrc/{MODULES[module][0]} (generated: the signatures are',
             f'the reference\'s, :mod:`fusion_altitude.reference.{module}`)."""', "",
             "from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union", "",
             "import numpy as np", ""]
    lines += [f"from {_relative_to_package(local[n].__module__)} import {n} as {n}"
              for n in used if local[n].__module__.startswith("fusion_altitude")]
    if settings_name not in used:
        lines.append(f"from ..reference.{module} import {settings_name} as {settings_name}")
    lines.append("")
    enum_lines = [line for line in generate_pxi(module, header).splitlines() if re.match(r"C_\w+_VALUES = ", line)]
    lines += [f"{line.split(' = ')[0]}: Dict[str, int]" for line in enum_lines]
    lines += EXTRA_STUBS[module]
    lines += ["def c_status_message(status: int) -> str: ...", "def c_settings_check(values: Any) -> int: ..."]
    if module != "alphabeta":
        lines.append("def c_default_settings() -> Dict[str, Any]: ...")
    lines += ["", "", f"class {estimator.__name__}:"]
    return "\n".join(lines) + "\n" + text + "\n"


# -- the firmware Makefile's estimators -------------------------------------------------------------------------

FIRMWARE_ESTIMATORS = CSRC / "firmware" / "estimators.mk"


def generate_estimators_mk() -> str:
    """``csrc/firmware/estimators.mk``: the estimators of :data:`MODULES`, included by ``csrc/firmware/Makefile``.

    Per estimator: its name (``ESTIMATORS``, in :data:`MODULES` order), its header (``HEADER_<name>``) and the
    function its RISC-V and AVR step counts wrap (``STEP_FUNCTION_<name>``: ``Sized<prefix>Update`` of
    ``sized_<name>.c``)."""
    lines = ["# Generated by tools/generate_bindings.py from its MODULES -- do not edit; run the script instead.",
             "# The estimators of csrc/firmware/Makefile: name, header, the Update function the step counts wrap.",
             "ESTIMATORS := " + " ".join(MODULES)]
    lines += [f"HEADER_{module} := $(CSRC)/{header}" for module, (header, *_) in MODULES.items()]
    lines += [f"STEP_FUNCTION_{module} := Sized{prefix}Update" for module, (_, prefix, *_) in MODULES.items()]
    return "\n".join(lines) + "\n"


# -- main ---------------------------------------------------------------------------------------------------------

def generate() -> Dict[Path, str]:
    """Every generated file's path and text."""
    base = parse_header(CSRC / "fusion_altitude.h")
    headers = {m: parse_header(CSRC / h, base) for m, (h, *_) in MODULES.items()}
    defaults, messages = read_from_c(headers)
    files = {PACKAGE / "_c_tables.py": generate_tables(headers, defaults, messages)}
    for module in MODULES:
        files[PACKAGE / f"_{module}_fields.pxi"] = generate_pxi(module, headers[module])
        files[PACKAGE / f"_{module}.pyi"] = generate_stub(module, headers[module])
        files[PACKAGE / PXD_NAMES[module]] = generate_pxd(module, headers[module],
                                                          files[PACKAGE / f"_{module}_fields.pxi"])
    files.update(settings_words.generate(headers, MODULES, CSRC))
    files[FIRMWARE_ESTIMATORS] = generate_estimators_mk()
    exports = package_init.estimator_exports(MODULES, ESTIMATORS, SETTINGS_CLASSES, ENUM_NAMES)
    files.update(package_init.generate(ROOT / "fusion_altitude", exports))
    return files


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if a generated file differs from the headers")
    args = parser.parse_args(argv)
    stale = []
    for path, text in generate().items():
        current = path.read_text() if path.exists() else ""
        if current == text:
            continue
        if args.check:
            stale.append(path)
            sys.stdout.writelines(difflib.unified_diff(current.splitlines(True), text.splitlines(True),
                                                       str(path.relative_to(ROOT)), "generated"))
        else:
            path.write_text(text)
            print(f"wrote {path.relative_to(ROOT)}")
    if stale:
        print(f"stale: {', '.join(str(p.relative_to(ROOT)) for p in stale)}; run python tools/generate_bindings.py",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
