"""PX4 ULog topics decoded at memory speed: C walks the messages as pyulog does
(:func:`fusion_altitude.logs._decode.ulog_definitions` and :func:`~fusion_altitude.logs._decode.ulog_data_walk`:
unknown or damaged messages stepped over, reading resumed after a sync sequence, appended data read segment by
segment), the definitions (formats, nested types flattened as pyulog flattens them) and subscriptions are read in
Python, and the data messages of each asked-for subscription are gathered by msg_id into one numpy structured
array (the dtype pyulog builds), so each field is bit for bit what pyulog's ``ULog(path, names).data_list`` holds.

What the definitions say is the same for every log of one firmware, so it is kept between logs
(:func:`firmware_definitions`, an LRU of :data:`FIRMWARES` entries keyed by the bytes of the F messages, whole):
the parsed formats, the layout (flattened fields, dtype, timestamp offset) of each subscribed topic name, and the
plan of each segment's subscriptions keyed by the bytes of its A messages and the names asked for. Only the
per-log byte offsets are taken from each log; a log declined once is declined again for the same reason. Every
kept object is immutable once published, or a dict only ever given equal values (GIL-atomic ``get``/set), so
threads reading logs at once (Dask) share it safely.

Logs whose reading depends on what pyulog does on an exception (a cut message in the definitions, flags it
refuses, appended offsets it cannot seek to, a msg_id subscribed twice in one segment, messages whose parsing
would make pyulog stop or flag corruption) are declined with :class:`NeedsReference`, and the caller reads them
with pyulog, so the result is the same either way.
"""

from __future__ import annotations

import functools
import struct
from collections.abc import Mapping
from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ._dataflash_fast import NeedsReference, decoder_module

HEADER_BYTES = b"\x55\x4c\x6f\x67\x01\x12\x35"
#: pyulog's basic types: (bytes, numpy dtype).
TYPES = {"int8_t": (1, np.int8), "uint8_t": (1, np.uint8), "int16_t": (2, np.int16), "uint16_t": (2, np.uint16),
         "int32_t": (4, np.int32), "uint32_t": (4, np.uint32), "int64_t": (8, np.int64), "uint64_t": (8, np.uint64),
         "float": (4, np.float32), "double": (8, np.float64), "bool": (1, np.int8), "char": (1, np.int8)}
_STRUCT = {"int8_t": "b", "uint8_t": "B", "int16_t": "h", "uint16_t": "H", "int32_t": "i", "uint32_t": "I",
           "int64_t": "q", "uint64_t": "Q", "float": "f", "double": "d", "bool": "?", "char": "c"}


def _text(raw: bytes) -> str:
    """pyulog's ``parse_string`` (UTF-8, undecodable bytes dropped)."""
    return str(raw, "utf-8", "ignore")


def _parse_format(payload: bytes) -> Tuple[str, List[tuple]]:
    """An F message: (name, [(type, array size, field name), …]) as pyulog's MessageFormat; raises on what
    makes pyulog flag corruption."""
    parts = _text(payload).split(":")
    name = parts[0]
    fields = []
    for item in parts[1].split(";"):
        if not item:
            continue
        words = item.split(" ")
        type_text, field = words[0], words[1]
        at = type_text.find("[")
        if at == -1:
            fields.append((type_text, 0, field))
        else:
            size = int(type_text[at + 1:type_text.find("]")])
            if size < 0 or size > 0xFFFF:
                raise ValueError("invalid array size")
            fields.append((type_text[:at], size, field))
    return name, fields


def _info_ok(payload: bytes, multiple: bool = False, default: bool = False) -> bool:
    """Whether pyulog parses an I/M/P/Q message without an exception (one would flag corruption, and a
    struct.error in the data section stops reading)."""
    if multiple or default:
        payload = payload[1:]
        if len(payload) < 1:
            return False
    if len(payload) < 1:
        return False
    key_length = payload[0]
    words = _text(payload[1:1 + key_length]).split(" ")
    if len(words) < 2:
        return False
    kind = words[0]
    if kind.startswith("char[") or kind not in _STRUCT:
        return True
    return len(payload) - 1 - key_length == struct.calcsize("<" + _STRUCT[kind])


#: Firmwares (distinct F messages) whose definitions :func:`firmware_definitions` keeps, the least recently read
#: dropped first.
FIRMWARES = 32
#: Most topic layouts and most segment plans one :class:`Firmware` keeps (a damaged or odd log may name many
#: topics, or subscribe in many orders; past these the rest are computed for each log).
LAYOUTS = 1024
PLANS = 64
#: Why pyulog flags an info or parameter message, or a format.
_BAD_INFO = "an info or parameter message pyulog cannot parse"
_BAD_FORMAT = "a definition pyulog cannot parse"


class Layout(NamedTuple):
    """How the samples of one topic are laid out, from the formats alone: pyulog's dtype (nested types
    flattened, trailing padding dropped) and the byte offset of the uint64 ``timestamp`` in a sample; or, when
    pyulog reads the topic otherwise, ``problem`` (why the log is declined) and no dtype."""

    dtype: Optional[np.dtype]
    timestamp_offset: int
    problem: Optional[str]


class Subscription(NamedTuple):
    """One asked-for A message of a segment: its index among the segment's A messages, msg_id, multi_id,
    topic name and :class:`Layout`."""

    index: int
    msg_id: int
    multi_id: int
    name: str
    layout: Layout


class Plan(NamedTuple):
    """The subscriptions of one segment's A messages for the names asked for, in file order; or ``problem``
    (a msg_id subscribed twice, a topic pyulog reads otherwise) and none."""

    subscriptions: Tuple[Subscription, ...]
    problem: Optional[str]


class Firmware:
    """What the F messages of one firmware define (``format_messages``: their bytes, whole, joined): the
    formats (name → fields, the last F message of a name wins, as in pyulog's dict; parsed when first needed,
    the C check of :func:`_decode.ulog_format_names` having vouched that they parse), the :class:`Layout` of
    each topic asked for and the :class:`Plan` of each segment's A messages; ``problem`` if pyulog cannot parse
    a format.

    Shared between logs and threads: ``problem`` and the unparsed payloads are fixed at construction; the
    other dicts only ever get, under the GIL, a value equal to any another thread may store."""

    def __init__(self, format_messages: bytes) -> None:
        self.problem: Optional[str] = None
        self._payloads: Dict[str, bytes] = {}
        self._parsed: Dict[str, Tuple[tuple, ...]] = {}
        self._layouts: Dict[str, Layout] = {}
        self._plans: Dict[tuple, Plan] = {}
        _decode = decoder_module()
        offsets, sizes = _decode.ulog_split_messages(format_messages)
        names = _decode.ulog_format_names(np.frombuffer(format_messages, dtype=np.uint8),
                                          np.array(offsets, dtype=np.uint64), np.array(sizes, dtype=np.uint16))
        if None not in names:  # each vouched for in C (as a PX4 log's are): the last of a name wins
            self._payloads = {name: format_messages[offset + 3:offset + 3 + size]
                              for offset, size, name in zip(offsets, sizes, names)}
            return
        for offset, size, name in zip(offsets, sizes, names):
            payload = format_messages[offset + 3:offset + 3 + size]
            if name is not None:
                self._parsed.pop(name, None)
                self._payloads[name] = payload
                continue
            try:
                name, fields = _parse_format(payload)
            except (IndexError, ValueError, KeyError, OverflowError, struct.error):
                self.problem = _BAD_FORMAT
                return
            self._payloads.pop(name, None)
            self._parsed[name] = tuple(fields)

    def format_fields(self, name: str) -> Optional[Tuple[tuple, ...]]:
        """The fields (type, array size, field name) of the format ``name``, or None if there is none."""
        fields = self._parsed.get(name)
        if fields is None:
            payload = self._payloads.get(name)
            if payload is None:
                return None
            fields = self._parsed[name] = tuple(decoder_module().ulog_format_fields(payload, len(name)))
        return fields

    def layout(self, name: str) -> Layout:
        """The :class:`Layout` of the topic ``name`` (kept: at most :data:`LAYOUTS`)."""
        layout = self._layouts.get(name)
        if layout is None:
            layout = _layout(name, self)
            if len(self._layouts) < LAYOUTS:
                self._layouts[name] = layout
        return layout

    def plan(self, subscribe_messages: bytes, names: Optional[Tuple[str, ...]]) -> Plan:
        """The :class:`Plan` of a segment's A messages (their bytes, whole, joined) for the topic ``names``
        (None: every topic); kept, at most :data:`PLANS`."""
        key = (names, subscribe_messages)
        plan = self._plans.get(key)
        if plan is None:
            plan = _plan(self, subscribe_messages, names)
            if len(self._plans) < PLANS:
                self._plans[key] = plan
        return plan


@functools.lru_cache(maxsize=FIRMWARES)
def firmware_definitions(format_messages: bytes) -> Firmware:
    """The :class:`Firmware` of the F messages ``format_messages`` (their bytes, whole, joined), kept for the
    :data:`FIRMWARES` most recently read firmwares (``firmware_definitions.cache_clear()`` empties it)."""
    return Firmware(format_messages)


def _flatten(fields: List[tuple], prefix: str, type_name: str, firmware: Firmware) -> None:
    """pyulog's ``_parse_nested_type``: (name, type) of each basic field of ``type_name`` appended to
    ``fields``, arrays as ``name[i]``, nested types as ``outer.inner``."""
    formats = firmware.format_fields(type_name)
    if formats is None:
        raise NeedsReference(f"no format {type_name!r}")
    for kind, size, field in formats:
        if kind in TYPES:
            if size > 0:
                fields += [(f"{prefix}{field}[{i}]", kind) for i in range(size)]
            else:
                fields.append((prefix + field, kind))
        elif size > 0:
            for i in range(size):
                _flatten(fields, f"{prefix}{field}[{i}].", kind, firmware)
        else:
            _flatten(fields, f"{prefix}{field}.", kind, firmware)


def _layout(name: str, firmware: Firmware) -> Layout:
    """The :class:`Layout` of the topic ``name`` in the formats of ``firmware``."""
    fields: List[tuple] = []
    try:
        _flatten(fields, "", name, firmware)
        while fields and fields[-1][0].startswith("_padding"):
            fields.pop()
        dtype = np.dtype([(field, TYPES[kind][1]) for field, kind in fields]).newbyteorder("<")
    except NeedsReference as error:
        return Layout(None, 0, str(error))
    except (ValueError, TypeError) as error:  # e.g. two fields of one name: pyulog flags corruption
        return Layout(None, 0, f"subscription {name}: {error}")
    offset = 0
    for field, kind in fields:
        if field == "timestamp":
            if kind != "uint64_t":
                return Layout(None, 0, f"{name}: timestamp is {kind}")
            return Layout(dtype, offset, None)
        offset += TYPES[kind][0]
    return Layout(None, 0, f"{name}: no timestamp field")


def _plan(firmware: Firmware, subscribe_messages: bytes, names: Optional[Tuple[str, ...]]) -> Plan:
    """The :class:`Plan` of a segment's A messages (their bytes, whole, joined) for the topic ``names``."""
    subscriptions = []
    seen_ids = set()
    wanted = None if names is None else frozenset(names)
    try:
        subscribed = decoder_module().ulog_subscriptions(subscribe_messages)
    except ValueError:  # an A message of under 3 bytes: the segment's message checks decline the log first
        return Plan((), "an A message too short for pyulog")
    for index, (msg_id, multi_id, name) in enumerate(subscribed):
        if msg_id in seen_ids:
            return Plan((), f"msg_id {msg_id} subscribed twice")
        seen_ids.add(msg_id)
        if wanted is not None and name not in wanted:
            continue
        layout = firmware.layout(name)
        if layout.problem is not None:
            return Plan((), layout.problem)
        subscriptions.append(Subscription(index, msg_id, multi_id, name, layout))
    return Plan(tuple(subscriptions), None)


class Topic(Mapping):
    """field name → samples of one subscription, as pyulog's ``data`` dict holds them: each field a view of
    ``table`` (the samples as a structured array of pyulog's dtype), made when asked for."""

    __slots__ = ("table", "_fields")

    def __init__(self, table: np.ndarray) -> None:
        self.table = table
        self._fields = table.dtype.fields

    def __getitem__(self, name: str) -> np.ndarray:
        if name not in self._fields:
            raise KeyError(name)
        return self.table[name]

    def __contains__(self, name) -> bool:
        return name in self._fields

    def __iter__(self):
        return iter(self.table.dtype.names)

    def __len__(self) -> int:
        return len(self.table.dtype.names)


class ULogTopics:
    """The topics of a ULog: ``data[(name, multi_id)]`` → :class:`Topic` (field → array), what pyulog's
    data_list holds for the names asked for (only those subscriptions are materialised)."""

    def __init__(self, blob: bytes, names: Optional[Sequence[str]]) -> None:
        _decode = decoder_module()
        if len(blob) < 16 or blob[:7] != HEADER_BYTES:
            raise NeedsReference("not a ULog header (pyulog's error)")
        if blob[7] > 1:
            raise NeedsReference("unknown ULog version")
        self.blob = blob
        self.array = np.frombuffer(blob, dtype=np.uint8)
        offsets, types, sizes, section_start, found, cut = _decode.ulog_definitions(self.array)
        if cut or not found:
            raise NeedsReference("no data section, or a cut message before it")
        appended = self._definitions(offsets, types, sizes)
        plain = 3 * sizes.size + int(sizes.sum(dtype=np.uint64)) == section_start - 16  # no byte stepped over
        offsets, types, sizes, segment_ends, skipped, _ = _decode.ulog_data_walk(self.array, section_start, appended)
        #: Byte after the last whole message of the plain walk, when the walks were plain (else None: see
        #: :meth:`missing_bytes`).
        self.plain_end = None
        if plain and not skipped and len(segment_ends) == 1 and offsets.size:
            self.plain_end = int(offsets[-1]) + 3 + int(sizes[-1])
        self.data = self._data_section(offsets, types, sizes, segment_ends, None if names is None else tuple(names))

    def missing_bytes(self) -> Optional[int]:
        """:func:`_truncation.ulog_missing_bytes` in C: bytes missing from a cut last message. The end of the
        plain walk (every header taken as sound) is where the walks ended when they stepped over no byte, read
        one segment and skipped no message (:attr:`plain_end`); else it is walked again in C."""
        size = len(self.blob)
        self.end = self.plain_end if self.plain_end is not None else decoder_module().ulog_plain_end(self.array)
        if self.end == size:
            return None
        if size - self.end >= 3:  # the payload is cut
            return self.end + 3 + (self.blob[self.end] | (self.blob[self.end + 1] << 8)) - size
        return 3 - (size - self.end)  # the header is cut

    def _definitions(self, offsets, types, sizes) -> List[int]:
        """Read the definitions (the messages pyulog reads before the data section): check them, look up the
        :class:`Firmware` of the F messages; return the appended-data offsets pyulog uses (empty unless the flag
        bits say data was appended)."""
        self._check_messages(offsets, types, sizes)
        _decode = decoder_module()
        self.firmware = firmware_definitions(_decode.ulog_typed_messages(self.array, offsets, types, sizes,
                                                                         ord("F"))[0])
        if self.firmware.problem is not None:
            raise NeedsReference(self.firmware.problem)
        flags = _decode.ulog_typed_messages(self.array, offsets, types, sizes, ord("B"))[1]
        return self._appended_offsets(flags, [self.blob[offset] | (self.blob[offset + 1] << 8) for offset in flags])

    def _appended_offsets(self, offsets: List[int], sizes: List[int]) -> List[int]:
        """The appended-data offsets of the flag-bits messages, as pyulog takes them: the last one of at least
        40 bytes wins (a shorter one is a parse error pyulog passes over), its trailing zero offsets dropped,
        used only if incompatible flag bit 0 (data appended) is set."""
        incompatible, appended = bytes(8), []
        for offset, size in zip(offsets, sizes):
            if size < 40:
                continue
            payload = self.blob[offset + 3:offset + 3 + size]
            incompatible = payload[8:16]
            appended = list(struct.unpack("<3Q", payload[16:40]))
            while appended and appended[-1] == 0:
                appended.pop()
            if incompatible[0] & ~1 or any(incompatible[1:]):
                raise NeedsReference("unknown incompatible flags (pyulog refuses the log)")
        if not incompatible[0] & 1:
            return []
        if any(offset >= 2 ** 63 for offset in appended):
            raise NeedsReference("an appended offset pyulog cannot seek to")
        return appended

    def _check_messages(self, offsets, types, sizes) -> None:
        """Decline if a message would make pyulog raise (:func:`_decode.ulog_message_checks`)."""
        failing, undecided = decoder_module().ulog_message_checks(self.array, offsets, types, sizes)
        self._decline_if_failing(failing, undecided, offsets, types, sizes)

    def _decline_if_failing(self, failing: bytes, undecided: List[int], offsets, types, sizes) -> None:
        """Decline if some message failed the C checks (``failing``: the types of those, in ``b"LCADOIMPQ"``
        order) or an I/M/P/Q message with a non-ASCII key (``undecided``: indices) fails as pyulog decodes it."""
        for kind in failing:
            if kind == ord("O"):
                raise NeedsReference("a dropout message that is not 2 bytes")
            raise NeedsReference(f"a {chr(kind)} message too short for pyulog" if kind in b"LCAD" else _BAD_INFO)
        for k in undecided:
            offset, size = int(offsets[k]), int(sizes[k])
            if not _info_ok(self.blob[offset + 3:offset + 3 + size], multiple=int(types[k]) in b"MQ"):
                raise NeedsReference(_BAD_INFO)

    def _data_section(self, offsets, types, sizes, segment_ends, names) -> Dict[tuple, Topic]:
        """The topics of the data-section messages pyulog reads (``segment_ends``: messages after each segment;
        pyulog forgets the subscriptions at the end of each, and a later segment's data of a topic wins). The
        messages are checked as their samples are counted; a failed check declines the log before a segment's
        own reason does, as pyulog's parse errors come first."""
        out: Dict[tuple, Topic] = {}
        failing, undecided, problem = set(), [], None
        first = 0
        for end in segment_ends:
            topics, segment_failing, segment_undecided, segment_problem = self._segment(
                offsets[first:end], types[first:end], sizes[first:end], names)
            failing.update(segment_failing)
            undecided += [first + k for k in segment_undecided]
            problem = problem or segment_problem
            out.update(topics)
            first = end
        self._decline_if_failing(bytes(kind for kind in b"LCADOIMPQ" if kind in failing), undecided, offsets,
                                 types, sizes)
        if problem is not None:
            raise NeedsReference(problem)
        return out

    def _segment(self, offsets, types, sizes, names) -> Tuple[Dict[tuple, Topic], bytes, List[int], Optional[str]]:
        """The topics of one segment of the data section (its subscriptions, then their samples), the checks of
        its messages (failing types, undecided indices) and the reason to decline, if any."""
        _decode = decoder_module()
        subscribe_messages, starts = _decode.ulog_typed_messages(self.array, offsets, types, sizes, ord("A"))
        plan = self.firmware.plan(subscribe_messages, names)
        tables, failing, undecided = _decode.ulog_checked_tables(self.array, offsets, types, sizes, [
            (s.msg_id, starts[s.index], s.layout.dtype.itemsize) for s in plan.subscriptions])
        out: Dict[tuple, Topic] = {}
        for subscription, bodies in zip(plan.subscriptions, tables):
            if not bodies.shape[0]:
                continue
            key = (subscription.name, subscription.multi_id)
            if key in out:
                return out, failing, undecided, f"{key} subscribed twice"
            out[key] = Topic(np.frombuffer(bodies.data, dtype=subscription.layout.dtype))
        return out, failing, undecided, plan.problem
