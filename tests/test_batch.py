"""update_batch: equal to per-sample updates, flexible inputs, preallocated outputs, GIL released."""

import math
import threading
import time

import numpy as np
import pytest

import fusion_altitude


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
