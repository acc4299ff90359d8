"""Seeds of csrc/fuzz/fuzz_ulog.c: the ULog test fixtures (new and old PX4 styles; plain, with damaged bytes before
sync messages, and with data appended), short so that the fuzzer mutates whole logs. Run from the repository root: ``python csrc/fuzz/make_seeds_ulog.py``."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_seeds_dataflash import ROOT, fx, write_seeds  # noqa: E402

CORPUS = ROOT / "csrc" / "fuzz" / "corpus_ulog"


def _write(path, damage=None, **options) -> None:
    if damage is None:
        fx.write_ulog(path, **options)
    else:
        fx.write_ulog_damaged(path, damage, **options)


def main() -> None:
    cases = [dict(style=style, damage=damage) for damage in (None, "sync", "appended") for style in ("new", "old")]
    write_seeds(CORPUS, _write, cases, ".ulg")


if __name__ == "__main__":
    main()
