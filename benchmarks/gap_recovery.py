"""The 2 s logging-gap figures of docs/cli.md and README.md: every estimator on the simulated `realistic`
flight with a 2 s gap cut at twelve phases of its 10 s bob (the flight and the cuts of tests/test_gaps.py).

Per estimator (C binding, defaults; the alpha-beta fusion with no lower altitude band, as `compare` runs it),
over the twelve gaps: the error of the first sample after the gap, the worst error in the 2 s after the gap,
the worst error from 2 s to 10 s after it (all |altitude − truth|, m), the same worst error without any gap
(the estimator's own floor over those windows), and the largest change of the bias estimate against the
no-gap run (m/s², estimators with a bias state).

    python benchmarks/gap_recovery.py
"""

from __future__ import annotations

import math

import numpy as np

import fusion_altitude as fa
from fusion_altitude.scenarios import run_scenario

GAP_STARTS = np.arange(15.0, 45.0, 2.5)  # s, as tests/test_gaps.py
GAP = 2.0  # s


def _estimator(name: str):
    if name == "observer":
        return fa.AltitudeEstimator()
    if name == "kalman":
        return fa.KalmanEstimator()
    if name == "complementary":
        return fa.ComplementaryFilter()
    return fa.AlphaBetaFusion(fa.AlphaBetaSettings(**{s: {"altitude_min": -math.inf} for s in ("imu", "baro", "gps")}))


def _run(name: str, accel, baro, dt):
    estimator = _estimator(name)
    if name in ("observer", "complementary"):
        return estimator.update_batch(accel, baro, dt)
    return estimator.update_batch(accel, dt=dt, baro_altitude=baro)


def table() -> list:
    result = run_scenario("realistic", seed=0, attitude="truth")
    time = result.time
    accel = np.asarray(result.vertical_acceleration, np.float32)
    baro = np.asarray(result.baro_altitude, np.float32)
    truth = result.trajectory.altitude
    step = np.float32(result.trajectory.dt)
    rows = []
    for name in ("observer", "kalman", "complementary", "alphabeta"):
        full = _run(name, accel, baro, np.full(accel.size, step))
        full_error = np.abs(np.asarray(full.altitude, float) - truth)
        first, within, after, floor, bias = 0.0, 0.0, 0.0, 0.0, math.nan
        for start in GAP_STARTS:
            keep = np.flatnonzero(~((time >= start) & (time < start + GAP)))
            kept = time[keep]
            dt = np.diff(kept, prepend=kept[0] - float(step)).astype(np.float32)
            out = _run(name, accel[keep], baro[keep], dt)
            error = np.abs(np.asarray(out.altitude, float) - truth[keep])
            end = start + GAP
            first = max(first, float(error[np.flatnonzero(kept >= end)[0]]))
            within = max(within, float(error[(kept >= end) & (kept < end + 2.0)].max()))
            after = max(after, float(error[(kept >= end + 2.0) & (kept < end + 10.0)].max()))
            floor = max(floor, float(full_error[(time >= end) & (time < end + 10.0)].max()))
            if hasattr(out, "accel_bias"):
                change = np.abs(np.asarray(out.accel_bias, float) - np.asarray(full.accel_bias, float)[keep]).max()
                bias = float(change) if math.isnan(bias) else max(bias, float(change))
        rows.append((name, first, within, after, floor, bias))
    return rows


def main() -> None:
    print("| estimator | first sample after the gap (m) | worst in the 2 s after (m) | worst 2–10 s after (m) "
          "| worst without a gap, same windows (m) | bias change (m/s²) |")
    print("|---|---|---|---|---|---|")
    for name, first, within, after, floor, bias in table():
        bias_text = "—" if math.isnan(bias) else f"{bias:.4f}"
        print(f"| {name} | {first:.2f} | {within:.2f} | {after:.2f} | {floor:.2f} | {bias_text} |")


if __name__ == "__main__":
    main()
