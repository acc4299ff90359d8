"""The stability-limit gap rule and the baro timeout of the observer, the complementary filter and the sweep
(issue 20): no non-finite or runaway output from finite input, no dead reckoning past the baro's horizon.

Each behaviour is checked in the C core (through the binding) and in the pure-Python reference, and the two
are compared bit for bit on telemetry-like step sequences.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import fusion_altitude as fa
from fusion_altitude import reference, runner, tuning
from fusion_altitude.logs import LogWarning

IMPLEMENTATIONS = {"c": fa, "reference": reference}


def running(impl, preset: str, gap_period: float = math.inf):
    """An observer with a preset's gains (and the given gap period, s) after 1 s of a 100 Hz hover at 10 m."""
    settings = impl.AltitudeSettings.preset(preset).replace(gap_period=gap_period)
    estimator = impl.AltitudeEstimator(settings)
    estimator.update_batch(np.zeros(100), np.full(100, 10.0), 0.01)
    return estimator


def telemetry_steps(n: int, seed: int, noise: float = 2.0):
    """Telemetry-like steps: 60 % 0.1 s, 25 % 0.1-1 s, 15 % 0.5-4 s; a true altitude moving at up to 3 m/s, the baro
    on 90 % of the steps within 1 m of it, accel ±``noise`` m/s² around the true acceleration."""
    rng = np.random.default_rng(seed)
    u = rng.random(n)
    dt = np.where(u < 0.6, 0.1, np.where(u < 0.85, 0.1 + 0.9 * rng.random(n), 0.5 + 3.5 * rng.random(n)))
    velocity = np.clip(np.cumsum(rng.uniform(-2, 2, n) * dt), -3, 3)
    truth = 100 + np.cumsum(velocity * dt)
    accel = np.gradient(velocity, np.cumsum(dt)) + rng.uniform(-noise, noise, n)
    baro = np.where(rng.random(n) < 0.9, truth + rng.uniform(-1, 1, n), np.nan)
    return accel, baro, dt, truth


def bits(values):
    return np.ascontiguousarray(values, dtype=np.float32).view(np.uint32)


# -- the stability-limit gap rule -----------------------------------------------------------------------------


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
@pytest.mark.parametrize("preset", ["vtol", "racing"])
def test_a_1_s_baro_step_is_a_gap_at_the_default_and_racing_gains(impl, preset):
    estimator = running(impl, preset)
    velocity = estimator.vertical_velocity
    estimator.update(0.0, 12.0, 1.0)
    assert estimator.gap_count == 1
    assert estimator.altitude == 12.0  # restarted at this step's sample, not integrated
    # the velocity moves part of the way (D/(D + Kh/Kv)) toward the mean velocity over the step, 2 m/s
    assert velocity < estimator.vertical_velocity < 2.0


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
def test_a_20_ms_baro_step_is_no_gap_at_the_racing_gains(impl):
    estimator = running(impl, "racing")
    estimator.update(0.0, 10.5, 0.02)
    assert estimator.gap_count == 0
    assert estimator.baro_residual != 0.0  # corrected, not restarted


@pytest.mark.parametrize("preset, limit", [("vtol", 0.413), ("racing", 0.124), ("fixed_wing", 1.24),
                                           ("balloon", 3.10)])
def test_the_stability_limit_is_jury_with_a_1_5_margin(preset, limit):
    gains = tuple(np.float32(g) for g in reference.AltitudeSettings.preset(preset).as_tuple())
    below, above = np.float32(limit * 0.99), np.float32(limit * 1.01)
    assert reference.observer.step_stable(*gains, below, below)
    assert not reference.observer.step_stable(*gains, above, above)
    settings = reference.AltitudeSettings.preset(preset)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fa.DiscretisationWarning)
        settings.validate(float(above) * 1.4)  # plain Jury still passes well past the rule's limit: the margin


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
@pytest.mark.parametrize("preset", ["vtol", "racing"])
def test_telemetry_like_steps_keep_the_observer_finite_and_within_20_m(impl, preset):
    accel, baro, dt, truth = telemetry_steps(3000 if impl is fa else 1500, seed=4)
    estimator = impl.AltitudeEstimator(impl.AltitudeSettings.preset(preset).replace(gap_period=1.0))
    out = estimator.update_batch(accel, baro, dt)
    for field in (out.altitude, out.vertical_velocity, out.accel_bias):
        assert np.all(np.isfinite(field))
    started = np.arange(baro.size) >= np.argmax(np.isfinite(baro))  # from the first baro sample (the reference)
    assert np.max(np.abs(out.altitude - truth)[started]) < 50.0  # measured 11.5 m (vtol), 30.5 m (racing) in C
    assert estimator.gap_count > 0


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
def test_telemetry_like_steps_keep_the_complementary_filter_finite_and_within_20_m(impl):
    accel, baro, dt, truth = telemetry_steps(3000 if impl is fa else 1500, seed=5)
    out = impl.ComplementaryFilter(impl.ComplementarySettings(gap_period=1.0)).update_batch(accel, baro, dt)
    assert np.all(np.isfinite(out.altitude)) and np.all(np.isfinite(out.vertical_velocity))
    started = np.arange(baro.size) >= np.argmax(np.isfinite(baro))
    assert np.max(np.abs(out.altitude - truth)[started]) < 20.0


def test_c_equals_reference_bit_for_bit_on_telemetry_like_steps_with_timeouts():
    accel, baro, dt, _ = telemetry_steps(1500, seed=6)
    baro[600:700] = np.nan  # a long outage: a timeout
    for settings in (fa.AltitudeSettings.preset("racing").replace(gap_period=1.0), fa.AltitudeSettings()):
        c = fa.AltitudeEstimator(settings).update_batch(accel, baro, dt)
        r = reference.AltitudeEstimator(settings).update_batch(accel, baro, dt)
        for field in c._fields:
            assert np.array_equal(bits(getattr(c, field)), bits(getattr(r, field))), field
    c = fa.ComplementaryFilter(fa.ComplementarySettings(gap_period=1.0)).update_batch(accel, baro, dt)
    r = reference.ComplementaryFilter(reference.ComplementarySettings(gap_period=1.0)).update_batch(accel, baro, dt)
    for field in c._fields:
        assert np.array_equal(bits(getattr(c, field)), bits(getattr(r, field))), field


def test_c_sweep_equals_the_reference_sweep_where_the_stability_rule_differs_between_settings():
    accel, baro, dt, truth = telemetry_steps(800, seed=7)
    settings = [fa.AltitudeSettings.preset(name) for name in ("balloon", "fixed_wing", "vtol", "racing")]
    c = fa.sweep(accel, baro, dt, settings, reference=truth, outputs=True, gap_period=1.0)
    r = reference.sweep(accel, baro, dt, settings, reference=truth, outputs=True, gap_period=1.0)
    for field in c.outputs._fields:
        assert np.array_equal(bits(getattr(c.outputs, field)), bits(getattr(r.outputs, field))), field
    assert np.array_equal(bits(c.sum_squared_error), bits(r.sum_squared_error))


def test_the_sweep_applies_one_stability_rule_whatever_the_thread_split():
    accel, baro, dt, truth = telemetry_steps(600, seed=8)
    settings = [fa.AltitudeSettings.from_bandwidth(omega) for omega in np.geomspace(0.2, 6.0, 130)]
    one = fa.sweep(accel, baro, dt, settings, outputs=True, gap_period=1.0, threads=1)
    two = fa.sweep(accel, baro, dt, settings, outputs=True, gap_period=1.0, threads=2)
    assert np.array_equal(bits(one.outputs.altitude), bits(two.outputs.altitude))


# -- the baro timeout ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
def test_the_default_baro_timeout_is_2_s(impl):
    assert impl.AltitudeSettings().baro_timeout == 2.0
    assert impl.ComplementarySettings().baro_timeout == 2.0
    assert impl.AltitudeSettings.preset("balloon").baro_timeout == 10.0


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan])
def test_a_baro_timeout_not_positive_is_rejected_naming_it(impl, bad):
    with pytest.raises(ValueError, match="baro_timeout"):
        impl.AltitudeSettings(baro_timeout=bad)
    with pytest.raises(ValueError, match="baro_timeout"):
        impl.ComplementarySettings(baro_timeout=bad)


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
@pytest.mark.parametrize("estimator", ["observer", "complementary"])
def test_past_the_baro_timeout_the_output_is_flagged_and_counted_once(impl, estimator):
    e = running(impl, "vtol") if estimator == "observer" else impl.ComplementaryFilter()
    if estimator == "complementary":
        e.update_batch(np.zeros(100), np.full(100, 10.0), 0.01)
    e.update_batch(np.full(190, 0.5), np.full(190, np.nan), 0.01)
    assert not e.baro_timed_out and e.baro_timeouts == 0
    e.update_batch(np.full(20, 0.5), np.full(20, np.nan), 0.01)
    assert e.baro_timed_out and e.baro_timeouts == 1
    e.update_batch(np.full(500, 0.5), np.full(500, np.nan), 0.01)
    assert e.baro_timeouts == 1


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
@pytest.mark.parametrize("estimator", ["observer", "complementary"])
def test_timed_out_the_velocity_decays_and_the_altitude_moves_at_most_v_times_the_timeout(impl, estimator):
    e = running(impl, "vtol") if estimator == "observer" else impl.ComplementaryFilter()
    if estimator == "complementary":
        e.update_batch(np.zeros(100), np.full(100, 10.0), 0.01)
    e.update_batch(np.full(250, 1.0), np.full(250, np.nan), 0.01)  # 2.5 s: timed out with v > 0
    assert e.baro_timed_out
    v, h = e.vertical_velocity, e.altitude
    out = e.update_batch(np.full(6000, 5.0), np.full(6000, np.nan), 0.01)  # 60 s more, a large accel ignored
    assert np.all(np.diff(out.vertical_velocity) <= 0) and out.vertical_velocity[-1] < 0.01 * v
    assert 0 <= out.altitude[-1] - h <= v * 2.0 + 1e-3


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
@pytest.mark.parametrize("estimator", ["observer", "complementary"])
def test_the_next_baro_sample_after_a_timeout_restarts_at_it_and_clears_the_flag(impl, estimator):
    e = running(impl, "vtol") if estimator == "observer" else impl.ComplementaryFilter()
    if estimator == "complementary":
        e.update_batch(np.zeros(100), np.full(100, 10.0), 0.01)
    e.update_batch(np.full(300, 1.0), np.full(300, np.nan), 0.01)
    v = e.vertical_velocity
    e.update(0.0, 42.0, 0.01)
    assert not e.baro_timed_out
    assert e.altitude == 42.0 and e.vertical_velocity == v
    assert e.gap_count == 0


@pytest.mark.parametrize("impl", IMPLEMENTATIONS.values(), ids=IMPLEMENTATIONS)
def test_an_infinite_baro_timeout_dead_reckons_as_before(impl):
    e = impl.AltitudeEstimator(impl.AltitudeSettings(baro_timeout=math.inf))
    e.update_batch(np.zeros(100), np.full(100, 10.0), 0.01)
    out = e.update_batch(np.full(1000, 1.0), np.full(1000, np.nan), 0.01)
    assert not e.baro_timed_out
    assert out.vertical_velocity[-1] > 9.0  # 10 s of 1 m/s² (less the small bias learned on the hover)


# -- the runner: preset from the baro rate, timeout warning and column ---------------------------------------------


def test_steps_per_baro_is_the_baro_rate_where_the_baro_is_present():
    baro = np.full(1000, np.nan)
    baro[:200:4] = 10.0  # a baro every 4th step for 200 steps, then none
    assert tuning.steps_per_baro(baro) == 4.0


def test_default_preset_leaves_vtol_for_a_2_hz_baro():
    time = np.arange(0, 60, 0.004)
    baro = np.where(np.arange(time.size) % 125 == 0, 10.0, np.nan)  # 2 Hz
    data = fa.logs.LogData(time=time, vertical_acceleration=np.zeros(time.size), baro_altitude=baro, source="test")
    assert runner.default_preset(data) == "fixed_wing"
    baro20 = np.where(np.arange(time.size) % 12 == 0, 10.0, np.nan)  # 21 Hz
    data20 = fa.logs.LogData(time=time, vertical_acceleration=np.zeros(time.size), baro_altitude=baro20,
                             source="test")
    assert runner.default_preset(data20) == "vtol"


@pytest.mark.parametrize("estimator, bound", [("observer", 5.0), ("complementary", 15.0)])
def test_a_baro_that_stops_is_warned_about_marked_and_not_dead_reckoned(estimator, bound):
    time = np.arange(0, 72, 0.01)
    baro = np.where((np.arange(time.size) % 4 == 0) & (time < 14.4), 10.0, np.nan)
    accel = np.full(time.size, 0.3)  # an accelerometer bias the estimators cannot learn after the baro stops
    data = fa.logs.LogData(time=time, vertical_acceleration=accel, baro_altitude=baro, source="test")
    with pytest.warns(LogWarning, match="not baro-aided"):
        run = runner.run_log(data, estimator=estimator)
    altitude = np.asarray(run.estimate.altitude)
    assert np.all(np.isfinite(altitude))
    at_stop = altitude[np.flatnonzero(np.isfinite(baro))[-1]]
    # measured 0.1 m (observer) and 10.9 m (complementary; 630 m without the timeout): the complementary filter has
    # no bias state and carries a velocity error b·TV = 3 m/s into the 2 s before the timeout and the 2 s decay
    assert np.max(np.abs(altitude[time > 14.4] - at_stop)) < bound
    aided = np.asarray(run.estimate.baro_aided)
    assert aided[time < 14.0].all() and not aided[time > 17.0].any()
