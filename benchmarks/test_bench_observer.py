"""pytest-benchmark suite for the observer. Not part of the test command; run

    pytest benchmarks/                       # or: pytest benchmarks/ --benchmark-only

Inputs: 100 Hz IMU with a baro sample every 4th step (NaN between), seeded
noise, dt = 0.01 s (see _signals.py). Each benchmark stores its time per
sample in extra_info["ns_per_sample"] (``--benchmark-json``); for one run with
ratios against a plain C loop use ``python benchmarks/compare.py``.
"""

import numpy as np
import pytest
from conftest import BATCH_SAMPLES, PER_SAMPLE_CHUNK, REFERENCE_SAMPLES

import fusion_altitude
from fusion_altitude import reference


def _per_sample(benchmark, samples):
    benchmark.extra_info["samples_per_round"] = samples
    benchmark.extra_info["ns_per_sample"] = benchmark.stats.stats.min * 1e9 / samples


@pytest.mark.benchmark(group="update() per sample")
def test_update_per_sample(benchmark, signals):
    """AltitudeEstimator.update from a Python for loop over Python floats."""
    accel = signals.accel[:PER_SAMPLE_CHUNK].tolist()
    baro = signals.baro_altitude[:PER_SAMPLE_CHUNK].tolist()
    dt = signals.dt
    estimator = fusion_altitude.AltitudeEstimator()
    update = estimator.update

    def run():
        for a, z in zip(accel, baro):
            update(a, z, dt)

    benchmark(run)
    _per_sample(benchmark, PER_SAMPLE_CHUNK)
    assert estimator.reference_set


@pytest.mark.benchmark(group="update_batch 1e6 samples")
def test_update_batch_out(benchmark, signals, out_arrays):
    """update_batch on 1e6 float32 samples into preallocated out= arrays."""

    def run():
        return fusion_altitude.AltitudeEstimator().update_batch(signals.accel, signals.baro_altitude, signals.dt,
                                                                out=out_arrays)

    result = benchmark(run)
    _per_sample(benchmark, BATCH_SAMPLES)
    assert result.altitude is out_arrays.altitude
    assert np.isfinite(result.altitude).all()


@pytest.mark.benchmark(group="update_batch 1e6 samples")
def test_update_batch_allocating(benchmark, signals):
    """update_batch on 1e6 float32 samples, allocating the 4 output arrays.

    Each round's result is dropped, so malloc usually recycles the previous
    round's pages; a caller who keeps every result pays first-touch page faults
    on top (compare.py measures both).
    """

    def run():
        return fusion_altitude.AltitudeEstimator().update_batch(signals.accel, signals.baro_altitude, signals.dt)

    result = benchmark(run)
    _per_sample(benchmark, BATCH_SAMPLES)
    assert result.altitude.shape == (BATCH_SAMPLES,)


@pytest.mark.benchmark(group="update_batch 1e6 samples")
def test_update_batch_float64_inputs(benchmark, signals, out_arrays):
    """update_batch on 1e6 float64 samples (converted to float32 inside), out= arrays."""
    accel64 = signals.accel.astype(np.float64)
    baro64 = signals.baro_altitude.astype(np.float64)

    def run():
        return fusion_altitude.AltitudeEstimator().update_batch(accel64, baro64, signals.dt, out=out_arrays)

    benchmark(run)
    _per_sample(benchmark, BATCH_SAMPLES)


@pytest.mark.benchmark(group="update_batch 1e6 samples")
def test_update_batch_dt_array(benchmark, signals, out_arrays):
    """update_batch on 1e6 float32 samples with a per-sample dt array, out= arrays."""

    def run():
        return fusion_altitude.AltitudeEstimator().update_batch(signals.accel, signals.baro_altitude,
                                                                signals.dt_array, out=out_arrays)

    benchmark(run)
    _per_sample(benchmark, BATCH_SAMPLES)


@pytest.mark.benchmark(group="pure-Python reference")
def test_reference_update_batch(benchmark, signals):
    """The pure-Python reference's update_batch on 2e4 samples (it is ~1000x slower)."""
    accel = signals.accel[:REFERENCE_SAMPLES]
    baro = signals.baro_altitude[:REFERENCE_SAMPLES]

    def run():
        return reference.AltitudeEstimator().update_batch(accel, baro, signals.dt)

    result = benchmark.pedantic(run, rounds=3, iterations=1, warmup_rounds=0)
    _per_sample(benchmark, REFERENCE_SAMPLES)
    expected = fusion_altitude.AltitudeEstimator().update_batch(accel, baro, signals.dt)
    for got, want in zip(result, expected):
        assert np.array_equal(got.view(np.uint32), want.view(np.uint32))
