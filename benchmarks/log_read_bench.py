"""Time reading a large generic CSV log (1 million rows; 5.7 s before numpy's C parser was used).

Run::

    python benchmarks/log_read_bench.py [--rows 1000000] [--repeat 3]

Writes ``time,accel,baro,reference`` rows (baro on every 10th row, empty
elsewhere) to a temporary file, then reads it with
:func:`fusion_altitude.logs.read_csv_log` and prints the best wall-clock and
CPU (process) time over ``--repeat`` reads. CPU time is the fairer figure on
a shared machine.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

from fusion_altitude.logs import read_csv_log


def write_csv(path: str, rows: int, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    time_s = np.arange(rows) * 0.01
    accel = rng.standard_normal(rows)
    altitude = 100.0 + np.cumsum(rng.standard_normal(rows)) * 0.01
    with open(path, "w") as handle:
        handle.write("time,accel,baro,reference\n")
        for i in range(rows):
            baro = f"{altitude[i]:.3f}" if i % 10 == 0 else ""
            handle.write(f"{time_s[i]:.3f},{accel[i]:.5f},{baro},{altitude[i]:.3f}\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "big.csv")
        write_csv(path, args.rows)
        walls, cpus = [], []
        for _ in range(args.repeat):
            wall, cpu = time.perf_counter(), time.process_time()
            data = read_csv_log(path, "time", "accel", "baro", reference_column="reference")
            walls.append(time.perf_counter() - wall)
            cpus.append(time.process_time() - cpu)
        size = os.path.getsize(path) / 1e6
    print(f"{args.rows} rows ({size:.1f} MB, {data.time.size} samples): best wall {min(walls):.2f} s, "
          f"best CPU {min(cpus):.2f} s over {args.repeat} reads")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
