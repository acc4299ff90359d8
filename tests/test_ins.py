"""The inertial navigation filter through its binding and its reference twin:
the twin equals the C bit for bit, and the Python API behaves as documented."""

import copy
import math
import pickle

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import fusion_altitude as fa
from fusion_altitude import _ins_glue
from fusion_altitude.reference import ins as reference

G = 9.80665


def bits(value) -> np.ndarray:
    """float32 values as their bit patterns (NaN and -0.0 compare exactly); others unchanged."""
    array = np.atleast_1d(np.asarray(value))
    return array.view(np.uint32) if array.dtype == np.float32 else array


def same_state(a, b) -> bool:
    sa, sb = a.state_dict(), b.state_dict()
    return sa.keys() == sb.keys() and all(np.array_equal(bits(sa[k]), bits(sb[k])) for k in sa)


def flight(n=600, seed=0, rate=100.0):
    """A rest-then-tumble IMU stream (rad/s, m/s²) with a baro every 4th step and a mag every 2nd."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate
    moving = t > 2.0
    gyro = np.stack([0.3 * np.sin(t), 0.2 * np.cos(0.7 * t), 0.1 * np.sin(0.3 * t)], axis=1) * moving[:, None]
    gyro += np.array([0.01, -0.008, 0.005]) + 0.002 * rng.standard_normal((n, 3))
    tilt = np.cumsum(gyro[:, :2] - np.array([0.01, -0.008]), axis=0) / rate
    accel = np.stack([-G * tilt[:, 1], G * tilt[:, 0], np.full(n, G + 0.1)], axis=1) + 0.05 * rng.standard_normal((n, 3))
    baro = np.where(np.arange(n) % 4 == 0, 50.0 + 0.2 * rng.standard_normal(n), np.nan)
    mag = np.where((np.arange(n) % 2 == 0)[:, None], np.array([0.4, 0.05, -0.3]) + 0.01 * rng.standard_normal((n, 3)),
                   np.nan)
    return gyro, accel, np.full(n, 1.0 / rate), baro, mag


# -- the reference twin --------------------------------------------------------------------------

def f32s(low, high):
    """floats in [low, high] rounded to float32 (what the C sees)."""
    return st.floats(low, high, allow_nan=False).map(lambda x: float(np.float32(x)))


finite = f32s(-30.0, 30.0)
step = st.fixed_dictionaries({
    "gyro": st.lists(f32s(-3.0, 3.0), min_size=3, max_size=3),
    "accel": st.lists(finite, min_size=3, max_size=3),
    "dt": st.sampled_from([0.002, 0.005, 0.01, 0.02, 0.25]),
    "baro": st.one_of(st.just(math.nan), f32s(-100.0, 100.0)),
    "mag": st.one_of(st.none(), st.lists(f32s(-2.0, 2.0), min_size=3, max_size=3)),
})
still = st.fixed_dictionaries({
    "gyro": st.lists(f32s(-0.02, 0.02), min_size=3, max_size=3),
    "accel": st.tuples(f32s(-0.3, 0.3), f32s(-0.3, 0.3), f32s(9.5, 10.1)),
    "dt": st.just(0.1),
    "baro": st.one_of(st.just(math.nan), f32s(90.0, 91.0)),
    "mag": st.none(),
})
setting_values = st.fixed_dictionaries({
    "accel_attitude_noise": st.floats(0.005, 0.5),
    "accel_rejection": st.floats(0.0, 1.0),
    "recovery_trigger_period": st.floats(0.0, 1.0),
    "stationary_window": st.floats(0.0, 0.5),
    "gap_period": st.floats(0.01, 0.5),
})


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(steps=st.lists(st.one_of(step, still, still), min_size=1, max_size=40), values=setting_values)
def test_reference_equals_the_c_bit_for_bit_on_any_steps(steps, values):
    c = fa.InsEstimator(fa.InsSettings(**values))
    r = reference.InsEstimator(reference.InsSettings(**values))
    for s in steps:
        c.update(s["gyro"], s["accel"], s["dt"], s["baro"], s["mag"])
        r.update(s["gyro"], s["accel"], s["dt"], s["baro"], s["mag"])
        assert same_state(c, r)


def test_reference_equals_the_c_bit_for_bit_over_a_long_flight():
    gyro, accel, dt, baro, mag = flight(1500)
    dt[700] = 0.5  # a gap
    c = fa.InsEstimator().update_batch(gyro, accel, dt, baro, mag)
    r = reference.InsEstimator().update_batch(gyro, accel, dt, baro, mag)
    for field in ("height_above_start", "altitude", "vertical_velocity", "quaternion", "global_quaternion", "gyro_bias",
                  "accel_z_bias", "baro_bias", "is_stationary"):
        assert np.array_equal(bits(getattr(c, field)), bits(getattr(r, field))), field


# -- batch, copy, pickle -------------------------------------------------------------------------

@pytest.mark.parametrize("impl", [fa, reference], ids=["c", "reference"])
def test_batch_equals_per_sample_updates(impl):
    gyro, accel, dt, baro, mag = flight(300)
    one = impl.InsEstimator()
    altitude = []
    for i in range(300):
        one.update(gyro[i], accel[i], dt[i], baro[i], None if np.isnan(mag[i]).all() else mag[i])
        altitude.append(one.altitude)
    batch = impl.InsEstimator().update_batch(gyro, accel, dt, baro, mag)
    assert np.array_equal(bits(batch.altitude), bits(np.array(altitude, dtype=np.float32)))
    assert batch.quaternion[-1].tolist() == one.quaternion.tolist()


def test_batch_writes_into_out():
    gyro, accel, dt, baro, mag = flight(100)
    out = fa.InsBatch.empty(100)
    result = fa.InsEstimator().update_batch(gyro, accel, 0.01, baro, mag, out=out)
    assert result is out
    assert np.array_equal(out.altitude, fa.InsEstimator().update_batch(gyro, accel, 0.01, baro, mag).altitude)


def test_batch_rejects_a_wrong_out_naming_the_field():
    gyro, accel, dt, baro, mag = flight(10)
    out = fa.InsBatch.empty(11)
    with pytest.raises(ValueError, match="out.height_above_start"):
        fa.InsEstimator().update_batch(gyro, accel, dt, baro, mag, out=out)


@pytest.mark.parametrize("how", ["copy", "deepcopy", "pickle"])
def test_copy_and_pickle_resume_bit_identical(how):
    gyro, accel, dt, baro, mag = flight(400)
    estimator = fa.InsEstimator(gyro_units="rad/s")
    estimator.update_batch(gyro[:200], accel[:200], dt[:200], baro[:200], mag[:200])
    clone = {"copy": copy.copy, "deepcopy": copy.deepcopy, "pickle": lambda e: pickle.loads(pickle.dumps(e))}[how](estimator)
    a = estimator.update_batch(gyro[200:], accel[200:], dt[200:], baro[200:], mag[200:])
    b = clone.update_batch(gyro[200:], accel[200:], dt[200:], baro[200:], mag[200:])
    assert np.array_equal(bits(a.altitude), bits(b.altitude))
    assert same_state(estimator, clone)


def test_reference_pickles_and_resumes_bit_identical():
    gyro, accel, dt, baro, mag = flight(60)
    estimator = reference.InsEstimator()
    estimator.update_batch(gyro[:30], accel[:30], dt[:30], baro[:30], mag[:30])
    clone = pickle.loads(pickle.dumps(estimator))
    estimator.update_batch(gyro[30:], accel[30:], dt[30:], baro[30:], mag[30:])
    clone.update_batch(gyro[30:], accel[30:], dt[30:], baro[30:], mag[30:])
    assert same_state(estimator, clone)


# -- bad input -----------------------------------------------------------------------------------

BAD = [
    ("gyro", dict(gyro=(math.nan, 0, 0))),
    ("gyro", dict(gyro=(0, 2e6, 0))),
    ("accel", dict(accel=(0, 0, math.inf))),
    ("mag", dict(mag=(1.0, math.nan, 0.0))),
    ("baro_altitude", dict(baro_altitude=math.inf)),
    ("dt", dict(dt=0.0)),
    ("dt", dict(dt=-0.01)),
    ("dt", dict(dt=math.nan)),
]


@pytest.mark.parametrize("impl", [fa, reference], ids=["c", "reference"])
@pytest.mark.parametrize("name, change", BAD)
def test_bad_input_raises_naming_the_argument_and_leaves_the_state(impl, name, change):
    gyro, accel, dt, baro, mag = flight(150)
    estimator = impl.InsEstimator()
    estimator.update_batch(gyro, accel, dt, baro, mag)
    before = copy.deepcopy(estimator)
    arguments = dict(gyro=(0.0, 0.0, 0.0), accel=(0.0, 0.0, G), dt=0.01, baro_altitude=50.0, mag=None)
    arguments.update(change)
    with pytest.raises(ValueError, match=f"^{name} "):
        estimator.update(**arguments)
    assert same_state(estimator, before)


@pytest.mark.parametrize("impl", [fa, reference], ids=["c", "reference"])
def test_non_numbers_raise_type_error_naming_the_argument(impl):
    with pytest.raises(TypeError, match="gyro"):
        impl.InsEstimator().update(("a", 0, 0), (0, 0, G), 0.01)
    with pytest.raises(ValueError, match="accel"):
        impl.InsEstimator().update((0, 0, 0), (0, G), 0.01)


@pytest.mark.parametrize("impl", [fa, reference], ids=["c", "reference"])
def test_batch_bad_row_names_the_argument_and_first_index_and_applies_nothing(impl):
    gyro, accel, dt, baro, mag = flight(50)
    accel[17, 1] = np.inf
    accel[30, 0] = np.nan
    estimator = impl.InsEstimator()
    before = copy.deepcopy(estimator)
    with pytest.raises(ValueError, match=r"^accel\[17\] "):
        estimator.update_batch(gyro, accel, dt, baro, mag)
    assert same_state(estimator, before)


BAD_BATCHES = {  # (argument, row, column or None, value), the one that must be named last
    "gyro inf": [("gyro", 12, 2, np.inf)],
    "accel beyond 1e6": [("accel", 3, 0, 2e6)],
    "mag partly NaN": [("mag", 40, 1, np.nan)],
    "mag inf": [("mag", 8, 2, -np.inf)],
    "baro inf": [("baro", 21, None, np.inf)],
    "dt zero": [("dt", 33, None, 0.0)],
    "dt NaN": [("dt", 0, None, np.nan)],
    "last row": [("dt", 49, None, -0.01)],
    "two in one row: gyro first": [("dt", 25, None, -1.0), ("gyro", 25, 0, np.nan)],
    "two in one row: mag before baro": [("baro", 9, None, -np.inf), ("mag", 9, 0, np.inf)],
    "earlier row wins": [("accel", 30, 1, np.nan), ("dt", 29, None, np.inf)],
}


@pytest.mark.parametrize("case", sorted(BAD_BATCHES))
def test_batch_rejection_by_the_c_loop_equals_the_reference(case):
    """update_batch leaves the per-step checks to the C update inside its loop (no numpy pass first): the error
    (argument, first bad index, values) equals the reference's, which checks every step before the loop, and the
    state is left as it was, also mid-flight."""
    gyro, accel, dt, baro, mag = flight(50)
    arrays = {"gyro": gyro, "accel": accel, "mag": mag, "baro": baro, "dt": dt}
    warm = flight(50)
    messages, states = [], []
    for impl in (fa, reference):
        estimator = impl.InsEstimator()
        estimator.update_batch(*warm)
        batch = {name: array.copy() for name, array in arrays.items()}
        for name, row, column, value in BAD_BATCHES[case]:
            if column is None:
                batch[name][row] = value
            else:
                batch[name][row, column] = value
        before = copy.deepcopy(estimator)
        with pytest.raises(ValueError) as error:
            estimator.update_batch(batch["gyro"], batch["accel"], batch["dt"], batch["baro"], batch["mag"])
        assert same_state(estimator, before)
        messages.append(str(error.value))
    assert messages[0] == messages[1]
    name, row = BAD_BATCHES[case][-1][:2]  # each case lists its expected error last
    assert messages[0].startswith(f"{'baro_altitude' if name == 'baro' else name}[{row}] "), messages[0]


def test_wrong_shapes_are_named():
    with pytest.raises(ValueError, match=r"accel must have shape \(5, 3\)"):
        fa.InsEstimator().update_batch(np.zeros((5, 3)), np.zeros((4, 3)), 0.01)
    with pytest.raises(ValueError, match="baro_altitude"):
        fa.InsEstimator().update_batch(np.zeros((5, 3)), np.zeros((5, 3)), 0.01, baro_altitude=np.zeros(4))


# -- settings, units, statuses -------------------------------------------------------------------

# The defaults, the status enum and its messages are generated from the header (tools/generate_bindings.py
# --check) and held by tests/test_contract.py, as for every estimator.


@pytest.mark.parametrize("impl", [fa, reference], ids=["c", "reference"])
@pytest.mark.parametrize("name, value", [("baro_noise", 0.0), ("gap_period", math.nan), ("gyro_noise", -1.0),
                                         ("accel_noise", 2e6)])
def test_settings_out_of_range_raise_naming_the_setting(impl, name, value):
    with pytest.raises(ValueError, match=name):
        impl.InsSettings(**{name: value})


def test_unknown_setting_is_a_type_error():
    with pytest.raises(TypeError, match="gyro_nois"):
        fa.InsSettings(gyro_nois=1.0)


def test_settings_can_be_replaced_mid_run_keeping_the_state():
    gyro, accel, dt, baro, mag = flight(100)
    estimator = fa.InsEstimator()
    estimator.update_batch(gyro, accel, dt, baro, mag)
    altitude = estimator.altitude
    estimator.settings = estimator.settings.replace(baro_noise=1.0)
    assert estimator.settings.baro_noise == 1.0 and estimator.altitude == altitude


@pytest.mark.parametrize("impl", [fa, reference], ids=["c", "reference"])
def test_degrees_per_second_and_g_inputs_equal_the_si_inputs(impl):
    gyro, accel, dt, baro, mag = flight(200)
    si = impl.InsEstimator().update_batch(gyro, accel, dt, baro, mag)
    imu = impl.InsEstimator(gyro_units="deg/s", accel_units="g").update_batch(np.degrees(gyro), accel / G, dt, baro, mag)
    assert np.max(np.abs(si.altitude - imu.altitude)) < 1e-4
    assert np.max(np.abs(si.quaternion - imu.quaternion)) < 1e-5


def test_unknown_units_are_named():
    with pytest.raises(ValueError, match="gyro_units"):
        fa.InsEstimator(gyro_units="rpm")
    with pytest.raises(ValueError, match="accel_units"):
        fa.InsEstimator(accel_units="ft/s^2")


def test_euler_is_roll_pitch_yaw_in_degrees():
    estimator = fa.InsEstimator()
    roll = math.radians(20.0)
    estimator.update((0, 0, 0), (0.0, G * math.sin(roll), G * math.cos(roll)), 0.01)  # aligns: 20° roll
    assert estimator.euler == pytest.approx([20.0, 0.0, 0.0], abs=1e-4)


def test_quaternions_are_unit_and_global_differs_from_local_by_a_yaw_only():
    gyro, accel, dt, baro, mag = flight(300)
    result = fa.InsEstimator().update_batch(gyro, accel, dt, baro, mag)
    assert np.allclose(np.linalg.norm(result.quaternion, axis=1), 1.0, atol=1e-6)
    assert np.allclose(result.euler[:, :2], result.global_euler[:, :2], atol=1e-3)


# -- baro timeout and the dead-reckoning horizon ------------------------------------------------------------------

NO_STATIONARY = {"stationary_window": 1000.0}  # a level IMU at rest would otherwise hold v = 0 by itself


def level_steps(seconds, baro, accel_error=0.2, rate=100.0):
    """A level IMU (rad/s, m/s²) whose accelerometer reads ``accel_error`` m/s² too much, with the baro (m)
    at every step (NaN: none)."""
    n = int(round(seconds * rate))
    gyro = np.zeros((n, 3))
    accel = np.tile([0.0, 0.0, G + accel_error], (n, 1))
    return gyro, accel, np.full(n, 1.0 / rate), np.full(n, baro)


def run_level(ins, *segments):
    for seconds, baro in segments:
        gyro, accel, dt, b = level_steps(seconds, baro)
        ins.update_batch(gyro, accel, dt, b)
    return ins


def test_a_baro_silent_for_longer_than_its_timeout_marks_the_ins_not_baro_aided(impl):
    ins = run_level(impl.InsEstimator(impl.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (1.6, math.nan))
    assert ins.baro_timed_out and ins.baro_timeouts == 1 and not ins.height_held


def test_a_baro_silent_for_less_than_its_timeout_is_not_a_timeout(impl):
    ins = run_level(impl.InsEstimator(impl.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (1.4, math.nan))
    assert not ins.baro_timed_out and ins.baro_timeouts == 0


def test_each_baro_silence_longer_than_the_timeout_is_counted_once(impl):
    ins = run_level(impl.InsEstimator(impl.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (10.0, math.nan), (1.0, 0.0))
    assert not ins.baro_timed_out and ins.baro_timeouts == 1
    run_level(ins, (2.0, math.nan))
    assert ins.baro_timed_out and ins.baro_timeouts == 2


def test_beyond_the_horizon_the_ins_stops_dead_reckoning_and_stays_near_the_last_baro_height(impl):
    """A 0.2 m/s² accelerometer error dead-reckoned for 30 s is 90 m; stopped after the 5 s horizon the height
    moves at most |v| × 5 s more: within 10 m, the velocity decayed towards 0."""
    ins = run_level(impl.InsEstimator(impl.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (30.0, math.nan))
    assert ins.height_held and abs(ins.height_above_start) < 10.0 and abs(ins.vertical_velocity) < 0.05


def test_without_the_horizon_the_same_silence_dead_reckons_far(impl):
    ins = run_level(impl.InsEstimator(impl.InsSettings(dead_reckoning_horizon=1e6, **NO_STATIONARY)),
                    (2.0, 0.0), (30.0, math.nan))
    assert not ins.height_held and ins.height_above_start > 50.0


def test_the_height_variance_grows_while_dead_reckoning_is_stopped(impl):
    ins = run_level(impl.InsEstimator(impl.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (6.0, math.nan))
    variances = []
    for _ in range(5):
        run_level(ins, (1.0, math.nan))
        variances.append(ins.covariance[6, 6])
    assert np.all(np.diff(variances) > 0)


def test_the_first_baro_reading_after_the_horizon_sets_the_height_again(impl):
    ins = run_level(impl.InsEstimator(impl.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (30.0, math.nan))
    ins.update(np.zeros(3), [0.0, 0.0, G + 0.2], 0.01, baro_altitude=0.0)
    assert not ins.baro_timed_out and not ins.height_held and abs(ins.height_above_start) < 0.5


def test_baro_timeout_and_horizon_c_equals_the_reference_bit_for_bit():
    c = run_level(fa.InsEstimator(fa.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (30.0, math.nan), (1.0, 0.0))
    r = run_level(reference.InsEstimator(reference.InsSettings(**NO_STATIONARY)), (2.0, 0.0), (30.0, math.nan),
                  (1.0, 0.0))
    assert same_state(c, r)


def _octorotor_with_the_baro_cut_at(seconds):
    """px4_octorotor_2hz_baro.ulg (shared data) with its baro stream ending at ``seconds`` s, as a user saw it."""
    import os
    import warnings
    from pathlib import Path

    from fusion_altitude import logs

    data_dir = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA",
                                   Path(__file__).resolve().parents[1] / ".." / "shared" / "data"))
    assert data_dir.is_dir(), f"shared data not found at {data_dir}: set FUSION_ALTITUDE_SHARED_DATA"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = logs.load_log(str(data_dir / "px4_octorotor_2hz_baro.ulg"))
    data.baro_altitude = np.where(data.time < seconds, data.baro_altitude, np.nan)
    return data


def test_the_ins_on_a_log_whose_baro_stops_holds_the_height_near_the_last_baro_and_says_so():
    """Without the horizon the INS dead-reckons 72 m away from the baro's range within the 80 s left."""
    from fusion_altitude import runner

    data = _octorotor_with_the_baro_cut_at(14.4)
    run = runner.run_log(data, estimator="ins")
    late = data.time > 14.4 + 2.0
    assert np.all(run.estimate.baro_timed_out[late])
    assert np.nanmax(np.abs(run.estimate.altitude[late] - np.nanmedian(data.baro_altitude))) < 10.0
    assert any(w.startswith("INS: the baro timed out 1 time(s)") for w in data.warnings)


def test_a_zero_accel_does_not_align_even_when_the_norm_test_lets_it_through(impl):
    """accel_norm_rejection >= g lets |accel| = 0 pass the norm test; fuzz_ins.c found the NaN attitude that the
    alignment on it made (csrc/fuzz/findings/ins_zero_accel_alignment.bin). It waits for a direction instead."""
    ins = impl.InsEstimator(impl.InsSettings(accel_norm_rejection=9.9))
    ins.update(np.zeros(3), np.zeros(3), 0.01, baro_altitude=10.0)
    assert np.all(np.isfinite(ins.quaternion)) and np.isfinite(ins.covariance).all()
    ins.update(np.zeros(3), [0.0, 0.0, G], 0.01, baro_altitude=10.0)
    ins.update(np.zeros(3), np.zeros(3), 0.01, baro_altitude=10.0)  # aligned: a zero accel is no gravity direction
    assert ins.is_accel_rejected and np.isfinite(ins.covariance).all() and np.all(np.isfinite(ins.quaternion))
