"""Simulated flights with known truth for the Kalman filter.

The truth + sensor generator is here (small, seeded): cosine-blended altitude
legs with analytic velocity and acceleration, terrain under the vehicle, a
100 Hz IMU with a 0.012 g bias and 0.005 g white noise on the vertical axis
(the vertical-axis simplification of an AHRS output), and baro / rangefinder /
GPS streams with NaN where a sensor has no sample. All runs go through the C
batch path. Errors are taken after 5 s, as for the observer's figures.

Each scenario prints its figures (``pytest -s``); ``KALMAN_TABLE`` collects
them for the README table.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import fusion_altitude as fa
from fusion_altitude import GRAVITY, KalmanResult

DT = 0.01  # s
BARO_REFERENCE = 100.0  # m: the baro's reading on the ground at take-off
GPS_REFERENCE = 137.0  # m: GPS altitude on the ground at take-off (a different datum)


def profile(duration, legs, dt=DT):
    """Truth altitude, velocity, acceleration from (start s, length s, climb m) cosine-blended legs."""
    t = np.arange(int(round(duration / dt))) * dt
    h = np.zeros_like(t)
    v = np.zeros_like(t)
    a = np.zeros_like(t)
    for start, length, climb in legs:
        u = np.clip((t - start) / length, 0.0, 1.0)
        inside = (t >= start) & (t <= start + length)
        w = np.pi / length
        h += climb * (1 - np.cos(np.pi * u)) / 2
        v += np.where(inside, climb * w / 2 * np.sin(np.pi * u), 0.0)
        a += np.where(inside, climb * w * w / 2 * np.cos(np.pi * u), 0.0)
    return t, h, v, a


def measured_accel(a_true, rng):
    return a_true + 0.012 * GRAVITY + rng.normal(0.0, 0.005 * GRAVITY, a_true.shape)


def on_every(n, period, phase=0):
    return (np.arange(n) % period) == phase


def rms(error, t, start=5.0):
    return float(np.sqrt(np.mean(error[t >= start] ** 2)))


def worst(error, t, start=5.0):
    return float(np.max(np.abs(error[t >= start])))


def kalman(settings=None):
    return fa.KalmanEstimator(settings)


# -- (a) baro only: the observer's realistic scenario -------------------------------------------

def flight_a(seed):
    rng = np.random.default_rng(seed)
    t = np.arange(6000) * DT
    w = 2 * np.pi * 0.1
    truth = 5 * np.sin(w * t)
    a_true = -5 * w * w * np.sin(w * t)
    baro = BARO_REFERENCE + truth + 0.30 * np.sin(2 * np.pi * 8 * t) + rng.normal(0.0, 0.10, t.shape)
    return t, BARO_REFERENCE + truth, measured_accel(a_true, rng), baro


@pytest.fixture(scope="module")
def scenario_a():
    rows = []
    for seed in range(20):
        t, truth, accel, baro = flight_a(seed)
        observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
        result = kalman().update_batch(accel, dt=DT, baro_altitude=baro)
        rows.append((rms(observer - truth, t), rms(result.altitude - truth, t), rms(baro - truth, t),
                     float(result.accel_bias[-1]) / GRAVITY))
    return np.array(rows)


def test_a_baro_only_kalman_beats_the_observer_on_the_realistic_flight(scenario_a):
    observer, kalman_rms, raw, bias = scenario_a.mean(axis=0)
    print(f"\n(a) baro only, 20 seeds: RMS raw baro {raw:.3f} m, observer {observer:.4f} m, Kalman {kalman_rms:.4f} m; "
          f"Kalman bias {bias:.4f} g")
    assert kalman_rms < observer < raw / 4
    assert kalman_rms < 0.025
    assert abs(bias - 0.012) < 0.001


# -- (b) baro + rangefinder over a 1 m terrain step, out of range above 8 m ------------------------

def flight_b(seed):
    rng = np.random.default_rng(100 + seed)
    legs = [(2, 8, 4.0), (40, 10, 8.0), (60, 10, -9.0), (85, 8, -3.0)]
    t, altitude, _, a_true = profile(100.0, legs)
    ground = np.where(t >= 25.0, 1.0, 0.0)  # flying over a 1 m step up at t = 25 s
    height = altitude - ground
    n = t.size
    baro = BARO_REFERENCE + altitude + 0.3 * np.sin(2 * np.pi * 8 * t) + rng.normal(0.0, 0.1, n)
    baro += 0.3 * t / 100.0  # 0.3 m of weather drift over the flight
    rangefinder = np.where(on_every(n, 5), height + rng.normal(0.0, 0.03, n), np.nan)  # 20 Hz
    rangefinder[height > 8.0] = np.nan  # no echo above 8 m
    return t, altitude, height, measured_accel(a_true, rng), baro, rangefinder


@pytest.fixture(scope="module")
def scenario_b():
    t, altitude, height, accel, baro, rangefinder = flight_b(0)
    observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
    estimator = kalman()
    result = estimator.update_batch(accel, dt=DT, baro_altitude=baro, range_distance=rangefinder)
    drift = 0.3 * t / 100.0
    return t, altitude + BARO_REFERENCE + drift, height, observer, result, estimator


def test_b_terrain_step_moves_the_baro_offset_not_the_altitude(scenario_b):
    t, baro_truth, height, observer, result, estimator = scenario_b
    altitude_error = result.altitude - baro_truth
    height_error = result.height_above_ground - height
    print(f"\n(b) baro + range, 1 m step: altitude RMS observer {rms(observer - baro_truth, t):.4f} m, "
          f"Kalman {rms(altitude_error, t):.4f} m; height RMS {rms(height_error, t):.4f} m "
          f"(in range, excluding 2 s after the step {rms(height_error[(height < 8) & ((t < 25) | (t > 27))], t[(height < 8) & ((t < 25) | (t > 27))]):.4f} m); "
          f"range resets {estimator.resets.range}")
    around = (t > 20) & (t < 35)
    assert np.max(np.abs(altitude_error[around])) < 0.15  # no altitude jump at the step
    before = result.baro_offset[(t > 20) & (t < 25)].mean()
    after = result.baro_offset[(t > 28) & (t < 33)].mean()
    assert after - before == pytest.approx(1.0, abs=0.1)
    assert np.max(np.abs(height_error[(t > 27) & (t < 40)])) < 0.1  # height follows the new ground
    assert estimator.resets.range == 1


def test_b_rangefinder_out_of_range_above_8_m_and_back(scenario_b):
    t, baro_truth, height, observer, result, estimator = scenario_b
    above = height > 8.0
    assert above.any()
    assert np.all(result.result[above, 1] != KalmanResult.FUSED)
    back = (t > 72) & (t < 84)
    assert np.max(np.abs(result.height_above_ground[back] - height[back])) < 0.1
    assert rms(result.altitude - baro_truth, t) < 0.05


# -- (c) baro + 5 Hz GPS: a 10 m GPS jump and a 20 s outage --------------------------------------

def flight_c(seed):
    rng = np.random.default_rng(200 + seed)
    legs = [(2, 10, 20.0), (50, 10, 10.0), (80, 10, -30.0)]
    t, altitude, _, a_true = profile(100.0, legs)
    n = t.size
    baro = BARO_REFERENCE + altitude + 0.3 * np.sin(2 * np.pi * 8 * t) + rng.normal(0.0, 0.1, n)
    satellites = np.full(n, 10)
    sigma = 1.0 + 1.0 / math.sqrt(10)
    gps = np.where(on_every(n, 20), GPS_REFERENCE + altitude + rng.normal(0.0, sigma, n), np.nan)  # 5 Hz
    gps[t >= 30.0] += 10.0  # the GPS altitude jumps by 10 m and stays
    gps[(t >= 45.0) & (t < 65.0)] = np.nan  # 20 s outage
    return t, altitude, measured_accel(a_true, rng), baro, gps, satellites


@pytest.fixture(scope="module")
def scenario_c():
    t, altitude, accel, baro, gps, satellites = flight_c(0)
    observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
    estimator = kalman()
    result = estimator.update_batch(accel, dt=DT, baro_altitude=baro, gps_altitude=gps, gps_satellites=satellites)
    return t, altitude, observer, result, estimator


def test_c_gps_jump_resets_the_gps_offset_without_an_altitude_jump(scenario_c):
    t, altitude, observer, result, estimator = scenario_c
    truth = BARO_REFERENCE + altitude
    altitude_error = result.altitude - truth
    height_error = result.height_above_ground - altitude
    print(f"\n(c) baro + GPS, 10 m jump, 20 s outage: altitude RMS observer {rms(observer - truth, t):.4f} m, "
          f"Kalman {rms(altitude_error, t):.4f} m; height RMS {rms(height_error, t):.4f} m; "
          f"GPS rejections {estimator.rejections.gps}, resets {estimator.resets.gps}")
    assert estimator.resets.gps == 1
    reset_time = t[np.argmax(result.result[:, 2] == KalmanResult.RESET)]
    assert 30.0 < reset_time < 31.5
    assert np.max(np.abs(altitude_error[(t > 28) & (t < 40)])) < 0.2
    assert np.max(np.abs(height_error[(t > 28) & (t < 40)])) < 0.5
    before = result.gps_offset[(t > 25) & (t < 30)].mean()
    after = result.gps_offset[(t > 35) & (t < 45)].mean()
    assert after - before == pytest.approx(10.0, abs=1.0)


def test_c_gps_comes_back_after_the_outage_without_a_reset_or_jump(scenario_c):
    t, altitude, observer, result, estimator = scenario_c
    outage = (t >= 45.0) & (t < 65.0)
    assert np.all(result.result[outage, 2] == KalmanResult.NO_SAMPLE)
    returned = t >= 65.0
    assert np.all(result.result[returned, 2] != KalmanResult.RESET)
    step = np.abs(np.diff(result.altitude[(t > 60) & (t < 70)]))
    assert step.max() < 0.05
    assert np.max(np.abs(result.height_above_ground[(t > 65) & (t < 80)] - altitude[(t > 65) & (t < 80)])) < 0.6


# -- (d) a 10 s baro dropout with the rangefinder still working --------------------------------

def flight_d(seed):
    rng = np.random.default_rng(300 + seed)
    legs = [(2, 6, 3.0), (15, 4, 2.0), (22, 4, -1.5), (28, 4, 1.5), (45, 6, -5.0)]
    t, altitude, _, a_true = profile(55.0, legs)
    n = t.size
    baro = BARO_REFERENCE + altitude + 0.3 * np.sin(2 * np.pi * 8 * t) + rng.normal(0.0, 0.1, n)
    baro[(t >= 20.0) & (t < 30.0)] = np.nan  # dropout
    rangefinder = np.where(on_every(n, 5), altitude + rng.normal(0.0, 0.03, n), np.nan)
    return t, altitude, measured_accel(a_true, rng), baro, rangefinder


def test_d_baro_dropout_is_bridged_by_the_rangefinder():
    t, altitude, accel, baro, rangefinder = flight_d(0)
    truth = BARO_REFERENCE + altitude
    observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
    estimator = kalman()
    result = estimator.update_batch(accel, dt=DT, baro_altitude=baro, range_distance=rangefinder)
    dropout = (t >= 20.0) & (t < 30.0)
    print(f"\n(d) 10 s baro dropout: altitude RMS observer {rms(observer - truth, t):.4f} m "
          f"(worst in dropout {np.max(np.abs(observer - truth)[dropout]):.3f} m), Kalman {rms(result.altitude - truth, t):.4f} m "
          f"(worst in dropout {np.max(np.abs(result.altitude - truth)[dropout]):.3f} m); "
          f"height RMS {rms(result.height_above_ground - altitude, t):.4f} m")
    assert np.max(np.abs(result.height_above_ground - altitude)[dropout]) < 0.1
    assert np.max(np.abs(result.altitude - truth)[dropout]) < 0.15
    assert estimator.resets.baro == 0 and estimator.rejections.baro == 0
    assert np.max(np.abs(np.diff(result.altitude[(t > 29) & (t < 32)]))) < 0.05


# -- the table of docs/kalman.md ("Accuracy"): python tests/test_kalman_scenarios.py ---------------

def _row(name, sensors, observer, kalman_altitude, height=None):
    height_cell = "—" if height is None else f"{100 * height:.2f}"
    return f"| {name} | {sensors} | {100 * observer:.2f} | {100 * kalman_altitude:.2f} | {height_cell} |"


def accuracy_table():
    """The four scenarios' altitude RMS after 5 s (cm), as a markdown table."""
    rows = ["| scenario | sensors | altitude RMS, observer (cm) | altitude RMS, Kalman (cm) | Kalman height-above-ground RMS (cm; (b): in range, outside the 2 s after the step) |",
            "|---|---|---:|---:|---:|"]
    errors = []
    for seed in range(20):
        t, truth, accel, baro = flight_a(seed)
        observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
        result = kalman().update_batch(accel, dt=DT, baro_altitude=baro)
        errors.append((rms(observer - truth, t), rms(result.altitude - truth, t)))
    rows.append(_row("(a) 5 m sinusoid, 60 s, mean of 20 seeds", "baro", *np.mean(errors, axis=0)))
    t, altitude, height, accel, baro, rangefinder = flight_b(0)
    truth = altitude + BARO_REFERENCE + 0.3 * t / 100.0
    observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
    result = kalman().update_batch(accel, dt=DT, baro_altitude=baro, range_distance=rangefinder)
    in_range = (height < 8.0) & ((t < 25.0) | (t > 27.0))  # in range, outside the 2 s after the step
    rows.append(_row("(b) 1 m terrain step, climb to 12 m (range lost above 8 m), 100 s", "baro + range 20 Hz",
                     rms(observer - truth, t), rms(result.altitude - truth, t),
                     rms((result.height_above_ground - height)[in_range], t[in_range])))
    t, altitude, accel, baro, gps, satellites = flight_c(0)
    observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
    result = kalman().update_batch(accel, dt=DT, baro_altitude=baro, gps_altitude=gps, gps_satellites=satellites)
    rows.append(_row("(c) 10 m GPS jump at 30 s, 20 s GPS outage, 100 s", "baro + GPS 5 Hz",
                     rms(observer - BARO_REFERENCE - altitude, t), rms(result.altitude - BARO_REFERENCE - altitude, t),
                     rms(result.height_above_ground - altitude, t)))
    t, altitude, accel, baro, rangefinder = flight_d(0)
    observer = fa.AltitudeEstimator().update_batch(accel, baro, DT).altitude
    result = kalman().update_batch(accel, dt=DT, baro_altitude=baro, range_distance=rangefinder)
    rows.append(_row("(d) 10 s baro dropout", "baro + range 20 Hz", rms(observer - BARO_REFERENCE - altitude, t),
                     rms(result.altitude - BARO_REFERENCE - altitude, t), rms(result.height_above_ground - altitude, t)))
    return "\n".join(rows)


if __name__ == "__main__":
    print(accuracy_table())
