"""The rocket estimator on the logs flight computers really write (issue 20), on simulated fixtures.

Fixtures from fusion_altitude.rocket_sim: every flight as a log with a live IMU,
a dead IMU (all zero), an IMU that saturates in boost, no accelerometer at all
(baro_only), a flight computer's along-axis accelerometer, and one that stops
4.5 s after launch; each at 100 Hz and as 10 Hz ground-station telemetry with
gaps of 0.6-4 s (7 % of the packets; the gaps are kept 2 s away from the true
apogee so that the apogee timing is measured apart from the data a gap removes:
a gap over the apogee has its own test). Run through ``run_log(estimator="rocket")``,
i.e. the input choice of rocket.rocket_accel_input and the C rocket estimator.

Figures measured over these fixtures (seeds 0-5; the table in docs/rocket.md, "Logs without a
good accelerometer"): apogee 0.14-0.79 s after the truth, height within 0.37 %, the largest fall
during the ascent 5.3 m, the final height within 12 m; the bounds below leave room for other seeds.
"""

import math
import warnings

import numpy as np
import pytest

from fusion_altitude import logs, rocket, runner
from fusion_altitude.reference.rocket import RocketEstimator as ReferenceRocket
from fusion_altitude.rocket_sim import (LOG_KINDS, RocketFlightModel, flight_log, simulate_rocket_flight,
                                        telemetry_indices)
from fusion_altitude.sim import GRAVITY

SEEDS = range(6)
#: An IMU that does not saturate (the simulator's default clips at 12 g at the thrust peak).
WIDE_IMU = RocketFlightModel(saturation=50 * GRAVITY)


def _flight(seed, kind):
    return simulate_rocket_flight(seed, WIDE_IMU if kind == "imu" else None)


def _run(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return runner.run_log(data, estimator="rocket")


@pytest.fixture(scope="module")
def runs():
    """{(kind, rate): [(flight, indices, run)]} for every fixture kind at 100 Hz and as telemetry."""
    out = {}
    for kind in LOG_KINDS:
        for rate in ("100 Hz", "telemetry"):
            cases = []
            for seed in SEEDS:
                flight = _flight(seed, kind)
                indices = (telemetry_indices(flight, seed, quiet=(flight.apogee_time,)) if rate == "telemetry"
                           else np.arange(flight.time.size))
                cases.append((flight, indices, _run(flight_log(flight, kind, indices))))
            out[kind, rate] = cases
    return out


CASES = [(kind, rate) for kind in LOG_KINDS for rate in ("100 Hz", "telemetry")]
by_case = pytest.mark.parametrize("kind, rate", CASES, ids=[f"{kind}-{rate}" for kind, rate in CASES])


@by_case
def test_apogee_is_declared_within_1_s_after_the_true_apogee_and_never_before(runs, kind, rate):
    for flight, _, run in runs[kind, rate]:
        delay = run.events["apogee"].time - flight.apogee_time
        assert 0.0 <= delay <= 1.0, (kind, rate, delay)


@by_case
def test_apogee_height_is_within_2_percent_of_the_truth(runs, kind, rate):
    for flight, _, run in runs[kind, rate]:
        assert abs(run.events["apogee"].height - flight.apogee_height) <= 0.02 * flight.apogee_height


@by_case
def test_launch_apogee_main_and_landed_all_fire_in_flight_order(runs, kind, rate):
    for _, _, run in runs[kind, rate]:
        names = ("launch", "apogee", "main", "landed")
        assert all(run.events[name].occurred for name in names), run.events
        times = [run.events[name].time for name in names]
        assert times == sorted(times)


@by_case
def test_the_height_never_falls_more_than_10_m_during_the_ascent(runs, kind, rate):
    """Baro noise 1 m; measured at most 3.5 m at 100 Hz and 5.3 m as telemetry."""
    for _, _, run in runs[kind, rate]:
        events = run.events
        ascent = np.asarray(run.estimate.height[events["launch"].sample:events["apogee"].sample + 1], float)
        assert (np.maximum.accumulate(ascent) - ascent).max() <= 10.0


@by_case
def test_no_runaway_the_height_stays_within_2_percent_above_apogee_and_ends_within_20_m_of_the_ground(runs, kind, rate):
    for flight, _, run in runs[kind, rate]:
        height = np.asarray(run.estimate.height, float)
        assert np.all(np.isfinite(height)) and np.all(np.isfinite(run.estimate.vertical_velocity))
        assert height.max() <= 1.02 * flight.apogee_height
        assert abs(height[-1]) <= 20.0


def test_a_dead_imu_is_not_taken_as_the_long_axis_the_flight_is_baro_led(runs):
    for _, _, run in runs["dead_imu", "100 Hz"]:
        assert any("no usable accelerometer" in note and "dead" in note for note in run.notes)
        assert run.events["launch"].occurred and not run.events["burnout"].occurred  # no accelerometer, no burnout


def test_a_saturating_imu_is_used_up_to_its_first_saturated_sample_only(runs):
    flight, _, run = runs["saturating_imu", "100 Hz"][0]
    data = flight_log(flight, "saturating_imu")
    accel, note = rocket.rocket_accel_input(data)
    saturated = np.abs(data.accel[:, 2]) >= 0.999 * np.abs(data.accel[:, 2]).max()
    first = int(np.argmax(saturated))
    assert "saturated from t =" in note
    assert np.all(np.isfinite(accel[:first])) and np.all(np.isnan(accel[first:]))


def test_the_readers_clipped_flag_marks_saturation_too():
    flight = _flight(0, "imu")
    data = flight_log(flight, "imu")
    data.clipped = np.zeros(flight.time.size, dtype=bool)
    data.clipped[400] = True
    accel, note = rocket.rocket_accel_input(data)
    assert "saturated" in note and np.isnan(accel[400:]).all() and np.isfinite(accel[:400]).all()


def test_the_flight_computers_along_axis_accelerometer_is_preferred_to_the_imu():
    flight = _flight(0, "imu")
    data = flight_log(flight, "imu")
    data.axial_acceleration = flight.accel + GRAVITY + 0.5  # a different sensor: 0.5 m/s² apart
    accel, note = rocket.rocket_accel_input(data)
    assert note == "rocket estimator: the flight computer's along-axis accelerometer"
    np.testing.assert_allclose(accel, flight.accel + 0.5)


def test_an_along_axis_accelerometer_that_ends_leaves_nan_from_1_s_after_its_last_sample():
    flight = _flight(0, "axial_ends")
    data = flight_log(flight, "axial_ends")
    accel, _ = rocket.rocket_accel_input(data)
    last = flight.time[np.flatnonzero(np.isfinite(data.axial_acceleration))[-1]]
    assert np.isfinite(accel[flight.time <= last]).all()
    assert np.isnan(accel[flight.time > last + rocket.ACCEL_HOLD]).all()


def test_a_baro_only_log_gives_no_accelerometer_input():
    flight = _flight(0, "baro_only")
    accel, note = rocket.rocket_accel_input(flight_log(flight, "baro_only"))
    assert np.isnan(accel).all() and "baro-only" in note


def test_a_long_axis_that_reads_minus_g_on_the_pad_is_refused():
    data = flight_log(_flight(0, "imu"), "imu")
    with pytest.raises(logs.LogError, match=r"^long axis -Z reads -\d+\.\d+ m/s² at rest on the pad"):
        runner.rocket_long_axis(data.accel, data.time, long_axis=(2, -1.0))


def test_a_long_axis_while_another_axis_carries_gravity_is_refused_naming_it():
    data = flight_log(_flight(0, "imu"), "imu")
    with pytest.raises(logs.LogError, match=r"long axis \+Y reads .*; Z reads \+\d+\.\d+ m/s² and carries gravity"):
        runner.rocket_long_axis(data.accel, data.time, long_axis=(1, 1.0))


def test_a_dead_column_is_refused_as_the_long_axis():
    accel = flight_log(_flight(0, "imu"), "dead_imu").accel
    with pytest.raises(logs.LogError, match=r"constant \(dead\)"):
        runner.rocket_long_axis(accel, None, long_axis=(2, 1.0))


def test_telemetry_gaps_around_the_apogee_delay_it_by_at_most_their_length_plus_2_s_and_never_early():
    """No quiet window: gaps fall where they fall (15 % of packets); ``gap`` is the longest step within 3 s
    of the true apogee. Measured over seeds 0-7: at worst 4.3 s late for a 2.8 s gap, height within 3.3 %."""
    for seed in range(8):
        flight = simulate_rocket_flight(seed)
        indices = telemetry_indices(flight, seed, gap_probability=0.15)
        times = flight.time[indices]
        near = np.abs(times[1:] - flight.apogee_time) <= 3.0
        gap = float(np.diff(times)[near].max())
        run = _run(flight_log(flight, "baro_only", indices))
        delay = run.events["apogee"].time - flight.apogee_time
        assert 0.0 <= delay <= gap + 2.0, (seed, gap, delay)
        assert abs(run.events["apogee"].height - flight.apogee_height) <= 0.05 * flight.apogee_height


def test_the_reported_apogee_is_baro_corrected_while_the_inertial_height_is_hundreds_of_metres_off():
    """An accelerometer whose bias shifts by +3 m/s² at launch: the inertial height is 300-800 m high when the
    lockout ends. The apogee event reports the baro's height; the output height blends down after apogee
    without a step (measured: at most 1.02 m between samples at 100 Hz)."""
    for seed in range(4):
        flight = simulate_rocket_flight(seed, WIDE_IMU)
        accel = flight.accel + np.where(flight.time > flight.launch_time, 3.0, 0.0)
        batch, events = rocket.run_rocket(flight.time, accel, flight.baro_altitude)
        height = batch.height.astype(float)
        k = events["apogee"].sample
        assert height[k] - flight.apogee_height > 150.0  # the output is still blending ...
        assert abs(events["apogee"].height - flight.apogee_height) <= 0.01 * flight.apogee_height  # ... the event is not
        assert np.abs(np.diff(height[k:])).max() <= 2.0
        assert abs(height[-1]) <= 5.0


def test_a_coast_the_baro_contradicts_ends_in_apogee():
    """An accelerometer that keeps the velocity positive after burnout (+9 m/s² from 2 s after burnout: the
    integrated coast hardly decelerates and stays above the lockout speed): the baro more than 20 m below its
    peak for 5 s (in the lockout; 1 s outside it) ends the coast. Measured: 6.9 s after the true apogee
    (2 s to fall 20 m, then 5 s), against 50 s with the contradiction confined to the unlocked baro."""
    flight = simulate_rocket_flight(0, WIDE_IMU)
    accel = flight.accel + np.where(flight.time > flight.burnout_time + 2.0, 9.0, 0.0)
    _, events = rocket.run_rocket(flight.time, accel, flight.baro_altitude)
    assert events["apogee"].occurred
    assert 0.0 <= events["apogee"].time - flight.apogee_time <= 8.0
    assert abs(events["apogee"].height - flight.apogee_height) <= 0.02 * flight.apogee_height


@pytest.mark.parametrize("kind", ["baro_only", "axial_ends"])
def test_c_and_reference_agree_bit_for_bit_on_a_telemetry_log(kind):
    flight = simulate_rocket_flight(1)
    indices = telemetry_indices(flight, 1)
    data = flight_log(flight, kind, indices)
    accel, _ = rocket.rocket_accel_input(data)
    c_batch, c_events = rocket.run_rocket(data.time, accel, data.baro_altitude)
    r_batch, r_events = rocket.run_rocket(data.time, accel, data.baro_altitude, estimator=ReferenceRocket())
    for c, r in zip(c_batch, r_batch):
        assert np.array_equal(np.asarray(c).view(np.uint8), np.asarray(r).view(np.uint8))
    assert [tuple(e) for e in c_events] == [tuple(e) for e in r_events]


def test_nan_accel_is_no_sample_not_an_error_and_inf_is_still_rejected():
    estimator = rocket.RocketEstimator()
    estimator.update(math.nan, 1400.0, 0.01)
    with pytest.raises(ValueError, match=r"^accel must be finite, or NaN for no accelerometer sample"):
        estimator.update(math.inf, 1400.0, 0.01)


def test_an_along_axis_accelerometer_whose_export_starts_in_boost_is_still_used():
    """A Raven export starts at launch: its first second reads the thrust, not +g."""
    flight = _flight(0, "axial")
    start = int(np.searchsorted(flight.time, flight.launch_time - 0.1))
    data = flight_log(flight, "axial", np.arange(start, flight.time.size))
    accel, note = rocket.rocket_accel_input(data)
    assert note == "rocket estimator: the flight computer's along-axis accelerometer"
    run = _run(data)
    assert run.events["launch"].occurred and run.events["burnout"].occurred
    assert abs(run.events["apogee"].height - flight.apogee_height) <= 0.02 * flight.apogee_height


# -- the table of docs/rocket.md ("Logs without a good accelerometer"): python tests/test_rocket_logs.py --------

def summary_table():
    """Over every fixture kind and seeds 0-5, per rate: the ranges and worst cases the tests above bound."""
    columns = {}
    for rate in ("100 Hz", "telemetry"):
        delays, errors, falls, overshoots, finals, fired = [], [], [], [], [], True
        for kind in LOG_KINDS:
            for seed in SEEDS:
                flight = _flight(seed, kind)
                indices = (telemetry_indices(flight, seed, quiet=(flight.apogee_time,)) if rate == "telemetry"
                           else np.arange(flight.time.size))
                run = _run(flight_log(flight, kind, indices))
                events, height = run.events, np.asarray(run.estimate.height, float)
                fired &= all(events[name].occurred for name in ("launch", "apogee", "main", "landed"))
                delays.append(events["apogee"].time - flight.apogee_time)
                errors.append(abs(events["apogee"].height - flight.apogee_height) / flight.apogee_height)
                ascent = height[events["launch"].sample:events["apogee"].sample + 1]
                falls.append((np.maximum.accumulate(ascent) - ascent).max())
                overshoots.append(height.max() / flight.apogee_height)
                finals.append(abs(height[-1]))
        columns[rate] = [f"{min(delays):.2f} – {max(delays):.2f}", f"≤ {100 * max(errors):.2f} %",
                         f"≤ {max(falls):.1f}", f"≤ {max(overshoots):.4f}", f"≤ {max(finals):.1f}",
                         "all fire" if fired else "not all fire"]
    labels = ["apogee after the true apogee (s)", "apogee height error",
              "largest fall of the height during the ascent (m)", "highest height / true apogee",
              "final height (m)", "launch, apogee, main, landed"]
    rows = ["| | 100 Hz | telemetry |", "|---|---|---|"]
    rows += [f"| {label} | {a} | {b} |" for label, a, b in zip(labels, columns["100 Hz"], columns["telemetry"])]
    return "\n".join(rows)


if __name__ == "__main__":
    print(summary_table())
