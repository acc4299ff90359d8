"""What users rely on from the observer, for the C binding and the reference alike."""

import math

import numpy as np
import pytest

DT = 0.01  # s, 100 Hz


def run(estimator, accel, baro_altitude, seconds, dt=DT):
    for _ in range(int(round(seconds / dt))):
        estimator.update(accel, baro_altitude, dt)


def test_first_baro_sample_auto_zeroes_and_ignores_accel(impl):
    estimator = impl.AltitudeEstimator()
    estimator.update(50.0, 123.5, DT)
    assert estimator.altitude == 123.5
    assert estimator.vertical_velocity == 0.0
    assert estimator.baro_residual == 0.0
    assert estimator.reference_set


def test_estimate_starts_at_zero_without_reference(impl):
    estimator = impl.AltitudeEstimator()
    assert (estimator.altitude, estimator.vertical_velocity, estimator.accel_bias, estimator.baro_residual) == (0, 0, 0, 0)
    assert not estimator.reference_set


def test_missing_baro_before_first_sample_waits_for_the_reference(impl):
    estimator = impl.AltitudeEstimator()
    estimator.update(1.0, math.nan, DT)
    assert not estimator.reference_set
    assert estimator.altitude == 0.0 and estimator.vertical_velocity == 0.0
    assert math.isnan(estimator.baro_residual)


def test_reset_keeps_the_bias_estimate(impl):
    estimator = impl.AltitudeEstimator()
    run(estimator, 0.2, 10.0, 20.0)
    bias = estimator.accel_bias
    assert bias != 0.0
    estimator.reset(42.0)
    assert (estimator.altitude, estimator.vertical_velocity, estimator.baro_residual) == (42.0, 0.0, 0.0)
    assert estimator.accel_bias == bias


def test_reset_with_accel_bias_warm_starts(impl):
    estimator = impl.AltitudeEstimator()
    estimator.reset(100.0, accel_bias=0.1177)
    assert estimator.reference_set
    assert estimator.accel_bias == pytest.approx(0.1177, rel=1e-7)


def test_warm_start_with_the_true_bias_removes_the_bias_transient(impl):
    true_bias = 0.012 * impl.GRAVITY
    cold, warm = impl.AltitudeEstimator(), impl.AltitudeEstimator()
    cold.reset(0.0)
    warm.reset(0.0, accel_bias=true_bias)
    cold_error = warm_error = 0.0
    for _ in range(500):
        cold.update(true_bias, 0.0, DT)
        warm.update(true_bias, 0.0, DT)
        cold_error = max(cold_error, abs(cold.altitude))
        warm_error = max(warm_error, abs(warm.altitude))
    assert warm_error < 1e-5 < cold_error


def test_stationary_estimate_converges_to_the_baro_altitude(impl):
    estimator = impl.AltitudeEstimator()
    estimator.reset(0.0)
    run(estimator, 0.0, 3.0, 60.0)
    assert estimator.altitude == pytest.approx(3.0, abs=1e-3)
    assert estimator.vertical_velocity == pytest.approx(0.0, abs=1e-3)


def test_constant_accel_bias_is_estimated_with_zero_steady_state_error(impl):
    true_bias = 0.012 * impl.GRAVITY  # 12 mg, m/s²
    estimator = impl.AltitudeEstimator()
    run(estimator, true_bias, 20.0, 60.0)
    assert estimator.accel_bias == pytest.approx(true_bias, abs=1e-3)
    assert estimator.altitude == pytest.approx(20.0, abs=1e-3)


def test_zero_bias_gain_parks_the_altitude_error_at_bias_over_velocity_gain(impl):
    true_bias = 0.012 * impl.GRAVITY
    settings = impl.AltitudeSettings(2.40, 2.88, 0.0)
    estimator = impl.AltitudeEstimator(settings)
    run(estimator, true_bias, 0.0, 30.0)
    assert estimator.accel_bias == 0.0
    assert estimator.altitude == pytest.approx(true_bias / settings.velocity_gain, rel=1e-3)  # about +4 cm


def test_residual_is_baro_minus_altitude_before_the_correction(impl):
    estimator = impl.AltitudeEstimator()
    estimator.reset(10.0)
    estimator.update(0.0, 10.5, DT)
    assert estimator.baro_residual == pytest.approx(0.5)
    assert estimator.altitude > 10.0  # the estimate moved toward the baro
    estimator.reset(10.0)
    estimator.update(0.0, 9.0, DT)
    assert estimator.baro_residual == pytest.approx(-1.0)


def test_residual_is_nan_on_a_step_without_baro_and_bias_is_kept(impl):
    estimator = impl.AltitudeEstimator()
    run(estimator, 0.3, 5.0, 5.0)
    bias, velocity = estimator.accel_bias, estimator.vertical_velocity
    estimator.update(1.0, math.nan, DT)
    assert math.isnan(estimator.baro_residual)
    assert estimator.accel_bias == bias
    assert estimator.vertical_velocity == pytest.approx(velocity + (1.0 - bias) * DT, rel=1e-6)


def test_baro_at_a_quarter_of_the_imu_rate_still_tracks_a_climb(impl):
    estimator = impl.AltitudeEstimator()
    estimator.reset(0.0)
    climb_rate = 2.0  # m/s
    for i in range(1, 3001):
        baro = climb_rate * i * DT if i % 4 == 0 else math.nan
        estimator.update(0.0, baro, DT)
    assert estimator.altitude == pytest.approx(climb_rate * 30.0, abs=0.05)
    assert estimator.vertical_velocity == pytest.approx(climb_rate, abs=0.01)


def test_settings_can_change_mid_run_without_losing_state(impl):
    estimator = impl.AltitudeEstimator()
    run(estimator, 0.1, 7.0, 3.0)
    before = (estimator.altitude, estimator.vertical_velocity, estimator.accel_bias)
    estimator.settings = impl.AltitudeSettings.preset("racing")
    assert (estimator.altitude, estimator.vertical_velocity, estimator.accel_bias) == before
    assert estimator.settings == impl.AltitudeSettings.preset("racing")


def test_tracks_a_motion_that_starts_at_rest_within_the_euler_step_error(impl):
    estimator = impl.AltitudeEstimator()
    omega = 2 * np.pi * 0.1  # rad/s
    worst = 0.0
    for i in range(3000):
        t = i * DT
        truth = 5 * (1 - np.cos(omega * t))  # m, starts at rest like the auto-zeroed filter
        estimator.update(5 * omega**2 * np.cos(omega * t), truth, DT)
        worst = max(worst, abs(estimator.altitude - truth))
    peak_speed = 5 * omega  # m/s
    assert worst < 1.2 * peak_speed * DT  # first-order integration: about one step of travel
