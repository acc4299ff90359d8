"""Seeds of csrc/fuzz/fuzz_dataflash.c: the DataFlash test fixtures (TimeMS and TimeUS generations, one with a
damaged tail), short so that the fuzzer mutates whole logs. Run from the repository root:
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


def main() -> None:
    cases = [dict(style="TimeMS"), dict(style="TimeUS"), dict(style="TimeUS", corrupt_tail=True, repeat_every=3)]
    write_seeds(CORPUS, fx.write_dataflash, cases, ".bin")


if __name__ == "__main__":
    main()
