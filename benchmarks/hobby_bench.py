"""Speed of the two hobbyist estimators. Not a timed test.

    python benchmarks/hobby_bench.py [--samples N] [--repeat K]

ns per step (minimum over ``repeat`` timed runs after a warm-up) of the C
batch (``update_batch``: nogil loop over the header), per-sample ``update()``
from a Python loop and the pure-Python reference, for the two-stage
complementary filter (baro every step) and the α-β fusion (IMU, baro, lidar
and GPS every step: the worst case). The slow cases run on a prefix
(``samples // 100``, at least 200). ``run(samples, repeat)`` returns the rows.
"""

from __future__ import annotations

import argparse
from typing import List, Tuple

import numpy as np

import fusion_altitude
from fusion_altitude import reference

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import best_ns  # noqa: E402

DT = 0.01


def make_inputs(n: int, seed: int = 7):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    h = 4 + 2 * np.sin(0.3 * t)
    accel = (-0.18 * np.sin(0.3 * t) + rng.normal(0, 0.3, n)).astype(np.float32)
    baro = (h + rng.normal(0, 0.4, n)).astype(np.float32)
    lidar = (h + rng.normal(0, 0.04, n)).astype(np.float32)
    gps = (h + rng.normal(0, 1.5, n)).astype(np.float32)
    return accel, baro, lidar, gps


def run(samples: int = 1_000_000, repeat: int = 5) -> List[Tuple[str, str, float]]:
    """[(estimator, case, ns per step)]."""
    accel, baro, lidar, gps = make_inputs(samples)
    short = max(samples // 100, 200)
    rows = []
    for label, module in (("C batch", fusion_altitude), ("reference batch", reference)):
        n = samples if module is fusion_altitude else short
        rows.append(("complementary", label, best_ns(
            lambda: module.ComplementaryFilter().update_batch(accel[:n], baro[:n], DT), repeat) / n))
        rows.append(("alpha-beta", label, best_ns(
            lambda: module.AlphaBetaFusion().update_batch(accel[:n], dt=DT, baro_altitude=baro[:n],
                                                  lidar_altitude=lidar[:n], gps_altitude=gps[:n]),
            repeat) / n))

    def per_sample_complementary():
        f = fusion_altitude.ComplementaryFilter()
        for i in range(short):
            f.update(accel[i], baro[i], DT)

    def per_sample_alphabeta():
        f = fusion_altitude.AlphaBetaFusion()
        for i in range(short):
            f.update(accel[i], dt=DT, baro_altitude=baro[i], lidar_altitude=lidar[i], gps_altitude=gps[i])

    rows.append(("complementary", "per-sample update()", best_ns(per_sample_complementary, repeat) / short))
    rows.append(("alpha-beta", "per-sample update()", best_ns(per_sample_alphabeta, repeat) / short))
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    print_table(run(args.samples, args.repeat))
    return 0


def print_table(rows) -> None:
    print("| estimator | case | ns/step |")
    print("|---|---|---:|")
    for estimator, case, ns in rows:
        print(f"| {estimator} | {case} | {ns:.1f} |")


if __name__ == "__main__":
    raise SystemExit(main())
