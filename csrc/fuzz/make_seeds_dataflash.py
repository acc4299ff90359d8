"""Seeds of csrc/fuzz/fuzz_dataflash.c: the DataFlash test fixtures (TimeMS and TimeUS generations, one with a
damaged tail, one with stray bytes, one with a type defined twice), short so that the fuzzer mutates whole logs. Run from the repository root:
``python csrc/fuzz/make_seeds_dataflash.py``."""

import hashlib
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))
import logfixtures as fx  # noqa: E402

CORPUS = ROOT / "csrc" / "fuzz" / "corpus_dataflash"


#: Rates (Hz) and length (s) of every seed: short, so that the fuzzer mutates whole logs.
SHORT = dict(duration=0.5, imu_rate=20.0, baro_rate=10.0, gps_rate=5.0)


def write_seeds(corpus: Path, write, cases, suffix: str) -> None:
    """Write ``write(path, **SHORT, **case)`` of each case into ``corpus`` under its content's SHA-1."""
    corpus.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as directory:
        for number, options in enumerate(cases):
            path = Path(directory) / f"seed{number}{suffix}"
            write(path, **SHORT, **options)
            data = path.read_bytes()
            (corpus / hashlib.sha1(data).hexdigest()).write_bytes(data)


def damaged_seeds(corpus: Path) -> None:
    """Two seeds of what the fast decoder reads since issue 25 item 2: stray bytes between messages (runs of zeros
    and of header-like bytes) and a second FMT for the BARO type (its columns swapped)."""
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / "seed.bin"
        fx.write_dataflash(path, style="TimeUS", **SHORT)
        data = path.read_bytes()
    fmt_at = data.index(b"\xa3\x95\x80" + bytes([132]))  # logfixtures' BARO type
    second = data[fmt_at:fmt_at + 25] + b"TimeUS,I,Press,Alt,Temp".ljust(64, b"\0")
    middle = len(data) // 2
    middle = data.index(b"\xa3\x95", middle)
    stray = data[:89] + b"\0\0\0" + data[89:middle] + b"\xa3\x00\x95\xa3" + data[middle:]
    for seed in (stray, data[:middle] + second + data[middle:]):
        (corpus / hashlib.sha1(seed).hexdigest()).write_bytes(seed)


def main() -> None:
    cases = [dict(style="TimeMS"), dict(style="TimeUS"), dict(style="TimeUS", corrupt_tail=True, repeat_every=3)]
    write_seeds(CORPUS, fx.write_dataflash, cases, ".bin")
    damaged_seeds(CORPUS)


if __name__ == "__main__":
    main()
