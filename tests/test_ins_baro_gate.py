"""The INS baro innovation gate, as specifications: a reading whose innovation
y (m) has y² > baro_gate² · S (S = P_dd + baro_noise², m²) is rejected and the
INS coasts on the IMU; a rejection streak older than baro_rejection_timeout
(s) resets the height from the baro (the INS is what drifted); a logging gap
ends a streak. The C binding and the reference agree bit for bit."""

import math

import numpy as np
import pytest

import fusion_altitude as fa
from fusion_altitude.reference import ins as reference

LEVEL = (0.0, 0.0, 9.80665)
DT = 0.01  # s, 100 Hz IMU; the baro on every 2nd step (50 Hz)
NAN = float("nan")


def _estimator(impl=fa, **settings):
    settings = {"stationary_gyro_threshold": 0.0, **settings}  # never stationary: every reading goes through the gate
    ins = impl.InsEstimator(impl.InsSettings(**settings))
    ins.update((0.0, 0.0, 0.0), LEVEL, DT)
    return ins


def _hold(ins, baro, seconds, gyro=(0.002, 0.0, 0.0)):
    """Steps of DT with a reading of ``baro`` (m) on every 2nd; the altitudes (m) after each."""
    altitudes = []
    for k in range(int(round(seconds / DT))):
        ins.update(gyro, LEVEL, DT, baro if k % 2 == 0 else NAN)
        altitudes.append(ins.height_above_start)
    return np.array(altitudes)


def test_defaults_are_five_sigma_and_one_second_as_the_kalman_filter():
    settings = fa.InsSettings()
    assert settings.baro_gate == 5.0
    assert settings.baro_rejection_timeout == 1.0


def test_a_glitch_burst_is_rejected_and_the_height_does_not_follow_it():
    ins = _estimator()
    _hold(ins, 100.0, 2.0)
    before = ins.height_above_start
    during = _hold(ins, 180.0, 0.5)  # 80 m for 0.5 s: shorter than the timeout
    assert ins.baro_rejections == 25
    assert ins.is_baro_rejecting
    assert np.max(np.abs(during - before)) < 0.05
    _hold(ins, 100.0, 0.1)
    assert not ins.is_baro_rejecting
    assert ins.baro_resets == 0


def test_without_the_gate_the_same_burst_pulls_the_height():
    ins = _estimator(baro_gate=1e6)
    _hold(ins, 100.0, 2.0)
    during = _hold(ins, 180.0, 0.5)
    assert ins.baro_rejections == 0
    assert np.max(during) > 20.0


def test_a_lasting_step_is_taken_after_the_timeout_and_the_height_reset_from_the_baro():
    ins = _estimator(baro_rejection_timeout=0.5)
    _hold(ins, 100.0, 2.0)
    altitudes = _hold(ins, 130.0, 1.5)
    assert ins.baro_resets == 1
    assert not ins.is_baro_rejecting
    reset_step = int(np.argmax(altitudes > 15.0))
    # rejected while the streak is at most 0.5 s old (readings at 0, 0.02, ... s), taken at the first one after
    assert 0.5 < reset_step * DT <= 0.54
    assert abs(altitudes[-1] - 30.0) < 0.3


def test_a_zero_timeout_resets_on_the_second_rejected_reading():
    ins = _estimator(baro_rejection_timeout=0.0)
    _hold(ins, 100.0, 2.0)
    _hold(ins, 130.0, 0.04)  # readings at 0 (rejected, streak starts) and 0.02 s (streak older than 0: reset)
    assert (ins.baro_rejections, ins.baro_resets) == (2, 1)
    assert abs(ins.height_above_start - 30.0) < 0.3


def test_a_logging_gap_ends_a_rejection_streak():
    ins = _estimator(baro_rejection_timeout=0.5)
    _hold(ins, 100.0, 2.0)
    _hold(ins, 130.0, 0.3)
    assert ins.is_baro_rejecting
    ins.update((0.0, 0.0, 0.0), LEVEL, 2.0, 130.0)  # a 2 s gap: the height is unknown, the reading sets it
    assert not ins.is_baro_rejecting
    assert ins.baro_resets == 0
    assert abs(ins.height_above_start - 30.0) < 0.3


def test_the_counters_survive_pickle_and_reset_with_reset():
    import pickle

    ins = _estimator()
    _hold(ins, 100.0, 2.0)
    _hold(ins, 180.0, 0.2)
    clone = pickle.loads(pickle.dumps(ins))
    assert (clone.baro_rejections, clone.is_baro_rejecting) == (ins.baro_rejections, True)
    ins.reset()
    assert (ins.baro_rejections, ins.baro_resets, ins.is_baro_rejecting) == (0, 0, False)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan, 2e6])
def test_a_gate_not_in_zero_to_1e6_is_refused_naming_it(bad):
    with pytest.raises(ValueError, match="baro_gate"):
        fa.InsSettings(baro_gate=bad)


@pytest.mark.parametrize("bad", [-0.1, math.inf, math.nan])
def test_a_negative_or_non_finite_timeout_is_refused_naming_it(bad):
    with pytest.raises(ValueError, match="baro_rejection_timeout"):
        fa.InsSettings(baro_rejection_timeout=bad)


def test_the_reference_equals_the_c_bit_for_bit_through_bursts_steps_and_a_gap():
    runs = []
    for impl in (fa, reference):
        ins = _estimator(impl, baro_gate=3.0, baro_rejection_timeout=0.3)
        states = []
        for baro, seconds in ((100.0, 1.0), (160.0, 0.2), (100.0, 0.4), (120.0, 1.0), (95.0, 0.2)):
            _hold(ins, baro, seconds, gyro=(0.01, -0.02, 0.005))
            states.append(ins.state_dict())
        ins.update((0.0, 0.0, 0.0), LEVEL, 0.5, 90.0)
        states.append(ins.state_dict())
        runs.append(states)
    for c, python in zip(*runs):
        assert c.keys() == python.keys()
        for key in c:
            assert np.array_equal(np.asarray(c[key]), np.asarray(python[key])), key


def _climbing_from_the_first_sample(**settings):
    """20 s of a level, still IMU (0.05 m/s² noise) climbing at 10 m/s from its first sample, the baro (0.3 m
    noise) on every 2nd step: the estimator, the times (s) and the |altitude error| (m) per step."""
    steps = 2000
    time = np.arange(steps) * DT
    altitude = 100.0 + 10.0 * time
    rng = np.random.default_rng(1)
    baro = np.where(np.arange(steps) % 2 == 0, altitude + 0.3 * rng.standard_normal(steps), np.nan)
    accel = np.tile(LEVEL, (steps, 1)) + 0.05 * rng.standard_normal((steps, 3))
    ins = fa.InsEstimator(fa.InsSettings(**settings))
    batch = ins.update_batch(np.zeros((steps, 3)), accel, DT, baro)
    return ins, time, np.abs(batch.altitude - altitude)


def test_a_log_that_starts_in_a_fast_climb_is_caught_by_the_first_reset():
    """The INS starts with v = 0 (sigma initial_velocity_sigma = 0.5 m/s) while the vehicle already climbs at
    10 m/s: the readings soon fail the gate, and the timeout's reset (with its velocity variance) catches up:
    within 0.5 m by 2 s, and one reset only."""
    ins, time, error = _climbing_from_the_first_sample()
    assert ins.baro_resets == 1
    assert error[time >= 2.0].max() < 0.5


def test_declaring_a_start_in_motion_with_the_initial_velocity_sigma_avoids_the_rejections():
    """The same 10 m/s climb from the first sample with initial_velocity_sigma = 5 m/s (the start is not known to
    be at rest): the gate's S includes the velocity's growing share of P_dd, nothing is rejected, and the height
    is within 0.3 m throughout (0.26 m at 0.25 s, while the velocity is learned) and 0.2 m after 0.5 s."""
    ins, time, error = _climbing_from_the_first_sample(initial_velocity_sigma=5.0)
    assert (ins.baro_rejections, ins.baro_resets) == (0, 0)
    assert error.max() < 0.3
    assert error[time >= 0.5].max() < 0.2
