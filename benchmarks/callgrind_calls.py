"""Instructions per per-sample ``update()`` call from Python, counted by callgrind.

    python benchmarks/callgrind_calls.py [--calls N] [CASE ...]

For each case, runs a Python loop of N and of 2N ``update()`` calls (on
Python floats from lists, loop included, after the same imports and set-up)
under ``valgrind --tool=callgrind`` and prints the difference / N: the
instructions one iteration costs, free of start-up and of the machine's load
(wall time on this shared 2-core machine is not). The ``empty`` case is the
bare ``for`` loop over the same lists (every loop zips a ``range(n)`` in, so
that both runs build the same lists). Needs valgrind (fails without it).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys

SETUP = """
import sys, numpy as np, fusion_altitude
n = int(sys.argv[2])
size = int(sys.argv[3])  # the lists are as long in both runs: only the loop's length differs
rng = np.random.default_rng(1)
a = (0.3 * rng.standard_normal(size)).tolist()
z = (4 + 0.4 * rng.standard_normal(size)).tolist()
l = (4 + 0.04 * rng.standard_normal(size)).tolist()
g = (4 + 1.5 * rng.standard_normal(size)).tolist()
s = [9] * size
dt = 0.01
case = sys.argv[1]
"""

LOOPS = {
    "empty": "for i, x, y in zip(range(n), a, z):\n    pass\n",
    "observer": "update = fusion_altitude.AltitudeEstimator().update\nfor i, x, y in zip(range(n), a, z):\n    update(x, y, dt)\n",
    "complementary": "update = fusion_altitude.ComplementaryFilter().update\nfor i, x, y in zip(range(n), a, z):\n    update(x, y, dt)\n",
    "alphabeta": ("update = fusion_altitude.AlphaBetaFusion().update\n"
                  "for i, x, y, w, v in zip(range(n), a, z, l, g):\n    update(x, dt, y, w, gps_altitude=v)\n"),
    "kalman": ("update = fusion_altitude.KalmanEstimator().update\n"
               "for i in range(n):\n    update(a[i], dt, 250 + z[i], l[i], 290 + g[i], s[i])\n"),
}


def instructions(case: str, calls: int, size: int) -> int:
    code = SETUP + LOOPS[case]
    result = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", sys.executable, "-c", code,
                             case, str(calls), str(size)], capture_output=True, text=True,
                            env={**os.environ, "PYTHONHASHSEED": "0"})  # the same start-up in both runs
    if result.returncode != 0:
        raise RuntimeError(result.stderr[-2000:])
    return int(re.search(r"Collected : (\d+)", result.stderr).group(1))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cases", nargs="*", metavar="CASE", help=f"any of {', '.join(LOOPS)} (default: all)")
    parser.add_argument("--calls", type=int, default=50_000)
    args = parser.parse_args(argv)
    cases = args.cases or list(LOOPS)
    unknown = [case for case in cases if case not in LOOPS]
    if unknown:
        parser.error(f"unknown case {unknown[0]!r}; choose from {', '.join(LOOPS)}")
    print(f"Python {sys.version.split()[0]}, {args.calls} vs {2 * args.calls} calls")
    print("| case | instructions per iteration (loop included) |")
    print("|---|---:|")
    for case in cases:
        size = 2 * args.calls
        per = (instructions(case, 2 * args.calls, size) - instructions(case, args.calls, size)) / args.calls
        print(f"| {case} | {per:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
