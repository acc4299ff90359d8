"""Prepares an AVR replay of csrc/tests/vectors/<name>_vectors.h that streams the records instead of holding
them (the vectors are up to 0.5 MB; an AVR has at most 256 KB of flash, and avr-gcc copies const data to RAM).

    python3 avr_vectors.py VECTORS_HEADER OUT_DIR

writes OUT_DIR/vectors/<name>_vectors.h, a stand-in for the header (found first on the include path, so
replay_<name>.c compiles unchanged): its types, constants and settings tables as in the original, but the
record and checkpoint arrays replaced by macros that call avr_stream.c, which asks the simulator host
(avr_stream_host.c) for the next record or checkpoint over the UART. And OUT_DIR/<name>.records and
OUT_DIR/<name>.checkpoints: the same records and checkpoints in the AVR's memory layout (no padding,
little-endian), in order, for the host to send.
"""

from __future__ import annotations

import re
import struct
import sys
from pathlib import Path

TYPES = {"uint8_t": "B", "uint32_t": "I"}


def defines(text: str) -> dict:
    values = {name: int(value, 0) for name, value in re.findall(r"^#define (\w+) \((0x[0-9a-fA-F]+|\d+)u?\)", text, re.M)}
    return values


def struct_fields(text: str, type_name: str, values: dict) -> list:
    """(format char, count) per field of `typedef struct {...} type_name;`."""
    end = text.index("\n} " + type_name + ";")
    body = text[text.rindex("typedef struct {", 0, end):end]
    fields = []
    for kind, _, count in re.findall(r"^\s*(uint8_t|uint32_t)\s+(\w+)(?:\[(\w+)\])?;", body, re.M):
        fields.append((TYPES[kind], 1 if not count else (int(count) if count.isdigit() else values[count])))
    return fields


def array(text: str, type_name: str):
    """(name, count macro, body text, start, end) of the `static const type_name name[COUNT] = {...};` array."""
    match = re.search(r"^static const " + type_name + r" (\w+)\[(\w+)\] = \{\n(.*?)\n\};\n", text, re.S | re.M)
    return match.group(1), match.group(2), match.group(3), match.start(), match.end()


def pack(body: str, fields: list, values: dict) -> bytes:
    tokens = re.findall(r"0x[0-9a-fA-F]+|\d+|[A-Z_][A-Z0-9_]*", re.sub(r"/\*.*?\*/", "", body, flags=re.S))
    numbers = [values[token] if token in values else int(token, 0) for token in tokens]
    per_record = sum(count for _, count in fields)
    assert len(numbers) % per_record == 0, (len(numbers), per_record)
    layout = "<" + "".join(f"{count}{kind}" for kind, count in fields)
    return b"".join(struct.pack(layout, *numbers[i:i + per_record]) for i in range(0, len(numbers), per_record))


def main(argv: list) -> int:
    header, out_dir = Path(argv[1]), Path(argv[2])
    name = header.name[: -len("_vectors.h")]
    text = header.read_text()
    values = defines(text)
    types = re.findall(r"^\} (\w+Vector(?:Checkpoint)?);", text, re.M)
    replaced = text
    streams = []
    for type_name in types:
        kind = "Checkpoints" if type_name.endswith("Checkpoint") else "Records"
        array_name, count, body, start, end = array(text, type_name)
        data = pack(body, struct_fields(text, type_name, values), values)
        (out_dir / f"{name}.{kind.lower()}").write_bytes(data)
        macro = (f"/* streamed by chips/avr_stream.c ({kind.lower()} of {header.name}) */\n"
                 f"#define {array_name} ((const {type_name} *) AvrStream{kind}((uint16_t) sizeof({type_name}), "
                 f"(uint16_t) ({count})))\n")
        streams.append((text[start:end], macro))
    for original, macro in streams:
        replaced = replaced.replace(original, macro)
    prototypes = ("\n/* chips/avr_stream.c: the next record / the current checkpoint, fetched from the host, at\n"
                  " * the address the replay's index expects (the replay reads them in order). */\n"
                  "const void *AvrStreamRecords(uint16_t size, uint16_t count);\n"
                  "const void *AvrStreamCheckpoints(uint16_t size, uint16_t count);\n")
    replaced = replaced.replace("#include <stdint.h>\n", "#include <stdint.h>\n" + prototypes, 1)
    (out_dir / "vectors").mkdir(parents=True, exist_ok=True)
    (out_dir / "vectors" / header.name).write_text(replaced)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
