"""The speed targets (docs/performance.md), each measured and checked in one run.

    python benchmarks/targets.py [--samples N] [--repeat K] [--per-sample]

Every case is timed ``repeat`` times (after a warm-up) and reports two
minima: wall time (``time.perf_counter_ns``) and this process's CPU time
(``time.process_time_ns``). On this 2-core machine shared with other jobs
wall time mostly measures the neighbours, CPU time does not count the time
the process waited for a core; the single-threaded cases are judged on CPU
time. The sweep cases use the default thread count (CPU time sums every
thread), so they are judged on wall time, with the one-thread CPU time
printed next to it.

Inputs are the other benchmarks': kalman_bench.make_inputs (baro,
rangefinder and GPS every step), hobby_bench.make_inputs (alpha-beta: IMU,
baro, lidar and GPS every step; complementary: baro every step),
_signals.make_signals (observer: baro every 4th step; sweep: baro every
step), ins_bench.make_inputs (INS: raw IMU of the `realistic`
scenario rocking ±10°, a magnetometer sample every step, a baro sample every
7th; its numpy-style float64 EKF runs on a prefix of max(200, N/1000) steps,
and its row is the ratio of the two CPU times, numpy-style over C batch, to
be at least the target). The per-sample cases call ``update`` from a Python ``for`` loop over
Python floats (lists), loop included; the Kalman filter and the alpha-beta
fusion by keyword after ``accel`` (positional arguments in the old order go
through the deprecation shim, which warns on every call). ``run()`` returns the rows;
``print_table`` prints them with PASS/FAIL.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import Callable, List, NamedTuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import hobby_bench  # noqa: E402
import ins_bench  # noqa: E402
import kalman_bench  # noqa: E402
import sweep_bench  # noqa: E402
from _signals import make_signals  # noqa: E402

import fusion_altitude  # noqa: E402

DT = 0.01


class Target(NamedTuple):
    case: str
    unit: str
    issue_now: float  # the issue's "now" column
    target: float
    wall: float  # minimum wall time per unit
    cpu: float  # minimum CPU time per unit (one thread for the sweep)
    judged_on: str  # "cpu" or "wall"
    at_least: bool = False  # a ratio to reach (measured >= target) rather than a time to stay under

    @property
    def measured(self) -> float:
        return self.cpu if self.judged_on == "cpu" else self.wall

    @property
    def passed(self) -> bool:
        return self.measured >= self.target if self.at_least else self.measured <= self.target

    @property
    def bound(self) -> str:
        return f"{'≥' if self.at_least else '≤'} {self.target:g}"


def best_wall_and_cpu(run: Callable[[], object], repeat: int):
    """(minimum wall ns, minimum CPU ns) over repeat calls of run(), after one warm-up call."""
    run()
    wall = cpu = None
    for _ in range(repeat):
        w0, c0 = time.perf_counter_ns(), time.process_time_ns()
        run()
        c1, w1 = time.process_time_ns(), time.perf_counter_ns()
        wall = (w1 - w0) if wall is None else min(wall, w1 - w0)
        cpu = (c1 - c0) if cpu is None else min(cpu, c1 - c0)
    return wall, cpu


def run(samples: int = 1_000_000, repeat: int = 7, sweep_samples: int = 100_000,
        per_sample_only: bool = False) -> List[Target]:
    rows: List[Target] = []
    per_sample_n = max(200, samples // 20)

    # Kalman
    accel, baro, rangefinder, gps, satellites = kalman_bench.make_inputs(samples)
    if not per_sample_only:
        out = fusion_altitude._kalman_glue.new_kalman_batch(samples)
        wall, cpu = best_wall_and_cpu(lambda: fusion_altitude.KalmanEstimator().update_batch(
            accel, dt=DT, baro_altitude=baro, range_distance=rangefinder, gps_altitude=gps,
            gps_satellites=satellites, out=out), repeat)
        rows.append(Target("Kalman C batch, baro + rangefinder + GPS every step", "ns/step", 124, 60,
                           wall / samples, cpu / samples, "cpu"))
        del out
    k = per_sample_n
    a_l, b_l, r_l, g_l, s_l = (x[:k].tolist() for x in (accel, baro, rangefinder, gps, satellites))

    def kalman_per_sample():
        update = fusion_altitude.KalmanEstimator().update
        for i in range(k):
            update(a_l[i], dt=DT, baro_altitude=b_l[i], range_distance=r_l[i], gps_altitude=g_l[i],
                   gps_satellites=s_l[i])
    wall, cpu = best_wall_and_cpu(kalman_per_sample, repeat)
    rows.append(Target("Kalman update() per sample from Python", "ns", 1122, 200, wall / k, cpu / k, "cpu"))

    # Complementary and alpha-beta
    accel, baro, lidar, gps = hobby_bench.make_inputs(samples)
    a_l, b_l, l_l, g_l = (x[:k].tolist() for x in (accel, baro, lidar, gps))

    def complementary_per_sample():
        update = fusion_altitude.ComplementaryFilter().update
        for a, z in zip(a_l, b_l):
            update(a, z, DT)
    wall, cpu = best_wall_and_cpu(complementary_per_sample, repeat)
    rows.append(Target("complementary update() per sample", "ns", 212, 80, wall / k, cpu / k, "cpu"))

    def alphabeta_per_sample():
        update = fusion_altitude.AlphaBetaFusion().update
        for a, zb, zl, zg in zip(a_l, b_l, l_l, g_l):
            update(a, dt=DT, baro_altitude=zb, lidar_altitude=zl, gps_altitude=zg)
    wall, cpu = best_wall_and_cpu(alphabeta_per_sample, repeat)
    rows.append(Target("alpha-beta update() per sample", "ns", 409, 100, wall / k, cpu / k, "cpu"))

    if not per_sample_only:
        wall, cpu = best_wall_and_cpu(lambda: fusion_altitude.AlphaBetaFusion().update_batch(
            accel, dt=DT, baro_altitude=baro, lidar_altitude=lidar, gps_altitude=gps), repeat)
        rows.append(Target("alpha-beta C batch (IMU, baro, lidar, GPS every step)", "ns/step", 66, 15,
                           wall / samples, cpu / samples, "cpu"))

    # Observer per sample (compare.py's per_sample case)
    signals = make_signals(samples)
    obs_a, obs_z = signals.accel[:k].tolist(), signals.baro_altitude[:k].tolist()

    def observer_per_sample():
        update = fusion_altitude.AltitudeEstimator().update
        for a, z in zip(obs_a, obs_z):
            update(a, z, DT)
    wall, cpu = best_wall_and_cpu(observer_per_sample, repeat)
    rows.append(Target("observer update() per sample (incl. loop)", "ns", 61, 50, wall / k, cpu / k, "cpu"))
    if per_sample_only:
        return rows

    # Sweep (sweep_bench's cases, baro every sample)
    signals = make_signals(sweep_samples, baro_every=1)
    sa, sz = signals.accel, signals.baro_altitude
    truth = np.nan_to_num(sz, nan=float(np.nanmean(sz))).astype(np.float32)
    sweep_repeat = max(1, min(repeat, 5))
    for count, issue_now, target, outputs in ((8, 1.8, 0.5, False), (64, 1.9, 1.2, True), (1024, 3.5, 1.2, True)):
        n = sweep_samples if count <= 64 else max(1000, sweep_samples // 8)
        a, z, ref = sa[:n], sz[:n], truth[:n]
        gains = sweep_bench.gains_grid(count)
        per = n * count
        if outputs:
            out = fusion_altitude.AltitudeBatch(*(np.empty((n, count), np.float32) for _ in range(4)))
            wall, _ = best_wall_and_cpu(lambda: fusion_altitude.sweep(a, z, DT, gains, out=out), sweep_repeat)
            _, cpu = best_wall_and_cpu(lambda: fusion_altitude.sweep(a, z, DT, gains, out=out, threads=1),
                                       sweep_repeat)
            case = f"sweep K = {count}, all four outputs, out= reused"
            del out
        else:
            wall, _ = best_wall_and_cpu(lambda: fusion_altitude.sweep(a, z, DT, gains, reference=ref), sweep_repeat)
            _, cpu = best_wall_and_cpu(lambda: fusion_altitude.sweep(a, z, DT, gains, reference=ref, threads=1),
                                       sweep_repeat)
            case = f"sweep K = {count}, metrics only"
        rows.append(Target(case, "ns per sample·setting", issue_now, target, wall / per, cpu / per, "wall"))

    # INS ("issue's now": the figures of docs/ins.md before this table)
    rows.extend(ins_rows(samples, repeat))
    return rows


def ins_rows(samples: int, repeat: int) -> List[Target]:
    """The INS speed targets: C batch <= 150 ns/step, >= 100x a numpy-style Python EKF (the ratio of the CPU
    times of one run), per-sample update() <= 1 µs."""
    gyro, accel, mag, baro = ins_bench.make_inputs(samples)
    out = fusion_altitude.InsBatch.empty(samples)
    wall, cpu = best_wall_and_cpu(lambda: fusion_altitude.InsEstimator().update_batch(gyro, accel, DT, baro, mag,
                                                                                     out=out), repeat)
    del out
    batch = Target("INS C batch(out=), raw IMU, mag every step, baro every 7th", "ns/step", 511, 150,
                   wall / samples, cpu / samples, "cpu")
    small = max(200, samples // 1000)
    numpy_style = ins_bench._numpy_style_runner(gyro[:small], accel[:small], baro[:small])
    numpy_wall, numpy_cpu = best_wall_and_cpu(numpy_style, max(1, min(repeat, 3)))
    ratio = Target("INS numpy-style Python EKF (float64 matrices) / C batch", "× (time ratio)", 397, 100,
                   (numpy_wall / small) / batch.wall, (numpy_cpu / small) / batch.cpu, "cpu", at_least=True)
    k = max(200, samples // 20)
    g_l = [tuple(x) for x in gyro[:k].tolist()]
    a_l = [tuple(x) for x in accel[:k].tolist()]
    b_l = baro[:k].tolist()

    def per_sample():
        update = fusion_altitude.InsEstimator().update
        for i in range(k):
            update(g_l[i], a_l[i], DT, b_l[i])
    wall, cpu = best_wall_and_cpu(per_sample, repeat)
    return [batch, ratio, Target("INS update() per sample from Python (tuples, incl. loop)", "ns", 732, 1000,
                                 wall / k, cpu / k, "cpu")]


def print_table(rows: List[Target]) -> None:
    load = os.getloadavg()[0]
    print(f"Speed targets (load average {load:.1f} on {os.cpu_count()} CPUs). Judged on CPU time for "
          "single-threaded cases, on wall time for the sweep (default threads; its CPU column is one thread).")
    print()
    print("| case | unit | issue's now | target | wall | CPU | judged | result |")
    print("|---|---|---:|---:|---:|---:|---|---|")
    for r in rows:
        print(f"| {r.case} | {r.unit} | {r.issue_now:g} | {r.bound} | {r.wall:.2f} | {r.cpu:.2f} | {r.judged_on} | "
              f"{'PASS' if r.passed else 'FAIL'} |")


def checks(rows: List[Target]):
    return [(f"{r.case}: {r.measured:.2f} {r.unit} ({r.judged_on}) {'>=' if r.at_least else '<='} {r.target:g}", r.passed)
            for r in rows]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--sweep-samples", type=int, default=100_000)
    parser.add_argument("--per-sample", action="store_true",
                        help="only the per-sample update() cases (samples // 20 calls each)")
    args = parser.parse_args(argv)
    rows = run(args.samples, args.repeat, args.sweep_samples, args.per_sample)
    print_table(rows)
    return 0 if all(r.passed for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
