"""Instructions per per-sample ``update()`` call from Python, counted by callgrind.

    python benchmarks/callgrind_calls.py [--calls N] [CASE ...]

For each case, runs a Python loop of N and of 2N ``update()`` calls (on
Python floats from lists, loop included, in a function with the names as locals, the garbage
collector off, after the same imports and set-up)
under ``valgrind --tool=callgrind`` and prints the difference / N: the
instructions one iteration costs, free of start-up and of the machine's load
(wall time on this shared 2-core machine is not). The ``empty`` case is the
bare ``for`` loop over the same lists (every loop zips a ``range(n)`` in, so
that both runs build the same lists); ``empty6`` the bare loop of the Kalman case's six lists. The
Kalman filter and the alpha-beta fusion are called by keyword after accel (the contract's fast path);
the ``-legacy`` cases call them in the deprecated positional order (accel, dt, baro_altitude, ...),
which goes through the deprecation shim (warning filtered to "ignore"). The ``noop-*`` cases call a Cython
method with the same parameters that does nothing, compiled here with the extension's flags: the floor of
the call itself. For the estimators, the last column counts the instructions on lines of the C header
(csrc/, wherever gcc inlined them; callgrind_annotate): the C update step. Needs valgrind and, for the
noop cases, Cython and a C compiler (fails without them).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile

SETUP = """
import gc, sys, numpy as np, fusion_altitude
n = int(sys.argv[2])
size = int(sys.argv[3])  # the lists are as long in both runs: only the loop's length differs
rng = np.random.default_rng(1)
a = (0.3 * rng.standard_normal(size)).tolist()
z = (4 + 0.4 * rng.standard_normal(size)).tolist()
l = (4 + 0.04 * rng.standard_normal(size)).tolist()
g = (4 + 1.5 * rng.standard_normal(size)).tolist()
s = [9] * size
zb = [250 + x for x in z]
zg = [290 + x for x in g]
dt = 0.01
case = sys.argv[1]


if case.startswith("noop"):
    import noop


def loop(n=n, a=a, z=z, l=l, g=g, s=s, zb=zb, zg=zg, dt=dt, fusion_altitude=fusion_altitude):  # names are locals
"""

NOOP_PYX = """
# cython: language_level=3
cdef class Noop:
    def three(self, accel, baro_altitude, dt):
        pass

    def alphabeta(self, accel, *args, baro_altitude=None, dt=None, lidar_altitude=None, sonar_altitude=None,
                  gps_altitude=None):
        pass

    def kalman(self, accel, *args, baro_altitude=None, dt=None, range_distance=None, gps_altitude=None,
               gps_satellites=None, gps_vertical_accuracy=None, ground_effect=None):
        pass
"""

#: The header whose update each case calls: the instructions on lines of csrc/ (this header and the helpers it
#: includes, inlined or not) are the C step.
C_CORE = {"observer": "fusion_altitude.h", "complementary": "fusion_altitude_complementary.h",
          "alphabeta": "fusion_altitude_alphabeta.h", "kalman": "fusion_altitude_kalman.h"}

RUN = """
gc.disable()  # a collection in one run and not the other would count as some 300 instructions per iteration
loop()
"""

LOOPS = {
    "empty": "for i, x, y in zip(range(n), a, z):\n    pass\n",
    "empty6": "for i, x, y, w, v, k in zip(range(n), a, zb, l, zg, s):\n    pass\n",
    "observer": "update = fusion_altitude.AltitudeEstimator().update\nfor i, x, y in zip(range(n), a, z):\n    update(x, y, dt)\n",
    "complementary": "update = fusion_altitude.ComplementaryFilter().update\nfor i, x, y in zip(range(n), a, z):\n    update(x, y, dt)\n",
    "alphabeta": ("update = fusion_altitude.AlphaBetaFusion().update\n"
                  "for i, x, y, w, v in zip(range(n), a, z, l, g):\n"
                  "    update(x, dt=dt, baro_altitude=y, lidar_altitude=w, gps_altitude=v)\n"),
    "kalman": ("update = fusion_altitude.KalmanEstimator().update\n"
               "for i, x, y, w, v, k in zip(range(n), a, zb, l, zg, s):\n"
               "    update(x, dt=dt, baro_altitude=y, range_distance=w, gps_altitude=v, gps_satellites=k)\n"),
    # The floor of the call: a Cython method with the same parameters that does nothing (compiled by this script
    # with the extension's flags), called the same way.
    "noop-3": "update = noop.Noop().three\nfor i, x, y in zip(range(n), a, z):\n    update(x, y, dt)\n",
    "noop-alphabeta": ("update = noop.Noop().alphabeta\n"
                       "for i, x, y, w, v in zip(range(n), a, z, l, g):\n"
                       "    update(x, dt=dt, baro_altitude=y, lidar_altitude=w, gps_altitude=v)\n"),
    "noop-kalman": ("update = noop.Noop().kalman\n"
                    "for i, x, y, w, v, k in zip(range(n), a, zb, l, zg, s):\n"
                    "    update(x, dt=dt, baro_altitude=y, range_distance=w, gps_altitude=v, gps_satellites=k)\n"),
    # the deprecated positional order (accel, dt, baro_altitude, ...): warns on every call
    "alphabeta-legacy": ("import warnings\nwarnings.simplefilter('ignore')\n"
                         "update = fusion_altitude.AlphaBetaFusion().update\n"
                         "for i, x, y, w, v in zip(range(n), a, z, l, g):\n    update(x, dt, y, w, gps_altitude=v)\n"),
    "kalman-legacy": ("import warnings\nwarnings.simplefilter('ignore')\n"
                      "update = fusion_altitude.KalmanEstimator().update\n"
                      "for i, x, y, w, v, k in zip(range(n), a, zb, l, zg, s):\n    update(x, dt, y, w, v, k)\n"),
}


# The same start-up in both runs: fixed hashing, and no BLAS worker threads (numpy's OpenBLAS threads
# spin for a varying number of instructions, some thousands per iteration of noise at small N).
SAME_START = {"PYTHONHASHSEED": "0", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def build_noop(directory: str) -> None:
    """Compile NOOP_PYX into ``directory`` (Cython and the extension's flags, as setup.py)."""
    with open(os.path.join(directory, "noop.pyx"), "w") as source:
        source.write(NOOP_PYX)
    script = ("from setuptools import Extension, setup; from Cython.Build import cythonize; "
              "setup(ext_modules=cythonize([Extension('noop', ['noop.pyx'], extra_compile_args=['-O2', "
              "'-ffp-contract=off', '-fno-fast-math'])], quiet=True), script_args=['build_ext', '--inplace', '-q'])")
    subprocess.run([sys.executable, "-c", script], cwd=directory, check=True, capture_output=True)


def instructions(case: str, calls: int, size: int, noop_dir: str, header: str = ""):
    """(instructions of the whole run, those on lines of csrc/``header``, 0 without a header)."""
    code = SETUP + "".join(f"    {line}\n" for line in LOOPS[case].splitlines()) + RUN
    with tempfile.TemporaryDirectory(prefix="callgrind_calls_") as tmp:
        out = os.path.join(tmp, "callgrind.out") if header else "/dev/null"
        env = {**os.environ, **SAME_START, "PYTHONPATH": os.pathsep.join(
            [noop_dir] + ([os.environ["PYTHONPATH"]] if os.environ.get("PYTHONPATH") else []))}
        result = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", sys.executable, "-c",
                                 code, case, str(calls), str(size)], capture_output=True, text=True, env=env)
        if result.returncode != 0:
            raise RuntimeError(result.stderr[-2000:])
        total = int(re.search(r"Collected : (\d+)", result.stderr).group(1))
        core = 0
        if header:  # self cost per file:function; the header's lines wherever gcc inlined them
            annotated = subprocess.run(["callgrind_annotate", "--threshold=100", out], capture_output=True, text=True,
                                       check=True).stdout
            for match in re.finditer(r"^\s*([\d,]+)\s+(?:\([^)]*\)\s+)?(\S+):\S", annotated, re.MULTILINE):
                if match.group(2).startswith("csrc/") or "/csrc/" in match.group(2):
                    core += int(match.group(1).replace(",", ""))
    return total, core


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cases", nargs="*", metavar="CASE", help=f"any of {', '.join(LOOPS)} (default: all)")
    parser.add_argument("--calls", type=int, default=50_000)
    args = parser.parse_args(argv)
    cases = args.cases or list(LOOPS)
    unknown = [case for case in cases if case not in LOOPS]
    if unknown:
        parser.error(f"unknown case {unknown[0]!r}; choose from {', '.join(LOOPS)}")
    where = subprocess.run([sys.executable, "-c", "import fusion_altitude; print(fusion_altitude._observer.__file__)"],
                           capture_output=True, text=True, check=True).stdout.strip()
    print(f"Python {sys.version.split()[0]}, {args.calls} vs {2 * args.calls} calls, bindings: {where}")
    print("| case | instructions per iteration (loop included) | of which the C update |")
    print("|---|---:|---:|")
    with tempfile.TemporaryDirectory(prefix="callgrind_noop_") as noop_dir:
        if any(case.startswith("noop") for case in cases):
            build_noop(noop_dir)
        for case in cases:
            size = 2 * args.calls
            header = C_CORE.get(case, "")
            total_1, core_1 = instructions(case, args.calls, size, noop_dir, header)
            total_2, core_2 = instructions(case, 2 * args.calls, size, noop_dir, header)
            core = f"{(core_2 - core_1) / args.calls:.0f}" if header else ""
            print(f"| {case} | {(total_2 - total_1) / args.calls:.0f} | {core} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
