"""Seeds of csrc/fuzz/fuzz_ulog.c for the fast decoder's per-message checks (ULogCheckMessages, ULogCheckAndCount,
ULogCopySamples): small hand-made ULogs whose data section has several subscriptions (samples interleaved, of another
size, of an unsubscribed msg_id, before their A message) and damaged messages a check rejects (L, C, A, D shorter than
pyulog parses, an O not of 2 bytes, info messages that fail or are undecided). Run from the repository root:
``python csrc/fuzz/make_seeds_ulog_checks.py``."""

import hashlib
import struct
from pathlib import Path

CORPUS = Path(__file__).resolve().parent / "corpus_ulog"
MAGIC = b"ULog\x01\x12\x35\x01"


def message(kind: str, payload: bytes) -> bytes:
    """One ULog message: payload size (uint16), type byte, payload."""
    return struct.pack("<HB", len(payload), ord(kind)) + payload


def info(kind: str, key: bytes, value: bytes, continued: bool = False) -> bytes:
    """An I/P (key length, key, value) or M/Q (a leading byte first) message."""
    head = bytes([int(continued)]) if kind in "MQ" else b""
    return message(kind, head + bytes([len(key)]) + key + value)


def definitions() -> bytes:
    """Three formats, a string info, a float parameter and a multi info."""
    out = b""
    for name in (b"baro", b"accel", b"gps"):
        out += message("F", name + b":uint64_t timestamp;float value;")
    out += info("I", b"char[4] sys_name", b"PX4!") + info("P", b"float P1", struct.pack("<f", 1.5))
    return out + info("M", b"char[3] hw", b"abc")


def subscribe(multi_id: int, msg_id: int, name: bytes) -> bytes:
    """An A message."""
    return message("A", struct.pack("<BH", multi_id, msg_id) + name)


def sample(msg_id: int, time_us: int, value: float, extra: bytes = b"") -> bytes:
    """A D message of a uint64 time stamp (us) and a float32."""
    return message("D", struct.pack("<HQf", msg_id, time_us, value) + extra)


def subscriptions() -> bytes:
    """A data section of three subscriptions, samples interleaved, with samples that are none of theirs."""
    out = sample(2, 5, 9.0) + subscribe(0, 0, b"baro") + subscribe(0, 1, b"accel")
    for k in range(6):
        out += sample(0, 100 * k, 1.0 + k) + sample(1, 100 * k + 50, -k)
        if k == 2:
            out += subscribe(0, 2, b"gps") + subscribe(1, 0, b"baro") + sample(7, 1, 0.0)
        if k >= 3:
            out += sample(2, 100 * k + 70, 0.5 * k) + sample(1, 1, 0.0, extra=b"xy")
    out += message("L", b"\x36" + struct.pack("<Q", 700) + b"ok") + message("O", struct.pack("<H", 20))
    return out + message("C", b"\x36" + struct.pack("<HQ", 1, 800) + b"tag")


def damaged() -> bytes:
    """Messages each check rejects, and more undecided info messages than the harness's capacity."""
    out = subscribe(0, 0, b"baro") + sample(0, 1, 2.0)
    out += message("L", b"\x36" + b"\x00" * 7) + message("C", b"\x36" + b"\x00" * 9) + message("A", b"\x00\x03")
    out += message("D", b"\x00") + message("O", b"\x01\x00\x00") + sample(0, 2, 3.0)
    out += info("I", b"float bad", b"\x00\x00") + info("M", b"oneword", b"x") + info("Q", b"uint8_t q", b"\x01")
    for k in range(5):
        out += info("I", b"char[2] n\xc3\xa9" + bytes([k]), b"ok")
    return out + info("P", b"int32_t P2", struct.pack("<i", 3)) + sample(0, 3, 4.0)


def main() -> None:
    for header_time, body in ((b"\x00" * 7 + b"\x03", subscriptions()), (b"\x10\x00\x20\x00\x30\x00\x01\x02", damaged())):
        data = MAGIC + header_time + definitions() + body
        (CORPUS / hashlib.sha1(data).hexdigest()).write_bytes(data)


if __name__ == "__main__":
    main()
