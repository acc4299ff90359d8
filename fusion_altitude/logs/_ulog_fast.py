"""PX4 ULog topics decoded at memory speed: C walks the messages as pyulog does
(:func:`fusion_altitude.logs._decode.ulog_definitions` and :func:`~fusion_altitude.logs._decode.ulog_data_walk`:
unknown or damaged messages stepped over, reading resumed after a sync sequence, appended data read segment by
segment), the definitions (formats, nested types flattened as pyulog flattens them) and subscriptions are read in
Python, and the data messages of each asked-for subscription are gathered by msg_id into one numpy structured
array (the dtype pyulog builds), so each field is bit for bit what pyulog's ``ULog(path, names).data_list`` holds.

Logs whose reading depends on what pyulog does on an exception (a cut message in the definitions, flags it
refuses, appended offsets it cannot seek to, a msg_id subscribed twice in one segment, messages whose parsing
would make pyulog stop or flag corruption) are declined with :class:`NeedsReference`, and the caller reads them
with pyulog, so the result is the same either way.
"""

from __future__ import annotations

import struct
from collections.abc import Mapping
from typing import Dict, List, Optional, Sequence, Tuple

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


def _infos_ok(array: np.ndarray, blob: bytes, offsets: np.ndarray, sizes: np.ndarray, skip: int) -> bool:
    """:func:`_info_ok` of many I/P messages at once (``skip``: bytes before the key length, 1 for M and Q):
    checked in C (:func:`_decode.ulog_infos_ok`), the few with a non-ASCII key one by one here."""
    if not offsets.size:
        return True
    ok, undecided = decoder_module().ulog_infos_ok(array, np.ascontiguousarray(offsets),
                                                    np.ascontiguousarray(sizes), skip)
    if not ok:
        return False
    for k in undecided:
        offset, size = int(offsets[k]), int(sizes[k])
        if not _info_ok(blob[offset + 3:offset + 3 + size], multiple=skip == 1):
            return False
    return True


class Formats(Mapping):
    """name → fields of a ULog's F messages (the last of a name wins, as pyulog's dict), each parsed by
    :func:`_parse_format` when first asked for; the C check (:func:`_decode.ulog_format_names`) already
    vouched that it parses."""

    def __init__(self) -> None:
        self._payloads: Dict[str, bytes] = {}
        self._parsed: Dict[str, List[tuple]] = {}

    def add_payload(self, name: str, payload: bytes) -> None:
        self._parsed.pop(name, None)
        self._payloads[name] = payload

    def add_parsed(self, name: str, fields: List[tuple]) -> None:
        self._payloads.pop(name, None)
        self._parsed[name] = fields

    def __getitem__(self, name: str) -> List[tuple]:
        if name not in self._parsed:
            self._parsed[name] = _parse_format(self._payloads.pop(name))[1]
        return self._parsed[name]

    def __contains__(self, name) -> bool:
        return name in self._parsed or name in self._payloads

    def __iter__(self):
        return iter(list(self._parsed) + list(self._payloads))

    def __len__(self) -> int:
        return len(self._parsed) + len(self._payloads)


class Subscription:
    """An A message: msg_id, multi_id, topic name, the flattened fields and pyulog's dtype."""

    def __init__(self, payload: bytes, formats: Dict[str, List[tuple]], offset: int) -> None:
        self.multi_id = payload[0]
        self.msg_id = payload[1] | (payload[2] << 8)
        self.name = _text(payload[3:])
        self.offset = offset
        self.fields: List[tuple] = []
        self._flatten("", self.name, formats)
        while self.fields and self.fields[-1][0].startswith("_padding"):
            self.fields.pop()
        self.dtype = np.dtype([(name, TYPES[kind][1]) for name, kind in self.fields]).newbyteorder("<")
        self.timestamp_offset = 0
        for name, kind in self.fields:
            if name == "timestamp":
                if kind != "uint64_t":
                    raise NeedsReference(f"{self.name}: timestamp is {kind}")
                break
            self.timestamp_offset += TYPES[kind][0]
        else:
            raise NeedsReference(f"{self.name}: no timestamp field")

    def _flatten(self, prefix: str, type_name: str, formats) -> None:
        """pyulog's ``_parse_nested_type``: arrays as ``name[i]``, nested types as ``outer.inner``."""
        if type_name not in formats:
            raise NeedsReference(f"no format {type_name!r}")
        for kind, size, field in formats[type_name]:
            if kind in TYPES:
                if size > 0:
                    self.fields += [(f"{prefix}{field}[{i}]", kind) for i in range(size)]
                else:
                    self.fields.append((prefix + field, kind))
            elif size > 0:
                for i in range(size):
                    self._flatten(f"{prefix}{field}[{i}].", kind, formats)
            else:
                self._flatten(f"{prefix}{field}.", kind, formats)


class ULogTopics:
    """The topics of a ULog: ``data[(name, multi_id)]`` → {field: array}, what pyulog's data_list holds for
    the names asked for (only those subscriptions are materialised)."""

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
        offsets, types, sizes, segment_ends, _, _ = _decode.ulog_data_walk(self.array, section_start, appended)
        self.data = self._data_section(offsets, types, sizes, segment_ends, names)

    def missing_bytes(self) -> Optional[int]:
        """:func:`_truncation.ulog_missing_bytes` in C: bytes missing from a cut last message."""
        size = len(self.blob)
        self.end = decoder_module().ulog_plain_end(self.array)
        if self.end == size:
            return None
        if size - self.end >= 3:  # the payload is cut
            return self.end + 3 + (self.blob[self.end] | (self.blob[self.end + 1] << 8)) - size
        return 3 - (size - self.end)  # the header is cut

    def _payload(self, offset: int, size: int) -> bytes:
        return self.blob[offset + 3:offset + 3 + size]

    def _definitions(self, offsets, types, sizes) -> List[int]:
        """Read the definitions (the messages pyulog reads before the data section); return the appended-data
        offsets pyulog uses (empty unless the flag bits say data was appended)."""
        self._check_infos(offsets, types, sizes)
        self.formats = Formats()
        format_rows = np.flatnonzero(types == ord("F"))
        names = decoder_module().ulog_format_names(self.array, np.ascontiguousarray(offsets[format_rows]),
                                                   np.ascontiguousarray(sizes[format_rows]))
        for k, name in zip(format_rows.tolist(), names):
            payload = self._payload(int(offsets[k]), int(sizes[k]))
            if name is not None:
                self.formats.add_payload(name, payload)
                continue
            try:
                self.formats.add_parsed(*_parse_format(payload))
            except (IndexError, ValueError, KeyError, OverflowError, struct.error):
                raise NeedsReference("a definition pyulog cannot parse") from None
        return self._appended_offsets(offsets[types == ord("B")].tolist(), sizes[types == ord("B")].tolist())

    def _appended_offsets(self, offsets: List[int], sizes: List[int]) -> List[int]:
        """The appended-data offsets of the flag-bits messages, as pyulog takes them: the last one of at least
        40 bytes wins (a shorter one is a parse error pyulog passes over), its trailing zero offsets dropped,
        used only if incompatible flag bit 0 (data appended) is set."""
        incompatible, appended = bytes(8), []
        for offset, size in zip(offsets, sizes):
            if size < 40:
                continue
            payload = self._payload(offset, size)
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

    def _check_infos(self, offsets, types, sizes, counts=None) -> None:
        """Decline if an I/M/P/Q message would make pyulog raise (``counts``: messages per type, if known)."""
        for kind in b"IMPQ":
            if counts is not None and not counts[kind]:
                continue
            mine = types == kind
            if np.any(mine) and not _infos_ok(self.array, self.blob, offsets[mine], sizes[mine],
                                              skip=1 if kind in b"MQ" else 0):
                raise NeedsReference("an info or parameter message pyulog cannot parse")

    def _data_section(self, offsets, types, sizes, segment_ends, names) -> Dict[tuple, Dict[str, np.ndarray]]:
        """The topics of the data-section messages pyulog reads (``segment_ends``: messages after each segment;
        pyulog forgets the subscriptions at the end of each, and a later segment's data of a topic wins)."""
        _decode = decoder_module()
        counts = _decode.ulog_type_counts(types)
        for kind, minimum in ((ord("L"), 9), (ord("C"), 11), (ord("A"), 3), (ord("D"), 2)):
            if counts[kind] and np.any(sizes[types == kind] < minimum):
                raise NeedsReference(f"a {chr(kind)} message too short for pyulog")
        if counts[ord("O")] and np.any(sizes[types == ord("O")] != 2):
            raise NeedsReference("a dropout message that is not 2 bytes")
        self._check_infos(offsets, types, sizes, counts)
        out: Dict[tuple, Dict[str, np.ndarray]] = {}
        first = 0
        for end in segment_ends:
            out.update(self._segment(offsets[first:end], types[first:end], sizes[first:end], names))
            first = end
        return out

    def _segment(self, offsets, types, sizes, names) -> Dict[tuple, Dict[str, np.ndarray]]:
        """The topics of one segment of the data section (its subscriptions, then their samples)."""
        subscriptions = self._subscriptions(offsets[types == ord("A")].tolist(),
                                            sizes[types == ord("A")].tolist(), names)
        wanted = [(msg_id, s.offset, s.dtype.itemsize) for msg_id, s in subscriptions]
        tables = decoder_module().ulog_data_tables(self.array, offsets, types, sizes, wanted)
        out: Dict[tuple, Dict[str, np.ndarray]] = {}
        for (_, subscription), bodies in zip(subscriptions, tables):
            if not bodies.shape[0]:
                continue
            key = (subscription.name, subscription.multi_id)
            if key in out:
                raise NeedsReference(f"{key} subscribed twice")
            table = np.frombuffer(bodies.data, dtype=subscription.dtype)
            out[key] = {name: table[name] for name in table.dtype.names}
        return out

    def _subscriptions(self, offsets: List[int], sizes: List[int], names) -> List[Tuple[int, Subscription]]:
        """(msg_id, :class:`Subscription`) of the A messages at ``offsets`` whose topic is in ``names``."""
        subscriptions = []
        seen_ids = set()
        for offset, size in zip(offsets, sizes):
            payload = self._payload(offset, size)
            msg_id = payload[1] | (payload[2] << 8)
            if msg_id in seen_ids:
                raise NeedsReference(f"msg_id {msg_id} subscribed twice")
            seen_ids.add(msg_id)
            name = _text(payload[3:])
            if names is not None and name not in names:
                continue
            try:
                subscriptions.append((msg_id, Subscription(payload, self.formats, offset)))
            except (ValueError, TypeError) as error:  # e.g. two fields of one name: pyulog flags corruption
                raise NeedsReference(f"subscription {name}: {error}") from None
        return subscriptions
