"""Specification of the error metrics."""

import numpy as np
import pytest

from fusion_altitude import AltitudeSettings
from fusion_altitude import metrics


def test_statistics_exclude_the_transient():
    time = np.arange(100) * 0.1
    error = np.where(time <= 5.0, 100.0, 1.0)
    stats = metrics.error_statistics(time, error, transient=5.0)
    assert (stats.mean, stats.rms, stats.max) == (1.0, 1.0, 1.0)


def test_statistics_of_a_known_signal():
    time = np.arange(5.0)
    stats = metrics.error_statistics(time, [0.0, 3.0, -4.0, 3.0, -4.0], transient=0.5)
    assert stats.mean == pytest.approx(-0.5)
    assert stats.rms == pytest.approx(np.sqrt(12.5))
    assert stats.max == 4.0
    assert stats.count == 4


def test_statistics_ignore_nan():
    stats = metrics.error_statistics(np.arange(4.0), [0.0, np.nan, 2.0, 2.0], transient=0.5)
    assert stats.count == 2 and stats.mean == 2.0


def test_statistics_without_samples_after_transient_raise():
    with pytest.raises(ValueError, match="transient"):
        metrics.error_statistics(np.arange(3.0), np.zeros(3), transient=10.0)


def test_settling_time_is_when_error_last_leaves_the_band():
    time = np.arange(10.0)
    error = np.array([5, 3, 0.5, 2, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1])
    assert metrics.settling_time(time, error, tolerance=1.0) == 4.0


def test_settling_time_is_infinite_if_never_settled():
    assert metrics.settling_time(np.arange(3.0), [0.0, 0.0, 2.0], 1.0) == float("inf")


def test_bias_convergence_time_uses_twenty_percent_band_by_default():
    time = np.arange(10.0)
    estimate = np.array([0, 0.5, 0.7, 0.85, 0.95, 1, 1, 1, 1, 1])
    assert metrics.bias_convergence_time(time, estimate, 1.0) == 3.0


def test_noise_gain_falls_with_bandwidth():
    slow = AltitudeSettings.preset("balloon").as_tuple()
    fast = AltitudeSettings.preset("racing").as_tuple()
    assert metrics.noise_gain(*slow, 0.01) < metrics.noise_gain(*fast, 0.01)


def test_noise_gain_predicts_simulated_output_noise():
    kh, kv, kb = AltitudeSettings().as_tuple()
    rng = np.random.default_rng(0)
    from fusion_altitude import AltitudeEstimator
    estimator = AltitudeEstimator()
    estimator.reset(0.0)
    out = estimator.update_batch(np.zeros(200_000), rng.standard_normal(200_000), 0.01)
    assert np.std(out.altitude[20_000:]) == pytest.approx(metrics.noise_gain(kh, kv, kb, 0.01), rel=0.05)


def test_discrete_poles_are_inside_unit_circle_for_presets():
    for name in ("balloon", "fixed_wing", "vtol", "racing"):
        assert np.all(np.abs(metrics.discrete_poles(*AltitudeSettings.preset(name).as_tuple(), 0.01)) < 1)


def test_discrete_poles_leave_the_unit_circle_when_sampling_too_slowly():
    assert np.max(np.abs(metrics.discrete_poles(*AltitudeSettings.preset("racing").as_tuple(), 0.5))) > 1


def test_step_settling_is_slower_for_lower_bandwidth():
    vtol = metrics.step_settling_time(*AltitudeSettings.preset("vtol").as_tuple(), 0.01)
    fixed = metrics.step_settling_time(*AltitudeSettings.preset("fixed_wing").as_tuple(), 0.01)
    assert vtol < fixed


def test_bias_settling_is_infinite_without_bias_estimation():
    assert metrics.bias_settling_time(2.0, 1.0, 0.0, 0.01) == float("inf")
