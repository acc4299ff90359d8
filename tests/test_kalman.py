"""The Kalman filter's API for both implementations, the C binding against the
pure-Python reference (bit for bit), and both against FilterPy's KalmanFilter
set up with the same F, B, H, Q, R."""

import copy
import math
import pickle

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter
from hypothesis import given, settings as hypothesis_settings
from hypothesis import strategies as st

import fusion_altitude
import fusion_altitude.reference
from fusion_altitude import KalmanResult, KalmanStatus, _kalman
from fusion_altitude._kalman_glue import KALMAN_SETTINGS as KALMAN_SETTINGS_TABLE

DT = 0.01


@pytest.fixture(params=["c", "reference"])
def impl(request):
    return fusion_altitude if request.param == "c" else fusion_altitude.reference


def bits(array):
    array = np.asarray(array)
    return array.view(np.uint32) if array.dtype == np.float32 else array


def estimator_bits(estimator):
    return (bits(estimator.state).tolist(), bits(estimator.covariance).tolist(),
            bits(np.array(estimator.innovations, dtype=np.float32)).tolist(),
            bits(np.array(estimator.nis, dtype=np.float32)).tolist(), tuple(estimator.rejections),
            tuple(estimator.resets), tuple(estimator.results), estimator.baro_initialised, estimator.gps_initialised)


def faulty_flight(n, seed):
    """All three sensors with every fault the filter handles: a start in the air, range dropouts and
    out-of-range readings, a GPS jump, too few satellites, a reported accuracy, ground effect."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    h = 3 + 2 * np.sin(0.5 * t)
    accel = -0.5 * np.sin(0.5 * t) + 0.1 + rng.normal(0, 0.3, n)
    baro = 150 + h + rng.normal(0, 0.3, n)
    baro[rng.random(n) < 0.3] = np.nan
    baro[n // 2: n // 2 + 5] += 30.0  # a baro glitch
    rangefinder = h + rng.normal(0, 0.03, n)
    rangefinder[::7] = np.nan
    rangefinder[::11] = 20.0  # out of range
    rangefinder[n // 3:] += 1.0  # terrain step
    gps = np.full(n, np.nan)
    gps[::20] = 180 + h[::20] + rng.normal(0, 1.2, n)[::20]
    gps[n // 4:] += 15.0
    satellites = rng.integers(2, 14, n)
    accuracy = np.where(rng.random(n) < 0.3, rng.uniform(0.5, 3.0, n), np.nan)
    ground_effect = t < 1.0
    return accel, baro, rangefinder, gps, satellites, accuracy, ground_effect


# -- reference agreement ---------------------------------------------------------------

@pytest.mark.parametrize("seed", [0, 1, 2])
def test_c_and_reference_agree_bit_for_bit_through_every_fault(seed):
    accel, baro, rangefinder, gps, satellites, accuracy, ground = faulty_flight(1500, seed)
    settings = dict(rejection_timeout=0.3) if seed == 2 else {}
    outputs = []
    estimators = []
    for module in (fusion_altitude, fusion_altitude.reference):
        estimator = module.KalmanEstimator(module.KalmanSettings(**settings))
        outputs.append(estimator.update_batch(accel, baro_altitude=baro, dt=DT, range_distance=rangefinder,
                                              gps_altitude=gps, gps_satellites=satellites,
                                              gps_vertical_accuracy=accuracy, ground_effect=ground))
        estimators.append(estimator)
    for field in outputs[0]._fields:
        assert np.array_equal(bits(getattr(outputs[0], field)), bits(getattr(outputs[1], field))), field
    assert estimator_bits(estimators[0]) == estimator_bits(estimators[1])
    results = outputs[0].result
    for code in (KalmanResult.FUSED, KalmanResult.REJECTED, KalmanResult.RESET, KalmanResult.INITIALISED,
                 KalmanResult.UNUSABLE):
        assert (results == code).any(), code  # every path was taken


def test_batch_equals_per_sample_updates(impl):
    accel, baro, rangefinder, gps, satellites, accuracy, ground = faulty_flight(400, 3)
    batch_estimator = impl.KalmanEstimator()
    result = batch_estimator.update_batch(accel, baro_altitude=baro, dt=DT, range_distance=rangefinder,
                                          gps_altitude=gps, gps_satellites=satellites, gps_vertical_accuracy=accuracy,
                                          ground_effect=ground)
    estimator = impl.KalmanEstimator()
    for i in range(accel.size):
        estimator.update(accel[i], baro_altitude=baro[i], dt=DT, range_distance=rangefinder[i], gps_altitude=gps[i],
                         gps_satellites=int(satellites[i]),
                         gps_vertical_accuracy=None if np.isnan(accuracy[i]) else accuracy[i],
                         ground_effect=bool(ground[i]))
        assert bits(np.float32(estimator.altitude)) == bits(result.altitude[i])
    assert estimator_bits(estimator) == estimator_bits(batch_estimator)


def test_batch_continues_from_the_state_and_splits_anywhere(impl):
    accel, baro, rangefinder, gps, satellites, accuracy, ground = faulty_flight(300, 4)
    whole = impl.KalmanEstimator()
    whole.update_batch(accel, baro_altitude=baro, dt=DT, range_distance=rangefinder, gps_altitude=gps,
                       gps_satellites=satellites, gps_vertical_accuracy=accuracy, ground_effect=ground)
    parts = impl.KalmanEstimator()
    for start, stop in ((0, 17), (17, 200), (200, 300)):
        parts.update_batch(accel[start:stop], baro_altitude=baro[start:stop], dt=DT,
                           range_distance=rangefinder[start:stop], gps_altitude=gps[start:stop],
                           gps_satellites=satellites[start:stop], gps_vertical_accuracy=accuracy[start:stop],
                           ground_effect=ground[start:stop])
    assert estimator_bits(parts) == estimator_bits(whole)


def test_defaults_match_the_header():
    assert fusion_altitude.KalmanSettings().as_dict() == _kalman.c_default_settings()
    assert fusion_altitude.reference.KalmanSettings() == fusion_altitude.KalmanSettings()


def test_status_and_result_enums_match_the_header():
    assert {s.name: int(s) for s in KalmanStatus} == _kalman.C_STATUS_VALUES
    assert {r.name: int(r) for r in KalmanResult} == _kalman.C_RESULT_VALUES
    for status in KalmanStatus:
        assert _kalman.kalman_status_message(status) != "unknown status"


# -- behaviour ------------------------------------------------------------------------

def test_starts_on_the_ground_at_rest_with_unknown_offsets(impl):
    estimator = impl.KalmanEstimator()
    assert estimator.height_above_ground == 0.0 and estimator.vertical_velocity == 0.0
    assert not estimator.baro_initialised and not estimator.gps_initialised
    assert all(math.isnan(v) for v in estimator.innovations)
    estimator.update(0.0, dt=DT, baro_altitude=523.25, gps_altitude=561.5, gps_satellites=12)
    assert estimator.altitude == 523.25 and estimator.baro_offset == 523.25 and estimator.gps_offset == 561.5
    assert estimator.height_above_ground == 0.0
    assert estimator.results == (KalmanResult.INITIALISED, KalmanResult.NO_SAMPLE, KalmanResult.INITIALISED)


def test_covariance_is_a_symmetric_copy(impl):
    estimator = impl.KalmanEstimator()
    estimator.update(0.1, dt=DT, baro_altitude=10.0, range_distance=1.0)
    P = estimator.covariance
    assert P.dtype == np.float32 and P.shape == (5, 5)
    assert np.array_equal(bits(P), bits(P.T))
    P[0, 0] = 1e9
    assert estimator.covariance[0, 0] != 1e9
    assert estimator.altitude_variance == pytest.approx(P[0, 0] * 0 + estimator.covariance[0, 0]
                                                        + 2 * estimator.covariance[0, 2] + estimator.covariance[2, 2],
                                                        rel=1e-6)


def test_gps_satellites_and_accuracy_set_the_gps_noise(impl):
    estimator = impl.KalmanEstimator()
    estimator.update(0.0, dt=DT, baro_altitude=0.0, gps_altitude=0.0, gps_satellites=16)
    estimator.update(0.0, dt=DT, gps_altitude=0.0, gps_satellites=16)
    s16 = estimator.innovation_variances.gps
    estimator.update(0.0, dt=DT, gps_altitude=0.0, gps_satellites=16, gps_vertical_accuracy=4.0)
    assert estimator.innovation_variances.gps > 16.0
    estimator.update(0.0, dt=DT, gps_altitude=0.0, gps_satellites=3)
    assert estimator.results.gps == KalmanResult.UNUSABLE
    assert 2 * 1.25 ** 2 < s16 < 2 * 1.25 ** 2 + 0.1  # S = P_hh + P_og + R with P_og = P_hh + R just after the first sample


def test_bias_estimation_can_be_turned_off(impl):
    settings = impl.KalmanSettings(estimate_accel_bias=False)
    estimator = impl.KalmanEstimator(settings)
    for _ in range(500):
        estimator.update(0.2, dt=DT, baro_altitude=5.0, range_distance=1.0)
    assert estimator.accel_bias == 0.0
    assert not estimator.covariance[4].any()
    estimator.settings = settings.replace(estimate_accel_bias=True)
    assert estimator.covariance[4, 4] == pytest.approx(0.04)


def test_copy_and_pickle_round_trip(impl):
    accel, baro, rangefinder, gps, satellites, accuracy, ground = faulty_flight(300, 5)
    estimator = impl.KalmanEstimator(impl.KalmanSettings(gate=4.0))
    estimator.update_batch(accel[:150], baro_altitude=baro[:150], dt=DT, range_distance=rangefinder[:150],
                           gps_altitude=gps[:150], gps_satellites=satellites[:150])
    clones = [copy.copy(estimator), copy.deepcopy(estimator), pickle.loads(pickle.dumps(estimator))]
    for clone in clones:
        assert estimator_bits(clone) == estimator_bits(estimator)
        assert clone.settings == estimator.settings
    estimator.update_batch(accel[150:], baro_altitude=baro[150:], dt=DT, range_distance=rangefinder[150:],
                           gps_altitude=gps[150:], gps_satellites=satellites[150:])
    for clone in clones:
        clone.update_batch(accel[150:], baro_altitude=baro[150:], dt=DT, range_distance=rangefinder[150:],
                           gps_altitude=gps[150:], gps_satellites=satellites[150:])
        assert estimator_bits(clone) == estimator_bits(estimator)
    settings = pickle.loads(pickle.dumps(estimator.settings))
    assert settings == estimator.settings and hash(settings) == hash(estimator.settings)


# -- bad input ---------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, message", [
    (dict(accel=math.nan), r"^accel must be finite"),
    (dict(dt=0.0), r"^dt must be finite and > 0"),
    (dict(dt=-1.0), r"^dt must be finite and > 0"),
    (dict(baro_altitude=math.inf), r"^baro_altitude must be finite"),
    (dict(gps_altitude=-math.inf), r"^gps_altitude must be finite"),
    (dict(gps_altitude=10.0, gps_vertical_accuracy=0.0), r"^gps_vertical_accuracy must be finite and > 0"),
])
def test_bad_update_raises_naming_the_argument_and_leaves_the_state(impl, kwargs, message):
    estimator = impl.KalmanEstimator()
    accel, baro, rangefinder, gps, satellites, accuracy, ground = faulty_flight(200, 6)
    estimator.update_batch(accel, baro_altitude=baro, dt=DT, range_distance=rangefinder, gps_altitude=gps,
                           gps_satellites=satellites, gps_vertical_accuracy=accuracy, ground_effect=ground)
    before = estimator_bits(estimator)
    arguments = dict(accel=0.0, dt=DT, baro_altitude=1.0)
    arguments.update(kwargs)
    with pytest.raises(ValueError, match=message):
        estimator.update(**arguments)
    assert estimator_bits(estimator) == before


def test_bad_batch_names_the_first_bad_index_and_applies_nothing(impl):
    accel, baro, rangefinder, gps, satellites, accuracy, ground = faulty_flight(300, 7)
    estimator = impl.KalmanEstimator()
    before = estimator_bits(estimator)
    gps[250] = np.inf
    with pytest.raises(ValueError, match=r"^gps_altitude\[250\] must be finite"):
        estimator.update_batch(accel, baro_altitude=baro, dt=DT, range_distance=rangefinder, gps_altitude=gps,
                               gps_satellites=satellites, gps_vertical_accuracy=accuracy, ground_effect=ground)
    assert estimator_bits(estimator) == before
    dt = np.full(300, DT, dtype=np.float32)
    dt[7] = 0.0
    with pytest.raises(ValueError, match=r"^dt\[7\] must be finite"):
        estimator.update_batch(accel, dt=dt)
    with pytest.raises(ValueError, match=r"^dt must be finite"):
        estimator.update_batch(accel, dt=-1.0)
    with pytest.raises(ValueError, match="baro_altitude has 3 samples but accel has 300"):
        estimator.update_batch(accel, dt=DT, baro_altitude=[1.0, 2.0, 3.0])
    with pytest.raises(TypeError, match="accel"):
        estimator.update_batch(["a"] * 3, dt=DT)
    assert estimator_bits(estimator) == before


@pytest.mark.parametrize("kwargs, message", [
    (dict(baro_noise=0.0), r"^baro_noise must be finite and > 0"),
    (dict(accel_noise=-1.0), r"^accel_noise must be finite and >= 0"),
    (dict(range_min=5.0, range_max=2.0), r"^range_max must be finite and > range_min"),
    (dict(gps_noise_base=0.0, gps_noise_satellite=0.0), r"gps_noise_base \+ gps_noise_satellite must be > 0"),
    (dict(gps_min_satellites=-1), r"^gps_min_satellites must be finite and >= 0"),
    (dict(gate=math.nan), r"^gate must be finite and > 0"),
    (dict(ground_effect_noise_scale=0.5), r"^ground_effect_noise_scale must be finite and >= 1"),
    # finite but so large that its square would overflow float32 (found by fuzzing)
    (dict(baro_noise=2.7e36), r"^baro_noise must be finite and <= 1e\+06"),
    (dict(baro_noise=1e5, ground_effect_noise_scale=100.0), r"^baro_noise \* ground_effect_noise_scale must be <="),
])
def test_bad_settings_raise_naming_the_field(impl, kwargs, message):
    with pytest.raises(ValueError, match=message):
        impl.KalmanSettings(**kwargs)


def test_unknown_or_mistyped_settings_raise_type_error(impl):
    with pytest.raises(TypeError, match="unknown Kalman setting"):
        impl.KalmanSettings(baro_sigma=1.0)
    with pytest.raises(TypeError, match="estimate_accel_bias must be a bool"):
        impl.KalmanSettings(estimate_accel_bias=1)
    with pytest.raises(TypeError, match="accel must be a real number"):
        impl.KalmanEstimator().update("x", dt=DT)


# -- against FilterPy ------------------------------------------------------------------

def filterpy_model(settings, dt):
    s = settings
    F = np.eye(5)
    F[0, 1] = dt
    F[0, 4] = -dt * dt / 2
    F[1, 4] = -dt
    B = np.array([[dt * dt / 2], [dt], [0.0], [0.0], [0.0]])
    Q = (s.accel_noise ** 2 / dt) * (B @ B.T) + dt * np.diag(
        [0.0, 0.0, s.baro_offset_random_walk ** 2, s.gps_offset_random_walk ** 2, s.accel_bias_random_walk ** 2])
    H = {"baro": np.array([[1.0, 0, 1, 0, 0]]), "range": np.array([[1.0, 0, 0, 0, 0]]),
         "gps": np.array([[1.0, 0, 0, 1, 0]])}
    return F, B, Q, H


def run_filterpy(settings, accel, baro, rangefinder, gps, satellites):
    """FilterPy's KalmanFilter (float64, Joseph-form update) on the same model; the unknown offsets get a
    1e8 m² prior, which the C filter's exact infinite-prior initialisation equals to ~1e-9 relative."""
    s = settings
    F, B, Q, H = filterpy_model(s, DT)
    kf = KalmanFilter(dim_x=5, dim_z=1, dim_u=1)
    kf.F, kf.B, kf.Q = F, B, Q
    kf.x = np.zeros((5, 1))
    kf.P = np.diag([s.initial_height_sigma ** 2, s.initial_velocity_sigma ** 2, 1e8, 1e8,
                    s.accel_bias_initial_sigma ** 2])
    states, variances = [], []
    for i in range(accel.size):
        kf.predict(u=np.array([[accel[i]]]))
        if not np.isnan(baro[i]):
            kf.update(np.array([[baro[i]]]), R=s.baro_noise ** 2, H=H["baro"])
        if not np.isnan(rangefinder[i]):
            kf.update(np.array([[rangefinder[i]]]), R=s.range_noise ** 2, H=H["range"])
        if not np.isnan(gps[i]):
            sigma = s.gps_noise_base + s.gps_noise_satellite / math.sqrt(satellites[i])
            kf.update(np.array([[gps[i]]]), R=sigma ** 2, H=H["gps"])
        states.append(kf.x[:, 0].copy())
        variances.append(np.diag(kf.P).copy())
    return np.array(states), np.array(variances)


def clean_flight(n, seed):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    h = 3 + 2 * np.sin(0.4 * t)
    accel = (-0.32 * np.sin(0.4 * t) + 0.1 + rng.normal(0, 0.3, n)).astype(np.float32)
    baro = (250 + h + rng.normal(0, 0.4, n)).astype(np.float32)
    rangefinder = np.where(np.arange(n) % 5 == 0, h + rng.normal(0, 0.04, n), np.nan).astype(np.float32)
    gps = np.where(np.arange(n) % 20 == 0, 290 + h + rng.normal(0, 1.2, n), np.nan).astype(np.float32)
    satellites = np.full(n, 9, dtype=np.int32)
    return accel, baro, rangefinder, gps, satellites


def test_c_and_reference_match_filterpy_on_the_same_model(impl):
    """float32 (ours) against float64 (FilterPy) over 20 s with all three sensors. Measured: h, v and b
    within 7e-6 (m, m/s, m/s²); the offsets (250-290 m, where one float32 ulp is 3.05e-5 m) within
    2.2e-4 m, 7.5e-7 relative (about 7 ulp); variances within 1.7e-5 relative; asserted with 3-6x margin. The float32 rounding of each
    step (relative 6e-8) accumulates through the filter's memory, which is the bound's origin."""
    n = 2000 if impl is fusion_altitude else 600
    accel, baro, rangefinder, gps, satellites = clean_flight(n, 8)
    settings = impl.KalmanSettings(gate=1e3)
    result = impl.KalmanEstimator(settings).update_batch(accel, baro_altitude=baro, dt=DT, range_distance=rangefinder,
                                                         gps_altitude=gps, gps_satellites=satellites)
    states, variances = run_filterpy(settings, accel.astype(np.float64), baro.astype(np.float64),
                                     rangefinder.astype(np.float64), gps.astype(np.float64), satellites)
    ours = np.stack([result.height_above_ground, result.vertical_velocity, result.baro_offset, result.gps_offset,
                     result.accel_bias], axis=1).astype(np.float64)
    state_error = np.abs(ours - states)
    assert state_error[:, [0, 1, 4]].max() < 2e-5, state_error.max(axis=0)
    assert (state_error[:, 2:4] / np.abs(states[:, 2:4])).max() < 2e-6, state_error.max(axis=0)
    variance_error = np.abs(result.covariance_diagonal.astype(np.float64) - variances) / variances
    assert variance_error.max() < 1e-4, variance_error.max(axis=0)  # measured 1.7e-5


def test_batch_writes_into_preallocated_out_arrays(impl):
    rng = np.random.default_rng(8)
    n = 300
    accel, baro = rng.normal(0, 0.5, n), 100 + rng.normal(0, 0.3, n)
    out = fusion_altitude._kalman_glue.new_kalman_batch(n)
    result = impl.KalmanEstimator().update_batch(accel, dt=0.01, baro_altitude=baro, out=out)
    assert all(r is o for r, o in zip(result, out))
    fresh = impl.KalmanEstimator().update_batch(accel, dt=0.01, baro_altitude=baro)
    for field in fresh._fields:
        assert np.array_equal(getattr(fresh, field).view(np.uint8), getattr(out, field).view(np.uint8)), field
    with pytest.raises(ValueError, match=r"out.covariance_diagonal must be a writeable contiguous float32 array"):
        impl.KalmanEstimator().update_batch(accel, dt=0.01, baro_altitude=baro,
                                            out=out._replace(covariance_diagonal=np.empty((n, 4), np.float32)))


SATELLITE_VALUES = [None, 0, 3, 9, 12, -1, -5, 2**31 - 1, 2**31, 2**40, -2**40, 9.0, 9.5, math.nan, True,
                    np.int64(8), np.int32(5), np.float32(7.0), np.bool_(True), "9", 9 + 0j]
ACCURACY_VALUES = [None, 1.5, 0.0, -1.0, math.nan, math.inf, 2, np.float32(2.5), "x"]


def _per_sample_outcome(estimator, **keywords):
    try:
        estimator.update(0.1, baro_altitude=300.0, dt=DT, gps_altitude=320.0, **keywords)
        outcome = "ok"
    except (TypeError, ValueError) as error:
        outcome = (type(error).__name__, str(error))
    return outcome, estimator_bits(estimator)


@pytest.mark.parametrize("keyword, values", [("gps_satellites", SATELLITE_VALUES),
                                             ("gps_vertical_accuracy", ACCURACY_VALUES),
                                             ("ground_effect", [False, True, None, 0, 1, "", "x", np.bool_(True)])])
def test_per_sample_gps_and_ground_effect_arguments_match_the_reference(keyword, values):
    """The binding converts these in Cython (a plain int, None and float without a Python call), the
    reference in Python: the same state, or the same error naming the argument, for every kind of value."""
    c, reference = fusion_altitude.KalmanEstimator(), fusion_altitude.reference.KalmanEstimator()
    for value in values:
        assert _per_sample_outcome(c, **{keyword: value}) == _per_sample_outcome(reference, **{keyword: value}), value


# --- Sensor timeouts ----------------------------------------------------------------------------------------------


def _baro_and_gps_then(impl, baro_after, gps_after, seconds=3.0, settings=None):
    """2 s of baro and GPS at 10 m (100 Hz, at rest), then ``seconds`` s with the given baro and GPS (NaN: none)."""
    estimator = impl.KalmanEstimator(settings)
    n, m = 200, int(round(100 * seconds))
    baro = np.r_[np.full(n, 10.0), np.full(m, baro_after)]
    gps = np.r_[np.full(n, 10.0), np.full(m, gps_after)]
    return estimator, estimator.update_batch(np.zeros(n + m), dt=0.01, baro_altitude=baro, gps_altitude=gps)


def test_a_baro_silent_for_longer_than_its_timeout_is_flagged(impl):
    estimator, _ = _baro_and_gps_then(impl, math.nan, 10.0, seconds=1.6)  # default baro_timeout 1.5 s
    assert estimator.baro_timed_out and not estimator.gps_timed_out


def test_a_baro_silent_for_less_than_its_timeout_is_not_flagged(impl):
    estimator, _ = _baro_and_gps_then(impl, math.nan, 10.0, seconds=1.4)
    assert not estimator.baro_timed_out and estimator.timeout_counts.baro == 0


def test_each_sensor_silence_longer_than_its_timeout_is_counted_once(impl):
    estimator, _ = _baro_and_gps_then(impl, math.nan, 10.0, seconds=5.0)
    assert estimator.timeout_counts == (1, 0, 0)
    estimator.update_batch(np.zeros(100), dt=0.01, baro_altitude=10.0, gps_altitude=10.0)
    assert not estimator.baro_timed_out and estimator.timeout_counts.baro == 1
    estimator.update_batch(np.zeros(200), dt=0.01, baro_altitude=math.nan, gps_altitude=10.0)
    assert estimator.baro_timed_out and estimator.timeout_counts.baro == 2


def test_a_sensor_never_sampled_is_not_timed_out(impl):
    estimator, _ = _baro_and_gps_then(impl, math.nan, 10.0, seconds=5.0)
    assert not estimator.range_timed_out and estimator.timeout_counts.range == 0


def test_gps_fixes_with_too_few_satellites_time_the_gps_out(impl):
    estimator = impl.KalmanEstimator()
    estimator.update_batch(np.zeros(100), dt=0.01, baro_altitude=10.0, gps_altitude=10.0, gps_satellites=10)
    estimator.update_batch(np.zeros(300), dt=0.01, baro_altitude=10.0, gps_altitude=10.0, gps_satellites=2)
    assert estimator.gps_timed_out and estimator.timeout_counts.gps == 1


def test_the_gps_carries_the_altitude_when_the_baro_times_out(impl):
    estimator = impl.KalmanEstimator()
    n, m = 200, 1000
    baro = np.r_[np.full(n, 10.0), np.full(m, math.nan)]
    gps = np.r_[np.full(n, 10.0), np.linspace(10.0, 15.0, m)]  # a 5 m climb at 0.5 m/s after the baro stopped
    accel = np.zeros(n + m)
    out = estimator.update_batch(accel, dt=0.01, baro_altitude=baro, gps_altitude=gps)
    assert estimator.baro_timed_out and not estimator.gps_timed_out
    assert abs(out.altitude[-1] - 15.0) < 0.5


def test_a_baro_back_after_a_silence_nothing_bridged_pulls_the_altitude_back_at_once(impl):
    """30 s with no height sensor and a 0.3 m/s² accelerometer error: dead reckoning drifts ~135 m; the baro's
    first sample after its timeout is fused with h and v inflated over the silence, not rejected."""
    estimator = impl.KalmanEstimator(impl.KalmanSettings(estimate_accel_bias=False))
    estimator.update_batch(np.zeros(200), dt=0.01, baro_altitude=10.0)
    estimator.update_batch(np.full(3000, 0.3), dt=0.01, baro_altitude=math.nan)
    assert estimator.baro_timed_out and abs(estimator.altitude - 10.0) > 100.0
    estimator.update(0.3, baro_altitude=10.0, dt=0.01)
    assert estimator.results.baro == KalmanResult.FUSED and abs(estimator.altitude - 10.0) < 1.0
    assert not estimator.baro_timed_out


def test_a_baro_back_while_the_gps_bridged_its_silence_is_gated_as_usual(impl):
    estimator, _ = _baro_and_gps_then(impl, math.nan, 10.0, seconds=5.0)
    velocity_variance = estimator.covariance[1, 1]  # the GPS vouched for the state: no inflation (+100 m²/s²)
    estimator.update(0.0, baro_altitude=10.0, dt=0.01, gps_altitude=10.0)
    assert estimator.results.baro == KalmanResult.FUSED and estimator.covariance[1, 1] <= velocity_variance


@pytest.mark.parametrize("name", ["baro_timeout", "range_timeout", "gps_timeout"])
@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan, 2e6])
def test_a_sensor_timeout_not_in_0_to_1e6_is_rejected_naming_it(impl, name, bad):
    with pytest.raises(ValueError, match=f"^{name} must be finite"):
        impl.KalmanSettings(**{name: bad})


def test_the_kalman_filter_on_a_log_whose_baro_stops_carries_on_with_the_gps_and_says_so():
    import os
    import warnings
    from pathlib import Path

    from fusion_altitude import logs, runner

    data_dir = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA",
                                   Path(__file__).resolve().parents[1] / ".." / "shared" / "data"))
    assert data_dir.is_dir(), f"shared data not found at {data_dir}: set FUSION_ALTITUDE_SHARED_DATA"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = logs.load_log(str(data_dir / "px4_octorotor_2hz_baro.ulg"))
    data.baro_altitude = np.where(data.time < 14.4, data.baro_altitude, np.nan)
    run = runner.run_log(data, estimator="kalman")
    assert np.all(np.isfinite(run.estimate.altitude))
    assert "kalman: the baro timed out 1 time(s) (no sample for > 1.5 s): the altitude there is carried by the GPS" \
        in data.warnings


@hypothesis_settings(max_examples=300, deadline=None)
@given(changes=st.dictionaries(st.sampled_from([name for name, *_ in KALMAN_SETTINGS_TABLE if name != "estimate_accel_bias"
                                                and name != "gps_min_satellites"]),
                               st.floats(-10.0, 2e6, width=32) | st.sampled_from([0.0, math.inf, -math.inf, math.nan]),
                               max_size=4))
def test_the_reference_twin_of_the_settings_check_equals_the_c_function(changes):
    from fusion_altitude.reference import kalman as reference_kalman

    values = {name: default for name, default, *_ in KALMAN_SETTINGS_TABLE}
    values.update(changes)
    assert int(reference_kalman._check(values)) == _kalman.c_settings_check(values)


def test_kalman_settings_check_with_the_c_function_once_the_binding_is_imported():
    from fusion_altitude import _kalman_glue

    assert _kalman_glue.C_SETTINGS_FUNCTIONS["check"] is _kalman.c_settings_check
