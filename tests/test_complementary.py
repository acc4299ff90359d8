"""Two-stage complementary filter (seed 001): C binding vs reference bit for bit, the write-up's
behaviours (baro step with the documented response, bias offset b·T_v·T_h), batch, state and bad input."""

import copy
import math
import pickle
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import fusion_altitude as c
import fusion_altitude.reference as ref
from fusion_altitude import _complementary

ROOT = Path(__file__).resolve().parents[1]


def floats32(low, high):
    return st.floats(float(np.float32(low)), float(np.float32(high)), width=32)


def state_bits(f):
    state = f._get_state()
    return (state[0], *(int(np.float32(x).view(np.uint32)) for x in state[1:8]), state[8], state[9])


step = st.one_of(
    st.tuples(st.just("update"), floats32(-50, 50), st.one_of(floats32(-500, 9000), st.just(math.nan)),
              floats32(1e-4, 0.05)),
    st.tuples(st.just("update"), floats32(-50, 50), st.one_of(floats32(-500, 9000), st.just(math.nan)),
              floats32(1e-4, 0.05)),
    st.tuples(st.just("reset"), floats32(-500, 9000)),
    st.tuples(st.just("settings"), st.booleans(), floats32(0, 2), floats32(0, 2), floats32(0, 1), floats32(0, 1),
              floats32(0, 30), floats32(0, 30)),
    st.tuples(st.just("bad"), st.sampled_from([(math.nan, 1.0, 0.01), (math.inf, 1.0, 0.01), (0.0, math.inf, 0.01),
                                                (0.0, 1.0, 0.0), (0.0, 1.0, -1.0), (0.0, 1.0, math.nan)])),
)


def apply(module, f, operation):
    kind = operation[0]
    try:
        if kind == "update":
            f.update(*operation[1:])
        elif kind == "reset":
            f.reset(operation[1])
        elif kind == "settings":
            per, ta, tb, cv, ch, tv, th = operation[1:]
            f.settings = module.ComplementarySettings(
                per_sample_coefficients=per, accel_time_constant=ta, baro_time_constant=tb, velocity_coefficient=cv,
                altitude_coefficient=ch, velocity_time_constant=tv, altitude_time_constant=th)
        else:
            f.update(*operation[1])
    except ValueError as error:
        return str(error).split(" ")[0]
    return None


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(operations=st.lists(step, min_size=1, max_size=100))
def test_c_and_reference_agree_bit_for_bit(operations):
    fast, slow = c.ComplementaryFilter(), ref.ComplementaryFilter()
    for operation in operations:
        assert apply(c, fast, operation) == apply(ref, slow, operation)
        assert state_bits(fast) == state_bits(slow)


def flight(n=4000, seed=3, baro_every=4):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    accel = -0.4 * np.sin(0.4 * t) + 0.05 + rng.normal(0, 0.3, n)
    baro = 2.5 * np.sin(0.4 * t) + 100 + rng.normal(0, 0.4, n)
    baro[np.arange(n) % baro_every != 0] = np.nan
    baro[rng.random(n) < 0.05] = np.nan
    return accel, baro, t


@pytest.mark.parametrize("per_sample", [False, True])
def test_batch_on_a_flight_agrees_bit_for_bit_and_equals_per_sample_updates(per_sample):
    accel, baro, _ = flight(2000)
    settings_c = c.ComplementarySettings.from_coefficients() if per_sample else c.ComplementarySettings()
    settings_r = ref.ComplementarySettings.from_coefficients() if per_sample else ref.ComplementarySettings()
    fast, slow, single = (c.ComplementaryFilter(settings_c), ref.ComplementaryFilter(settings_r),
                          c.ComplementaryFilter(settings_c))
    a = fast.update_batch(accel, baro, 0.01)
    b = slow.update_batch(accel, baro, np.full(accel.size, 0.01))
    for field in a._fields:
        assert np.array_equal(getattr(a, field).view(np.uint32), getattr(b, field).view(np.uint32)), field
    for i in range(accel.size):
        single.update(accel[i], baro[i], 0.01)
    assert state_bits(single) == state_bits(fast) == state_bits(slow)


def test_defaults_and_enums_match_the_header():
    assert _complementary.c_default_settings() == c.ComplementarySettings().as_dict() \
        == ref.ComplementarySettings().as_dict()
    assert {s.name: s.value for s in c.ComplementaryStatus} == _complementary.C_STATUS_VALUES
    assert c.ComplementarySettings().velocity_time_constant == pytest.approx(9.99, abs=1e-6)
    per = c.ComplementarySettings.from_coefficients()
    assert per.per_sample_coefficients and per.velocity_coefficient == pytest.approx(0.999)


def response(t, tv=9.99, th=4.99):
    """Documented baro-step response h(t)/S = 1 − (p e^{−pt} − q e^{−qt})/(p − q), p = 1/T_h, q = 1/T_v."""
    p, q = 1 / th, 1 / tv
    return 1 - (p * np.exp(-p * t) - q * np.exp(-q * t)) / (p - q)


@pytest.mark.parametrize("rate", [100.0, 25.0])
def test_a_baro_step_is_tracked_with_the_documented_time_constants_at_any_rate(impl, rate):
    """With the time-constant form the step response is the documented one at 100 Hz and at 25 Hz."""
    dt = 1.0 / rate
    n = int(40 * rate)
    f = impl.ComplementaryFilter()
    f.update(0.0, 0.0, dt)
    out = f.update_batch(np.zeros(n), np.ones(n), dt)
    t = (np.arange(n) + 1) * dt
    assert np.max(np.abs(out.altitude - response(t))) < 0.02
    half = t[np.argmax(out.altitude >= 0.5)]
    assert half == pytest.approx(2.14, abs=0.1)  # p e^{-pt} - q e^{-qt} = (p - q)/2
    assert out.altitude.max() == pytest.approx(1.125, abs=0.01)


def test_per_sample_coefficients_change_behaviour_with_the_rate():
    """The write-up's fixed coefficients: a 25 Hz loop responds 4 times slower than a 100 Hz one (T = c·D/(1 − c))."""
    half = {}
    for rate in (100.0, 25.0):
        dt = 1.0 / rate
        f = c.ComplementaryFilter(c.ComplementarySettings.from_coefficients())
        f.update(0.0, 0.0, dt)
        out = f.update_batch(np.zeros(int(40 * rate)), np.ones(int(40 * rate)), dt)
        half[rate] = (np.argmax(out.altitude >= 0.5) + 1) * dt
    assert half[25.0] == pytest.approx(4 * half[100.0], rel=0.05)


def test_a_12_mg_accelerometer_bias_gives_the_documented_altitude_offset():
    bias = 0.012 * c.GRAVITY
    f = c.ComplementaryFilter()
    out = f.update_batch(np.full(20000, bias), np.zeros(20000), 0.01)
    assert out.altitude[-1] == pytest.approx(bias * 9.99 * 4.99, rel=0.02)  # 5.87 m
    assert out.vertical_velocity[-1] == pytest.approx(bias * 9.99, rel=0.02)


def test_copy_and_pickle_round_trip(impl):
    accel, baro, _ = flight(500)
    f = impl.ComplementaryFilter(impl.ComplementarySettings(baro_time_constant=0.2))
    f.update_batch(accel[:300], baro[:300], 0.01)
    for clone in (copy.copy(f), copy.deepcopy(f), pickle.loads(pickle.dumps(f))):
        assert state_bits(clone) == state_bits(f)
        a = clone.update_batch(accel[300:], baro[300:], 0.01)
        assert state_bits(clone) != state_bits(f)
    b = f.update_batch(accel[300:], baro[300:], 0.01)
    assert np.array_equal(a.altitude, b.altitude)


@pytest.mark.parametrize("args, message", [
    ((math.nan, 1.0, 0.01), "accel must be finite"),
    ((math.inf, 1.0, 0.01), "accel must be finite"),
    ((0.0, -math.inf, 0.01), "baro_altitude must be finite"),
    ((0.0, 1.0, 0.0), "dt must be finite and > 0"),
    ((0.0, 1.0, math.inf), "dt must be finite and > 0"),
])
def test_bad_update_raises_naming_the_argument_and_leaves_the_state(impl, args, message):
    f = impl.ComplementaryFilter()
    f.update_batch(*flight(200)[:2], 0.01)
    before = state_bits(f)
    with pytest.raises(ValueError, match=re.escape(message)):
        f.update(*args)
    assert state_bits(f) == before


def test_bad_batch_names_the_first_bad_index_and_applies_nothing(impl):
    accel, baro, _ = flight(300)
    f = impl.ComplementaryFilter()
    f.update_batch(accel[:100], baro[:100], 0.01)
    before = state_bits(f)
    bad_accel = accel.copy()
    bad_accel[[150, 170]] = np.inf
    with pytest.raises(ValueError, match=r"^accel\[150\] must be finite"):
        f.update_batch(bad_accel, baro, 0.01)
    bad_baro = baro.copy()
    bad_baro[42] = -np.inf
    with pytest.raises(ValueError, match=r"^baro_altitude\[42\] must be finite"):
        f.update_batch(accel, bad_baro, 0.01)
    dt = np.full(accel.size, 0.01)
    dt[7] = 0.0
    with pytest.raises(ValueError, match=r"^dt\[7\] must be finite and > 0"):
        f.update_batch(accel, baro, dt)
    with pytest.raises(ValueError, match=r"^dt must be finite and > 0"):
        f.update_batch(accel, baro, -0.01)
    with pytest.raises(ValueError, match="baro_altitude has 299 samples but accel has 300"):
        f.update_batch(accel, baro[:-1], 0.01)
    with pytest.raises(TypeError, match="accel must be an array of real numbers"):
        f.update_batch(np.array(["a"] * 300), baro, 0.01)
    with pytest.raises(TypeError, match="accel must be a real number"):
        f.update("x", 1.0, 0.01)
    with pytest.raises(ValueError, match="baro_altitude must be finite"):
        f.reset(math.nan)
    assert state_bits(f) == before


@pytest.mark.parametrize("kwargs, message", [
    ({"accel_time_constant": -0.1}, "accel_time_constant must be finite and >= 0"),
    ({"velocity_time_constant": math.inf}, "velocity_time_constant must be finite and >= 0"),
    ({"velocity_coefficient": 1.01}, r"velocity_coefficient must be finite and in \[0, 1\]"),
    ({"altitude_coefficient": math.nan}, r"altitude_coefficient must be finite and in \[0, 1\]"),
])
def test_bad_settings_raise_naming_the_field(impl, kwargs, message):
    with pytest.raises(ValueError, match=message):
        impl.ComplementarySettings(**kwargs)
    with pytest.raises(TypeError, match="unknown complementary setting"):
        impl.ComplementarySettings(tau=1.0)
    with pytest.raises(TypeError, match="per_sample_coefficients must be a bool"):
        impl.ComplementarySettings(per_sample_coefficients=1)
    with pytest.raises(TypeError, match="settings must be ComplementarySettings"):
        impl.ComplementaryFilter().settings = 3
