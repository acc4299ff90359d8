"""The observer (``fusion_altitude.h``): settings, behaviour, bad input, batches, checkpoints, C = reference.

What every estimator promises is in tests/test_contract.py; this file holds what is particular to the
observer. Most tests run against both implementations (the ``impl`` fixture).
"""

import copy
import math
import pickle
import threading
import time
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings as hypothesis_settings
from hypothesis import strategies as st

import fusion_altitude
import fusion_altitude as c
import fusion_altitude.reference as ref
from fusion_altitude import DiscretisationWarning, Status, _observer


# -- Gains: defaults, presets, the bandwidth formulas and the stability checks. ---------------------------------------

PRESET_OMEGA = {"balloon": 0.2, "fixed_wing": 0.5, "vtol": 1.5, "racing": 5.0}


def test_defaults_are_the_vtol_gains(impl):
    settings = impl.AltitudeSettings()
    assert settings.as_tuple() == tuple(float(np.float32(g)) for g in (2.40, 2.88, 0.675))
    assert settings == impl.AltitudeSettings.preset("vtol")


@pytest.mark.parametrize("name, omega", sorted(PRESET_OMEGA.items()))
def test_presets_are_the_exact_formulas_rounded_to_float32(impl, name, omega):
    zeta, omega_b = 0.7, (0.0 if name == "rocket" else omega / 5)  # the rocket learns no bias in flight
    exact = (2 * zeta * omega + omega_b, omega**2 + 2 * zeta * omega * omega_b, omega**2 * omega_b)
    assert impl.AltitudeSettings.preset(name).as_tuple() == tuple(float(np.float32(g)) for g in exact)


def test_balloon_and_fixed_wing_presets_follow_the_formulas_not_the_quoted_table(impl):
    # A widely copied table gives Kv 0.06 / Kb 0.008 for the balloon and Kv 0.35 for the fixed-wing.
    assert impl.AltitudeSettings.preset("balloon").velocity_gain == pytest.approx(0.0512)
    assert impl.AltitudeSettings.preset("balloon").bias_gain == pytest.approx(0.0016)
    assert impl.AltitudeSettings.preset("fixed_wing").velocity_gain == pytest.approx(0.32)


def test_unknown_preset_lists_the_known_ones(impl):
    with pytest.raises(ValueError, match="balloon, fixed_wing, vtol, racing"):
        impl.AltitudeSettings.preset("helicopter")


def test_from_bandwidth_defaults_to_zeta_0_7_and_omega_b_a_fifth_of_omega(impl):
    settings = impl.AltitudeSettings.from_bandwidth(1.5)
    assert settings.as_tuple() == pytest.approx((2.40, 2.88, 0.675), rel=1e-6)
    explicit = impl.AltitudeSettings.from_bandwidth(1.5, zeta=0.7, omega_b=0.3)
    assert explicit.as_tuple() == pytest.approx(settings.as_tuple(), rel=1e-6)


def test_from_bandwidth_with_zero_omega_b_disables_the_bias_loop(impl):
    assert impl.AltitudeSettings.from_bandwidth(2.0, 1.0, 0.0).bias_gain == 0.0


@pytest.mark.parametrize("arguments", [(0.0,), (-1.0,), (float("nan"),), (1.0, 0.0), (1.0, 0.7, -0.1)])
def test_from_bandwidth_rejects_out_of_range_arguments(impl, arguments):
    with pytest.raises(ValueError, match="omega"):
        impl.AltitudeSettings.from_bandwidth(*arguments)


def test_validate_accepts_the_defaults_at_100_hz_without_warning(impl):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        impl.AltitudeSettings().validate(0.01)


def test_validate_warns_when_omega_dt_reaches_0_1_but_stays_stable(impl):
    with pytest.warns(DiscretisationWarning, match="omega \\* dt"):
        impl.AltitudeSettings.preset("racing").validate(0.05)


def test_validate_rejects_a_step_that_makes_the_update_diverge(impl):
    with pytest.raises(ValueError, match="unstable at dt"):
        impl.AltitudeSettings.preset("racing").validate(0.3)


def test_validate_rejects_bad_dt(impl):
    with pytest.raises(ValueError, match="^dt"):
        impl.AltitudeSettings().validate(0.0)


def update_matrix(kh, kv, kb, dt):
    """The homogeneous semi-implicit update of (h, v, b), derived from the update equations."""
    return np.array([[1 - kh * dt - kv * dt**2, dt, -dt**2],
                     [-kv * dt, 1, -dt],
                     [kb * dt, 0, 1]])


def test_jury_test_agrees_with_the_eigenvalues_of_the_update():
    rng = np.random.default_rng(1)
    checked = 0
    for _ in range(4000):
        kh, kv, kb = rng.uniform(0, 30, 3) * rng.integers(0, 2, 3)
        dt = 10 ** rng.uniform(-3, 0)
        try:
            settings = fusion_altitude.AltitudeSettings(kh, kv, kb)
        except ValueError:
            continue
        gains = [float(g) for g in settings.as_tuple()]
        radius = np.max(np.abs(np.linalg.eigvals(update_matrix(*gains, dt))))
        if gains[2] == 0:
            # the bias mode is the eigenvalue 1 by construction; so is v's when Kv = 0
            keep = 1 if gains[1] == 0 else 2
            radius = np.max(np.abs(np.linalg.eigvals(update_matrix(*gains, dt)[:keep, :keep])))
        if abs(radius - 1) < 1e-3:
            continue  # too close to the boundary for float32 to decide
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                settings.validate(dt)
                stable = True
            except ValueError:
                stable = False
        assert stable == (radius < 1), (gains, dt, radius)
        checked += 1
    assert checked > 1000


def test_settings_compare_equal_across_implementations():
    assert fusion_altitude.AltitudeSettings() == fusion_altitude.reference.AltitudeSettings()


def test_settings_have_a_readable_repr(impl):
    assert repr(impl.AltitudeSettings()) == \
        "AltitudeSettings(position_gain=2.4, velocity_gain=2.88, bias_gain=0.675, gap_period=0.5, baro_timeout=2.0)"


def test_settings_pickle_and_hash(impl):
    settings = impl.AltitudeSettings.preset("fixed_wing")
    assert pickle.loads(pickle.dumps(settings)) == settings
    assert len({settings, impl.AltitudeSettings.preset("fixed_wing")}) == 1


def test_settings_are_read_only(impl):
    with pytest.raises(AttributeError):
        impl.AltitudeSettings().position_gain = 1.0



# The settings class is shared by both implementations, so these hold its formulas to the C functions.

@hypothesis_settings(max_examples=200, deadline=None)
@given(omega=st.floats(float(np.float32(1e-3)), 50.0, width=32), zeta=st.floats(float(np.float32(0.05)), 3.0, width=32),
       omega_b=st.one_of(st.none(), st.floats(0.0, 10.0, width=32)))
def test_from_bandwidth_equals_the_c_function(omega, zeta, omega_b):
    omega_b32 = float(np.float32(omega) / np.float32(5)) if omega_b is None else omega_b
    status, gains = _observer.c_settings_from_bandwidth(omega, zeta, omega_b32)
    if status != Status.OK:
        with pytest.raises(ValueError):
            fusion_altitude.AltitudeSettings.from_bandwidth(omega, zeta, omega_b)
    else:
        assert fusion_altitude.AltitudeSettings.from_bandwidth(omega, zeta, omega_b).as_dict() == gains


@hypothesis_settings(max_examples=200, deadline=None)
@given(omega=st.floats(-1.0, 50.0, width=32), zeta=st.floats(-0.5, 3.0, width=32), omega_b=st.floats(-1.0, 10.0, width=32))
def test_the_reference_twin_of_from_bandwidth_equals_the_c_function(omega, zeta, omega_b):
    from fusion_altitude.reference import observer as reference_observer

    c_status, c_gains = _observer.c_settings_from_bandwidth(omega, zeta, omega_b)
    status, gains = reference_observer._from_bandwidth(np.float32(omega), np.float32(zeta), np.float32(omega_b))
    assert int(status) == c_status
    if c_status == Status.OK:
        assert tuple(float(g) for g in gains) == (c_gains["position_gain"], c_gains["velocity_gain"],
                                                  c_gains["bias_gain"])


def test_from_bandwidth_calls_the_c_function_once_the_binding_is_imported():
    from fusion_altitude import _observer_glue

    assert _observer_glue.C_SETTINGS_FUNCTIONS["from_bandwidth"] is _observer.c_settings_from_bandwidth


@pytest.mark.parametrize("name", sorted(PRESET_OMEGA))
def test_presets_equal_the_c_function(name):
    preset = c.AltitudeSettings.preset(name)
    assert preset.as_dict() == _observer.c_settings_from_preset(_observer.C_PRESET_VALUES[name.upper()])


@hypothesis_settings(max_examples=200, deadline=None)
@given(gains=st.tuples(st.floats(0.0, 20.0, width=32), st.floats(0.0, 60.0, width=32), st.floats(0.0, 40.0, width=32)),
       dt=st.floats(float(np.float32(1e-4)), 2.0, width=32))
def test_validate_rejects_exactly_what_the_c_function_rejects(gains, dt):
    try:
        settings = c.AltitudeSettings(*gains)
    except ValueError:
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DiscretisationWarning)
        try:
            settings.validate(dt)
            accepted = True
        except ValueError:
            accepted = False
    assert accepted == (_observer.c_settings_validate(settings.as_dict(), dt) == Status.OK)

# -- What users rely on from the observer, for the C binding and the reference alike. ---------------------------------

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


# -- Bad input raises an error that names the argument, and never changes the state. ----------------------------------

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


# -- update_batch: equal to per-sample updates, flexible inputs, preallocated outputs, GIL released. ------------------

def flight(n=2000, seed=3, gap_every=4):
    rng = np.random.default_rng(seed)
    accel = rng.normal(0.0, 0.5, n)  # m/s²
    baro = 50 + np.cumsum(rng.normal(0.0, 0.02, n))  # m
    baro[np.arange(n) % gap_every != 0] = np.nan
    return accel, baro


def per_sample(estimator, accel, baro, dt):
    rows = []
    dts = np.broadcast_to(dt, accel.shape)
    for a, z, t in zip(accel.tolist(), baro.tolist(), dts.tolist()):
        estimator.update(a, z, t)
        rows.append((estimator.altitude, estimator.vertical_velocity, estimator.accel_bias, estimator.baro_residual))
    return np.array(rows, dtype=np.float32).T


def as_bits(array):
    return np.asarray(array, dtype=np.float32).view(np.uint32)


@pytest.mark.parametrize("dt", [0.01, "per-sample"])
def test_batch_equals_per_sample_updates_bit_for_bit(impl, dt):
    accel, baro = flight(n=3000 if impl is fusion_altitude else 800)
    if dt == "per-sample":
        dt = np.random.default_rng(0).uniform(0.005, 0.015, accel.size)
    batch = impl.AltitudeEstimator().update_batch(accel, baro, dt)
    expected = per_sample(impl.AltitudeEstimator(), accel.astype(np.float32).astype(float),
                          baro.astype(np.float32).astype(float), np.float32(dt).astype(float))
    for name, column in zip(batch._fields, expected):
        assert np.array_equal(as_bits(getattr(batch, name)), as_bits(column)), name


def test_batch_continues_from_the_current_state(impl):
    accel, baro = flight(n=600)
    whole = impl.AltitudeEstimator().update_batch(accel, baro, 0.01)
    estimator = impl.AltitudeEstimator()
    first = estimator.update_batch(accel[:250], baro[:250], 0.01)
    second = estimator.update_batch(accel[250:], baro[250:], 0.01)
    assert np.array_equal(as_bits(np.concatenate([first.altitude, second.altitude])), as_bits(whole.altitude))
    assert estimator.altitude == whole.altitude[-1]


def test_batch_returns_float32_arrays_named_by_quantity(impl):
    result = impl.AltitudeEstimator().update_batch([0.0, 0.1], [5.0, math.nan], 0.01)
    assert result._fields == ("altitude", "vertical_velocity", "accel_bias", "baro_residual")
    assert all(array.dtype == np.float32 and array.shape == (2,) for array in result)
    assert result.altitude[0] == 5.0 and math.isnan(result.baro_residual[1])


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64, np.int32])
def test_batch_accepts_any_real_dtype(dtype):
    accel, baro = flight(n=100, gap_every=1)  # no NaN: integers have none
    expected = fusion_altitude.AltitudeEstimator().update_batch(accel.astype(dtype).astype(np.float32),
                                                                baro.astype(dtype).astype(np.float32), 0.01)
    result = fusion_altitude.AltitudeEstimator().update_batch(accel.astype(dtype), baro.astype(dtype), 0.01)
    assert np.array_equal(as_bits(result.altitude), as_bits(expected.altitude))


def test_batch_accepts_strided_views_and_lists():
    accel, baro = flight(n=200)
    wide = np.zeros((200, 3))
    wide[:, 1] = accel
    strided = fusion_altitude.AltitudeEstimator().update_batch(wide[:, 1], baro[::-1][::-1], 0.01)
    listed = fusion_altitude.AltitudeEstimator().update_batch(accel.tolist(), baro.tolist(), 0.01)
    assert np.array_equal(as_bits(strided.altitude), as_bits(listed.altitude))


def test_batch_writes_into_preallocated_out_arrays(impl):
    accel, baro = flight(n=300)
    out = impl.AltitudeBatch(*(np.empty(300, np.float32) for _ in range(4)))
    result = impl.AltitudeEstimator().update_batch(accel, baro, 0.01, out=out)
    assert all(r is o for r, o in zip(result, out))
    fresh = impl.AltitudeEstimator().update_batch(accel, baro, 0.01)
    assert np.array_equal(as_bits(out.vertical_velocity), as_bits(fresh.vertical_velocity))


def test_batch_of_no_samples_changes_nothing(impl, state_bits):
    estimator = impl.AltitudeEstimator()
    estimator.update(0.0, 3.0, 0.01)
    before = state_bits(estimator)
    result = estimator.update_batch([], [], 0.01)
    assert all(array.size == 0 for array in result)
    assert state_bits(estimator) == before


def test_batch_releases_the_gil():
    n = 20_000_000  # about 50-150 ms of C work
    accel = np.zeros(n, np.float32)
    baro = np.zeros(n, np.float32)
    out = fusion_altitude.AltitudeBatch(*(np.empty(n, np.float32) for _ in range(4)))
    estimator = fusion_altitude.AltitudeEstimator()
    estimator.update_batch(accel[:1000], baro[:1000], 0.01, out=tuple(a[:1000] for a in out))  # warm up
    started = threading.Event()
    finished = threading.Event()
    ticks_during_batch = []

    def run_batch():
        started.set()
        estimator.update_batch(accel, baro, 0.01, out=out)
        finished.set()

    worker = threading.Thread(target=run_batch)
    worker.start()
    started.wait()
    ticks = 0
    while not finished.is_set():
        ticks += 1
        time.sleep(0)  # yields the GIL; without nogil the batch would hold it to the end
    ticks_during_batch.append(ticks)
    worker.join()
    assert ticks_during_batch[0] > 100


# -- The full state survives copy and pickle, so runs can be checkpointed and resumed. --------------------------------

def warmed_up(impl):
    estimator = impl.AltitudeEstimator(impl.AltitudeSettings.preset("fixed_wing"))
    rng = np.random.default_rng(5)
    estimator.update_batch(rng.normal(0, 1, 500), 10 + rng.normal(0, 0.1, 500), 0.01)
    estimator.update(0.3, math.nan, 0.01)  # leaves a NaN residual in the state
    return estimator


@pytest.mark.parametrize("clone", [copy.copy, copy.deepcopy, lambda e: pickle.loads(pickle.dumps(e))],
                         ids=["copy", "deepcopy", "pickle"])
def test_clone_carries_the_full_state(impl, state_bits, clone):
    estimator = warmed_up(impl)
    assert state_bits(clone(estimator)) == state_bits(estimator)


def test_resumed_checkpoint_gives_identical_results(impl):
    estimator = warmed_up(impl)
    checkpoint = pickle.dumps(estimator)
    rng = np.random.default_rng(6)
    accel, baro = rng.normal(0, 1, 300), 10 + rng.normal(0, 0.1, 300)
    original = estimator.update_batch(accel, baro, 0.01)
    resumed = pickle.loads(checkpoint).update_batch(accel, baro, 0.01)
    for a, b in zip(original, resumed):
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_copies_are_independent(impl):
    estimator = warmed_up(impl)
    clone = copy.copy(estimator)
    clone.update(1.0, 20.0, 0.01)
    assert clone.altitude != estimator.altitude


def test_reference_checkpoint_resumes_in_the_c_binding(state_bits):
    estimator = warmed_up(fusion_altitude.reference)
    restored = fusion_altitude._observer._restore(estimator._get_state())
    assert state_bits(restored) == state_bits(estimator)


# -- The C core (through the binding) and the pure-Python reference agree bit for bit. --------------------------------

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


@hypothesis_settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow, *SHARED_FIXTURE])
@given(operations=st.lists(step, min_size=1, max_size=120))
def test_per_sample_sequences_agree_bit_for_bit(state_bits, operations):
    fast, slow = c.AltitudeEstimator(), ref.AltitudeEstimator()
    for operation in operations:
        assert apply(c, fast, operation) == apply(ref, slow, operation)
        assert state_bits(fast) == state_bits(slow)


@hypothesis_settings(max_examples=60, deadline=None, suppress_health_check=SHARED_FIXTURE)
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


@hypothesis_settings(max_examples=200, deadline=None)
@given(omega=floats32(0.01, 100.0), zeta=floats32(0.05, 3.0),
       omega_b=st.one_of(st.none(), floats32(0.0, 20.0)))
def test_settings_from_bandwidth_agree_bit_for_bit(omega, zeta, omega_b):
    def build(module):
        try:
            return module.AltitudeSettings.from_bandwidth(omega, zeta, omega_b).as_tuple()
        except ValueError as error:
            return str(error)
    assert build(c) == build(ref)


@hypothesis_settings(max_examples=300, deadline=None)
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
