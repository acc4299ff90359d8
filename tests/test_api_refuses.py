"""The Python API refuses what it cannot honour (out= arrays that share memory)."""

import re

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


@pytest.mark.parametrize("value", [1e30, 1e200, np.inf])
def test_a_gain_beyond_the_largest_the_core_accepts_is_named_with_the_value_given(value):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy overflow warning on the way
        with pytest.raises(ValueError, match="^" + re.escape(f"position_gain must be finite, >= 0 and <= 1e+15, got "
                                                             f"{value!r}") + "$"):
            fa.AltitudeSettings(position_gain=value, velocity_gain=value)


def test_the_largest_gain_is_the_headers():
    from fusion_altitude import _c_tables

    assert _c_tables.FUSION_ALTITUDE_MAXIMUM_GAIN == 1e15
    fa.AltitudeSettings(position_gain=1e15, velocity_gain=1e15, bias_gain=1.0)


def test_a_negative_satellite_count_is_refused_and_the_state_kept():
    estimator = fa.KalmanEstimator()
    estimator.update(0.0, baro_altitude=10.0, dt=0.01)
    before = estimator.altitude
    with pytest.raises(ValueError, match=r"^gps_satellites must be >= 0 \(None or NaN: unknown\), got -3$"):
        estimator.update(0.0, baro_altitude=10.0, dt=0.01, gps_altitude=12.0, gps_satellites=-3)
    assert estimator.altitude == before


def test_a_negative_satellite_count_in_a_batch_is_named_by_its_index():
    with pytest.raises(ValueError, match=r"^gps_satellites\[1\] must be >= 0 \(NaN: unknown\), got -2$"):
        fa.KalmanEstimator().update_batch(np.zeros(3), baro_altitude=np.zeros(3), dt=0.01, gps_altitude=np.zeros(3),
                                          gps_satellites=np.array([5, -2, 3]))


def test_the_ins_refuses_outputs_that_share_memory():
    batch = fa.InsEstimator().update_batch(np.zeros((4, 3)), np.tile([0.0, 0.0, 9.80665], (4, 1)), 0.01)
    out = list(batch)
    out[1] = out[0]  # one array for altitude and vertical velocity (both per-sample float32)
    with pytest.raises(ValueError, match="share memory"):
        fa.InsEstimator().update_batch(np.zeros((4, 3)), np.tile([0.0, 0.0, 9.80665], (4, 1)), 0.01, out=out)


def test_the_rocket_layer_refuses_outputs_that_share_memory():
    from fusion_altitude._rocket import RocketEstimator

    shared = np.zeros(5, np.float32)
    out = (shared, shared, np.zeros(5, np.float32), np.zeros(5, np.uint8), np.zeros(5, np.uint8))
    with pytest.raises(ValueError, match="share memory"):
        RocketEstimator().update_batch(np.full(5, 9.8), np.zeros(5), 0.01, out=out)
