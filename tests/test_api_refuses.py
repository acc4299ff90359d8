"""The Python API refuses what it cannot honour (out= arrays that share memory)."""

import numpy as np
import pytest

import fusion_altitude as fa


def test_one_array_for_every_output_is_refused_and_the_state_kept():
    estimator = fa.AltitudeEstimator()
    estimator.update(0.0, 10.0, 0.01)
    before = estimator.altitude, estimator.vertical_velocity
    shared = np.zeros(8, np.float32)
    with pytest.raises(ValueError, match="out.altitude and out.vertical_velocity share memory"):
        estimator.update_batch(np.zeros(8), np.full(8, 11.0), 0.01, out=fa.AltitudeBatch(shared, shared, shared, shared))
    assert (estimator.altitude, estimator.vertical_velocity) == before


def test_overlapping_views_of_one_buffer_are_refused():
    buffer = np.zeros(20, np.float32)
    out = (buffer[:10], buffer[5:15], np.zeros(10, np.float32), np.zeros(10, np.float32))
    with pytest.raises(ValueError, match="share memory"):
        fa.ComplementaryFilter().update_batch(np.zeros(10), np.zeros(10), 0.01, out=out)


def test_disjoint_views_of_one_buffer_are_accepted():
    buffer = np.zeros(40, np.float32)
    out = tuple(buffer[10 * k:10 * (k + 1)] for k in range(4))
    result = fa.AltitudeEstimator().update_batch(np.zeros(10), np.full(10, 3.0), 0.01, out=out)
    assert result is out and np.all(buffer[:10] == 3.0)
