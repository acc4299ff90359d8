"""Fuzz the log readers: truncated and bit-flipped logs of every format must raise nothing but LogError.

Run for a while and report::

    python tests/fuzz_readers.py --seconds 60 [--seed 1] [--data ../shared/data]

Seeds are fixtures written by tests/logfixtures.py (DataFlash TimeMS and
TimeUS, PX4 ULog — plain, damaged before sync messages, with data
appended —, AltOS CSV — current, 1.4 and telemetry —, CATS set, generic
CSV, Featherweight Raven, Missile Works RRC3) plus, if the shared data
directory is there, the PX4 ULog sample. Every mutation is a truncation, bit flips,
random bytes or deleted runs (:func:`logfixtures.mutations`). A finding is
any exception other than LogError, or a read that takes longer than
``--timeout`` s; each is printed once per (format, exception type, message
start). Exit status 1 if there were findings.
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402

CSV_OPTIONS = dict(time_column="time", accel_column="accel", baro_column="baro", reference_column="reference")


class _Timeout(Exception):
    pass


def seeds(directory: str, data_dir: str | None = None) -> dict:
    """Seed files per format: name → (bytes, file name, load_log options, sibling files)."""
    d = Path(directory)
    fx.write_dataflash(d / "ms.bin", style="TimeMS", duration=2.0, imu_rate=25.0)
    fx.write_dataflash(d / "us.bin", style="TimeUS", duration=2.0, imu_rate=25.0)
    fx.write_altos_csv(d / "altos.csv", duration=2.0, pad_time=1.0, rate=10.0)
    fx.write_generic_csv(d / "generic.csv", duration=2.0, rate=20.0, baro_every=2)
    fx.write_ulog(d / "fixture.ulg", duration=2.0, imu_rate=20.0, baro_rate=10.0, gps_rate=5.0)
    for damage in ("sync", "appended"):
        fx.write_ulog_damaged(d / f"{damage}.ulg", damage, duration=2.0, imu_rate=20.0, baro_rate=10.0, gps_rate=5.0)
    cats = d / "cats"
    cats.mkdir()
    fx.write_cats_set(cats, duration=1.0, pad_time=1.0, rate=20.0)
    out = {
        "dataflash-TimeMS": ((d / "ms.bin").read_bytes(), "log.bin", {}, {}),
        "dataflash-TimeUS": ((d / "us.bin").read_bytes(), "log.bin", {}, {}),
        "altos": ((d / "altos.csv").read_bytes(), "altos.csv", {}, {}),
        "ulog-fixture": ((d / "fixture.ulg").read_bytes(), "log.ulg", {}, {}),
        "ulog-sync": ((d / "sync.ulg").read_bytes(), "log.ulg", {}, {}),
        "ulog-appended": ((d / "appended.ulg").read_bytes(), "log.ulg", {}, {}),
        "csv": ((d / "generic.csv").read_bytes(), "log.csv", CSV_OPTIONS, {}),
        "cats": ((cats / "flight_baro.csv").read_bytes(), "flight_baro.csv", {},
                 {"flight_imu.csv": (cats / "flight_imu.csv").read_bytes(),
                  "flight_flight_info.csv": (cats / "flight_flight_info.csv").read_bytes()}),
        "cats-imu": ((cats / "flight_imu.csv").read_bytes(), "flight_imu.csv", {},
                     {"flight_baro.csv": (cats / "flight_baro.csv").read_bytes()}),
    }
    small = d / "small"
    small.mkdir()
    fx.write_altos_rocket_csv(small / "altos14.csv", style="1.4", duration=2.0, pad_time=0.5, rate=10.0)
    fx.write_altos_rocket_csv(small / "telemetry.csv", style="v5", telemetry=True, duration=4.0, pad_time=0.5)
    out.update({
        "altos-1.4": ((small / "altos14.csv").read_bytes(), "altos.csv", {}, {}),
        "altos-telemetry": ((small / "telemetry.csv").read_bytes(), "altos.csv", {}, {}),
        "raven": (Path(fx.raven_csv(small, duration=2.0, accel_seconds=0.5)).read_bytes(), "raven.csv", {}, {}),
        "rrc3": (Path(fx.rrc3_csv(small)).read_bytes(), "rrc3.csv", {}, {}),
    })
    if data_dir and os.path.exists(os.path.join(data_dir, "px4_sample_log_small.ulg")):
        with open(os.path.join(data_dir, "px4_sample_log_small.ulg"), "rb") as handle:
            out["ulog-px4-sample"] = (handle.read(), "log.ulg", {}, {})
    return out


def run_one(directory: str, name: str, data: bytes, siblings: dict, options: dict, timeout: float):
    """Read one mutated file; return None (LogError or success) or a finding string."""
    case = tempfile.mkdtemp(dir=directory)
    try:
        fx.write_bytes(os.path.join(case, name), data)
        for sibling, content in siblings.items():
            fx.write_bytes(os.path.join(case, sibling), content)
        previous = signal.signal(signal.SIGALRM, lambda *_: (_ for _ in ()).throw(_Timeout()))
        signal.setitimer(signal.ITIMER_REAL, timeout)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                logs.load_log(os.path.join(case, name), **options)
        except logs.LogError as error:
            if "\n" in str(error):
                return f"LogError with a line break: {str(error)[:80]!r}"
        except _Timeout:
            return f"took longer than {timeout} s"
        except Exception as error:  # the finding
            return f"{type(error).__name__}: {str(error)[:100]}"
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
        return None
    finally:
        shutil.rmtree(case, ignore_errors=True)


def fuzz(seconds: float, seed: int = 1, data_dir: str | None = None, timeout: float = 20.0,
         max_runs: int | None = None) -> tuple:
    """Fuzz round-robin over the formats for ``seconds`` (or ``max_runs``); return (runs per format, findings)."""
    rng = np.random.default_rng(seed)
    runs, findings = {}, {}
    with tempfile.TemporaryDirectory() as directory:
        base = seeds(directory, data_dir)
        names = sorted(base)
        start = time.monotonic()
        total = 0
        while time.monotonic() - start < seconds and (max_runs is None or total < max_runs):
            fmt = names[total % len(names)]
            data, file_name, options, siblings = base[fmt]
            mutated = fx.mutations(data, rng, 1)[0]
            finding = run_one(directory, file_name, mutated, siblings, options, timeout)
            runs[fmt] = runs.get(fmt, 0) + 1
            total += 1
            if finding is not None:
                key = (fmt, finding[:60])
                if key not in findings:
                    findings[key] = mutated
    return runs, findings


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds one read may take")
    parser.add_argument("--data", default=os.environ.get("FUSION_ALTITUDE_SHARED_DATA"),
                        help="shared data directory (for the ULog seed)")
    parser.add_argument("--save", help="directory to write the inputs of findings to")
    args = parser.parse_args(argv)
    began = time.monotonic()
    runs, findings = fuzz(args.seconds, args.seed, args.data, args.timeout)
    elapsed = time.monotonic() - began
    print(f"{sum(runs.values())} reads in {elapsed:.1f} s (seed {args.seed}): "
          + ", ".join(f"{name} {count}" for name, count in sorted(runs.items())))
    for (fmt, finding), data in findings.items():
        print(f"FINDING {fmt}: {finding}")
        if args.save:
            os.makedirs(args.save, exist_ok=True)
            path = os.path.join(args.save, f"{fmt}-{len(os.listdir(args.save))}.bin")
            fx.write_bytes(path, data)
    print(f"{len(findings)} finding(s)")
    return 1 if findings else 0


if __name__ == "__main__":
    raise SystemExit(main())
