"""The C core (through the binding) and the pure-Python reference agree bit for bit."""

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import fusion_altitude as c
import fusion_altitude.reference as ref

# The state_bits fixture is a pure function, safe to share across hypothesis examples.
SHARED_FIXTURE = [HealthCheck.function_scoped_fixture]

def floats32(low, high):
    """float32 values in [low, high] (bounds rounded to float32)."""
    return st.floats(float(np.float32(low)), float(np.float32(high)), width=32)


finite_accel = floats32(-50.0, 50.0)
baro_or_gap = st.one_of(floats32(-500.0, 9000.0), st.just(math.nan))
sample_period = floats32(1e-4, 0.05)
gains = st.tuples(floats32(0.0, 20.0), floats32(0.0, 60.0), floats32(0.0, 40.0))

step = st.one_of(
    st.tuples(st.just("update"), finite_accel, baro_or_gap, sample_period),
    st.tuples(st.just("update"), finite_accel, baro_or_gap, sample_period),
    st.tuples(st.just("update"), finite_accel, baro_or_gap, sample_period),
    st.tuples(st.just("reset"), floats32(-500.0, 9000.0)),
    st.tuples(st.just("warm_start"), floats32(-500.0, 9000.0), floats32(-2.0, 2.0)),
    st.tuples(st.just("settings"), gains),
    st.tuples(st.just("bad"), st.sampled_from([
        (math.nan, 1.0, 0.01), (math.inf, 1.0, 0.01), (0.0, -math.inf, 0.01), (0.0, 1.0, 0.0), (0.0, 1.0, -1.0)])),
)


def apply(module, estimator, operation):
    """Apply one operation; return the exception type raised, if any."""
    kind = operation[0]
    try:
        if kind == "update":
            estimator.update(*operation[1:])
        elif kind == "reset":
            estimator.reset(operation[1])
        elif kind == "warm_start":
            estimator.reset(operation[1], accel_bias=operation[2])
        elif kind == "settings":
            estimator.settings = module.AltitudeSettings(*operation[1])
        else:
            estimator.update(*operation[1])
    except ValueError as error:
        return type(error), str(error).split(" ")[0]
    return None


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow, *SHARED_FIXTURE])
@given(operations=st.lists(step, min_size=1, max_size=120))
def test_per_sample_sequences_agree_bit_for_bit(state_bits, operations):
    fast, slow = c.AltitudeEstimator(), ref.AltitudeEstimator()
    for operation in operations:
        assert apply(c, fast, operation) == apply(ref, slow, operation)
        assert state_bits(fast) == state_bits(slow)


@settings(max_examples=60, deadline=None, suppress_health_check=SHARED_FIXTURE)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(0, 400), gap_every=st.integers(1, 8),
       per_sample_dt=st.booleans(), preset=st.sampled_from(["balloon", "fixed_wing", "vtol", "racing"]))
def test_batches_agree_bit_for_bit(state_bits, seed, n, gap_every, per_sample_dt, preset):
    rng = np.random.default_rng(seed)
    accel = rng.normal(0.0, 2.0, n)
    baro = np.cumsum(rng.normal(0.0, 0.3, n)) + 100.0
    baro[np.arange(n) % gap_every != 0] = np.nan
    dt = rng.uniform(0.002, 0.03, n) if per_sample_dt else 0.01
    fast = c.AltitudeEstimator(c.AltitudeSettings.preset(preset))
    slow = ref.AltitudeEstimator(ref.AltitudeSettings.preset(preset))
    fast_out = fast.update_batch(accel, baro, dt)
    slow_out = slow.update_batch(accel, baro, dt)
    for name in c.AltitudeBatch._fields:
        assert np.array_equal(getattr(fast_out, name).view(np.uint32), getattr(slow_out, name).view(np.uint32)), name
    assert state_bits(fast) == state_bits(slow)


@settings(max_examples=200, deadline=None)
@given(omega=floats32(0.01, 100.0), zeta=floats32(0.05, 3.0),
       omega_b=st.one_of(st.none(), floats32(0.0, 20.0)))
def test_settings_from_bandwidth_agree_bit_for_bit(omega, zeta, omega_b):
    def build(module):
        try:
            return module.AltitudeSettings.from_bandwidth(omega, zeta, omega_b).as_tuple()
        except ValueError as error:
            return str(error)
    assert build(c) == build(ref)


@settings(max_examples=300, deadline=None)
@given(gains=gains, dt=floats32(1e-4, 2.0))
def test_discrete_stability_checks_agree(gains, dt):
    def verdict(module):
        try:
            settings_ = module.AltitudeSettings(*gains)
        except ValueError:
            return "invalid"
        try:
            import warnings
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                settings_.validate(dt)
        except ValueError:
            return "unstable"
        return "stable"
    assert verdict(c) == verdict(ref)
