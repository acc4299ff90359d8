"""ArduPilot DataFlash messages decoded at memory speed: one C pass finds every message
(:func:`fusion_altitude.logs._decode.dataflash_index`, the walk of pymavlink's indexer), then the
asked-for types are gathered and read as numpy structured arrays, one column per field.

The values are those pymavlink's ``DFMessage.to_dict`` gives, bit for bit: integers as they are,
``c``/``C``/``e``/``E`` divided by 100, ``L`` by 10⁷, floats widened to float64; the messages are
those pymavlink's ``recv_match(type=...)`` returns (a message cut off by the end of the file, and
everything after it, is not read).

Logs whose reading depends on pymavlink's internals beyond that (bytes that start no message,
types redefined by a second FMT, two types of one name, a field the reader uses that holds text,
FMT/FMTU content that makes pymavlink raise) are declined with :class:`NeedsReference`, and the
caller reads them with pymavlink, so the result is the same either way.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Dict, Iterable, List, Sequence

import numpy as np

#: Format characters: (numpy dtype, multiplier as pymavlink's FORMAT_TO_STRUCT has it).
FORMAT_CHARS = {
    "a": ("V64", None), "b": ("<i1", None), "B": ("<u1", None), "g": ("<f2", None), "h": ("<i2", None),
    "H": ("<u2", None), "i": ("<i4", None), "I": ("<u4", None), "f": ("<f4", None), "n": ("S4", None),
    "N": ("S16", None), "Z": ("S64", None), "c": ("<i2", 0.01), "C": ("<u2", 0.01), "e": ("<i4", 0.01),
    "E": ("<u4", 0.01), "L": ("<i4", 1.0e-7), "d": ("<f8", None), "M": ("<i1", None), "q": ("<i8", None),
    "Q": ("<u8", None),
}
#: Bytes of each format character.
_SIZES = {char: np.dtype(kind).itemsize for char, (kind, _) in FORMAT_CHARS.items()}
#: Characters whose values are text (or pymavlink's int16 array): not numbers.
TEXT_CHARS = set("anNZ")
#: Types pymavlink's ``recv_match`` always walks besides the asked-for ones (it stops at the first cut-off one).
ALWAYS_WALKED = ("MODE", "MSG", "PARM", "STAT", "ORGN", "VER")
#: Fields pymavlink's clocks and message bookkeeping compute with: text in them makes it skip messages.
CLOCK_FIELDS = {"TimeUS", "TimeMS", "T", "Week", "GWk", "GMS", "Wk", "TWk", "GPSTime", "StartTime", "ModeNum",
                "MainState", "Default", "BU"}


class NeedsReference(Exception):
    """The log needs pymavlink's own reading to give the same result (the reason is the message)."""


_DECODE = None
#: Structured dtype of each format string met so far (a function of the string alone, so kept between logs).
_DTYPES: Dict[str, np.dtype] = {}


def decoder_module():
    """The compiled scanners (``fusion_altitude.logs._decode``); NeedsReference if the extension is not built
    (a source checkout without ``build_ext``: the reference libraries read every log then)."""
    global _DECODE
    if _DECODE is not None:
        return _DECODE
    try:
        # the compiled submodule itself (grimp, which has no source for an extension, would read a static
        # import as one of this package's __init__)
        decode = importlib.import_module(f"{__package__}._decode")
    except ImportError:
        raise NeedsReference("the extension fusion_altitude.logs._decode is not built") from None
    _DECODE = decode
    return decode


def _null_term(raw: bytes) -> str:
    """pymavlink's ``null_term`` of bytes: decoded with backslash escapes, cut at the first NUL."""
    text = raw.decode(errors="backslashreplace")
    cut = text.find("\0")
    return text if cut == -1 else text[:cut]


class Format:
    """One FMT message: type number, name, length (bytes, header included), format characters, columns."""

    def __init__(self, type_id: int, name: str, length: int, chars: str, columns: Sequence[str]) -> None:
        self.type_id, self.name, self.length, self.chars = type_id, name, length, chars
        self.columns = list(columns)
        # (the characters, the length and the column count were checked in C by _decode.dataflash_formats)
        self.colhash = dict(zip(self.columns, range(len(self.columns))))
        self._dtype = None
        #: Whether every column name is a word of letters, digits and "_" (checked in C).
        self.columns_are_words = True

    @property
    def columns_once(self) -> List[str]:
        """The column names, each once, in order (the keys of pymavlink's ``to_dict`` after its type name)."""
        return list(self.colhash)

    @property
    def dtype(self) -> np.dtype:
        """The structured dtype of a body (fields f0, f1, … in format order), built when first asked for."""
        if self._dtype is None:
            self._dtype = _DTYPES.get(self.chars)
            if self._dtype is None:
                self._dtype = np.dtype([(f"f{k}", FORMAT_CHARS[c][0]) for k, c in enumerate(self.chars)])
                if len(_DTYPES) < 4096:
                    _DTYPES[self.chars] = self._dtype
        return self._dtype

    def char_of(self, field: str) -> str:
        """Format character of ``field``."""
        return self.chars[self.colhash[field]]


class Formats(Mapping):
    """type → :class:`Format` of a log's FMT messages, each built from its raw fields when first asked for."""

    def __init__(self, raw: Dict[int, tuple]) -> None:
        self._raw = raw
        self._built: Dict[int, Format] = {}

    def __getitem__(self, type_id: int) -> Format:
        fmt = self._built.get(type_id)
        if fmt is None:
            # the fields are cut at their first NUL already, so pymavlink's null_term is the decoding alone
            name, length, chars, columns, words = self._raw[type_id]
            fmt = Format(type_id, name, length, chars.decode("utf-8", "backslashreplace"),
                         columns.decode("utf-8", "backslashreplace").split(",") if columns else [])
            fmt.columns_are_words = words
            self._built[type_id] = fmt
        return fmt

    def __iter__(self):
        return iter(self._raw)

    def __len__(self) -> int:
        return len(self._raw)


class DataFlashIndex:
    """The messages of a DataFlash log: where each starts, of which type, and the formats (from FMT)."""

    def __init__(self, data, path: str) -> None:
        _decode = decoder_module()
        self.data = np.frombuffer(data, dtype=np.uint8)
        self.size = self.data.size
        self.path = path
        offsets, types, bad, status, stop, lengths = _decode.dataflash_index(self.data)
        if status != "ok":
            # pymavlink's indexer ends the program here (exit status 1); the fast reader refuses the log
            raise ValueError(f"{status} at byte {stop} (where pymavlink's indexer stops the program)")
        if bad:
            raise NeedsReference(f"{bad} bytes start no message")
        self.offsets, self.types = offsets, types
        self.final_lengths = lengths
        self._read_formats()
        self._check_units()

    def check_clock(self, names: Iterable[str]) -> None:
        """Decline logs in which pymavlink's clock or bookkeeping would fail on a message it reads (it prints
        "bad msg", which the reader counts): odd column names (bit flips), text in a time field, GPS messages
        without the partner of their week field, without any week field (its GPS-interpolated clock multiplies
        a missing week) or without a boot time."""
        for name in set(names) | set(ALWAYS_WALKED):
            if name not in self.name_to_id:
                continue
            fmt = self.formats[self.name_to_id[name]]
            if fmt.columns and not fmt.columns_are_words:
                raise NeedsReference(f"{name}: a column name that is not a word")
            for column_name in CLOCK_FIELDS.intersection(fmt.colhash):
                if fmt.char_of(column_name) in TEXT_CHARS:
                    raise NeedsReference(f"{name}.{column_name} holds text")
            if name in ("GPS", "GPS2"):
                have = set(fmt.columns)
                if ("Week" in have and "TimeMS" not in have) or \
                        ("Week" not in have and "GWk" in have and "GMS" not in have) or \
                        ("Week" not in have and "GWk" not in have and "Wk" in have and "TWk" not in have) or \
                        ("Week" not in have and "GWk" not in have and "Wk" not in have and "GPSTime" not in have) or \
                        ("T" not in have and "TimeUS" not in have):
                    raise NeedsReference(f"{name}: a GPS time pymavlink's clock cannot read")

    def missing_bytes(self, blob: bytes):
        """:func:`_truncation.dataflash_missing_bytes` of the log, walking only from its last message on."""
        from ._truncation import dataflash_missing_bytes
        if not self.offsets.size:
            return dataflash_missing_bytes(self.path, blob)
        lengths = {k: int(v) for k, v in enumerate(self.final_lengths.tolist()) if v}
        return dataflash_missing_bytes(self.path, blob, int(self.offsets[-1]), lengths)

    def _bodies(self, type_id: int, length: int) -> np.ndarray:
        _decode = decoder_module()
        offsets = np.ascontiguousarray(self.offsets[self.types == type_id])
        bodies, _ = _decode.dataflash_gather(self.data, offsets, length)
        return offsets, bodies

    def _read_formats(self) -> None:
        """The FMT messages, in file order, as pymavlink's indexer reads them (it stops at a cut-off one): checked
        in C (:func:`_decode.dataflash_formats`), made :class:`Format` objects only when a type is asked for."""
        fmt_offsets = np.ascontiguousarray(self.offsets[self.types == 0x80])
        problem, raw, self.name_to_id, self.lengths = decoder_module().dataflash_formats(self.data, fmt_offsets)
        if problem is not None:
            raise NeedsReference(problem)
        self.formats = Formats(raw)
        present = np.bincount(self.types, minlength=256).astype(bool)
        present[0x80] = False
        present[list(raw)] = False
        if present.any():
            raise NeedsReference(f"messages of type {int(np.flatnonzero(present)[0])} without a readable FMT")

    def _check_units(self) -> None:
        """FMTU/UNIT/MULT only name units (no value changes), but odd ones make pymavlink raise: decline those."""
        if "FMTU" in self.name_to_id:
            fmtu = self.formats[self.name_to_id["FMTU"]]
            for char in ("UnitIds", "MultIds"):
                if char in fmtu.colhash and fmtu.char_of(char) not in "nNZ":
                    raise NeedsReference(f"FMTU.{char} is not text")
            if "MultIds" in fmtu.colhash and "UnitIds" not in fmtu.colhash:
                raise NeedsReference("FMTU with multipliers but no units")
            if "UnitIds" in fmtu.colhash:
                if len(fmtu.columns) < 2 or fmtu.chars[1] in TEXT_CHARS:
                    raise NeedsReference("FMTU without a numeric second field")
                fields = [fmtu.columns[1]] + [c for c in ("UnitIds", "MultIds") if c in fmtu.colhash]
                for record in self.records("FMTU", fields):
                    target = self.formats.get(int(record[fmtu.columns[1]]))  # pymavlink: int(elements[1])
                    if target is None:
                        continue
                    if "#" in record["UnitIds"]:
                        raise NeedsReference("FMTU with an instance field")
                    if "MultIds" in record and len(record["MultIds"]) < len(target.columns):
                        raise NeedsReference("FMTU with fewer multipliers than columns")
        for name in ("UNIT", "MULT"):
            if name in self.name_to_id:
                chars = self.formats[self.name_to_id[name]].chars
                if len(chars) < 3 or chars[1] in TEXT_CHARS or chars[2] in TEXT_CHARS:
                    raise NeedsReference(f"{name} without numeric second and third fields")

    def messages(self, names: Iterable[str]):
        """Offsets and types of the messages pymavlink's ``recv_match(type=names)`` returns, in file order."""
        wanted = np.zeros(256, dtype=bool)
        wanted[[self.name_to_id[n] for n in set(names) | set(ALWAYS_WALKED) if n in self.name_to_id]] = True
        mask = wanted[self.types]
        offsets, types = self.offsets[mask], self.types[mask]
        cut = np.flatnonzero(offsets + self.lengths[types] > self.size)
        if cut.size:  # pymavlink returns None at a message cut off by the end: nothing after it is read
            offsets, types = offsets[:cut[0]], types[:cut[0]]
        return offsets, types

    def records(self, name: str, fields: Sequence[str]) -> List[dict]:
        """Text-friendly, slow path for a few messages: the ``fields`` of every ``name`` message as dicts."""
        type_id = self.name_to_id[name]
        fmt = self.formats[type_id]
        offsets, bodies = self._bodies(type_id, fmt.length)
        complete = offsets + fmt.length <= self.size
        table = bodies[complete].view(fmt.dtype).reshape(-1)
        out = []
        for row in table:
            out.append({field: _python_value(fmt, field, row[f"f{fmt.colhash[field]}"]) for field in fields})
        return out


def _python_value(fmt: Format, field: str, value):
    """A value as pymavlink's ``DFMessage.__getattr__`` gives it (text decoded, multiplier applied)."""
    char = fmt.char_of(field)
    if char in "nNZ":
        raw = bytes(value)
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            text = raw.decode("ISO-8859-1")
        cut = text.find("\0")
        return text if cut == -1 else text[:cut]
    if char == "a":
        return bytes(value)
    multiplier = FORMAT_CHARS[char][1]
    if multiplier is None:
        return value.item()
    if 0.0 < multiplier < 1.0:
        return float(value) / (1 / multiplier)
    return float(value) * multiplier


def column(fmt: Format, table: np.ndarray, field: str) -> np.ndarray:
    """One numeric field of a structured table as float64, the value pymavlink gives converted to float."""
    char = fmt.char_of(field)
    if char in TEXT_CHARS:
        raise NeedsReference(f"{fmt.name}.{field} holds text")
    values = table[f"f{fmt.colhash[field]}"].astype(np.float64)
    multiplier = FORMAT_CHARS[char][1]
    if multiplier is not None:
        if 0.0 < multiplier < 1.0:
            values /= 1 / multiplier
        else:
            values *= multiplier
    return values


class ArrayRows:
    """The messages of one reader family (e.g. IMU and IMU2), in file order, as float64 columns.

    The same questions as a list of pymavlink dicts answers: ``len``, the fields of the first message,
    a column (NaN where a message's type lacks the field), the time stamps (``_time_of``)."""

    def __init__(self, parts: List[tuple], fields_used: Sequence[str]) -> None:
        # parts: (offsets, fmt, table) per type, merged here by offset
        self.first_fields: List[str] = []
        if not parts:
            self.order = np.zeros(0, dtype=np.intp)
            self.size = 0
            self.columns: Dict[str, np.ndarray] = {}
            self.time = np.zeros(0)
            return
        if len(parts) == 1:  # one type: already in file order
            self._one_part(*parts[0], fields_used)
            return
        offsets = np.concatenate([p[0] for p in parts])
        # several types (IMU and IMU2): merged by offset
        order = np.argsort(offsets, kind="stable")
        self.size = offsets.size
        first_part = int(np.searchsorted(np.cumsum([p[0].size for p in parts]), order[0], side="right"))
        # as pymavlink's to_dict: its type name first, then each column once
        self.first_fields = ["mavpackettype"] + list(parts[first_part][1].colhash)
        self.columns = {}
        for field in fields_used:
            if not any(field in fmt.colhash for _, fmt, _ in parts):
                continue
            pieces = [column(fmt, table, field) if field in fmt.colhash else np.full(table.size, np.nan)
                      for _, fmt, table in parts]
            self.columns[field] = np.concatenate(pieces)[order]
        pieces = [_times(fmt, table) for _, fmt, table in parts]
        self.time = np.concatenate(pieces)[order]

    def _one_part(self, offsets: np.ndarray, fmt: Format, table: np.ndarray, fields_used: Sequence[str]) -> None:
        """The rows of a family of one message type (no merge)."""
        self.size = offsets.size
        self.first_fields = ["mavpackettype"] + fmt.columns_once
        self.columns = {field: column(fmt, table, field) for field in fields_used if field in fmt.colhash}
        self.time = _times(fmt, table, self.columns)

    def __len__(self) -> int:
        return self.size

    def has(self, field: str) -> bool:
        return field in self.first_fields

    def values(self, field: str) -> np.ndarray:
        return self.columns.get(field, np.full(self.size, np.nan))

    def times(self) -> np.ndarray:
        return self.time

    def truthy(self, field: str) -> np.ndarray:
        return self.values(field) != 0

    def keep(self, mask: np.ndarray) -> "ArrayRows":
        self.columns = {k: v[mask] for k, v in self.columns.items()}
        self.time = self.time[mask]
        self.size = int(np.count_nonzero(mask))
        return self


def _times(fmt: Format, table: np.ndarray, columns=None) -> np.ndarray:
    """``_time_of`` of every message of one type, s: TimeUS·1e-6, else GPS's T·1e-3 (with Week), else TimeMS·1e-3
    (from ``columns``, the float64 columns of ``table`` already converted, where they hold the field)."""
    columns = columns or {}
    if "TimeUS" in fmt.colhash:
        return (columns["TimeUS"] if "TimeUS" in columns else column(fmt, table, "TimeUS")) * 1e-6
    if "T" in fmt.colhash and "Week" in fmt.colhash:
        return (columns["T"] if "T" in columns else column(fmt, table, "T")) * 1e-3
    if "TimeMS" in fmt.colhash:
        return (columns["TimeMS"] if "TimeMS" in columns else column(fmt, table, "TimeMS")) * 1e-3
    return np.full(table.size, np.nan)


def read_families(index: DataFlashIndex, kinds: Sequence[str], fields_used: Sequence[str],
                  select) -> tuple:
    """The reader's rows per family and the firmware text, from the messages ``recv_match(type=kinds)`` gives.

    ``select(kind, fmt, table)`` → (family or None, boolean mask of the messages kept)."""
    index.check_clock(kinds)
    offsets, types = index.messages(kinds)
    parts: Dict[str, List[tuple]] = {}
    firmware = ""
    kind_ids = [index.name_to_id[name] for name in kinds if name in index.name_to_id]
    keep = np.zeros(256, dtype=bool)
    keep[kind_ids] = True
    keep = keep[types]
    tables = decoder_module().dataflash_tables(index.data, offsets[keep], types[keep], index.lengths)
    for type_id, (mine, bodies) in sorted(tables.items()):
        fmt = index.formats[type_id]
        table = bodies.view(fmt.dtype).reshape(-1)
        if fmt.name == "MSG":
            if "Message" in fmt.colhash:
                if fmt.char_of("Message") not in "nNZ":
                    raise NeedsReference("MSG.Message is not text")
                for row in table:
                    text = _python_value(fmt, "Message", row[f"f{fmt.colhash['Message']}"])
                    if text.startswith(("Ardu", "APM:")):
                        firmware = text  # earliest in file order wins below
                        break
                parts.setdefault("MSG", []).append((mine, fmt, table))
            continue
        for field in fmt.colhash.keys() & fields_used:
            if fmt.char_of(field) in TEXT_CHARS:
                raise NeedsReference(f"{fmt.name}.{field} holds text")
        family, mask = select(fmt.name, fmt, table)
        if family is not None and mask.all():
            parts.setdefault(family, []).append((mine, fmt, table))
        elif family is not None and mask.any():
            parts.setdefault(family, []).append((mine[mask], fmt, table[mask]))
    return parts, firmware
