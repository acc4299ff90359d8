"""Every estimator, through `run`'s path (fusion_altitude.runner.run_log), on random step sequences and extreme but
finite inputs: the output is finite and bounded, whatever the steps (issue: "no non-finite or runaway output from
finite input").

Step sequences: log-uniform from 0.1 ms to 10 s, and telemetry-like mixes (0.1 s with 0.5–4 s steps), as
ground-station exports of AltOS flight computers have them. Inputs: accelerations up to ±160 m/s² (a 16 g rocket
IMU), baro random walks with dropouts and ±1e4 m jumps. The stated bound: every output is finite, the altitude
stays within the span of the log's height sources widened on each side by 1 km plus that span (a filter's overshoot
of a 10 km baro jump is allowed; a divergence is not), and |vertical velocity| ≤ 1e6 m/s (a 10 km jump within a
0.1 ms step is itself 1e8 m/s).
"""

import numpy as np
import pytest

from fusion_altitude import health, runner
from fusion_altitude.logs import LogData

ESTIMATORS = ["observer", "kalman", "complementary", "alphabeta", "ins", "rocket"]
SEEDS = range(12)


def steps(rng, kind, n):
    """Per-sample periods, s."""
    if kind == "log-uniform":
        return 10.0 ** rng.uniform(-4.0, 1.0, n)
    dt = np.full(n, 0.1)
    long = rng.random(n) < 0.15
    dt[long] = rng.uniform(0.5, 4.0, long.sum())
    return dt


def fuzzed_log(seed, kind, n=1500):
    rng = np.random.default_rng(seed)
    time = np.cumsum(steps(rng, kind, n))
    accel_z = rng.uniform(-160.0, 160.0, n) * (rng.random(n) < 0.3) + rng.normal(0.0, 1.0, n)
    baro = 200.0 + np.cumsum(rng.normal(0.0, 2.0, n))
    jumps = rng.random(n) < 0.01
    baro[jumps] += rng.choice([-1e4, 1e4], jumps.sum())
    baro[rng.random(n) < 0.3] = np.nan
    baro[0] = 200.0
    accel = np.column_stack([rng.normal(0.0, 0.5, n), rng.normal(0.0, 0.5, n), accel_z + 9.80665])
    gyro = rng.normal(0.0, 0.2, (n, 3))
    return LogData(f"fuzz {kind} {seed}", time, accel_z, baro, accel=accel, gyro=gyro, imu_frame="FLU",
                   vehicle="rocket" if seed % 2 else "")


@pytest.mark.parametrize("kind", ["log-uniform", "telemetry"])
@pytest.mark.parametrize("estimator", ESTIMATORS)
def test_random_steps_and_extreme_inputs_give_a_finite_bounded_estimate(estimator, kind):
    for seed in SEEDS:
        data = fuzzed_log(seed, kind)
        run = runner.run_log(data, estimator=estimator)
        altitude = np.asarray(run.estimate.altitude, float)
        velocity = np.asarray(run.estimate.vertical_velocity, float)
        where = f"{estimator}, {kind} steps, seed {seed}"
        assert np.isfinite(altitude).all() and np.isfinite(velocity).all(), where
        low, high = health.height_range(run)
        margin = health.RUNAWAY_MARGIN + (high - low)
        assert np.all((altitude >= low - margin) & (altitude <= high + margin)), \
            f"{where}: altitude {altitude.min():.6g} … {altitude.max():.6g} m, sources {low:.6g} … {high:.6g} m"
        assert np.all(np.abs(velocity) <= 1e6), f"{where}: |v| {np.abs(velocity).max():.6g} m/s"
