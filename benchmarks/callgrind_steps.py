"""Instructions per step of each estimator's C update, counted by callgrind.

    python benchmarks/callgrind_steps.py [--steps N] [--csrc DIR] [CASE ...]

Compiles benchmarks/c_steps.c against the headers in ``--csrc`` (default:
this checkout's csrc/; point it at another checkout's csrc/ for a before/after
comparison) with the flags setup.py uses, runs it under
``valgrind --tool=callgrind`` for N steps and for 0 steps, and prints
(instructions(N) - instructions(0)) / N per case. Unlike wall time, the count
does not depend on what else the machine is running. Needs valgrind and a C
compiler (fails without them).
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
CASES = ("alphabeta", "kalman", "complementary", "observer", "ins")
CFLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-math-errno"]  # setup.py's


def instructions(executable: Path, case: str, steps: int) -> int:
    result = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", str(executable), case,
                             str(steps)], capture_output=True, text=True, check=True)
    match = re.search(r"Collected : (\d+)", result.stderr)
    if match is None:
        raise RuntimeError(f"no callgrind count in:\n{result.stderr}")
    return int(match.group(1))


def per_step(csrc: Path, cases, steps: int, cc: str = "gcc"):
    """{case: instructions per step}."""
    with tempfile.TemporaryDirectory(prefix="c_steps_") as tmp:
        executable = Path(tmp) / "c_steps"
        subprocess.run([cc, *CFLAGS, f"-I{csrc}", str(HERE / "c_steps.c"), "-o", str(executable), "-lm"], check=True)
        return {case: (instructions(executable, case, steps) - instructions(executable, case, 0)) / steps
                for case in cases}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cases", nargs="*", metavar="CASE", help=f"any of {', '.join(CASES)} (default: all)")
    parser.add_argument("--steps", type=int, default=100_000)
    parser.add_argument("--csrc", type=Path, default=HERE.parent / "csrc")
    parser.add_argument("--cc", default="gcc")
    args = parser.parse_args(argv)
    unknown = [case for case in args.cases if case not in CASES]
    if unknown:
        parser.error(f"unknown case {unknown[0]!r}; choose from {', '.join(CASES)}")
    counts = per_step(args.csrc.resolve(), args.cases or CASES, args.steps, args.cc)
    print(f"headers: {args.csrc.resolve()}, {args.cc} {' '.join(CFLAGS)}, {args.steps} steps")
    print("| case | instructions/step |")
    print("|---|---:|")
    for case, count in counts.items():
        print(f"| {case} | {count:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
