"""Seeds of csrc/fuzz/fuzz_ulog.c: the ULog test fixtures (new and old PX4 styles), short so that the fuzzer
mutates whole logs. Run from the repository root: ``python csrc/fuzz/make_seeds_ulog.py``."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_seeds_dataflash import ROOT, fx, write_seeds  # noqa: E402

CORPUS = ROOT / "csrc" / "fuzz" / "corpus_ulog"


def main() -> None:
    write_seeds(CORPUS, fx.write_ulog, [dict(style="new"), dict(style="old")], ".ulg")


if __name__ == "__main__":
    main()
