"""Seeds of csrc/fuzz/fuzz_csv.c: the bodies (first 40 data lines) of the CSV test fixtures — generic, RRC3, Raven,
one with awkward cells — each after a byte choosing the numeric and text cell positions. Run from the repository
root: ``python csrc/fuzz/make_seeds_csv.py``."""

import hashlib
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))
import logfixtures as fx  # noqa: E402

CORPUS = ROOT / "csrc" / "fuzz" / "corpus_csv"
#: Two bits per cell position 0..3 (0 skipped, 1 numeric, 2 text): all numeric; numbers then two text columns.
ROLES = (0b01010101, 0b10100101)
AWKWARD = ("0,1e5,,NA\n0.05, -5.391191E-05 ,nan,-\n0.10,1.2605042016806722,inf,n/a\n0.15,.5,5.,-.5e+3\n"
           "0.20,9007199254740993,1e-400,1e309\n\n0.25,1,2,3")


def main() -> None:
    CORPUS.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as directory:
        fx.write_generic_csv(Path(directory) / "generic.csv", duration=2.0, rate=20.0)
        paths = [Path(directory) / "generic.csv", Path(fx.rrc3_csv(directory)), Path(fx.raven_csv(directory))]
        bodies = [b"\n".join(p.read_bytes().replace(b"\r\n", b"\n").split(b"\n")[1:41]) for p in paths]
    for body in bodies + [AWKWARD.encode()]:
        for role in ROLES:
            data = bytes([role]) + body
            (CORPUS / hashlib.sha1(data).hexdigest()).write_bytes(data)


if __name__ == "__main__":
    main()
