"""CSV read and ``run -o`` write throughput, old (Python) and new (pyarrow / C) paths in the same run.

Run::

    python benchmarks/csv_bench.py [--rows 1000000] [--repeat 3]

Read: the shared Hedy CATS export (``hedy_imu.csv``, ``hedy_baro.csv``,
``hedy_flight_info.csv`` read together by
:func:`fusion_altitude.logs.load_log`) and a generated generic CSV of
``--rows`` rows (``time,accel,baro,reference``, baro on every 10th row,
empty elsewhere) read by :func:`fusion_altitude.logs.read_csv_log`; MB/s is
the bytes of the files read over the CPU (process) time. Most of the CATS
reader's time is not parsing (its strapdown gyro integration,
:func:`fusion_altitude.sensors.gyro_attitude`, a Python loop), so a row
times the parse alone: the three files' text, header and numeric columns
(:func:`fusion_altitude.logs._table.numeric_columns`). Write: the
observer's run on each log written with :func:`fusion_altitude.runner.write_csv`
(``run -o out.csv``); MB/s is the bytes written over the CPU time. Each
figure is the best of ``--repeat`` runs after one warm-up, the old path
(``csv_engine("python")``: numpy's ``loadtxt`` and Python ``%`` formatting)
and the new one measured in turn; both write the same bytes (checked).
Shared data from ``FUSION_ALTITUDE_SHARED_DATA`` (default ``../shared/data``).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import tempfile
import time

import numpy as np

from fusion_altitude._core import _csv_write
from fusion_altitude.logs import _csv_fast, load_log, read_csv_log
from fusion_altitude.logs._table import numeric_columns, read_text, split_header
from fusion_altitude.runner import run_log, write_csv


def shared_data() -> str:
    here = os.path.dirname(os.path.abspath(__file__))
    path = os.environ.get("FUSION_ALTITUDE_SHARED_DATA", os.path.join(here, "..", "..", "shared", "data"))
    if not os.path.isdir(path):
        raise SystemExit(f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA")
    return path


def write_generated(path: str, rows: int, seed: int = 0) -> None:
    """``time,accel,baro,reference`` rows: time s (10 ms steps), accel m/s² (noise), baro m on every 10th row."""
    rng = np.random.default_rng(seed)
    time_s = np.char.mod("%.3f", np.arange(rows) * 0.01)
    accel = np.char.mod("%.5f", rng.standard_normal(rows))
    altitude = np.char.mod("%.3f", 100.0 + np.cumsum(rng.standard_normal(rows)) * 0.01)
    baro = np.where(np.arange(rows) % 10 == 0, altitude, "")
    with open(path, "w") as handle:
        handle.write("time,accel,baro,reference\n")
        handle.write("\n".join(",".join(cells) for cells in zip(time_s, accel, baro, altitude)) + "\n")


def parse_numbers(path: str):
    """Only the CSV parse of what a reader does: the text, its header and every column but ``id`` as numbers."""
    table = split_header(path, read_text(path))
    return numeric_columns(table, [i for i, name in enumerate(table.header) if name != "id"])


def best_cpu(run, repeat: int) -> float:
    """Least CPU (process) time of ``run()`` over ``repeat`` calls after a warm-up, s."""
    run()
    best = None
    for _ in range(repeat):
        start = time.process_time()
        run()
        elapsed = time.process_time() - start
        best = elapsed if best is None else min(best, elapsed)
    return best


@contextlib.contextmanager
def old_path():
    with _csv_fast.engine("python"), _csv_write.engine("python"):
        yield


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=1_000_000, help="rows of the generated CSV")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    data = shared_data()
    hedy = os.path.join(data, "hedy_imu.csv")
    hedy_bytes = sum(os.path.getsize(os.path.join(data, f"hedy_{n}.csv")) for n in ("imu", "baro", "flight_info"))
    rows = []
    with tempfile.TemporaryDirectory() as directory:
        generated = os.path.join(directory, "generated.csv")
        write_generated(generated, args.rows)
        cases = [("Hedy CATS CSV (3 files)", lambda: load_log(hedy), hedy_bytes),
                 ("generated CSV", lambda: read_csv_log(generated, "time", "accel", "baro",
                                                        reference_column="reference"),
                  os.path.getsize(generated))]
        hedy_files = [os.path.join(data, f"hedy_{n}.csv") for n in ("imu", "baro", "flight_info")]
        parse = [("Hedy CSV columns only (3 files)", lambda: [parse_numbers(p) for p in hedy_files], hedy_bytes)]
        for label, read, size in cases[:1] + parse + cases[1:]:
            with old_path():
                old = best_cpu(read, args.repeat)
            new = best_cpu(read, args.repeat)
            rows.append((f"read {label}", size, old, new))
        for label, read, _ in cases:
            run = run_log(read())
            out_old, out_new = os.path.join(directory, "old.csv"), os.path.join(directory, "new.csv")
            with old_path():
                old = best_cpu(lambda: write_csv(run, out_old), args.repeat)
            new = best_cpu(lambda: write_csv(run, out_new), args.repeat)
            with open(out_old, "rb") as a, open(out_new, "rb") as b:
                if a.read() != b.read():
                    raise SystemExit(f"write {label}: the new writer's bytes differ from the old writer's")
            rows.append((f"write -o {label}", os.path.getsize(out_new), old, new))
    print(f"CSV read and write, CPU time, best of {args.repeat} ({args.rows} generated rows)\n")
    print("| case | MB | old MB/s | new MB/s | new ÷ old |")
    print("|---|---:|---:|---:|---:|")
    for label, size, old, new in rows:
        print(f"| {label} | {size / 1e6:.1f} | {size / 1e6 / old:.1f} | {size / 1e6 / new:.1f} | {old / new:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
