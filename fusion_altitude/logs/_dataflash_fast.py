"""ArduPilot DataFlash messages decoded at memory speed: one C pass finds every message
(:func:`fusion_altitude.logs._decode.dataflash_index`, the walk of pymavlink's indexer), then the
asked-for types are gathered and read as numpy structured arrays, one column per field.

The values are those pymavlink's ``DFMessage.to_dict`` gives, bit for bit: integers as they are,
``c``/``C``/``e``/``E`` divided by 100, ``L`` by 10⁷, floats widened to float64; the messages are
those pymavlink's ``recv_match(type=...)`` returns (a message cut off by the end of the file, and
everything after it, is not read).

Bytes that start no message are stepped over as pymavlink's indexer does, and its printed reports
of them are counted as it prints them ("bad header" per byte; "Skipped N bad bytes" per run its clock
set-up walk passes, :meth:`DataFlashIndex.skipped_runs`). Logs whose reading depends on pymavlink's
internals beyond that (types redefined by a second FMT, two types of one name, a field the reader
uses that holds text, FMT/FMTU content that makes pymavlink raise) are declined with
:class:`NeedsReference`, and the caller reads them with pymavlink, so the result is the same either
way.
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Mapping
from types import MappingProxyType
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

from ._truncation import dataflash_missing_bytes

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
CLOCK_FIELDS = ("TimeUS", "TimeMS", "T", "Week", "GWk", "GMS", "Wk", "TWk", "GPSTime", "StartTime", "ModeNum",
                "MainState", "Default", "BU")
_CLOCK_FIELD_BYTES = tuple(name.encode() for name in CLOCK_FIELDS)
#: Fields of the time stamps (``_times``; all clock fields), read besides the asked-for ones.
_TIME_FIELDS = ("TimeUS", "T", "Week", "TimeMS")
#: Format characters holding text, as bytes (the field tables hold characters as numbers).
_TEXT_BYTES = frozenset(b"anNZ")
#: Length (bytes, header included) of an FMT message.
DATAFLASH_FMT_LENGTH = 89
#: Types the FMTU/UNIT/MULT checks read besides the asked-for ones.
_UNIT_NAMES = ("FMTU", "UNIT", "MULT")


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
        self._keys: Optional[frozenset] = None
        #: Whether every column name is a word of letters, digits and "_" (checked in C).
        self.columns_are_words = True

    @property
    def columns_once(self) -> List[str]:
        """The column names, each once, in order (the keys of pymavlink's ``to_dict`` after its type name)."""
        return list(self.colhash)

    @property
    def keys(self) -> frozenset:
        """The keys of pymavlink's ``to_dict`` of a message of this type (its type name, the columns), built once."""
        if self._keys is None:
            self._keys = frozenset(("mavpackettype", *self.colhash))
        return self._keys

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
    """type → :class:`Format` of a log's FMT messages of the names asked for, each built from its raw fields when
    first asked for."""

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

    def name(self, type_id: int) -> str:
        """The name of a type (without building its Format)."""
        return self._raw[type_id][0]

    def has_column(self, type_id: int, column: str) -> bool:
        """Whether a type has a column of that name (without building its Format)."""
        fmt = self._built.get(type_id)
        if fmt is not None:
            return column in fmt.colhash
        return column.encode() in self._raw[type_id][3].split(b",")

    def __iter__(self):
        return iter(self._raw)

    def __len__(self) -> int:
        return len(self._raw)


#: How many firmwares' format tables :func:`format_table` keeps (a fleet's logs come from a few firmwares).
FORMAT_CACHE_SIZE = 32
#: Bytes of an FMT message's body (after its 3-byte header): what :func:`_decode.dataflash_formats` reads of it.
_FMT_BODY = 86
#: Verdicts a :class:`FormatTable` keeps per kind (name sets asked for, FMTU contents met).
_VERDICTS = 8


class FormatTable:
    """What a log's FMT messages say for the names and fields a reader asks for (:func:`_decode.dataflash_formats`
    on their bodies): the same for every log whose FMT bodies are the same bytes (one firmware), so
    :func:`format_table` keeps it between logs.

    Nothing a log reads from it is changed afterwards: the arrays are read-only, ``name_to_id`` a read-only view;
    the formats are built once each when first asked for; ``clock_verdicts`` and ``unit_verdicts`` memoise the
    checks of :meth:`DataFlashIndex.check_clock` and :meth:`DataFlashIndex._check_units`, ``plans`` what
    :func:`read_families` looks up (each key is set once, to the one value it can have; a single dict store, atomic
    under the GIL, so threads may share a table; at most :data:`_VERDICTS` keys each)."""

    def __init__(self, result: tuple) -> None:
        problem, raw, name_to_id, lengths, column_counts, field_chars, field_offsets, redefined = result
        #: Why pymavlink's own reading is needed (the first FMT failing a check), else None.
        self.problem: Optional[str] = problem
        self.raw: Dict[int, tuple] = raw
        self.name_to_id: Mapping = MappingProxyType(name_to_id)
        undefined = lengths == 0
        undefined[0x80] = False
        for array in (lengths, column_counts, field_chars, field_offsets, undefined):
            array.setflags(write=False)
        self.lengths, self.column_counts, self.field_chars, self.field_offsets = \
            lengths, column_counts, field_chars, field_offsets
        #: Types no FMT defines (FMT's own type aside): a log with messages of one is declined.
        self.undefined = undefined
        self.redefined: Tuple[int, ...] = tuple(redefined)
        self.formats = Formats(raw)
        self.clock_verdicts: Dict[tuple, Optional[str]] = {}
        self.unit_verdicts: Dict[bytes, Optional[str]] = {}
        #: :func:`read_families`' fields, their columns and the types, per (kinds, fields) asked for.
        self.plans: Dict[tuple, tuple] = {}


@functools.lru_cache(maxsize=FORMAT_CACHE_SIZE)
def format_table(bodies: bytes, names: Tuple[str, ...], fields: Tuple[str, ...]) -> FormatTable:
    """The :class:`FormatTable` of FMT messages with these ``bodies`` (86 bytes each, in file order; only the ones
    wholly inside the file: the reader stops at a cut-off one), asked for ``names`` (and the types pymavlink always
    walks and the unit checks read) and ``fields``. Kept for the last :data:`FORMAT_CACHE_SIZE` keys (an LRU,
    thread-safe): the result is a function of the arguments alone, so a warm and a cold cache give the same.
    The formats are read as the first pass of :meth:`DataFlashIndex._read_formats` (a type defined twice is read
    again per log, where the clock set-up walk stopped)."""
    count = len(bodies) // _FMT_BODY
    # the bodies laid out as a log of FMT messages: message k at byte 86 k, its body 3 bytes on
    log = np.frombuffer(b"\0\0\0" + bodies, dtype=np.uint8)
    offsets = np.arange(count, dtype=np.uint64) * np.uint64(_FMT_BODY)
    wanted = {name.encode() for name in (*names, *ALWAYS_WALKED, *_UNIT_NAMES)}
    return FormatTable(decoder_module().dataflash_formats(log, offsets, wanted, [f.encode() for f in fields]))


@functools.lru_cache(maxsize=FORMAT_CACHE_SIZE)
def _field_layout(fields: Tuple[str, ...]) -> Tuple[Tuple[str, ...], Mapping]:
    """The columns of the field tables (the clock fields, then ``fields``, each once) and each one's column."""
    columns = tuple(dict.fromkeys((*CLOCK_FIELDS, *fields)))
    return columns, MappingProxyType({name: k for k, name in enumerate(columns)})


_UNSET = object()


class DataFlashIndex:
    """The messages of a DataFlash log: where each starts, of which type, and the formats (from FMT) of the types
    named in ``names`` (and those pymavlink always walks or the unit checks read), with the byte and format
    character of each of ``fields`` (and the clock fields) in them; every FMT is checked."""

    def __init__(self, data, path: str, names: Iterable[str] = (), fields: Iterable[str] = ()) -> None:
        _decode = decoder_module()
        self.data = np.frombuffer(data, dtype=np.uint8)
        self.size = self.data.size
        self.path = path
        offsets, types, bad, status, stop, lengths = _decode.dataflash_index(self.data)
        if status != "ok":
            # pymavlink's indexer ends the program here (exit status 1); the fast reader refuses the log
            raise ValueError(f"{status} at byte {stop} (where pymavlink's indexer stops the program)")
        #: Bytes that start no message, as pymavlink's indexer counts them (it prints "bad header" for each).
        self.bad_headers = bad
        self.offsets, self.types = offsets, types
        self.final_lengths = lengths
        #: The fields of the field tables, in their column order.
        self.fields, self.field_column = _field_layout(tuple(fields))
        self._read_formats(names)
        self._check_units()

    def check_clock(self, names: Iterable[str]) -> None:
        """Decline logs in which pymavlink's clock or bookkeeping would fail on a message it reads (it prints
        "bad msg", which the reader counts): odd column names (bit flips), text in a time field, GPS messages
        without the partner of their week field, without any week field (its GPS-interpolated clock multiplies
        a missing week) or without a boot time. (Each format's clock fields were looked up in C; the verdict is
        a function of the formats and ``names``, kept on the format table.)"""
        key = tuple(names)
        verdicts = self.table.clock_verdicts
        problem = verdicts.get(key, _UNSET)
        if problem is _UNSET:
            problem = self._clock_problem(key)
            if len(verdicts) < _VERDICTS:
                verdicts[key] = problem
        if problem is not None:
            raise NeedsReference(problem)

    def _clock_problem(self, names: Iterable[str]) -> Optional[str]:
        """Why :meth:`check_clock` declines the log, else None."""
        clock = len(CLOCK_FIELDS)  # the clock fields are the first columns of the field tables
        for name in sorted(set(names) | set(ALWAYS_WALKED)):
            type_id = self.name_to_id.get(name)
            if type_id is None:
                continue
            _, _, _, columns, words = self._raw_formats[type_id]
            if columns and not words:
                return f"{name}: a column name that is not a word"
            chars = self.field_chars[type_id, :clock].tobytes()
            if not _TEXT_BYTES.isdisjoint(chars):
                return f"{name}: a time field holds text"
            if name in ("GPS", "GPS2"):
                have = {field for field, char in zip(CLOCK_FIELDS, chars) if char}
                if ("Week" in have and "TimeMS" not in have) or \
                        ("Week" not in have and "GWk" in have and "GMS" not in have) or \
                        ("Week" not in have and "GWk" not in have and "Wk" in have and "TWk" not in have) or \
                        ("Week" not in have and "GWk" not in have and "Wk" not in have and "GPSTime" not in have) or \
                        ("T" not in have and "TimeUS" not in have):
                    return f"{name}: a GPS time pymavlink's clock cannot read"
        return None

    def skipped_runs(self) -> int:
        """How many "Skipped N bad bytes" lines pymavlink prints reading this log: one per run of bad bytes
        before a message that its clock set-up walk (``DFReader.init_clock``, every message from the start until
        it settles on a clock) reaches, where 528 bytes or more of the file remain from that message on."""
        if not self.bad_headers or self.offsets.size < 2:
            return 0  # (a run printed is at least 528 bytes from the end, so its bytes are counted bad)
        ends = self.offsets + self.final_lengths[self.types]
        runs = np.flatnonzero((self.offsets[1:] > ends[:-1]) & (self.size - self.offsets[1:] >= 528)) + 1
        if not runs.size:
            return 0
        return int(np.count_nonzero(runs <= self._clock_walk_end()))

    def _clock_walk_end(self) -> int:
        """Index of the message at which pymavlink's clock set-up walk stops (the last one if it reads on to
        the end): a transcription of ``DFReader.init_clock`` with ``zero_time_base``, on the values pymavlink
        gives (read in C)."""
        problem, raw, names, _, _, chars, byte_offsets, _ = decoder_module().dataflash_formats(
            self.data, np.ascontiguousarray(self.offsets[self.types == 0x80]), None, _CLOCK_FIELD_BYTES)
        if problem is not None:  # (the same FMT messages were read without a problem in __init__)
            raise NeedsReference(problem)
        last = self.offsets.size - 1
        column = {name: k for k, name in enumerate(CLOCK_FIELDS)}
        has_us = chars[:, column["TimeUS"]] != 0
        first_us = np.flatnonzero(has_us[self.types])
        first_us = int(first_us[0]) if first_us.size else last + 1
        walked = [names[name] for name in ("GPS", "GPS2", "TIME") if name in names]
        for type_id in walked[:-1] if "TIME" in names else walked:  # GPS, GPS2: their clock fields as numbers
            if any(chars[type_id, column[field]] == ord("g") for field in CLOCK_FIELDS) or \
                    any(chars[type_id, column[field]] in b"qQ" for field in ("TimeMS", "Week")):
                raise NeedsReference(f"type {type_id}: a GPS time field pymavlink compares that is not exact")
        tables = decoder_module().dataflash_columns(self.data, self.offsets, self.types, self.lengths, walked,
                                                    chars, byte_offsets, list(range(len(CLOCK_FIELDS))),
                                                    CLOCK_FIELDS)
        gps = names.get("GPS")
        modern = gps in tables and all(chars[gps, column[f]] for f in ("TimeUS", "GWk", "GMS"))
        events = [(first_us, None, {})] if first_us <= last else []
        for type_id, (mine, columns, _) in tables.items():
            positions = np.searchsorted(self.offsets, mine)
            for row, position in enumerate(positions.tolist()):
                events.append((position, type_id, {name: values[row] for name, values in columns.items()}))
        events.sort(key=lambda event: event[0])
        first_us_seen = False
        gps1 = None
        px4_time = px4_gps = False
        for position, type_id, values in events:
            if not first_us_seen and has_us[self.types[position]]:
                first_us_seen = True
                if modern:
                    return position
            if type_id is None:
                continue
            if type_id in (names.get("GPS"), names.get("GPS2")):
                if values.get("TimeUS", 0) != 0 and values.get("GWk", 0) != 0:
                    return position
                if values.get("T", 0) != 0 and values.get("Week", 0) != 0:
                    return position
                if values.get("GPSTime", 0) != 0:
                    px4_gps = True
                if values.get("Week", 0) != 0:
                    if "TimeMS" not in values:  # pymavlink's clock set-up raises (AttributeError)
                        raise NeedsReference("a GPS message with a Week but no numeric TimeMS")
                    if gps1 is not None and (gps1["TimeMS"] != values["TimeMS"] or gps1["Week"] != values["Week"]):
                        return position
                    gps1 = values
            elif chars[type_id, column["StartTime"]]:  # TIME with a StartTime: px4-style logs
                px4_time = True
            if px4_time and px4_gps:
                return position
        return last

    def raw_chars(self, type_id: int) -> bytes:
        """The format characters of a type named in the index's names, as the FMT holds them."""
        return self._raw_formats[type_id][2]

    def missing_bytes(self, blob: bytes):
        """:func:`_truncation.dataflash_missing_bytes` of the log, walking only from its last message on."""
        if not self.offsets.size:
            return dataflash_missing_bytes(self.path, blob)
        last = int(self.offsets[-1])
        length = int(self.final_lengths[self.types[-1]])
        if last + length > self.size:  # the last message is cut off (the walk's first step from it)
            return last + length - self.size
        lengths = {int(k): int(self.final_lengths[k]) for k in np.flatnonzero(self.final_lengths)}
        return dataflash_missing_bytes(self.path, blob, last, lengths)

    def _bodies(self, type_id: int, length: int) -> np.ndarray:
        _decode = decoder_module()
        offsets = np.ascontiguousarray(self.offsets[self.types == type_id])
        bodies, _ = _decode.dataflash_gather(self.data, offsets, length)
        return offsets, bodies

    def _read_formats(self, names: Iterable[str]) -> None:
        """The FMT messages, in file order, as pymavlink's indexer reads them (it stops at a cut-off one): checked
        in C (:func:`_decode.dataflash_formats`), made :class:`Format` objects only when a type is asked for. The
        table of every log with the same FMT bytes is the same one (:func:`format_table`), but where a type is
        defined twice (read per log, where pymavlink's clock set-up walk stopped)."""
        _decode = decoder_module()
        names = tuple(names)
        fmt_offsets = np.ascontiguousarray(self.offsets[self.types == 0x80])
        bodies, complete = _decode.dataflash_gather(self.data, fmt_offsets, DATAFLASH_FMT_LENGTH)
        table = format_table(bodies[:complete].tobytes(), names, self.fields)
        if table.problem is not None:
            raise NeedsReference(table.problem)
        if table.redefined:  # each such type takes the FMT pymavlink's clock set-up walk read last
            self._use(table)  # (the walk reads the first pass's formats)
            wanted = {name.encode() for name in (*names, *ALWAYS_WALKED, *_UNIT_NAMES)}
            table = FormatTable(_decode.dataflash_formats(self.data, fmt_offsets, wanted,
                                                          [f.encode() for f in self.fields],
                                                          int(self.offsets[self._clock_walk_end()])))
        self._use(table)
        if complete < fmt_offsets.size:  # (else every FMT the scan met was read: each message's type has one)
            present = np.flatnonzero(np.bincount(self.types, minlength=256).astype(bool) & table.undefined)
            if present.size:
                raise NeedsReference(f"messages of type {int(present[0])} without a readable FMT")

    def _use(self, table: FormatTable) -> None:
        """Read the log with the formats of ``table``."""
        self.table = table
        self.name_to_id, self.lengths, self.column_counts = table.name_to_id, table.lengths, table.column_counts
        self.field_chars, self.field_offsets = table.field_chars, table.field_offsets
        self._raw_formats, self.formats = table.raw, table.formats

    def _check_units(self) -> None:
        """FMTU/UNIT/MULT only name units (no value changes), but odd ones make pymavlink raise: decline those.
        The verdict is a function of the formats and the FMTU messages' bytes, kept on the format table."""
        key = b""
        if "FMTU" in self.name_to_id:
            type_id = self.name_to_id["FMTU"]
            offsets, bodies = self._bodies(type_id, int(self.lengths[type_id]))
            key = bodies[offsets + self.lengths[type_id] <= self.size].tobytes()
        verdicts = self.table.unit_verdicts
        problem = verdicts.get(key, _UNSET)
        if problem is _UNSET:
            problem = self._units_problem()
            if len(verdicts) < _VERDICTS:
                verdicts[key] = problem
        if problem is not None:
            raise NeedsReference(problem)

    def _units_problem(self) -> Optional[str]:
        """Why :meth:`_check_units` declines the log, else None."""
        if "FMTU" in self.name_to_id:
            fmtu = self.formats[self.name_to_id["FMTU"]]
            for char in ("UnitIds", "MultIds"):
                if char in fmtu.colhash and fmtu.char_of(char) not in "nNZ":
                    return f"FMTU.{char} is not text"
            if "MultIds" in fmtu.colhash and "UnitIds" not in fmtu.colhash:
                return "FMTU with multipliers but no units"
            if "UnitIds" in fmtu.colhash:
                if len(fmtu.columns) < 2 or fmtu.chars[1] in TEXT_CHARS:
                    return "FMTU without a numeric second field"
                fields = [fmtu.columns[1]] + [c for c in ("UnitIds", "MultIds") if c in fmtu.colhash]
                for record in self.records("FMTU", fields):
                    target = int(record[fmtu.columns[1]])  # pymavlink: int(elements[1])
                    if not 0 <= target < 256 or not self.lengths[target]:
                        continue
                    if "#" in record["UnitIds"]:
                        return "FMTU with an instance field"
                    if "MultIds" in record and len(record["MultIds"]) < int(self.column_counts[target]):
                        return "FMTU with fewer multipliers than columns"
        for name in ("UNIT", "MULT"):
            if name in self.name_to_id:
                chars = self.formats[self.name_to_id[name]].chars
                if len(chars) < 3 or chars[1] in TEXT_CHARS or chars[2] in TEXT_CHARS:
                    return f"{name} without numeric second and third fields"
        return None

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
        # parts: (offsets, fmt, columns: field → float64 values of the fields the type has) per type, in file
        # order within each; fmt: a callable giving the type's Format (its column names are only built if asked)
        self._first_format = parts[0][1] if parts else None
        self._first_fields: Optional[List[str]] = None if parts else []
        self._field_set: Optional[frozenset] = None
        if not parts:
            self.size = 0
            self.columns: Dict[str, np.ndarray] = {}
            self.time = np.zeros(0)
            return
        if len(parts) == 1:  # one type: already in file order
            offsets, _, columns = parts[0]
            self.size = offsets.size
            self.columns = {field: values for field, values in columns.items() if field in fields_used}
            self.time = _times(columns, offsets.size)
            return
        offsets = np.concatenate([p[0] for p in parts])
        # several types (IMU and IMU2): merged by offset
        order = np.argsort(offsets, kind="stable")
        self.size = offsets.size
        first_part = int(np.searchsorted(np.cumsum([p[0].size for p in parts]), order[0], side="right"))
        self._first_format = parts[first_part][1]
        self.columns = {}
        for field in fields_used:
            if not any(field in columns for _, _, columns in parts):
                continue
            pieces = [columns[field] if field in columns else np.full(mine.size, np.nan)
                      for mine, _, columns in parts]
            self.columns[field] = np.concatenate(pieces)[order]
        pieces = [_times(columns, mine.size) for mine, _, columns in parts]
        self.time = np.concatenate(pieces)[order]

    @property
    def first_fields(self) -> List[str]:
        """The keys of pymavlink's ``to_dict`` of the first message: its type name, then each column once."""
        if self._first_fields is None:
            self._first_fields = ["mavpackettype"] + self._first_format().columns_once
        return self._first_fields

    def __len__(self) -> int:
        return self.size

    def has(self, field: str) -> bool:
        if self._field_set is None:  # (the first message's type's keys: kept on its Format, built once)
            self._field_set = self._first_format().keys if self._first_format is not None else frozenset()
        return field in self._field_set

    def values(self, field: str) -> np.ndarray:
        values = self.columns.get(field)
        return np.full(self.size, np.nan) if values is None else values

    def times(self) -> np.ndarray:
        return self.time

    def truthy(self, field: str) -> np.ndarray:
        return self.values(field) != 0

    def keep(self, mask: np.ndarray) -> "ArrayRows":
        self.columns = {k: v[mask] for k, v in self.columns.items()}
        self.time = self.time[mask]
        self.size = int(np.count_nonzero(mask))
        return self


def time_of(fields: Mapping):
    """Boot time of a message (or of every message of a type, given its columns), s: ``TimeUS`` (µs, current
    logs), else GPS's ``T`` (ms boot time in old logs, whose ``TimeMS`` is the GPS week time), else ``TimeMS``
    (ms, ArduCopter ≤ 3.3); None without any."""
    if "TimeUS" in fields:
        return fields["TimeUS"] * 1e-6
    if "T" in fields and "Week" in fields:
        return fields["T"] * 1e-3
    if "TimeMS" in fields:
        return fields["TimeMS"] * 1e-3
    return None


def _times(columns: Dict[str, np.ndarray], count: int) -> np.ndarray:
    """:func:`time_of` of every message of one type, s (``columns``: the float64 columns of the fields the type
    has, its time fields among them); NaN without a time field."""
    times = time_of(columns)
    return np.full(count, np.nan) if times is None else times


def read_families(index: DataFlashIndex, kinds: Sequence[str], fields_used: Sequence[str],
                  select) -> tuple:
    """The reader's rows per family and the firmware text, from the messages ``recv_match(type=kinds)`` gives.

    ``select(kind, columns, count)`` → (family or None, boolean mask of the messages kept or None for all);
    ``columns``: the
    ``fields_used`` the type has (float64, the values pymavlink gives) and its time fields. The numeric fields
    are read in C (:func:`_decode.dataflash_columns`), straight from the file's bytes; ``fields_used`` must be
    among the index's fields."""
    kinds, fields_used = tuple(kinds), tuple(fields_used)
    index.check_clock(kinds)
    key = (kinds, fields_used)
    plan = index.table.plans.get(key)
    if plan is None:  # (a function of the formats, the kinds and the fields: kept on the format table)
        wanted = tuple(dict.fromkeys((*fields_used, *_TIME_FIELDS)))
        plan = (wanted, tuple(index.field_column[field] for field in wanted),
                tuple(index.name_to_id[name] for name in kinds if name in index.name_to_id))
        if len(index.table.plans) < _VERDICTS:
            index.table.plans[key] = plan
    wanted, positions, type_ids = plan
    tables = decoder_module().dataflash_columns(index.data, index.offsets, index.types, index.lengths, type_ids,
                                                index.field_chars, index.field_offsets, positions, wanted)
    parts: Dict[str, List[tuple]] = {}
    firmware = ""
    for type_id, (mine, columns, unreadable) in sorted(tables.items()):
        name = index.formats.name(type_id)
        fmt = functools.partial(index.formats.__getitem__, type_id)
        if name == "MSG":  # only its Message text is read (check_clock declined a text time field)
            if index.formats.has_column(type_id, "Message"):
                firmware = _firmware(index, index.formats[type_id], mine)
                parts.setdefault("MSG", []).append((mine, fmt, columns))
            continue
        if unreadable is not None:
            raise NeedsReference(f"{name}.{unreadable} holds text or a half float")
        family, mask = select(name, columns, mine.size)
        if family is None:
            continue
        if mask is None:
            parts.setdefault(family, []).append((mine, fmt, columns))
        elif mask.any():
            parts.setdefault(family, []).append((mine[mask], fmt, {k: v[mask] for k, v in columns.items()}))
    return parts, firmware


#: Format characters (as numbers) the column reader leaves as NaN: text and half floats.
_NOT_NUMBERS = frozenset(b"anNZg")


def _firmware(index: DataFlashIndex, fmt: Format, offsets: np.ndarray) -> str:
    """The first MSG text that names the firmware ("Ardu…", "APM:…"), else "". (A text starts so exactly when its
    first four bytes do, whichever decoding pymavlink's falls back to: the rows are picked by those bytes.)"""
    if fmt.char_of("Message") not in "nNZ":
        raise NeedsReference("MSG.Message is not text")
    column = fmt.colhash["Message"]
    start = 3 + fmt.dtype.fields[f"f{column}"][1]  # the field's first byte in a message
    width = _SIZES[fmt.chars[column]]
    log = index.data.data
    for offset in offsets.tolist():
        if log[offset + start:offset + start + 4] in (b"Ardu", b"APM:"):
            # (trailing NULs, which numpy's bytes() would cut, change neither the decoding nor the text before a NUL)
            return _python_value(fmt, "Message", bytes(log[offset + start:offset + start + width]))
    return ""
