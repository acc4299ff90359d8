"""fit(): searches omega, zeta, omega_b for gains that match a reference better than the default."""

import warnings

import numpy as np
import pytest

import fusion_altitude


def balloon_like_log(seconds=300.0, rate=50.0, seed=0):
    """Slow ascent (5 m/s) with a noisy barometer (0.8 m) and a good accelerometer: low gains win."""
    rng = np.random.default_rng(seed)
    n = int(seconds * rate)
    t = np.arange(n) / rate
    truth = 5.0 * t + 20 * np.sin(2 * np.pi * t / 120)  # m
    accel = -20 * (2 * np.pi / 120) ** 2 * np.sin(2 * np.pi * t / 120) + 0.02 + rng.normal(0, 0.05, n)  # m/s²
    baro = truth + rng.normal(0, 0.8, n)  # m
    return accel, baro, 1.0 / rate, truth, t > 60.0


def test_fit_beats_the_default_gains_where_they_are_far_from_optimal():
    accel, baro, dt, truth, mask = balloon_like_log()
    result = fusion_altitude.fit(accel, baro, dt, truth, mask=mask)
    assert result.rms_error < 0.75 * result.default_rms_error  # measured: 0.116 m vs 0.181 m
    assert result.omega < 1.5  # slower than the VTOL default


def test_fit_returns_stable_settings_that_reproduce_its_metric():
    accel, baro, dt, truth, mask = balloon_like_log(seconds=120.0)
    result = fusion_altitude.fit(accel, baro, dt, truth, mask=mask, refinements=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fusion_altitude.DiscretisationWarning)
        result.settings.validate(dt)
    altitude = fusion_altitude.AltitudeEstimator(result.settings).update_batch(accel, baro, dt).altitude
    rms = np.sqrt(np.mean((altitude.astype(float) - truth.astype(np.float32))[mask] ** 2))
    assert rms == pytest.approx(result.rms_error, rel=1e-4)


def test_fit_landscape_lists_every_candidate_best_first():
    accel, baro, dt, truth, mask = balloon_like_log(seconds=60.0)
    result = fusion_altitude.fit(accel, baro, dt, truth, refinements=0)
    assert result.landscape.dtype.names == ("omega", "zeta", "omega_b", "rms_error")
    assert np.all(np.diff(result.landscape["rms_error"]) >= 0)
    assert result.landscape["rms_error"][0] == result.rms_error
    assert len(result.landscape) > 100


def test_fit_rejects_an_empty_omega_range():
    accel, baro, dt, truth, _ = balloon_like_log(seconds=10.0)
    with pytest.raises(ValueError, match="omega_range"):
        fusion_altitude.fit(accel, baro, dt, truth, omega_range=(2.0, 1.0))
