"""Gain-sweep timings for compare.py: ns per sample·setting.

    python benchmarks/sweep_bench.py [--samples N] [--repeat K]

Cases, for K = 8, 64, 1024 settings over the same log: ``fusion_altitude.sweep``
with metrics only (one thread and the default split), with all four (T, K)
outputs; the same K settings as a Python loop over ``update_batch`` plus numpy
metrics (what a user writes without ``sweep``); the pure-Python reference; and
``scipy.signal.lfilter`` on the observer's equivalent linear filter (valid when
dt is constant and every sample has baro; checked against the observer first).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _signals import make_signals  # noqa: E402
from _timing import best_ns  # noqa: E402

import fusion_altitude  # noqa: E402
from fusion_altitude import reference  # noqa: E402

COUNTS = (8, 64, 1024)



def gains_grid(count: int) -> np.ndarray:
    omegas = np.geomspace(0.2, 6.0, count)
    return np.array([fusion_altitude.AltitudeSettings.from_bandwidth(w, 0.7).as_tuple() for w in omegas])


def equivalent_filters(gains: np.ndarray, dt: float):
    """(b, a) of the transfer functions accel → altitude and baro → altitude, from the update equations."""
    from scipy import signal
    kh, kv, kb = gains
    a_matrix = np.array([[1 - kh * dt - kv * dt**2, dt, -dt**2], [-kv * dt, 1, -dt], [kb * dt, 0, 1]])
    b_matrix = np.array([[dt**2, kv * dt**2 + kh * dt], [dt, kv * dt], [0, -kb * dt]])
    c_matrix = np.array([[1.0, 0.0, 0.0]]) @ a_matrix  # altitude after the update
    d_matrix = np.array([[1.0, 0.0, 0.0]]) @ b_matrix
    filters = []
    for column in range(2):
        numerator, denominator = signal.ss2tf(a_matrix, b_matrix[:, [column]], c_matrix, d_matrix[:, [column]])
        filters.append((numerator[0], denominator))
    return filters


def lfilter_run(filters, accel, baro):
    from scipy import signal
    (b_a, a_a), (b_z, a_z) = filters
    return signal.lfilter(b_a, a_a, accel) + signal.lfilter(b_z, a_z, baro)


def run(samples: int = 100_000, repeat: int = 5, baro_every: int = 1):
    """Return (rows, checks): rows of (case, ns per sample·setting), checks of (text, passed)."""
    signals = make_signals(samples, baro_every=baro_every)
    accel, baro, dt = signals.accel, signals.baro_altitude, float(signals.dt)
    truth = np.nan_to_num(baro, nan=float(np.nanmean(baro))).astype(np.float32)  # a stand-in reference
    rows, checks = [], []
    for count in COUNTS:
        n = samples if count <= 64 else max(1000, samples // 8)  # keeps the (T, K) outputs near 0.2-0.4 GB
        a, z, ref = accel[:n], baro[:n], truth[:n]
        gains = gains_grid(count)
        per = n * count
        t_metrics_1 = best_ns(lambda: fusion_altitude.sweep(a, z, dt, gains, reference=ref, threads=1), repeat) / per
        t_metrics = best_ns(lambda: fusion_altitude.sweep(a, z, dt, gains, reference=ref), repeat) / per
        t_fresh = best_ns(lambda: fusion_altitude.sweep(a, z, dt, gains, outputs=True), max(1, repeat // 2)) / per
        out = fusion_altitude.AltitudeBatch(*(np.empty((n, count), np.float32) for _ in range(4)))
        t_outputs = best_ns(lambda: fusion_altitude.sweep(a, z, dt, gains, out=out), repeat) / per
        del out
        loop_count = min(count, 64)

        loop_out = fusion_altitude.AltitudeBatch(*(np.empty(n, np.float32) for _ in range(4)))

        def python_loop():
            for row in gains[:loop_count]:
                estimator = fusion_altitude.AltitudeEstimator(fusion_altitude.AltitudeSettings(*row))
                result = estimator.update_batch(a, z, dt, out=loop_out)
                error = result.altitude - ref
                np.sqrt(np.mean(error.astype(np.float64) ** 2))

        t_loop = best_ns(python_loop, max(1, repeat // 2)) / (n * loop_count)
        rows += [(f"K={count}: sweep, metrics only, 1 thread", t_metrics_1),
                 (f"K={count}: sweep, metrics only, default threads", t_metrics),
                 (f"K={count}: sweep, all four (T, K) outputs, out= reused", t_outputs),
                 (f"K={count}: sweep, all four (T, K) outputs, allocated by each call (page faults)", t_fresh),
                 (f"K={count}: Python loop over update_batch(out=) + numpy RMS", t_loop)]
        checks += [(f"K={count}: metrics only <= 0.5 ns/sample·setting: {t_metrics:.2f}", t_metrics <= 0.5),
                   (f"K={count}: with outputs <= 1.5 ns/sample·setting: {t_outputs:.2f}", t_outputs <= 1.5),
                   (f"K={count}: sweep >= 5x faster than looping update_batch: metrics {t_loop / t_metrics:.0f}x, "
                    f"outputs {t_loop / t_outputs:.1f}x", t_loop >= 5 * t_metrics and t_loop >= 5 * t_outputs)]
    # pure-Python reference and scipy on a shorter log
    n, count = min(samples, 5000), 8
    gains = gains_grid(count)
    t_reference = best_ns(lambda: reference.sweep(accel[:n], baro[:n], dt, gains, reference=truth[:n]), 1) / (n * count)
    rows.append((f"K={count}: pure-Python reference sweep ({n} samples)", t_reference))
    try:
        import scipy  # noqa: F401
    except ImportError:
        rows.append(("scipy.signal.lfilter: scipy not installed (pip install scipy)", float("nan")))
        return rows, checks
    known = np.flatnonzero(~np.isnan(baro))
    full_baro = np.interp(np.arange(samples), known, baro[known]).astype(np.float32)
    full_baro[0] = 0.0  # the observer auto-zeroes here; lfilter starts from a zero state
    filters = [equivalent_filters(row, dt) for row in gains]
    observed = fusion_altitude.AltitudeEstimator(fusion_altitude.AltitudeSettings(*gains[0])).update_batch(
        accel, full_baro, dt).altitude
    linear = lfilter_run(filters[0], accel[1:].astype(np.float64), full_baro[1:].astype(np.float64))
    agreement = float(np.max(np.abs(linear - observed[1:])))
    t_lfilter = best_ns(lambda: [lfilter_run(f, accel.astype(np.float64), full_baro.astype(np.float64))
                                 for f in filters], repeat) / (samples * count)
    out = fusion_altitude.AltitudeBatch(*(np.empty((samples, count), np.float32) for _ in range(4)))
    t_sweep_full = best_ns(lambda: fusion_altitude.sweep(accel, full_baro, dt, gains, out=out), repeat) / (samples * count)
    rows.append((f"K={count}: scipy.signal.lfilter, equivalent LTI filter, float64 (max abs diff {agreement:.1e} m)", t_lfilter))
    rows.append((f"K={count}: sweep with out= on the same baro-every-sample log", t_sweep_full))
    return rows, checks


def print_table(rows, checks) -> None:
    print("| case | ns per sample·setting |")
    print("|---|---:|")
    for case, ns in rows:
        print(f"| {case} | {ns:.2f} |")
    print()
    for text, ok in checks:
        print(f"- [{'PASS' if ok else 'FAIL'}] {text}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--baro-every", type=int, default=1,
                        help="one baro sample every this many samples (default 1: every sample runs the full "
                             "correction, the case the targets were set for)")
    args = parser.parse_args(argv)
    rows, checks = run(args.samples, args.repeat, args.baro_every)
    print_table(rows, checks)
    return 0 if all(ok for _, ok in checks) else 1


if __name__ == "__main__":
    sys.exit(main())
