"""Seeds of csrc/fuzz/fuzz_ulog.c: the ULog test fixtures (new and old PX4 styles), short so that the fuzzer
mutates whole logs. Run from the repository root: ``python csrc/fuzz/make_seeds_ulog.py``."""

import hashlib
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))
import logfixtures as fx  # noqa: E402

CORPUS = ROOT / "csrc" / "fuzz" / "corpus_ulog"


def main() -> None:
    CORPUS.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as directory:
        for style in ("new", "old"):
            path = Path(directory) / f"{style}.ulg"
            fx.write_ulog(path, style=style, duration=0.5, imu_rate=20.0, baro_rate=10.0, gps_rate=5.0)
            data = path.read_bytes()
            (CORPUS / hashlib.sha1(data).hexdigest()).write_bytes(data)


if __name__ == "__main__":
    main()
