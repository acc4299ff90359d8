"""sweep(): K observers over one log, each column equal to its own single run."""

import threading

import numpy as np
import pytest
from hypothesis import given, settings as hypothesis_settings
from hypothesis import strategies as st

import fusion_altitude
import fusion_altitude.reference
from fusion_altitude import AltitudeEstimator, AltitudeSettings


def log(n=3000, seed=0, gap_every=4, per_sample_dt=False):
    rng = np.random.default_rng(seed)
    accel = rng.normal(0.0, 1.0, n)  # m/s²
    baro = 30 + np.cumsum(rng.normal(0.0, 0.05, n))  # m
    baro[np.arange(n) % gap_every != 0] = np.nan
    dt = rng.uniform(0.005, 0.02, n) if per_sample_dt else 0.01  # s
    reference = baro.copy()
    reference[np.isnan(reference)] = 30.0
    return accel, baro, dt, reference


def grid(count):
    return [AltitudeSettings.from_bandwidth(omega, zeta) for omega, zeta in
            zip(np.geomspace(0.1, 8.0, count), np.resize([0.5, 0.7, 1.0], count))]


def bits(array):
    return np.ascontiguousarray(array, dtype=np.float32).view(np.uint32)


@pytest.mark.parametrize("count", [1, 7, 8, 9, 33, 70])
@pytest.mark.parametrize("per_sample_dt", [False, True])
def test_each_column_equals_the_single_filter_bit_for_bit(count, per_sample_dt):
    accel, baro, dt, _ = log(per_sample_dt=per_sample_dt)
    settings = grid(count)
    result = fusion_altitude.sweep(accel, baro, dt, settings, outputs=True)
    for k, setting in enumerate(settings):
        single = AltitudeEstimator(setting).update_batch(accel, baro, dt)
        for field in single._fields:
            assert np.array_equal(bits(getattr(result.outputs, field)[:, k]), bits(getattr(single, field))), (k, field)


def test_metrics_equal_numpy_on_the_single_run_outputs():
    accel, baro, dt, reference = log(n=5000, seed=1)
    mask = np.random.default_rng(2).random(5000) > 0.2
    reference[10] = np.nan  # unknown reference samples are left out
    settings = grid(40)
    result = fusion_altitude.sweep(accel, baro, dt, settings, reference=reference, mask=mask)
    counted = mask & np.isfinite(reference)
    assert result.metric_samples == np.count_nonzero(counted)
    for k, setting in enumerate(settings):
        altitude = AltitudeEstimator(setting).update_batch(accel, baro, dt).altitude.astype(np.float64)
        error = (altitude - reference.astype(np.float32))[counted]
        assert result.rms_error[k] == pytest.approx(np.sqrt(np.mean(error**2)), rel=1e-5)
        assert result.mean_error[k] == pytest.approx(np.mean(error), rel=1e-4, abs=1e-6)
        assert result.max_abs_error[k] == pytest.approx(np.max(np.abs(error)), rel=1e-6)


def test_metrics_only_and_outputs_give_the_same_metrics():
    accel, baro, dt, reference = log(seed=4)
    settings = grid(50)
    metrics_only = fusion_altitude.sweep(accel, baro, dt, settings, reference=reference)
    with_outputs = fusion_altitude.sweep(accel, baro, dt, settings, reference=reference, outputs=True)
    assert metrics_only.outputs is None
    assert np.array_equal(bits(metrics_only.sum_squared_error), bits(with_outputs.sum_squared_error))
    assert np.array_equal(metrics_only.max_abs_error, with_outputs.max_abs_error)


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_splitting_across_threads_changes_no_bit(threads):
    accel, baro, dt, reference = log(seed=5)
    settings = grid(100)
    one = fusion_altitude.sweep(accel, baro, dt, settings, reference=reference, outputs=True, threads=1)
    split = fusion_altitude.sweep(accel, baro, dt, settings, reference=reference, outputs=True, threads=threads)
    assert np.array_equal(bits(one.sum_squared_error), bits(split.sum_squared_error))
    assert np.array_equal(bits(one.outputs.altitude), bits(split.outputs.altitude))


@hypothesis_settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(1, 2500), count=st.integers(1, 12), gap_every=st.integers(1, 6),
       per_sample_dt=st.booleans())
def test_agrees_with_the_reference_sweep_bit_for_bit(seed, n, count, gap_every, per_sample_dt):
    accel, baro, dt, reference = log(n=n, seed=seed, gap_every=gap_every, per_sample_dt=per_sample_dt)
    gains = np.array([s.as_tuple() for s in grid(count)])
    fast = fusion_altitude.sweep(accel, baro, dt, gains, reference=reference, outputs=True)
    slow = fusion_altitude.reference.sweep(accel, baro, dt, gains, reference=reference, outputs=True)
    assert fast.metric_samples == slow.metric_samples
    for name in ("sum_error", "sum_squared_error"):
        assert np.array_equal(bits(getattr(fast, name)), bits(getattr(slow, name))), name
    assert np.array_equal(fast.max_abs_error, slow.max_abs_error)
    for field in fast.outputs._fields:
        assert np.array_equal(bits(getattr(fast.outputs, field)), bits(getattr(slow.outputs, field)))


def test_accepts_a_gain_array_or_settings():
    accel, baro, dt, reference = log(n=500)
    settings = grid(5)
    from_objects = fusion_altitude.sweep(accel, baro, dt, settings, reference=reference)
    from_array = fusion_altitude.sweep(accel, baro, dt, np.array([s.as_tuple() for s in settings]), reference=reference)
    assert np.array_equal(from_objects.rms_error, from_array.rms_error)
    assert from_array.gains.shape == (5, 3)


def test_bad_sample_is_named_with_its_index():
    accel, baro, dt, reference = log(n=100)
    accel[42] = np.inf
    with pytest.raises(ValueError, match=r"^accel\[42\] must be finite"):
        fusion_altitude.sweep(accel, baro, dt, grid(3), reference=reference)


def test_unstable_setting_is_named_with_its_index():
    accel, baro, dt, reference = log(n=100)
    with pytest.raises(ValueError, match=r"^settings\[1\]: gains are unstable"):
        fusion_altitude.sweep(accel, baro, dt, [(2.4, 2.88, 0.675), (1.0, 1.0, 5.0)], reference=reference)


GAIN_VALUES = [0.0, 1e-30, 0.3, 1.0, 2.4, 3.0, 1e20, 3.4e38, 1e39, -0.0, -1.0, np.nan, np.inf, -np.inf]


@hypothesis_settings(max_examples=200, deadline=None)
@given(rows=st.lists(st.tuples(*[st.sampled_from(GAIN_VALUES) | st.floats(-1, 50)] * 3), min_size=1, max_size=6))
def test_accepts_exactly_the_gains_altitude_settings_accepts(rows):
    """The sweep checks all K rows at once (vectorised); it must accept and reject exactly as AltitudeSettings,
    naming the first bad row with the same message."""
    accel, baro, _, _ = log(n=20)
    first_bad, message = None, None
    for k, row in enumerate(rows):
        try:
            AltitudeSettings(*row)
        except ValueError as error:
            first_bad, message = k, str(error)
            break
    if first_bad is None:
        fusion_altitude.sweep(accel, baro, 0.01, np.array(rows), outputs=True)
    else:
        with pytest.raises(ValueError) as error:
            fusion_altitude.sweep(accel, baro, 0.01, np.array(rows), outputs=True)
        assert str(error.value) == f"settings[{first_bad}]: {message}"


def test_needs_a_reference_or_outputs():
    accel, baro, dt, _ = log(n=100)
    with pytest.raises(ValueError, match="nothing to compute"):
        fusion_altitude.sweep(accel, baro, dt, grid(2))


def test_rejects_a_mask_of_the_wrong_shape():
    accel, baro, dt, reference = log(n=100)
    with pytest.raises(ValueError, match="mask must be a boolean array of shape"):
        fusion_altitude.sweep(accel, baro, dt, grid(2), reference=reference, mask=np.ones(99, bool))


def test_releases_the_gil():
    accel, baro, dt, reference = log(n=1_000_000)  # about 0.1-0.3 s of C with 512 settings
    finished = threading.Event()
    worker = threading.Thread(target=lambda: (fusion_altitude.sweep(accel, baro, dt, grid(512), reference=reference,
                                                                    threads=1), finished.set()))
    worker.start()
    ticks = 0
    while not finished.is_set():
        ticks += 1
        threading.Event().wait(0.0005)
    worker.join()
    assert ticks > 100


def test_writes_into_preallocated_out_arrays():
    accel, baro, dt, _ = log(n=400)
    settings = grid(10)
    out = fusion_altitude.AltitudeBatch(*(np.empty((400, 10), np.float32) for _ in range(4)))
    result = fusion_altitude.sweep(accel, baro, dt, settings, out=out)
    assert all(r is o for r, o in zip(result.outputs, out))
    fresh = fusion_altitude.sweep(accel, baro, dt, settings, outputs=True)
    assert np.array_equal(bits(out.accel_bias), bits(fresh.outputs.accel_bias))
    with pytest.raises(ValueError, match=r"out.altitude must be a writeable contiguous float32 array of shape \(400, 10\)"):
        fusion_altitude.sweep(accel, baro, dt, settings, out=[np.empty((400, 9), np.float32)] + list(out[1:]))
