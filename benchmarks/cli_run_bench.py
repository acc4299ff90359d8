"""Time ``fusion-altitude run LOG -o OUT.csv --plot OUT.png`` on a 1-million-row CSV, stage by stage.

Run::

    python benchmarks/cli_run_bench.py [--rows 1000000] [--keep DIR]

Writes a generic CSV of ``--rows`` rows: ``time`` (Unix-epoch seconds,
100 Hz, 2 decimals), ``vertical_acceleration`` (m/s²) and ``baro_altitude``
(m, on every 10th row, empty elsewhere); then runs the command in a fresh
interpreter with every stage's time printed (the CLI prints only stages of
≥ 0.5 s) and reports the stage times, the whole command's wall-clock and CPU
time and the load average before and after (the machine is shared: CPU time
is the fairer figure).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np


def write_csv(path: str, rows: int, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    t = 1_700_000_000.0 + 0.01 * np.arange(rows)
    accel = rng.normal(0.0, 0.05, rows)
    baro = 100.0 + 5.0 * np.sin(np.arange(rows) * 1e-4) + rng.normal(0.0, 0.3, rows)
    with open(path, "w") as out:
        out.write("time,vertical_acceleration,baro_altitude\n")
        for start in range(0, rows, 100_000):
            stop = min(start + 100_000, rows)
            out.write("\n".join(f"{t[i]:.2f},{accel[i]:.4f},{baro[i]:.3f}" if i % 10 == 0
                                else f"{t[i]:.2f},{accel[i]:.4f}," for i in range(start, stop)) + "\n")


COMMAND = ("import sys, fusion_altitude.cli as cli; cli.STAGE_REPORT_SECONDS = 0.0; "
           "sys.exit(cli.main(sys.argv[1:]))")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rows", type=int, default=1_000_000)
    parser.add_argument("--keep", metavar="DIR", help="write the log and the outputs here (default: a temporary folder)")
    args = parser.parse_args()
    folder = args.keep or tempfile.mkdtemp(prefix="cli_run_bench.")
    log = os.path.join(folder, "million.csv")
    write_csv(log, args.rows)
    argv = ["run", log, "--time", "time", "--accel", "vertical_acceleration", "--baro", "baro_altitude",
            "-o", os.path.join(folder, "out.csv"), "--plot", os.path.join(folder, "out.png")]
    print(f"fusion-altitude {' '.join(argv)}")
    load_before = os.getloadavg()
    start = time.perf_counter()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-c", COMMAND, *argv], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(done.stderr)
    for line in done.stderr.splitlines():
        print(f"  {line}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print(f"whole command: {wall:.2f} s wall, {cpu:.2f} s CPU (user + system), {os.cpu_count()} cores; "
          f"load average {load_before[0]:.2f} before, {os.getloadavg()[0]:.2f} after")
    if not args.keep:
        for name in ("million.csv", "out.csv", "out.png"):
            os.remove(os.path.join(folder, name))
        os.rmdir(folder)


if __name__ == "__main__":
    main()
