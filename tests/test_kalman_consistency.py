"""Consistency of the Kalman filter's covariance with its actual errors.

A Monte Carlo of 50 flights whose truth follows the filter's own model with
its default settings: accelerometer white noise of density N_a entering
through B, bias and offset random walks, white measurement noise of the
modelled sigmas (baro every step, rangefinder at 20 Hz, GPS at 5 Hz with 9
satellites), initial height, velocity and bias drawn from the initial
covariance, offsets arbitrary (the filter sets them from the first samples).
A feedback law on the truth keeps the vehicle near 4 m so that the
rangefinder stays in range. The normalized estimation error squared
NEES = eᵀP⁻¹e (5 states) averaged over the runs must lie in the two-sided
95 % chi-square band for 50·5 degrees of freedom; so must each sensor's
normalized innovation squared.
"""

import numpy as np
import pytest

import fusion_altitude as fa

RUNS = 50
DT = 0.01
STEPS = 6000  # 60 s at 100 Hz
# Two-sided 95 % band of chi2(k)/RUNS: (chi2.ppf(0.025, k), chi2.ppf(0.975, k)) / RUNS for k = RUNS * dof,
# by the Wilson-Hilferty approximation (accurate to < 0.1 % here; no scipy needed).


def chi2_band(dof_total):
    z = 1.959964
    lo = dof_total * (1 - 2 / (9 * dof_total) - z * np.sqrt(2 / (9 * dof_total))) ** 3
    hi = dof_total * (1 - 2 / (9 * dof_total) + z * np.sqrt(2 / (9 * dof_total))) ** 3
    return lo, hi


def simulate(rng, settings):
    s = settings
    n = STEPS
    h = rng.normal(0.0, s.initial_height_sigma)
    v = rng.normal(0.0, s.initial_velocity_sigma)
    b = rng.normal(0.0, s.accel_bias_initial_sigma)
    ob = 250.0 + rng.normal(0.0, 20.0)
    og = 300.0 + rng.normal(0.0, 20.0)
    truth = np.empty((n, 5))
    accel = np.empty(n)
    accel_sigma = s.accel_noise / np.sqrt(DT)
    for k in range(n):
        a_true = float(np.clip(-0.8 * (h - 4.0) - 1.6 * v, -3.0, 3.0))
        accel[k] = a_true + b + rng.normal(0.0, accel_sigma)
        h += v * DT + 0.5 * a_true * DT * DT
        v += a_true * DT
        b += rng.normal(0.0, s.accel_bias_random_walk * np.sqrt(DT))
        ob += rng.normal(0.0, s.baro_offset_random_walk * np.sqrt(DT))
        og += rng.normal(0.0, s.gps_offset_random_walk * np.sqrt(DT))
        truth[k] = (h, v, ob, og, b)
    baro = truth[:, 0] + truth[:, 2] + rng.normal(0.0, s.baro_noise, n)
    rangefinder = np.where(np.arange(n) % 5 == 0, truth[:, 0] + rng.normal(0.0, s.range_noise, n), np.nan)
    gps_sigma = s.gps_noise_base + s.gps_noise_satellite / 3.0
    gps = np.where(np.arange(n) % 20 == 0, truth[:, 0] + truth[:, 3] + rng.normal(0.0, gps_sigma, n), np.nan)
    return truth, accel, baro, rangefinder, gps


@pytest.fixture(scope="module")
def monte_carlo():
    settings = fa.KalmanSettings()
    rng = np.random.default_rng(5)
    checkpoints = np.arange(100, STEPS, 100) - 1  # every 1 s from 1 s on
    nees = np.zeros((RUNS, checkpoints.size))
    nis = []
    for run in range(RUNS):
        truth, accel, baro, rangefinder, gps = simulate(rng, settings)
        estimator = fa.KalmanEstimator(settings)
        result = None
        errors = []
        covariances = []
        start = 0
        for stop in checkpoints + 1:
            result = estimator.update_batch(accel[start:stop], dt=DT, baro_altitude=baro[start:stop],
                                            range_distance=rangefinder[start:stop], gps_altitude=gps[start:stop],
                                            gps_satellites=9)
            nis.append(result.nis)
            start = stop
            errors.append(truth[stop - 1] - estimator.state.astype(np.float64))
            covariances.append(estimator.covariance.astype(np.float64))
        for i, (e, P) in enumerate(zip(errors, covariances)):
            nees[run, i] = e @ np.linalg.solve(P, e)
    return nees, np.concatenate(nis)


def test_mean_nees_is_inside_the_95_percent_chi_square_band(monte_carlo):
    nees, _ = monte_carlo
    mean_over_runs = nees.mean(axis=0)  # one value per checkpoint
    lo, hi = (x / RUNS for x in chi2_band(RUNS * 5))
    inside = np.mean((mean_over_runs >= lo) & (mean_over_runs <= hi))
    overall = mean_over_runs.mean()
    print(f"\nNEES: mean {overall:.3f} (5 states), band per checkpoint [{lo:.2f}, {hi:.2f}], "
          f"{inside:.0%} of {mean_over_runs.size} checkpoints inside")
    assert lo <= overall <= hi
    assert inside >= 0.85


def test_mean_nis_of_each_sensor_is_inside_the_95_percent_chi_square_band(monte_carlo):
    _, nis = monte_carlo
    for index, name in enumerate(("baro", "range", "gps")):
        values = nis[:, index]
        values = values[~np.isnan(values)]
        lo, hi = (x / values.size for x in chi2_band(values.size))
        print(f"NIS {name}: mean {values.mean():.4f} over {values.size} samples, band [{lo:.4f}, {hi:.4f}]")
        assert lo <= values.mean() <= hi
