"""Is a binary log cut short? A ULog or DataFlash file that ends inside a message was truncated (a crash, a
brown-out, a copy that stopped): its readers (pyulog, pymavlink) drop the partial message without a word, so the
log reads as a shorter flight. These scans walk the message framing only (no payload decoding)."""

from __future__ import annotations

import struct
from typing import Optional

#: ULog file header: 7 magic bytes, version byte, uint64 µs timestamp.
ULOG_HEADER = 16
#: DataFlash: message header 0xA3 0x95 <type>; the FMT message (type 128) defines every type's length.
DATAFLASH_HEAD = b"\xa3\x95"
DATAFLASH_FMT = 128
DATAFLASH_FMT_LENGTH = 89


def ulog_missing_bytes(path: str) -> Optional[int]:
    """Bytes missing from the last ULog message (its 3-byte header says more than the file holds), or None
    when the file ends on a message boundary."""
    with open(path, "rb") as handle:
        blob = handle.read()
    offset, size = ULOG_HEADER, len(blob)
    while offset + 3 <= size:
        length = struct.unpack_from("<H", blob, offset)[0]
        offset += 3 + length
    if offset == size:
        return None
    return offset - size if offset > size else 3 - (size - offset)


def dataflash_missing_bytes(path: str, blob: Optional[bytes] = None, start: int = 0,
                            lengths: Optional[dict] = None) -> Optional[int]:
    """Bytes missing from the last DataFlash message (lengths from the FMT messages), or None when the file
    ends on a message boundary (or in bytes that are no message start, which pymavlink skips as garbage).

    ``blob``: the file's bytes if already read; ``start`` (byte offset of a message) and ``lengths`` (type →
    length, bytes, as the FMT messages before ``start`` defined them): continue a walk there (the fast
    decoder's index has walked the rest)."""
    if blob is None:
        with open(path, "rb") as handle:
            blob = handle.read()
    lengths = {DATAFLASH_FMT: DATAFLASH_FMT_LENGTH} if lengths is None else dict(lengths)
    offset, size = start, len(blob)
    while offset + 3 <= size:
        if blob[offset:offset + 2] != DATAFLASH_HEAD:
            following = blob.find(DATAFLASH_HEAD, offset + 1)  # resynchronise as pymavlink does
            if following < 0:
                return None
            offset = following
            continue
        kind = blob[offset + 2]
        length = lengths.get(kind)
        if length is None:  # an undefined type: skip its header and resynchronise
            offset += 1
            continue
        if offset + length > size:
            return offset + length - size
        if kind == DATAFLASH_FMT and length == DATAFLASH_FMT_LENGTH:
            lengths[blob[offset + 3]] = blob[offset + 4]
        offset += length
    tail = blob[offset:]
    return 3 - len(tail) if tail and DATAFLASH_HEAD.startswith(tail[:2]) else None  # a header cut in two


def warn_if_truncated(data, path: str, missing_bytes) -> None:
    """Set ``data.truncated`` and warn (one line) when ``missing_bytes(path)`` finds the file cut short."""
    missing = missing_bytes(path)
    if missing is not None:
        data.truncated = True
        data.warn(f"{data.source}: the file ends inside a message ({missing} byte(s) short): truncated, the log "
                  f"stops at {float(data.time[-1]):.2f} s of a flight that may have gone on")
