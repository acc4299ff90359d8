"""Specification of the simulator: trajectories are consistent, sensor models do what they say."""

import numpy as np
import pytest

from fusion_altitude import GRAVITY, sim


@pytest.mark.parametrize("name", list(sim.TRAJECTORIES))
def test_trajectory_velocity_is_the_derivative_of_altitude(name):
    trajectory = sim.TRAJECTORIES[name]()
    derivative = np.gradient(trajectory.altitude, trajectory.time)
    scale = max(np.abs(trajectory.vertical_velocity).max(), 1.0)
    assert np.max(np.abs(derivative - trajectory.vertical_velocity)[2:-2]) < 0.02 * scale


@pytest.mark.parametrize("name", list(sim.TRAJECTORIES))
def test_trajectory_attitudes_are_unit_quaternions(name):
    trajectory = sim.TRAJECTORIES[name]()
    np.testing.assert_allclose(np.linalg.norm(trajectory.attitude, axis=1), 1.0, atol=1e-9)


def test_climb_cruise_descend_reaches_cruise_and_returns_to_ground():
    trajectory = sim.climb_cruise_descend(cruise_altitude=60.0)
    assert trajectory.altitude.max() == pytest.approx(60.0, abs=0.5)
    assert trajectory.altitude[-1] == pytest.approx(0.0, abs=0.5)


def test_takeoff_landing_starts_and_ends_on_the_ground():
    trajectory = sim.takeoff_landing(hover_altitude=5.0)
    assert trajectory.altitude[0] == 0.0
    assert trajectory.altitude.max() == pytest.approx(5.0, abs=0.2)
    assert abs(trajectory.altitude[-1]) < 0.2


def test_rocket_boosts_then_coasts_to_apogee_and_descends():
    trajectory = sim.rocket()
    apogee = int(np.argmax(trajectory.altitude))
    assert trajectory.vertical_acceleration[np.searchsorted(trajectory.time, 3.0)] > 100.0
    assert trajectory.vertical_acceleration[apogee - 50] < -GRAVITY
    assert trajectory.altitude[-1] < trajectory.altitude[apogee]


def test_level_imu_at_rest_reads_one_g_up_in_nwu():
    imu = sim.simulate_imu(sim.hover(1.0), sim.ImuModel(), np.random.default_rng(0))
    np.testing.assert_allclose(imu.accel, np.tile([0.0, 0.0, 1.0], (100, 1)), atol=1e-12)


def test_accel_bias_shifts_the_mean_reading():
    imu = sim.simulate_imu(sim.hover(10.0), sim.ImuModel(accel_bias=(0.01, -0.02, 0.03), accel_noise=0.005),
                           np.random.default_rng(0))
    np.testing.assert_allclose(imu.accel.mean(axis=0), [0.01, -0.02, 1.03], atol=0.002)


def test_accel_noise_has_the_requested_standard_deviation():
    imu = sim.simulate_imu(sim.hover(50.0), sim.ImuModel(accel_noise=0.01), np.random.default_rng(0))
    assert imu.accel[:, 0].std() == pytest.approx(0.01, rel=0.05)


def test_accel_range_clips_and_flags_readings():
    imu = sim.simulate_imu(sim.rocket(), sim.ImuModel(accel_range=10.0), np.random.default_rng(0))
    assert imu.accel.max() == 10.0
    assert imu.clipped.any() and not imu.clipped[0]


def test_gyro_reports_the_body_rate_of_a_rolling_trajectory():
    trajectory = sim.hover(2.0)
    roll = np.radians(30.0) * trajectory.time  # 30 °/s
    from fusion_altitude.sensors import euler_to_quaternion
    trajectory.attitude = euler_to_quaternion(roll, 0.0 * roll, 0.0 * roll)
    imu = sim.simulate_imu(trajectory, sim.ImuModel(), np.random.default_rng(0))
    np.testing.assert_allclose(imu.gyro[1:], np.tile([30.0, 0.0, 0.0], (199, 1)), atol=1e-6)


def test_baro_runs_at_its_own_rate():
    baro = sim.simulate_baro(sim.hover(10.0), sim.BaroModel(rate=25.0), np.random.default_rng(0))
    assert np.diff(baro.time).mean() == pytest.approx(0.04)


def test_baro_quantization_rounds_to_the_step():
    baro = sim.simulate_baro(sim.sinusoid(10.0), sim.BaroModel(quantization=0.25, noise=0.1), np.random.default_rng(0))
    np.testing.assert_allclose(baro.value / 0.25, np.round(baro.value / 0.25), atol=1e-9)


def test_baro_lag_delays_a_climb():
    trajectory = sim.climb_cruise_descend()
    lagged = sim.simulate_baro(trajectory, sim.BaroModel(lag=1.0), np.random.default_rng(0))
    climbing = (trajectory.vertical_velocity > 2.5)
    assert np.all(lagged.value[climbing] < trajectory.altitude[climbing])


def test_baro_drift_grows_with_time():
    baro = sim.simulate_baro(sim.hover(100.0, altitude=0.0), sim.BaroModel(drift_rate=0.01), np.random.default_rng(0))
    assert baro.value[-1] == pytest.approx(1.0, abs=0.01)


def test_baro_prop_wash_adds_the_periodic_disturbance():
    baro = sim.simulate_baro(sim.hover(10.0, altitude=0.0), sim.BaroModel(prop_wash_amplitude=0.3,
                                                                           prop_wash_frequency=8.0),
                             np.random.default_rng(0))
    assert np.max(np.abs(baro.value)) == pytest.approx(0.3, abs=0.01)


def test_baro_dropouts_are_nan_at_the_requested_rate():
    baro = sim.simulate_baro(sim.hover(100.0), sim.BaroModel(dropout_probability=0.1), np.random.default_rng(0))
    assert np.isnan(baro.value).mean() == pytest.approx(0.1, abs=0.02)


def test_baro_stuck_glitch_repeats_a_value():
    baro = sim.simulate_baro(sim.sinusoid(60.0), sim.BaroModel(noise=0.1, stuck_probability=0.002, stuck_duration=0.5),
                             np.random.default_rng(0))
    assert np.sum(np.diff(baro.value) == 0) > 40


def test_baro_spikes_produce_outliers():
    model = sim.BaroModel(spike_probability=0.01, spike_magnitude=5.0)
    baro = sim.simulate_baro(sim.hover(100.0, altitude=0.0), model, np.random.default_rng(0))
    assert np.sum(np.abs(baro.value) > 1.0) > 30


def test_baro_pressure_output_matches_the_isa_model():
    baro = sim.simulate_baro(sim.hover(1.0, altitude=1000.0), sim.BaroModel(), np.random.default_rng(0))
    assert baro.pressure[0] == pytest.approx(89874.6, abs=1.0)


def test_rangefinder_has_no_reading_beyond_its_range():
    trajectory = sim.climb_cruise_descend(cruise_altitude=60.0)
    stream = sim.simulate_rangefinder(trajectory, sim.RangefinderModel(max_range=12.0, dropout_probability=0.0),
                                      np.random.default_rng(0))
    high = np.interp(stream.time, trajectory.time, trajectory.altitude) > 13.0
    assert np.all(np.isnan(stream.value[high])) and np.isfinite(stream.value[~high & (stream.time > 2)]).any()


def test_rangefinder_measures_the_height_above_its_terrain_with_its_steps():
    model = sim.RangefinderModel(noise=0.0, dropout_probability=0.0,
                                 terrain=sim.Terrain(ground_altitude=2.0, steps=((10.0, 1.0), (20.0, -1.5))))
    stream = sim.simulate_rangefinder(sim.hover(30.0, altitude=7.0), model, np.random.default_rng(0))
    expected = np.select([stream.time < 10.0, stream.time < 20.0], [5.0, 4.0], 5.5)
    np.testing.assert_allclose(stream.value, expected, atol=1e-12)


def test_rangefinder_keywords_ground_altitude_and_terrain_steps_set_its_terrain():
    model = sim.RangefinderModel(ground_altitude=3.0, terrain_steps=((20.0, 1.0),))
    assert model.terrain == sim.Terrain(ground_altitude=3.0, steps=((20.0, 1.0),))
    assert (model.ground_altitude, model.terrain_steps) == (3.0, ((20.0, 1.0),))
    assert sim.RangefinderModel().terrain == sim.Terrain() == sim.Terrain(0.0, ())


def test_rangefinder_through_the_keywords_gives_the_same_readings_as_through_the_terrain():
    trajectory = sim.takeoff_landing()
    by_keywords = sim.RangefinderModel(ground_altitude=-0.5, terrain_steps=((3.0, 0.4), (6.0, -0.2)))
    by_terrain = sim.RangefinderModel(terrain=sim.Terrain(-0.5, ((3.0, 0.4), (6.0, -0.2))))
    first, second = (sim.simulate_rangefinder(trajectory, model, np.random.default_rng(5))
                     for model in (by_keywords, by_terrain))
    assert first.value.tobytes() == second.value.tobytes()


def test_gps_noise_grows_as_satellites_drop():
    model = sim.GpsModel(satellites=(20, 5), jump_probability=0.0, rate=10.0)
    trajectory = sim.hover(600.0, altitude=0.0)
    stream, satellites = sim.simulate_gps(trajectory, model, np.random.default_rng(0))
    assert np.nanstd(stream.value[satellites >= 16]) < np.nanstd(stream.value[(satellites <= 7) & (satellites >= 5)])


def test_gps_has_no_fix_below_minimum_satellites():
    stream, satellites = sim.simulate_gps(sim.hover(60.0), sim.GpsModel(satellites=(8, 2)), np.random.default_rng(0))
    assert np.all(np.isnan(stream.value[satellites < 5]))


def test_same_seed_gives_identical_sensor_streams():
    def streams(seed):
        rng = np.random.default_rng(seed)
        trajectory = sim.takeoff_landing()
        return (sim.simulate_imu(trajectory, sim.ImuModel(accel_noise=0.01, gyro_noise=0.1), rng).accel,
                sim.simulate_baro(trajectory, sim.BaroModel(noise=0.1, spike_probability=0.01), rng).value)
    for a, b in zip(streams(3), streams(3)):
        np.testing.assert_array_equal(a, b)


def test_ahrs_vertical_acceleration_is_near_zero_for_a_level_hover():
    imu = sim.simulate_imu(sim.hover(5.0), sim.ImuModel(), np.random.default_rng(0))
    assert np.max(np.abs(sim.ahrs_vertical_acceleration(imu))) < 1e-3


def test_ahrs_passes_tilt_error_from_gyro_bias_into_the_vertical_channel():
    trajectory = sim.hover(30.0)
    biased = sim.simulate_imu(trajectory, sim.ImuModel(gyro_bias=(2.0, 0.0, 0.0)), np.random.default_rng(0))
    clean = sim.simulate_imu(trajectory, sim.ImuModel(), np.random.default_rng(0))
    assert np.abs(sim.ahrs_vertical_acceleration(biased)).mean() > np.abs(sim.ahrs_vertical_acceleration(clean)).mean()


def test_align_to_places_each_sample_on_the_first_step_at_or_after_it():
    grid = np.arange(10) * 0.01
    aligned = sim.align_to(grid, sim.SensorStream(np.array([0.0, 0.025, 0.05]), np.array([1.0, 2.0, 3.0])))
    np.testing.assert_array_equal(np.flatnonzero(np.isfinite(aligned)), [0, 3, 5])


# --- logging faults ---------------------------------------------------------------------------

def test_logging_gap_removes_every_row_inside_it():
    from fusion_altitude.sim import LogFaultModel, apply_log_faults
    time = np.arange(0.0, 10.0, 0.01)
    written, columns, _ = apply_log_faults(time, {"a": time}, LogFaultModel(gap_start=3.0, gap_duration=2.0))
    assert not np.any((written >= 3.0) & (written < 5.0))
    assert np.max(np.diff(written)) == pytest.approx(2.01)
    np.testing.assert_array_equal(columns["a"], written)


def test_repeated_timestamp_fault_repeats_the_previous_time_and_keeps_values():
    from fusion_altitude.sim import LogFaultModel, apply_log_faults
    time = np.arange(0.0, 10.0, 0.01)
    written, columns, repeated = apply_log_faults(time, {"a": time}, LogFaultModel(repeat_probability=0.1),
                                                  np.random.default_rng(3))
    assert repeated == int(np.sum(np.diff(written) == 0)) and 50 < repeated < 150
    assert np.all(np.diff(written) >= 0)
    np.testing.assert_array_equal(columns["a"], time)


def test_coarse_timestamp_clock_makes_fast_rows_share_stamps():
    from fusion_altitude.sim import LogFaultModel, apply_log_faults
    time = np.arange(0.0, 1.0, 0.005)
    written, _, repeated = apply_log_faults(time, {}, LogFaultModel(timestamp_resolution=0.01))
    assert repeated == 100


def test_log_faults_are_deterministic_for_a_seed():
    from fusion_altitude.sim import LogFaultModel, apply_log_faults
    time = np.arange(0.0, 5.0, 0.01)
    model = LogFaultModel(repeat_probability=0.2)
    first = apply_log_faults(time, {}, model, np.random.default_rng(7))[0]
    second = apply_log_faults(time, {}, model, np.random.default_rng(7))[0]
    np.testing.assert_array_equal(first, second)


def test_log_fault_column_of_wrong_length_is_named():
    from fusion_altitude.sim import LogFaultModel, apply_log_faults
    with pytest.raises(ValueError, match="column 'baro' has 3 rows, time 5"):
        apply_log_faults(np.arange(5.0), {"baro": np.zeros(3)}, LogFaultModel())


def test_simulated_log_with_faults_reads_back_with_gap_and_repeats_counted(tmp_path):
    from fusion_altitude import logs
    from fusion_altitude.sim import LogFaultModel, apply_log_faults, write_log_csv
    time = np.arange(0.0, 20.0, 0.01)
    columns = {"accel": np.zeros(time.size), "baro": np.where(np.arange(time.size) % 5 == 0, 1.0, np.nan)}
    written, columns, repeated = apply_log_faults(
        time, columns, LogFaultModel(gap_start=8.0, gap_duration=2.0, repeat_probability=0.05),
        np.random.default_rng(1))
    write_log_csv(str(tmp_path / "sim.csv"), written, columns)
    with pytest.warns(logs.LogWarning):
        data = logs.read_csv_log(str(tmp_path / "sim.csv"), "time", "accel", "baro")
    assert data.repeated_timestamps == repeated
    assert data.gap_count == 1
