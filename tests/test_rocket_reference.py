"""The rocket estimator: C (through the binding) and the pure-Python reference agree bit for bit.

Hypothesis draws whole flights (pad, boost, coast, descent, landing) with
random settings, noise, baro dropouts, spikes, gaps and a possibly
uncalibrated pad, plus arbitrary step sequences with invalid inputs mixed in.
"""

import copy
import pickle

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fusion_altitude import rocket
from fusion_altitude._rocket import RocketEstimator as CRocket
from fusion_altitude.reference.rocket import RocketEstimator as RefRocket


def bits(array):
    array = np.asarray(array)
    return array.view(np.uint32) if array.dtype == np.float32 else array


def same_batch(a, b) -> bool:
    return all(np.array_equal(bits(x), bits(y)) for x, y in zip(a, b))


def same_state(c, r) -> bool:
    as_bits = lambda x: int(np.float32(x).view(np.uint32))
    return (as_bits(c.height) == as_bits(r.height) and as_bits(c.vertical_velocity) == as_bits(r.vertical_velocity)
            and as_bits(c.accel_bias) == as_bits(r.accel_bias) and as_bits(c.pad_altitude) == as_bits(r.pad_altitude)
            and as_bits(c.time) == as_bits(r.time) and c.phase == r.phase and c.baro == r.baro
            and c.locked_out == r.locked_out and c.calibrated == r.calibrated and c.gap_count == r.gap_count
            and c.events == r.events)


rocket_settings = st.builds(
    rocket.RocketSettings,
    observer=st.sampled_from([None, (1.4, 1.0, 0.0), (2.0, 1.5, 0.3), (0.8, 0.3, 0.0)]),
    stationary_accel=st.floats(0.5, 5.0), calibration_window=st.floats(0.1, 1.0),
    launch_accel=st.floats(5.0, 40.0), launch_time=st.floats(0.0, 0.2),
    burnout_accel=st.floats(-3.0, 2.0), burnout_time=st.floats(0.0, 0.3),
    apogee_margin=st.floats(0.0, 3.0), lockout_speed=st.floats(20.0, 400.0),
    spike_threshold=st.floats(2.0, 50.0), spike_time=st.floats(0.0, 0.5),
    offset_rate=st.floats(0.05, 1.0), main_altitude=st.floats(0.0, 800.0),
    landed_speed=st.floats(0.5, 5.0), landed_time=st.floats(0.0, 3.0),
    gap_period=st.sampled_from([0.1, 0.5, float("inf")]))


@st.composite
def flights(draw):
    """A short synthetic flight as (accel, baro, dt) float arrays."""
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    dt = draw(st.sampled_from([0.01, 0.02, 0.05]))
    pad = draw(st.integers(0, 120))
    boost_accel = draw(st.floats(15.0, 120.0))
    burn = draw(st.floats(0.3, 4.0))
    drogue = -draw(st.floats(5.0, 40.0))
    n = draw(st.integers(50, 2500))
    t = np.arange(n) * dt
    a = np.zeros(n)
    v = h = 0.0
    heights = np.zeros(n)
    apogee = False
    for i in range(n):
        ti = (i - pad) * dt
        if i < pad:
            ai = 0.0
        elif ti < burn:
            ai = boost_accel
        elif v > 0 and not apogee:
            ai = -9.8
        else:
            apogee = True
            ai = (drogue - v) if h > 0 else -v / dt
        v += ai * dt
        h = max(h + v * dt, 0.0)
        a[i] = ai
        heights[i] = h
    accel = a + draw(st.floats(-1.0, 1.0)) + draw(st.floats(0.0, 2.0)) * rng.standard_normal(n)
    baro = 500.0 + heights - 0.03 * np.gradient(heights, dt) ** 2 / 19.6 + rng.standard_normal(n)
    baro[rng.random(n) < draw(st.floats(0.0, 0.5))] = np.nan
    spikes = rng.random(n) < 0.01
    baro[spikes] += rng.choice([-300.0, 300.0], spikes.sum())
    steps = np.full(n, dt)
    steps[rng.random(n) < draw(st.sampled_from([0.0, 0.002]))] = 0.7
    return accel, baro, steps


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(flight=flights(), settings_=rocket_settings, vertical=st.booleans())
def test_c_and_reference_agree_bit_for_bit_on_whole_flights(flight, settings_, vertical):
    accel, baro, dt = flight
    c, r = CRocket(settings_), RefRocket(settings_)
    assert same_batch(c.update_batch(accel, baro, dt, accel_is_vertical=vertical),
                      r.update_batch(accel, baro, dt, accel_is_vertical=vertical))
    assert same_state(c, r)


finite = st.floats(-1e4, 1e4, width=32)
step = st.tuples(st.one_of(finite, st.sampled_from([float("nan"), float("inf"), 60.0, 25.0, 0.0])),
                 st.one_of(finite, st.sampled_from([float("nan"), float("-inf"), 500.0])),
                 st.one_of(st.floats(0.0001220703125, 1.0, width=32), st.sampled_from([0.0, -0.01, float("nan"), 5.0])),
                 st.booleans())


@settings(max_examples=200, deadline=None)
@given(operations=st.lists(step, min_size=1, max_size=150))
def test_c_and_reference_agree_on_every_step_including_rejected_ones(operations):
    c, r = CRocket(), RefRocket()
    for accel, baro, dt, vertical in operations:
        errors = []
        for estimator in (c, r):
            try:
                estimator.update(accel, baro, dt, accel_is_vertical=vertical)
                errors.append(None)
            except ValueError as error:
                errors.append(str(error))
        assert errors[0] == errors[1]
        assert same_state(c, r)


@pytest.mark.parametrize("make", [CRocket, RefRocket], ids=["c", "reference"])
def test_copy_and_pickle_resume_bit_identically(make):
    from fusion_altitude.rocket_sim import simulate_rocket_flight
    flight = simulate_rocket_flight(3)
    half = len(flight.time) // 2
    estimator = make()
    estimator.update_batch(flight.accel[:half], flight.baro_altitude[:half], flight.dt)
    clones = [copy.copy(estimator), copy.deepcopy(estimator), pickle.loads(pickle.dumps(estimator))]
    rest = estimator.update_batch(flight.accel[half:], flight.baro_altitude[half:], flight.dt)
    for clone in clones:
        assert same_batch(clone.update_batch(flight.accel[half:], flight.baro_altitude[half:], flight.dt), rest)
        assert clone.events == estimator.events


# -- the ascent never goes down by more than 1 m, whatever the baro does (within what the gate is built for) ---------
#
# Bad baro fed to simulated flights (fusion_altitude.rocket_sim, the transonic static-port error included), in
# the C binding and in the reference: spikes and bursts shorter than spikeTime (0.2 s) of 25-500 m, either
# sign, around the baro's re-admission after the lockout; lasting steps of 25-500 m, either sign, starting
# during the lockout or in the coast after re-admission (re-admitted through the baro offset, which the output
# absorbs without falling). The height (launch to the declared apogee) may never fall more than 1 m below its
# running maximum. Before the offset's downward rate was tied to the observer's rise, a -50 m step in the coast
# of seed 1 fell 1.66 m. NOT covered, because the rocket estimator fails it (docs/rocket.md, Limits): steps smaller
# than spikeThreshold (20 m), which are fused as they come and pull the velocity (a -10 m step 1 s before
# apogee: apogee 0.26 s early).

from functools import lru_cache

from fusion_altitude.rocket_sim import simulate_rocket_flight


@lru_cache(maxsize=None)
def clean_flight(seed: int):
    """(flight, first fused baro sample after launch, apogee sample) of a simulated flight."""
    flight = simulate_rocket_flight(seed)
    batch, events = rocket.run_rocket(flight.time, flight.accel, flight.baro_altitude)
    launch = events["launch"].sample
    fused = np.flatnonzero(batch.baro == rocket.BaroFate.FUSED)
    return flight, int(fused[fused > launch][0]), events["apogee"].sample


def ascent_drop(make, flight, baro) -> float:
    """Largest fall of the height below its running maximum between launch and apogee, m."""
    estimator = make()
    batch = estimator.update_batch(flight.accel, baro, flight.dt)
    events = estimator.events
    assert events["launch"].occurred and events["apogee"].occurred
    ascent = batch.height[events["launch"].sample:events["apogee"].sample + 1].astype(np.float64)
    return float((np.maximum.accumulate(ascent) - ascent).max())


def bad_baro(seed: int, kind: str, size: float, where: float, length: int):
    """A simulated flight and its baro altitude (m) with one defect:

    - ``burst``: ``size`` m added to ``length`` samples (≤ 0.15 s) from ``where`` s after the re-admission;
    - ``step``: ``size`` m added from ``where`` (−3…0.9) to the end of the log, where ``where`` < 0 is in s
      before the re-admission (in the lockout) and ``where`` ≥ 0 the fraction of the way from re-admission to
      apogee.
    """
    flight, readmit, apogee = clean_flight(seed)
    baro = flight.baro_altitude.copy()
    if kind == "burst":
        start = readmit + int(round(where / flight.dt))
        baro[start:start + length] += size
    else:
        start = readmit + (int(round(where / flight.dt)) if where < 0 else int(where * (apogee - readmit)))
        baro[start:] += size
    return flight, baro


CASES = [(seed, "burst", size, where, length) for seed in (0, 1, 7) for size in (-300.0, -25.0, 25.0, 300.0)
         for where, length in ((-0.1, 1), (0.0, 1), (0.0, 15), (0.05, 5))] + \
        [(seed, "step", size, where, 0) for seed in (1, 9) for size in (-300.0, -50.0, 25.0, 300.0)
         for where in (-3.0, -0.05, 0.1, 0.5, 0.7, 0.9)]


@pytest.mark.parametrize("make", [CRocket, RefRocket], ids=["c", "reference"])
def test_the_height_does_not_drop_more_than_1_m_in_the_ascent_with_bad_baro(make):
    drops = {case: ascent_drop(make, *bad_baro(*case)) for case in CASES}
    worst = max(drops, key=drops.get)
    assert drops[worst] <= 1.0, (worst, drops[worst])
    # the bad baro reached the estimator: a burst is rejected sample by sample
    flight, baro = bad_baro(0, "burst", 300.0, 0.0, 15)
    assert (make().update_batch(flight.accel, baro, flight.dt).baro == rocket.BaroFate.SPIKE).sum() >= 15


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 19), kind=st.sampled_from(["burst", "step"]),
       size=st.one_of(st.floats(-500.0, -25.0), st.floats(25.0, 500.0)), where=st.floats(0.0, 1.0),
       length=st.integers(1, 15))
def test_the_height_does_not_drop_more_than_1_m_in_the_ascent_with_drawn_bad_baro(seed, kind, size, where, length):
    where = -0.2 + 0.5 * where if kind == "burst" else -3.0 + 3.9 * where
    flight, baro = bad_baro(seed, kind, size, where, length)
    c, r = CRocket(), RefRocket()
    assert same_batch(c.update_batch(flight.accel, baro, flight.dt), r.update_batch(flight.accel, baro, flight.dt))
    assert c.events == r.events
    assert ascent_drop(CRocket, flight, baro) <= 1.0


@pytest.mark.parametrize("estimator", [CRocket, RefRocket], ids=["c", "reference"])
def test_a_batch_writes_into_out_and_returns_it(estimator):
    accel = np.linspace(-1.0, 30.0, 200)
    baro = np.linspace(300.0, 420.0, 200)
    expected = estimator().update_batch(accel, baro, 0.01)
    out = [np.full_like(array, 7) for array in expected]
    assert estimator().update_batch(accel, baro, 0.01, out=out) is out
    assert same_batch(out, expected)
