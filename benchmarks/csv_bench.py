"""CSV read and ``run -o`` write throughput, old (Python) and new (pyarrow / C) paths in the same run.

Run::

    python benchmarks/csv_bench.py [--rows 1000000] [--repeat 3] [--copies 400]

Read, each by :func:`fusion_altitude.logs.load_log` (the whole reader: parse, checks, time grid): the shared
Hedy CATS export (``hedy_imu.csv``, ``hedy_baro.csv``, ``hedy_flight_info.csv`` read together), the shared
RRC3 (``rrc3_juno3.csv``) and Raven (``raven_ndrt2020.csv``) exports, the same two exports scaled up
(``--copies`` copies of their rows, each copy's time columns shifted past the last: the format at the size of
a long flight) and a generated generic CSV of ``--rows`` rows (``time,accel,baro,reference``, baro on every
10th row, empty elsewhere) read by :func:`fusion_altitude.logs.read_csv_log`; a row times the CATS parse
alone (the three files' text, header and numeric columns,
:func:`fusion_altitude.logs._table.numeric_columns`). MB/s is the bytes of the files read over the CPU
(process) time. The shared RRC3 and Raven exports are 28 kB and 72 kB: a load of either repeats ``--inner``
times per timing, and their figures are bound by what every load costs whatever its size (opening and
sniffing the file, the log checks), not by parsing: bodies up to ``_csv_fast.SCAN_MAX_CHARS`` are parsed by
the C scan of ``logs/_csv_scan.h``, without pyarrow's set-up of a parse (about 0.2 ms). Write: the observer's run on the CATS and generated logs written
with :func:`fusion_altitude.runner.write_csv` (``run -o out.csv``); MB/s is the bytes written over the CPU
time. Each figure is the best of ``--repeat`` runs after one warm-up, the old path (``csv_engine("python")``:
numpy's ``loadtxt``, the Python loops, Python ``%`` formatting; the strapdown integration of the CATS reader
is C in both) and the new one measured in turn; both write the same bytes (checked). Shared data from
``FUSION_ALTITUDE_SHARED_DATA`` (default ``../shared/data``).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import tempfile
import time
import warnings

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


def scaled_copy(source: str, path: str, copies: int, time_columns) -> None:
    """The rows of the export ``source`` ``copies`` times into ``path``, each copy's ``time_columns`` (positions;
    s) shifted by the span of the one before plus 1 s: the same format, as long as a long flight's."""
    with open(source, encoding="utf-8") as handle:
        header, body = handle.read().split("\n", 1)
    rows = [line.split(",") for line in body.split("\n") if line.strip()]
    span = max(float(row[c]) for row in rows for c in time_columns if row[c].strip()) + 1.0
    lines = [header]
    for copy in range(copies):
        for row in rows:
            cells = list(row)
            for c in time_columns:
                if cells[c].strip():
                    cells[c] = f"{float(cells[c]) + copy * span:.5f}"
            lines.append(",".join(cells))
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines) + "\n")


def best_cpu(run, repeat: int, inner: int = 1) -> float:
    """Least CPU (process) time of ``run()`` over ``repeat`` timings of ``inner`` calls each after a warm-up, s a
    call."""
    run()
    best = None
    for _ in range(repeat):
        start = time.process_time()
        for _ in range(inner):
            run()
        elapsed = (time.process_time() - start) / inner
        best = elapsed if best is None else min(best, elapsed)
    return best


def quiet_load(path: str):
    """:func:`load_log` of ``path``, its warnings (the exports' real quirks) not printed."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_log(path)


@contextlib.contextmanager
def old_path():
    with _csv_fast.engine("python"), _csv_write.engine("python"):
        yield


def read_cases(data: str, directory: str, args):
    """(label, read, bytes, inner) of every read row."""
    hedy = os.path.join(data, "hedy_imu.csv")
    hedy_files = [os.path.join(data, f"hedy_{n}.csv") for n in ("imu", "baro", "flight_info")]
    hedy_bytes = sum(os.path.getsize(p) for p in hedy_files)
    generated = os.path.join(directory, "generated.csv")
    write_generated(generated, args.rows)
    cases = [("Hedy CATS CSV (3 files)", lambda: load_log(hedy), hedy_bytes, 1),
             ("Hedy CSV columns only (3 files)", lambda: [parse_numbers(p) for p in hedy_files], hedy_bytes, 1)]
    for name, label, time_columns in (("rrc3_juno3.csv", "RRC3 export", [0]),
                                      ("raven_ndrt2020.csv", "Raven export", [0, 3])):
        shared = os.path.join(data, name)
        scaled = os.path.join(directory, f"scaled_{name}")
        scaled_copy(shared, scaled, args.copies, time_columns)
        cases.append((f"{label} {name}", lambda p=shared: quiet_load(p), os.path.getsize(shared), args.inner))
        cases.append((f"{label} × {args.copies}", lambda p=scaled: quiet_load(p), os.path.getsize(scaled), 1))
    cases.append(("generated CSV", lambda: read_csv_log(generated, "time", "accel", "baro",
                                                       reference_column="reference"), os.path.getsize(generated), 1))
    return cases


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=1_000_000, help="rows of the generated CSV")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--copies", type=int, default=400, help="copies of the RRC3 and Raven rows, scaled rows")
    parser.add_argument("--inner", type=int, default=20, help="loads per timing of the small shared exports")
    args = parser.parse_args(argv)
    data = shared_data()
    rows = []
    with tempfile.TemporaryDirectory() as directory:
        cases = read_cases(data, directory, args)
        for label, read, size, inner in cases:
            with old_path():
                old = best_cpu(read, args.repeat, inner)
            new = best_cpu(read, args.repeat, inner)
            rows.append((f"read {label}", size, old, new))
        for label, read, _, _ in (cases[0], cases[-1]):
            run = run_log(read())
            out_old, out_new = os.path.join(directory, "old.csv"), os.path.join(directory, "new.csv")
            with old_path():
                old = best_cpu(lambda: write_csv(run, out_old), args.repeat)
            new = best_cpu(lambda: write_csv(run, out_new), args.repeat)
            with open(out_old, "rb") as a, open(out_new, "rb") as b:
                if a.read() != b.read():
                    raise SystemExit(f"write {label}: the new writer's bytes differ from the old writer's")
            rows.append((f"write -o {label}", os.path.getsize(out_new), old, new))
    print(f"CSV read and write, CPU time, best of {args.repeat} ({args.rows} generated rows, "
          f"{args.copies} copies; load average {os.getloadavg()[0]:.1f})\n")
    print("| case | MB | old MB/s | new MB/s | new ÷ old |")
    print("|---|---:|---:|---:|---:|")
    for label, size, old, new in rows:
        print(f"| {label} | {size / 1e6:.2f} | {size / 1e6 / old:.1f} | {size / 1e6 / new:.1f} | {old / new:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
