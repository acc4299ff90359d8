"""Specification of the shared log-assembly helpers' shortcuts (fusion_altitude/logs/_data.py, _checks.py,
sensors.vertical_acceleration): each answers what the long way answers, on the inputs that take it and on the
ones that fall back to the long way (issue 25: the fixed cost of reading a log)."""

import warnings

import numpy as np
import pytest

from fusion_altitude.logs import LogData, LogError, LogWarning, find_gaps, merge_repeated_timestamps
from fusion_altitude.logs._checks import check_time_units, drop_absurd, is_dead, median
from fusion_altitude.logs._data import align, finish, previous, reference_on_grid
from fusion_altitude.sensors import quaternion_to_matrix, vertical_acceleration

G = 9.80665


def grid_log(time, baro=None):
    """A LogData on ``time`` (s) with a live baro (m) and no other sensor."""
    time = np.asarray(time, dtype=float)
    baro = 10.0 + 0.01 * (np.arange(time.size) % 7) if baro is None else baro
    return LogData("x.csv (CSV)", time, np.zeros(time.size), baro)


def finished(data):
    """(data after ``finish``, [LogWarning texts]); any other warning fails the test."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("error")
        warnings.simplefilter("always", LogWarning)
        data = finish(data)
    return data, [str(w.message) for w in caught]


# --- finish: the median step is found only when a step could be a gap -----------------------------------

def test_a_grid_of_steps_up_to_a_tenth_of_a_second_has_no_gap():
    data, caught = finished(grid_log(np.r_[0.0, 0.1 + np.arange(100) * 0.01]))  # the first step: 0.1 s exactly
    assert data.gaps == [] and caught == []


def test_a_step_just_over_a_tenth_of_a_second_among_millisecond_steps_is_a_gap():
    time = np.r_[np.arange(100) * 0.001, 0.099 + 0.1001]
    data, _ = finished(grid_log(time))
    assert data.gaps == find_gaps(time) and len(data.gaps) == 1


def test_a_grid_in_milliseconds_is_still_refused():
    with pytest.raises(LogError, match="does not look like seconds"):
        finish(grid_log(np.arange(100) * 10.0))


def test_a_grid_with_an_infinite_time_is_refused_without_a_runtime_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(LogError, match="sample 2: time is not finite"):
            finish(grid_log([0.0, 0.01, np.inf, np.inf, 0.05]))


def test_a_grid_with_an_infinite_last_time_is_refused():
    with pytest.raises(LogError, match="sample 4: time is not finite"):
        finish(grid_log([0.0, 0.01, 0.02, 0.03, np.inf]))


# --- merge_repeated_timestamps: a finite, strictly increasing time is returned as it is --------------------

def test_an_increasing_time_is_returned_with_its_columns_unmerged():
    time, columns = np.arange(5) * 0.01, {"baro": np.arange(5.0)}
    merged_time, merged, repeated = merge_repeated_timestamps(time, columns, "x.csv")
    assert merged_time is time and merged is columns and repeated == 0


def test_an_infinite_last_time_is_refused_naming_its_line():
    with pytest.raises(LogError, match="line 5, column 'time': time must be a finite number"):
        merge_repeated_timestamps([0.0, 0.01, 0.02, np.inf], {}, "x.csv")


def test_an_infinite_first_time_is_refused_naming_its_line():
    with pytest.raises(LogError, match="line 2, column 'time': time must be a finite number"):
        merge_repeated_timestamps([-np.inf, 0.01, 0.02, 0.03], {}, "x.csv")


# --- check_time_units without a median: steps under 1 s pass without one --------------------------------

def test_a_column_in_milliseconds_with_a_missing_time_is_refused():
    time = np.arange(100) * 10.0
    time[50] = np.nan
    with pytest.raises(LogError, match="median step 10"):
        check_time_units("x.csv (CSV)", time, "fix")


def test_a_column_of_1_s_steps_spanning_more_than_a_day_is_refused():
    with pytest.raises(LogError, match="median step 1, span 89999"):
        check_time_units("x.csv (CSV)", np.arange(90_000) * 1.0, "fix")


def test_a_column_in_seconds_with_a_missing_time_passes():
    time = np.arange(100) * 0.01
    time[50] = np.nan
    check_time_units("x.csv (CSV)", time, "fix")


def test_a_column_in_seconds_with_repeated_infinities_passes_without_a_runtime_warning():
    time = np.arange(100) * 0.01
    time[50:52] = np.inf
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_time_units("x.csv (CSV)", time, "fix")


# --- align: every sample kept without masks, the masks when one is dropped ------------------------------

def test_align_puts_every_sample_on_the_first_step_at_or_after_it_newest_winning():
    out = align(np.arange(5.0), np.array([0.5, 0.7, 3.0]), np.array([1.0, 2.0, 3.0]))
    np.testing.assert_array_equal(out, [np.nan, 2.0, np.nan, 3.0, np.nan])


def test_align_drops_a_sample_after_the_last_step():
    out = align(np.arange(3.0), np.array([0.5, 7.0]), np.array([1.0, 2.0]))
    np.testing.assert_array_equal(out, [np.nan, 1.0, np.nan])


def test_align_keeps_the_older_sample_where_the_newer_is_not_finite():
    out = align(np.arange(3.0), np.array([0.5, 0.7]), np.array([1.0, np.inf]))
    np.testing.assert_array_equal(out, [np.nan, 1.0, np.nan])


def test_align_drops_a_row_of_several_axes_with_one_missing_axis():
    out = align(np.arange(3.0), np.array([0.5, 1.5]), np.array([[1.0, 2.0], [3.0, np.nan]]))
    np.testing.assert_array_equal(out, [[np.nan, np.nan], [1.0, 2.0], [np.nan, np.nan]])


# --- previous: a source on the grid itself gives each step its own sample ---------------------------------

def test_previous_of_a_source_on_the_grid_is_a_copy_of_its_samples():
    time, values = np.arange(4.0), np.arange(8.0).reshape(4, 2)
    out = previous(time, time.copy(), values)
    np.testing.assert_array_equal(out, values)
    assert out is not values


def test_previous_of_a_source_with_a_repeated_time_takes_the_latest_of_the_repeats():
    time = np.array([0.0, 1.0, 1.0, 2.0])
    np.testing.assert_array_equal(previous(time, time, np.arange(4.0)), [0.0, 2.0, 2.0, 3.0])


def test_previous_before_the_first_source_sample_takes_the_first():
    out = previous(np.arange(4.0), np.array([1.5, 2.5]), np.array(["disarmed", "armed"], dtype=object))
    assert out.tolist() == ["disarmed", "disarmed", "disarmed", "armed"]


# --- reference_on_grid: the datum shift is numpy.median's --------------------------------------------------

def test_the_reference_is_moved_onto_the_baro_by_the_median_difference_of_the_first_2_s():
    time = np.arange(0.0, 5.0, 0.1)
    baro = np.where(np.arange(time.size) % 3 == 0, 100.0 + np.sin(time), np.nan)
    reference = 3.0 * time ** 2
    altitude, _ = reference_on_grid(time, baro, time, reference, np.zeros(time.size))
    early = np.isfinite(baro) & (time <= 2.0)
    assert np.array_equal(altitude, reference + float(np.median(baro[early] - reference[early])))


def test_a_reference_that_never_meets_the_baro_is_not_moved():
    time = np.arange(0.0, 5.0, 0.1)
    altitude, _ = reference_on_grid(time, np.full(time.size, np.nan), time, time * 2.0, time)
    assert np.array_equal(altitude, time * 2.0)


# --- the checks' shortcuts -----------------------------------------------------------------------------------

def test_a_raw_accelerometer_whose_ends_differ_is_alive():
    accel = np.tile([0.0, 0.0, -20.0], (50, 1))
    accel[-1, 0] = 0.5
    assert not is_dead(accel)


def test_a_raw_accelerometer_with_equal_ends_and_a_change_inside_is_alive():
    accel = np.tile([0.0, 0.0, -20.0], (50, 1))
    accel[25, 1] = 0.5
    assert not is_dead(accel)


def test_a_channel_whose_ends_differ_only_beside_a_missing_axis_is_dead():
    accel = np.tile([1.0, 2.0, 3.0], (50, 1))
    accel[0] = [7.0, 2.0, np.nan]  # not a whole row: the rows that count are all constant
    assert is_dead(accel)


def test_an_absurd_cell_of_a_column_inside_a_table_is_found():
    table = np.column_stack([np.arange(30.0), np.full(30, 10.0)])
    table[12, 1] = 1e30
    values, message = drop_absurd("x.csv", "baro", table[:, 1], None, -1000.0, 100000.0, "m", "baro altitude")
    assert "sample 12" in message and np.isnan(values[12]) and np.isfinite(table[12, 1])


def test_median_is_numpys_median():
    values = np.random.default_rng(3).normal(size=1001)
    assert median(values) == float(np.median(values)) and median(values[:-1]) == float(np.median(values[:-1]))


# --- vertical_acceleration: the third row of the rotation matrix, in its order ------------------------------

def test_vertical_acceleration_of_quaternions_is_the_rotation_matrixs_third_row_bit_for_bit():
    rng = np.random.default_rng(7)
    quaternion, accel = rng.normal(size=(200, 4)), rng.normal(size=(200, 3)) * 20.0
    earth_z = np.sum(quaternion_to_matrix(quaternion)[:, 2, :] * accel, axis=-1)
    assert np.array_equal(vertical_acceleration(accel, quaternion, frame="ENU"), earth_z - G)


def test_vertical_acceleration_of_one_sample_is_a_scalar():
    value = vertical_acceleration([0.0, 0.0, -G], [1.0, 0.0, 0.0, 0.0])
    assert np.ndim(value) == 0 and value == 0.0


def test_vertical_acceleration_broadcasts_one_attitude_over_many_samples():
    accel = np.array([[0.0, 0.0, -G], [0.0, 0.0, -2.0 * G]])
    np.testing.assert_array_equal(vertical_acceleration(accel, [1.0, 0.0, 0.0, 0.0]), [0.0, G])
