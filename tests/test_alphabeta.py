"""Quality-weighted alpha-beta fusion (seed 003): C binding vs reference bit for bit, the write-up's
behaviours (a sensor beyond its gap maximum is dropped and recovered; quality rises and falls; band;
least-squares gains), batch, state and bad input."""

import copy
import math
import pickle
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import fusion_altitude as c
import fusion_altitude.reference as ref
from fusion_altitude import _alphabeta
from fusion_altitude._alphabeta_glue import ALPHABETA_DEFAULTS, AlphaBetaSensorSettings

NAN = math.nan


def floats32(low, high):
    return st.floats(float(np.float32(low)), float(np.float32(high)), width=32)


def state_bits(fusion):
    values, filters, h, v, total, coasting, gap_time, gap_count, started = fusion._get_state()
    bits = lambda x: int(np.float32(x).view(np.uint32))  # noqa: E731
    return (values, tuple((bits(x), bits(vi), bits(s), bits(i), bits(g), bits(w), q, n, st_, to)
                          for x, vi, s, i, g, w, q, n, st_, to in filters),
            bits(h), bits(v), bits(total), started, bits(coasting), bits(gap_time), gap_count)


sample = st.one_of(floats32(-20, 60), st.just(NAN))
step = st.one_of(
    st.tuples(st.just("update"), st.one_of(floats32(-20, 20), st.just(NAN)), floats32(1e-3, 0.3),
              sample, sample, sample, sample),
    st.tuples(st.just("update"), st.one_of(floats32(-20, 20), st.just(NAN)), floats32(1e-3, 0.3),
              sample, sample, sample, sample),
    st.tuples(st.just("settings"), st.sampled_from(["imu", "baro", "lidar", "sonar", "gps"]), floats32(0.1, 5),
              st.integers(2, 6), st.integers(0, 40), floats32(0, 10), floats32(0.5, 30), floats32(0.05, 2)),
    st.tuples(st.just("bad"), st.sampled_from([
        {"accel": math.inf, "dt": 0.01}, {"accel": 0.0, "dt": 0.0}, {"accel": 0.0, "dt": NAN},
        {"accel": 0.0, "dt": 0.01, "baro_altitude": math.inf}, {"accel": 0.0, "dt": 0.01, "gps_altitude": -math.inf},
        {"accel": 0.0, "dt": 0.01, "lidar_altitude": math.inf}, {"accel": 0.0, "dt": 0.01, "sonar_altitude": math.inf}])),
)


def apply(module, fusion, operation):
    kind = operation[0]
    try:
        if kind == "update":
            accel, dt, baro, lidar, sonar, gps = operation[1:]
            fusion.update(accel, baro_altitude=baro, dt=dt, lidar_altitude=lidar, sonar_altitude=sonar,
                          gps_altitude=gps)
        elif kind == "settings":
            sensor, threshold, qmin, extra, confidence, gap, timeout = operation[1:]
            fusion.settings = module.AlphaBetaSettings(**{sensor: {
                "threshold": threshold, "quality_min": qmin, "quality_max": qmin + extra, "confidence": confidence,
                "gap_max": gap, "timeout": timeout}})
        else:
            fusion.update(**operation[1])
    except ValueError as error:
        return str(error).split(" ")[0]
    return None


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(operations=st.lists(step, min_size=1, max_size=120))
def test_c_and_reference_agree_bit_for_bit(operations):
    fast, slow = c.AlphaBetaFusion(), ref.AlphaBetaFusion()
    for operation in operations:
        assert apply(c, fast, operation) == apply(ref, slow, operation)
        assert state_bits(fast) == state_bits(slow)


def flight(n=3000, seed=2):
    """100 Hz hop to 6 m: IMU every step, baro 50 Hz, lidar 20 Hz (to 40 m), sonar 10 Hz, GPS 5 Hz with a 30 m jump."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    h = 3 - 3 * np.cos(0.2 * t)
    accel = 0.6 * np.cos(0.2 * t) + rng.normal(0, 0.2, n)
    every = lambda k: np.arange(n) % k == 0  # noqa: E731
    baro = np.where(every(2), h + rng.normal(0, 0.3, n), NAN)
    lidar = np.where(every(5), h + rng.normal(0, 0.05, n), NAN)
    sonar = np.where(every(10) & (h < 5), h + rng.normal(0, 0.05, n), NAN)
    gps = np.where(every(20), h + rng.normal(0, 1.5, n), NAN)
    gps[(t > 12) & (t < 16)] += 30.0
    accel[rng.random(n) < 0.02] = NAN
    return accel, baro, lidar, sonar, gps, h, t


def test_batch_on_a_flight_agrees_bit_for_bit_and_equals_per_sample_updates():
    accel, baro, lidar, sonar, gps, *_ = flight(1500)
    fast, slow, single = c.AlphaBetaFusion(), ref.AlphaBetaFusion(), c.AlphaBetaFusion()
    a = fast.update_batch(accel, baro_altitude=baro, dt=0.01, lidar_altitude=lidar, sonar_altitude=sonar,
                          gps_altitude=gps)
    b = slow.update_batch(accel, baro_altitude=baro, dt=np.full(accel.size, 0.01), lidar_altitude=lidar,
                          sonar_altitude=sonar, gps_altitude=gps)
    for field in a._fields:
        assert np.array_equal(getattr(a, field).view(np.uint32), getattr(b, field).view(np.uint32)), field
    for i in range(accel.size):
        single.update(accel[i], baro_altitude=baro[i], dt=0.01, lidar_altitude=lidar[i], sonar_altitude=sonar[i],
                      gps_altitude=gps[i])
    assert state_bits(single) == state_bits(fast) == state_bits(slow)


def test_batch_splits_anywhere(impl):
    accel, baro, lidar, sonar, gps, *_ = flight(600)
    whole, parts = impl.AlphaBetaFusion(), impl.AlphaBetaFusion()
    expected = whole.update_batch(accel, baro_altitude=baro, dt=0.01, lidar_altitude=lidar, sonar_altitude=sonar,
                                  gps_altitude=gps)
    first = parts.update_batch(accel[:250], baro_altitude=baro[:250], dt=0.01, lidar_altitude=lidar[:250],
                               sonar_altitude=sonar[:250], gps_altitude=gps[:250])
    second = parts.update_batch(accel[250:], baro_altitude=baro[250:], dt=0.01, lidar_altitude=lidar[250:],
                                sonar_altitude=sonar[250:], gps_altitude=gps[250:])
    assert np.array_equal(np.concatenate([first.altitude, second.altitude]), expected.altitude)


def test_defaults_enums_and_gains_match_the_header():
    assert _alphabeta.c_default_settings() == ALPHABETA_DEFAULTS == c.AlphaBetaSettings().as_dict() \
        == ref.AlphaBetaSettings().as_dict()
    assert {s.name: s.value for s in c.AlphaBetaStatus} == _alphabeta.C_STATUS_VALUES
    for q in (2, 3, 10, 60, 120):
        assert _alphabeta.gains(q) == tuple(float(x) for x in ref.alphabeta.gains(q))
        alpha, beta = _alphabeta.gains(q)
        assert alpha == pytest.approx(2 * (2 * q - 1) / (q * (q + 1)), rel=1e-6)
        assert beta == pytest.approx(6 / (q * (q + 1)), rel=1e-6)


@pytest.mark.parametrize("q", [2, 3, 5, 10, 60])
def test_gains_are_the_least_squares_line_through_the_last_q_samples(q):
    """Started on Q samples of a noisy line, one more sample moves the filter to the least-squares fit."""
    rng = np.random.default_rng(q)
    y = 1.0 + 0.3 * np.arange(q + 40) + rng.normal(0, 0.5, q + 40)
    # Growing-memory filter: gains of depth n = 1, 2, ... equal the least-squares line fit of the first n samples.
    x, v = y[0], 0.0
    for n in range(2, q + 1):
        alpha, beta = ref.alphabeta.gains(n)
        x_pred = x + v
        r = y[n - 1] - x_pred
        x, v = x_pred + float(alpha) * r, v + float(beta) * r
    slope, intercept = np.polyfit(np.arange(q), y[:q], 1)
    assert x == pytest.approx(intercept + slope * (q - 1), abs=1e-4)
    assert v == pytest.approx(slope, abs=1e-4)


def test_a_sensor_beyond_its_gap_maximum_is_dropped_and_recovered(impl):
    """The write-up's claim: a lidar glitching by 10 m (> its 6 m maximum) loses its weight, and gets it back."""
    n = 300
    lidar = np.full(3 * n, 5.0)
    lidar[n:2 * n] = 15.0
    fusion = impl.AlphaBetaFusion()
    out = fusion.update_batch(np.zeros(3 * n), dt=0.01, baro_altitude=5.0, lidar_altitude=lidar)
    lidar_weight = out.weight[:, 2]
    assert lidar_weight[n - 1] == 80.0  # Q 8 · confidence 10
    dropped = np.flatnonzero(lidar_weight[n:2 * n] == 0.0)
    assert dropped.size and dropped[0] < 10  # within 0.1 s of the glitch
    assert np.all(lidar_weight[n + dropped[0]:2 * n] == 0.0)
    assert np.max(np.abs(out.altitude[n + dropped[0]:2 * n] - 5.0)) < 3.0
    assert abs(out.altitude[2 * n - 1] - 5.0) < 0.05
    assert np.all(lidar_weight[2 * n + 20:] > 0)  # recovered
    assert lidar_weight[-1] == 80.0 and abs(out.altitude[-1] - 5.0) < 1e-3


def test_quality_rises_while_agreeing_and_falls_otherwise(impl):
    fusion = impl.AlphaBetaFusion()
    out = fusion.update_batch(np.zeros(100), dt=0.01, baro_altitude=np.r_[np.zeros(80), np.full(20, 3.0)])
    baro_quality = out.quality[:, 1]
    assert baro_quality[0] == 10 and baro_quality[50] == 60  # +1 per agreeing sample, capped at Q max
    assert baro_quality[80] == 59 and baro_quality[81] == 58  # -1 per disagreeing one
    assert out.quality[-1, 0] == 4  # the IMU channel agrees with its own prediction


def test_sensors_outside_their_altitude_band_get_no_weight(impl):
    fusion = impl.AlphaBetaFusion()
    out = fusion.update_batch(np.zeros(50), dt=0.01, baro_altitude=8.0, sonar_altitude=8.0, lidar_altitude=8.0)
    assert out.weight[-1, 3] == 0.0 and out.weight[-1, 2] > 0  # sonar band 0..5 m, lidar 0..40 m
    fusion = impl.AlphaBetaFusion(impl.AlphaBetaSettings(sonar={"altitude_max": 10.0}))
    out = fusion.update_batch(np.zeros(50), dt=0.01, baro_altitude=8.0, sonar_altitude=8.0)
    assert out.weight[-1, 3] > 0


def test_tracks_a_multi_sensor_flight_and_rides_out_a_gps_jump():
    accel, baro, lidar, sonar, gps, h, t = flight()
    out = c.AlphaBetaFusion().update_batch(accel, baro_altitude=baro, dt=0.01, lidar_altitude=lidar,
                                           sonar_altitude=sonar, gps_altitude=gps)
    error = out.altitude - h
    assert np.sqrt(np.mean(error[t > 2] ** 2)) < 0.3
    jump = (t > 12.5) & (t < 16)
    assert np.all(out.weight[jump & ~np.isnan(gps), 4] == 0.0)  # GPS 30 m off: beyond its 20 m gap maximum


def test_nan_is_no_sample_for_every_sensor_including_the_imu(impl):
    fusion = impl.AlphaBetaFusion()
    fusion.update(NAN, dt=0.01)
    assert not fusion.started
    fusion.update(NAN, dt=0.01, gps_altitude=12.0)
    assert fusion.started and fusion.altitude == 12.0
    fusion.update(NAN, dt=0.01)
    assert fusion.weights.imu == 0.0 and fusion.weights.gps > 0


def test_copy_and_pickle_round_trip(impl):
    accel, baro, lidar, sonar, gps, *_ = flight(600)
    fusion = impl.AlphaBetaFusion(impl.AlphaBetaSettings(gps={"gap_max": 30.0}))
    fusion.update_batch(accel[:300], baro_altitude=baro[:300], dt=0.01, lidar_altitude=lidar[:300],
                        sonar_altitude=sonar[:300], gps_altitude=gps[:300])
    for clone in (copy.copy(fusion), copy.deepcopy(fusion), pickle.loads(pickle.dumps(fusion))):
        assert state_bits(clone) == state_bits(fusion)
        a = clone.update_batch(accel[300:], baro_altitude=baro[300:], dt=0.01, lidar_altitude=lidar[300:],
                               sonar_altitude=sonar[300:], gps_altitude=gps[300:])
    b = fusion.update_batch(accel[300:], baro_altitude=baro[300:], dt=0.01, lidar_altitude=lidar[300:],
                            sonar_altitude=sonar[300:], gps_altitude=gps[300:])
    assert np.array_equal(a.altitude, b.altitude)
    assert pickle.loads(pickle.dumps(fusion.settings)) == fusion.settings


@pytest.mark.parametrize("kwargs, message", [
    ({"accel": math.inf, "dt": 0.01}, "accel must be finite, or NaN"),
    ({"accel": 0.0, "dt": 0.0}, "dt must be finite and > 0"),
    ({"accel": 0.0, "dt": math.nan}, "dt must be finite and > 0"),
    ({"accel": 0.0, "dt": 0.01, "baro_altitude": math.inf}, "baro_altitude must be finite, or NaN"),
    ({"accel": 0.0, "dt": 0.01, "lidar_altitude": -math.inf}, "lidar_altitude must be finite, or NaN"),
    ({"accel": 0.0, "dt": 0.01, "sonar_altitude": math.inf}, "sonar_altitude must be finite, or NaN"),
    ({"accel": 0.0, "dt": 0.01, "gps_altitude": math.inf}, "gps_altitude must be finite, or NaN"),
])
def test_bad_update_raises_naming_the_argument_and_leaves_the_state(impl, kwargs, message):
    fusion = impl.AlphaBetaFusion()
    accel, baro, lidar, sonar, gps = flight(200)[:5]
    fusion.update_batch(accel, baro_altitude=baro, dt=0.01, lidar_altitude=lidar, sonar_altitude=sonar,
                        gps_altitude=gps)
    before = state_bits(fusion)
    with pytest.raises(ValueError, match="^" + re.escape(message)):
        fusion.update(**kwargs)
    assert state_bits(fusion) == before


def test_bad_batch_names_the_first_bad_index_and_applies_nothing(impl):
    accel, baro, lidar, sonar, gps, *_ = flight(300)
    fusion = impl.AlphaBetaFusion()
    fusion.update_batch(accel[:100], baro_altitude=baro[:100], dt=0.01, lidar_altitude=lidar[:100],
                        sonar_altitude=sonar[:100], gps_altitude=gps[:100])
    before = state_bits(fusion)
    bad = gps.copy()
    bad[[77, 99]] = np.inf
    with pytest.raises(ValueError, match=r"^gps_altitude\[77\] must be finite"):
        fusion.update_batch(accel, baro_altitude=baro, dt=0.01, lidar_altitude=lidar, sonar_altitude=sonar,
                            gps_altitude=bad)
    bad = accel.copy()
    bad[5] = -np.inf
    with pytest.raises(ValueError, match=r"^accel\[5\] must be finite"):
        fusion.update_batch(bad, baro_altitude=baro, dt=0.01, lidar_altitude=lidar, sonar_altitude=sonar,
                            gps_altitude=gps)
    with pytest.raises(ValueError, match=r"^baro_altitude must be finite"):
        fusion.update_batch(accel, baro_altitude=np.inf, dt=0.01)
    with pytest.raises(ValueError, match=r"^dt must be finite and > 0"):
        fusion.update_batch(accel, baro_altitude=baro, dt=0.0)
    with pytest.raises(ValueError, match="lidar_altitude has 299 samples but accel has 300"):
        fusion.update_batch(accel, baro_altitude=baro, dt=0.01, lidar_altitude=lidar[:-1])
    with pytest.raises(TypeError, match="dt must be a real number or an array"):
        fusion.update_batch(accel, baro_altitude=baro, dt=None)
    with pytest.raises(TypeError, match="gps_altitude must be a real number"):
        fusion.update(0.0, dt=0.01, gps_altitude="high")
    assert state_bits(fusion) == before


@pytest.mark.parametrize("kwargs, message", [
    ({"gps": {"threshold": 0.0}}, r"^gps\.threshold must be finite and > 0"),
    ({"baro": {"quality_min": 1}}, r"^baro\.quality_min must be >= 2"),
    ({"baro": {"quality_max": 9}}, r"^baro\.quality_max must be in \[quality_min, 10000\]"),
    ({"imu": {"confidence": -1.0}}, r"^imu\.confidence must be finite and in \[0, 1e6\]"),
    ({"gps": {"confidence": 1e36}}, r"^gps\.confidence must be finite and in \[0, 1e6\]"),
    ({"sonar": {"altitude_max": -1.0}}, r"^sonar\.altitude_min must be < altitude_max"),
    ({"lidar": {"gap_max": 0.0}}, r"^lidar\.gap_max must be > 0"),
    ({"lidar": {"timeout": math.inf}}, r"^lidar\.timeout must be finite and > 0"),
])
def test_bad_settings_raise_naming_sensor_and_field(impl, kwargs, message):
    with pytest.raises(ValueError, match=message):
        impl.AlphaBetaSettings(**kwargs)


def test_settings_types(impl):
    with pytest.raises(TypeError, match="unknown alpha-beta sensor"):
        impl.AlphaBetaSettings(radar={})
    with pytest.raises(TypeError, match="unknown gps setting"):
        impl.AlphaBetaSettings(gps={"depth": 3})
    with pytest.raises(TypeError, match=r"baro\.quality_min must be an int"):
        impl.AlphaBetaSettings(baro={"quality_min": 2.5})
    s = impl.AlphaBetaSettings(gps=AlphaBetaSensorSettings(5.0, 3, 9, 2.0, -math.inf, math.inf, math.inf, 2.0))
    assert s.gps.gap_max == math.inf and s.replace(gps={"threshold": 7.0}).gps.threshold == 7.0
    fusion = impl.AlphaBetaFusion()
    fusion.update_batch(np.zeros(100), dt=0.01, baro_altitude=0.0)
    fusion.settings = impl.AlphaBetaSettings(baro={"quality_max": 20})
    assert fusion.qualities.baro == 20


# --- On logs (fusion_altitude.runner): the baro filter's span and the GPS as fallback ---------------------------


def _log(seconds=120.0, imu_rate=100.0, baro_rate=2.0, gps_wander=6.0, baro_stops=None, seed=3):
    """A hover-climb-hover flight (m, +up) with a baro at ``baro_rate`` Hz (0.3 m noise) and a 5 Hz GPS that
    wanders ``gps_wander`` m (a slow sine, as a 10 m-accuracy receiver does), the baro ending at ``baro_stops`` s."""
    from fusion_altitude.logs import LogData

    rng = np.random.default_rng(seed)
    time = np.arange(0.0, seconds, 1.0 / imu_rate)
    truth = 380.0 + 4.0 * np.clip((time - 20.0) / 10.0, 0.0, 1.0) - 4.0 * np.clip((time - 80.0) / 10.0, 0.0, 1.0)
    accel = np.gradient(np.gradient(truth, time), time) + rng.normal(0.0, 0.1, time.size)
    baro = np.full(time.size, np.nan)
    every = int(round(imu_rate / baro_rate))
    baro[::every] = truth[::every] + rng.normal(0.0, 0.3, baro[::every].size)
    if baro_stops is not None:
        baro[time >= baro_stops] = np.nan
    gps = np.full(time.size, np.nan)
    gps[::20] = truth[::20] + gps_wander * np.sin(2 * np.pi * time[::20] / 40.0)
    return LogData("simulated", time, accel, baro, reference_altitude=truth, reference_velocity=None,
                   reference_name="truth", gps_altitude=gps)


def _rms(run):
    return run.comparison(transient=5.0).rms


def test_a_wandering_gps_does_not_make_the_fusion_worse_than_the_raw_baro_on_a_log():
    from fusion_altitude import runner

    run = runner.run_log(_log(), estimator="alphabeta")
    assert _rms(run) <= run.baro_comparison(transient=5.0).rms


def test_the_gps_carries_the_fusion_on_a_log_whose_baro_stops():
    from fusion_altitude import runner

    run = runner.run_log(_log(gps_wander=0.5, baro_stops=40.0), estimator="alphabeta")
    late = run.time > 45.0
    # 1.9 m at most, in the descent: the GPS filter fits its line to 120 samples (24 s at 5 Hz; the write-up's Qmax)
    assert np.max(np.abs(run.estimate.altitude[late] - run.reference_altitude[late])) < 2.5


def test_a_2hz_baro_filter_spans_3_s_not_60_samples_on_a_log():
    from fusion_altitude import adapters
    from fusion_altitude._alphabeta import AlphaBetaSettings

    changes = adapters.alphabeta_log_sensors(_log(baro_rate=2.0), AlphaBetaSettings())
    assert changes["baro"]["quality_max"] == 10  # round(3 s × 2 Hz) = 6, raised to Qmin = 10


def test_a_20hz_baro_keeps_the_write_ups_depth_on_a_log():
    from fusion_altitude import adapters
    from fusion_altitude._alphabeta import AlphaBetaSettings

    changes = adapters.alphabeta_log_sensors(_log(seconds=30.0, baro_rate=20.0), AlphaBetaSettings())
    assert changes["baro"]["quality_max"] == AlphaBetaSettings().baro.quality_max


def test_the_alphabeta_fusion_is_no_worse_than_the_raw_baro_on_the_2hz_baro_px4_log():
    import os
    from pathlib import Path

    from fusion_altitude import logs, runner

    data = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", Path(__file__).resolve().parents[1] / ".." / "shared" / "data"))
    assert data.is_dir(), f"shared data not found at {data}: set FUSION_ALTITUDE_SHARED_DATA"
    run = runner.run_log(logs.load_log(str(data / "px4_octorotor_2hz_baro.ulg")), estimator="alphabeta")
    assert run.comparison().rms <= run.baro_comparison().rms


# --- Sensor timeouts: flag, counter, fallback --------------------------------------------------------------------


def _baro_then_gps_only(impl, seconds_after=3.0, gps=True):
    """1 s of baro and GPS at 10.0 m, then the baro stops and the GPS (if any) goes on at 10.0 m; 100 Hz."""
    fusion = impl.AlphaBetaFusion()
    n, m = 100, int(round(100 * seconds_after))
    baro = np.r_[np.full(n, 10.0), np.full(m, NAN)]
    gps_altitude = np.full(n + m, 10.0 if gps else NAN)
    fusion.update_batch(np.zeros(n + m), dt=0.01, baro_altitude=baro, gps_altitude=gps_altitude)
    return fusion


def test_a_sensor_silent_for_longer_than_its_timeout_is_flagged_timed_out(impl):
    fusion = _baro_then_gps_only(impl, seconds_after=1.6)  # default timeout 1.5 s
    assert fusion.timed_out.baro and not fusion.timed_out.gps


def test_a_sensor_silent_for_less_than_its_timeout_is_not_flagged(impl):
    fusion = _baro_then_gps_only(impl, seconds_after=1.4)
    assert not fusion.timed_out.baro and fusion.timeout_counts.baro == 0


def test_each_silence_longer_than_the_timeout_is_counted_once(impl):
    fusion = _baro_then_gps_only(impl, seconds_after=5.0)
    assert fusion.timeout_counts.baro == 1
    fusion.update_batch(np.zeros(100), dt=0.01, baro_altitude=10.0, gps_altitude=10.0)  # back for 1 s
    assert not fusion.timed_out.baro and fusion.timeout_counts.baro == 1
    fusion.update_batch(np.zeros(200), dt=0.01, baro_altitude=NAN, gps_altitude=10.0)  # silent again for 2 s
    assert fusion.timed_out.baro and fusion.timeout_counts.baro == 2


def test_a_sensor_never_sampled_is_not_timed_out(impl):
    fusion = _baro_then_gps_only(impl, seconds_after=5.0)
    assert not fusion.timed_out.lidar and fusion.timeout_counts.lidar == 0


def test_the_gps_carries_the_fused_altitude_when_the_baro_times_out(impl):
    fusion = impl.AlphaBetaFusion()
    n = 100
    baro = np.r_[np.full(n, 10.0), np.full(5 * n, NAN)]
    gps = np.r_[np.full(n, 10.0), np.linspace(10.0, 12.0, 5 * n)]  # the vehicle climbs 2 m after the baro stopped
    out = fusion.update_batch(np.zeros(6 * n), dt=0.01, baro_altitude=baro, gps_altitude=gps)
    assert fusion.timed_out.baro and out.weight[-1, 1] == 0.0 and out.weight[-1, 4] > 0.0
    assert fusion.started and abs(out.altitude[-1] - 12.0) < 0.5


def test_a_timed_out_sensor_stays_flagged_through_a_restart(impl):
    fusion = _baro_then_gps_only(impl, seconds_after=2.0)
    fusion.update(0.0, baro_altitude=NAN, dt=2.0, gps_altitude=10.0)  # a gap: the fusion restarts from the GPS
    assert fusion.gap_count == 1 and fusion.timed_out.baro


# --- Stable steps: a sample interval far from the previous one restarts the filter ------------------------------


def _gap_free(impl):
    """Settings under which every step up to 5 s is integrated (no gap, no timeout), to test the interval rule."""
    return impl.AlphaBetaSettings(gap_period=5.0, **{k: {"timeout": 5.0} for k in ("imu", "baro", "lidar", "sonar", "gps")})


def test_a_sample_interval_more_than_4_times_the_previous_restarts_the_filter_at_the_sample(impl):
    fusion = impl.AlphaBetaFusion(_gap_free(impl))
    fusion.update_batch(np.full(30, NAN), dt=0.1, baro_altitude=np.linspace(10.0, 13.0, 30))
    assert fusion.qualities.baro > 10
    fusion.update(NAN, baro_altitude=20.0, dt=0.41)  # 4.1 × the previous 0.1 s
    assert fusion.qualities.baro == 10 and fusion.filter_altitudes.baro == 20.0


def test_a_sample_interval_up_to_4_times_the_previous_is_integrated(impl):
    fusion = impl.AlphaBetaFusion(_gap_free(impl))
    fusion.update_batch(np.full(30, NAN), dt=0.1, baro_altitude=np.linspace(10.0, 13.0, 30))
    quality = fusion.qualities.baro
    fusion.update(NAN, baro_altitude=13.4, dt=0.4)
    assert fusion.qualities.baro == quality + 1


@pytest.mark.parametrize("short", [1e-3, 1e-4])
def test_alternating_short_and_long_steps_stay_within_2_m_of_a_noisy_baro(impl, short):
    """Without the interval rule a velocity learnt over the short interval and applied over the long one took the
    fusion 4.1 km from a 0.5 m-noise baro at 100 m (alternating 0.1 ms and 1.4 s)."""
    rng = np.random.default_rng(1)
    steps = np.tile([short, 1.4], 200)
    out = impl.AlphaBetaFusion(_gap_free(impl)).update_batch(np.full(steps.size, NAN), dt=steps,
                                                             baro_altitude=100.0 + rng.normal(0.0, 0.5, steps.size))
    assert np.max(np.abs(out.altitude - 100.0)) < 2.0
