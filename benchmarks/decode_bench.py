"""Decoding speed of the log readers, MB/s of CPU time (best of 3), the fast decoder against pymavlink and pyulog
measured in the same run.

Run::

    python benchmarks/decode_bench.py [--data ../shared/data] [--repeat 3] [--fixture-seconds 120]

For each DataFlash log (every ``*.BIN``/``*.bin`` in the shared data, plus
one TimeUS fixture of ``--fixture-seconds`` s at 400 Hz IMU written by
tests/logfixtures.py, since the shared DataFlash log is only 64 kB) it
prints:

* ``decode``: the messages the reader asks for, as pymavlink's
  ``recv_match(type=...)`` returns them, decoded into float64 columns —
  fast: ``_dataflash_fast`` (C index + gather + columns); pymavlink:
  ``DFReader_binary`` + ``recv_match`` + ``to_dict`` (what the reader did
  before);
* ``read``: the whole ``read_dataflash`` (decoding, grid alignment, checks)
  with either decoder;

and the ratio fast/pymavlink. For each shared ULog (and a ULog fixture of
``--fixture-seconds`` s at 400 Hz) likewise: ``decode`` (the topics the
reader asks for: ``_ulog_fast.ULogTopics`` against pyulog's
``ULog(path, topics).data_list``) and ``read_ulog`` with either decoder.
For the shared CSVs (the CATS set ``hedy_*.csv`` as one read of its three
files) and a 1-million-row generic CSV
(``benchmarks/log_read_bench.py``'s) it prints ``load_log`` with the
columnar (pyarrow) parser and with numpy's parser only (the path before).
CPU time is ``time.process_time`` (this process, all threads), the best of
``--repeat`` measurements; a call shorter than 50 ms is measured as the mean of a loop of calls long enough
to take 50 ms, with the garbage collector off during a measurement (as ``timeit`` does), the same way for
both decoders.
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import io
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


#: shortest CPU time one measurement covers, s: a call shorter than this is timed in a loop of calls (as
#: ``timeit``'s autorange does), so a 0.3 ms read is not measured by one tick of the clock and one cold call
MIN_MEASUREMENT = 0.05


def calls_per_measurement(run) -> int:
    """Calls a measurement loops so that it takes at least :data:`MIN_MEASUREMENT` of CPU time (1 for a slow call)."""
    start = time.process_time()
    run()
    once = time.process_time() - start
    return 1 if once >= MIN_MEASUREMENT else min(1000, int(MIN_MEASUREMENT / max(once, 1e-6)) + 1)


def best_cpu(run, repeat: int) -> float:
    """Minimum CPU time of one ``run()`` call, s: the best of ``repeat`` measurements, each the mean of a loop of
    :func:`calls_per_measurement` calls."""
    calls = calls_per_measurement(run)
    best = None
    for _ in range(repeat):
        gc.collect()
        gc.disable()  # as timeit does: a collection of earlier calls' garbage is not this call's cost
        try:
            start = time.process_time()
            for _ in range(calls):
                run()
            elapsed = (time.process_time() - start) / calls
        finally:
            gc.enable()
        best = elapsed if best is None else min(best, elapsed)
    return best


def decode_fast(path: str) -> dict:
    """The reader's message families as float64 columns, by the fast decoder."""
    from fusion_altitude.logs import _dataflash_fast as fast
    from fusion_altitude.logs import dataflash

    data = Path(path).read_bytes()
    index = fast.DataFlashIndex(data, path, dataflash.KINDS, dataflash.FIELDS_USED)
    parts, _ = fast.read_families(index, dataflash.KINDS, dataflash.FIELDS_USED,
                                  lambda kind, columns, count: (kind, None))
    return {family: fast.ArrayRows(parts.get(family, []), dataflash.FIELDS_USED) for family in parts}


def decode_pymavlink(path: str) -> dict:
    """The same messages by pymavlink, as the reader took them: ``recv_match`` and ``to_dict``."""
    from pymavlink import DFReader

    from fusion_altitude.logs import dataflash

    chatter = io.StringIO()
    with contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
        reader = DFReader.DFReader_binary(path, zero_time_base=True)
        rows = {}
        while True:
            message = reader.recv_match(type=dataflash.KINDS)
            if message is None:
                break
            rows.setdefault(message.get_type(), []).append(message.to_dict())
        reader.filehandle.close()
    return {kind: {field: np.array([r.get(field, np.nan) for r in found], dtype=float)
                   for field in dataflash.FIELDS_USED if field in found[0]} for kind, found in rows.items()}


def dataflash_rows(path: str, repeat: int) -> list:
    from fusion_altitude.logs import dataflash

    size = os.path.getsize(path) / 1e6
    rows = []
    fast = best_cpu(lambda: decode_fast(path), repeat)
    reference = best_cpu(lambda: decode_pymavlink(path), repeat)
    rows.append((os.path.basename(path), "decode", size / fast, size / reference))
    fast = best_cpu(lambda: dataflash.read_dataflash(path, decoder="fast"), repeat)
    reference = best_cpu(lambda: dataflash.read_dataflash(path, decoder="pymavlink"), repeat)
    rows.append((os.path.basename(path), "read_dataflash", size / fast, size / reference))
    return rows


def decode_pyulog(path: str) -> dict:
    """The reader's topics by pyulog, as the reader took them: ``ULog(path, topics).data_list``."""
    from pyulog import ULog

    from fusion_altitude.logs import ulog

    with contextlib.redirect_stdout(io.StringIO()):
        log = ULog(path, ulog._TOPICS)
    return {(d.name, d.multi_id): d.data for d in log.data_list}


def decode_ulog_fast(path: str) -> dict:
    """The same topics by the fast decoder."""
    from fusion_altitude.logs import _ulog_fast, ulog

    return _ulog_fast.ULogTopics(Path(path).read_bytes(), ulog._TOPICS).data


def ulog_rows(path: str, repeat: int) -> list:
    from fusion_altitude.logs import ulog

    size = os.path.getsize(path) / 1e6
    rows = [(os.path.basename(path), "decode", size / best_cpu(lambda: decode_ulog_fast(path), repeat),
             size / best_cpu(lambda: decode_pyulog(path), repeat))]
    fast = best_cpu(lambda: ulog.read_ulog(path, decoder="fast"), repeat)
    reference = best_cpu(lambda: ulog.read_ulog(path, decoder="pyulog"), repeat)
    rows.append((os.path.basename(path), "read_ulog", size / fast, size / reference))
    return rows


def csv_rows(path: str, repeat: int, siblings=(), **options) -> list:
    """``load_log`` of a CSV with the columnar (pyarrow) path and with numpy's parser only (the path before);
    MB/s over the bytes of ``path`` and the ``siblings`` the reader also reads (a CATS set)."""
    from fusion_altitude import logs
    from fusion_altitude.logs import _csv_fast

    size = sum(os.path.getsize(p) for p in (path, *siblings)) / 1e6
    fast = best_cpu(lambda: logs.load_log(path, **options), repeat)
    with _csv_fast.engine("python"):  # numpy's parser only: the path before
        reference = best_cpu(lambda: logs.load_log(path, **options), repeat)
    return [(os.path.basename(path), "load_log (CSV)", size / fast, size / reference)]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.environ.get("FUSION_ALTITUDE_SHARED_DATA",
                                                         str(ROOT / ".." / "shared" / "data")))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--fixture-seconds", type=float, default=120.0)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    data = Path(args.data)
    if not data.is_dir():
        print(f"shared data not found at {data}", file=sys.stderr)
        return 1
    rows = []
    with tempfile.TemporaryDirectory() as directory:
        sys.path.insert(0, str(ROOT / "tests"))
        import logfixtures as fx

        fixture = Path(directory) / f"fixture_TimeUS_{args.fixture_seconds:g}s_400Hz.bin"
        fx.write_dataflash(fixture, style="TimeUS", duration=args.fixture_seconds, imu_rate=400.0)
        for path in sorted(data.glob("*.[Bb][Ii][Nn]")) + [fixture]:
            rows += dataflash_rows(str(path), args.repeat)
        ulog_fixture = Path(directory) / f"fixture_{args.fixture_seconds:g}s_400Hz.ulg"
        fx.write_ulog(ulog_fixture, duration=args.fixture_seconds, imu_rate=400.0)
        for path in sorted(data.glob("*.ulg")) + [ulog_fixture]:
            rows += ulog_rows(str(path), args.repeat)
        rows += csv_rows(str(data / "hedy_baro.csv"), args.repeat,
                         siblings=[str(data / "hedy_imu.csv"), str(data / "hedy_flight_info.csv")])
        for name in ("rrc3_juno3.csv", "raven_ndrt2020.csv"):
            rows += csv_rows(str(data / name), args.repeat)
        sys.path.insert(0, str(ROOT / "benchmarks"))
        import log_read_bench

        generic = Path(directory) / "generic_1M_rows.csv"
        log_read_bench.write_csv(str(generic), 1_000_000)
        rows += csv_rows(str(generic), args.repeat, time_column="time", accel_column="accel", baro_column="baro",
                         reference_column="reference")
    print("reference: pymavlink (.bin), pyulog (.ulg), numpy's loadtxt path (.csv)")
    print()
    print("| log | step | fast MB/s | reference MB/s | ratio |")
    print("|---|---|---:|---:|---:|")
    for name, step, fast, reference in rows:
        fast_text = f"{fast:.1f}" if fast is not None else "—"
        ratio = f"{fast / reference:.1f}×" if fast is not None else "—"
        print(f"| {name} | {step} | {fast_text} | {reference:.2f} | {ratio} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
