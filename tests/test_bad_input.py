"""Bad input raises an error that names the argument, and never changes the state."""

import math

import numpy as np
import pytest

INF = math.inf
NAN = math.nan


@pytest.fixture
def running(impl):
    estimator = impl.AltitudeEstimator()
    for i in range(50):
        estimator.update(0.2, 3.0 + 0.01 * i, 0.01)
    return estimator


@pytest.mark.parametrize("accel, baro_altitude, dt, name", [
    (NAN, 1.0, 0.01, "accel"),
    (INF, 1.0, 0.01, "accel"),
    (-INF, NAN, 0.01, "accel"),
    (1e39, 1.0, 0.01, "accel"),  # overflows float32
    (0.0, INF, 0.01, "baro_altitude"),
    (0.0, -INF, 0.01, "baro_altitude"),
    (0.0, 1.0, 0.0, "dt"),
    (0.0, 1.0, -0.01, "dt"),
    (0.0, 1.0, NAN, "dt"),
    (0.0, 1.0, INF, "dt"),
    (0.0, 1.0, 1e-50, "dt"),  # rounds to 0 in float32
])
def test_update_rejects_bad_values_naming_the_argument(running, state_bits, accel, baro_altitude, dt, name):
    before = state_bits(running)
    with pytest.raises(ValueError, match=rf"^{name} "):
        running.update(accel, baro_altitude, dt)
    assert state_bits(running) == before


@pytest.mark.parametrize("position", [0, 1, 2])
def test_update_rejects_non_numbers_with_type_error_naming_the_argument(running, state_bits, position):
    names = ["accel", "baro_altitude", "dt"]
    arguments = [0.0, 1.0, 0.01]
    arguments[position] = "1.0"
    before = state_bits(running)
    with pytest.raises(TypeError, match=names[position]):
        running.update(*arguments)
    assert state_bits(running) == before


def test_first_sample_also_rejects_bad_accel_and_dt(impl, state_bits):
    estimator = impl.AltitudeEstimator()
    before = state_bits(estimator)
    with pytest.raises(ValueError, match="^accel"):
        estimator.update(INF, 1.0, 0.01)
    with pytest.raises(ValueError, match="^dt"):
        estimator.update(0.0, 1.0, 0.0)
    assert state_bits(estimator) == before


@pytest.mark.parametrize("baro_altitude, accel_bias, name", [
    (NAN, None, "baro_altitude"),
    (INF, None, "baro_altitude"),
    (1.0, NAN, "accel_bias"),
    (1.0, -INF, "accel_bias"),
    (NAN, 0.1, "baro_altitude"),
])
def test_reset_rejects_non_finite_values(running, state_bits, baro_altitude, accel_bias, name):
    before = state_bits(running)
    with pytest.raises(ValueError, match=rf"^{name} "):
        running.reset(baro_altitude, accel_bias=accel_bias)
    assert state_bits(running) == before


@pytest.mark.parametrize("gains, name", [
    ((-1.0, 2.88, 0.675), "position_gain"),
    ((2.4, NAN, 0.675), "velocity_gain"),
    ((2.4, 2.88, INF), "bias_gain"),
    ((2.4, 2.88, -0.1), "bias_gain"),
])
def test_settings_reject_negative_or_non_finite_gains(impl, gains, name):
    with pytest.raises(ValueError, match=rf"^{name} "):
        impl.AltitudeSettings(*gains)


def test_settings_reject_gains_violating_routh_hurwitz(impl):
    with pytest.raises(ValueError, match="Routh-Hurwitz"):
        impl.AltitudeSettings(1.0, 1.0, 1.5)


def test_settings_assignment_rejects_non_settings(running, state_bits):
    before = state_bits(running)
    with pytest.raises(TypeError, match="settings"):
        running.settings = (2.4, 2.88, 0.675)
    assert state_bits(running) == before


@pytest.mark.parametrize("field, bad_index, bad_value, name", [
    ("accel", 7, NAN, "accel"),
    ("accel", 0, INF, "accel"),
    ("baro_altitude", 3, INF, "baro_altitude"),
    ("dt", 9, 0.0, "dt"),
    ("dt", 5, -1.0, "dt"),
])
def test_batch_names_the_argument_and_first_bad_index_and_applies_nothing(running, state_bits, field, bad_index,
                                                                          bad_value, name):
    n = 12
    inputs = {"accel": np.zeros(n), "baro_altitude": np.full(n, 3.0), "dt": np.full(n, 0.01)}
    inputs[field][bad_index] = bad_value
    inputs[field][bad_index + 1] = bad_value  # a later bad sample must not be the one reported
    before = state_bits(running)
    with pytest.raises(ValueError, match=rf"^{name}\[{bad_index}\] "):
        running.update_batch(inputs["accel"], inputs["baro_altitude"], inputs["dt"])
    assert state_bits(running) == before


def test_batch_with_bad_scalar_dt_names_dt_without_an_index(running, state_bits):
    before = state_bits(running)
    with pytest.raises(ValueError, match=r"^dt must"):
        running.update_batch(np.zeros(4), np.zeros(4), 0.0)
    assert state_bits(running) == before


def test_batch_rejects_mismatched_lengths(running):
    with pytest.raises(ValueError, match="baro_altitude has 3 samples but accel has 4"):
        running.update_batch(np.zeros(4), np.zeros(3), 0.01)
    with pytest.raises(ValueError, match="dt has 2 samples"):
        running.update_batch(np.zeros(4), np.zeros(4), np.full(2, 0.01))


def test_batch_rejects_non_numeric_arrays_with_type_error(running):
    with pytest.raises(TypeError, match="accel"):
        running.update_batch(["a", "b"], [1.0, 2.0], 0.01)
    with pytest.raises(TypeError, match="baro_altitude"):
        running.update_batch([1.0, 2.0], np.array([1 + 1j, 2j]), 0.01)


def test_batch_rejects_two_dimensional_input(running):
    with pytest.raises(ValueError, match="accel must be 1-D"):
        running.update_batch(np.zeros((2, 2)), np.zeros(4), 0.01)


def test_batch_rejects_unsuitable_out_arrays(running):
    good = [np.empty(4, np.float32) for _ in range(4)]
    with pytest.raises(ValueError, match="out.vertical_velocity"):
        running.update_batch(np.zeros(4), np.zeros(4), 0.01, out=[good[0], np.empty(4), good[2], good[3]])
    with pytest.raises(ValueError, match="out.altitude"):
        running.update_batch(np.zeros(4), np.zeros(4), 0.01, out=[np.empty(5, np.float32)] + good[1:])
    with pytest.raises(ValueError, match="out must hold 4 arrays"):
        running.update_batch(np.zeros(4), np.zeros(4), 0.01, out=good[:3])
