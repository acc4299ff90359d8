"""Specification of the sensor conversions: ISA pressure ↔ altitude and body accel → vertical accel."""

import numpy as np
import pytest

from fusion_altitude import GRAVITY
from fusion_altitude.sensors import (altitude_to_pressure, euler_to_quaternion, gyro_attitude, pressure_to_altitude,
                                     quaternion_to_matrix, vertical_acceleration)

G = GRAVITY


# --- pressure ↔ altitude -----------------------------------------------------

def test_sea_level_pressure_is_altitude_zero():
    assert pressure_to_altitude(101325.0) == pytest.approx(0.0, abs=1e-9)


def test_isa_pressure_at_1000_m_matches_the_standard_table():
    # ISA table: 89 874.6 Pa at 1000 m.
    assert pressure_to_altitude(89874.6) == pytest.approx(1000.0, abs=0.5)


def test_isa_pressure_at_tropopause_matches_the_standard_table():
    # ISA table: 22 632 Pa at 11 000 m.
    assert altitude_to_pressure(11000.0) == pytest.approx(22632.0, rel=1e-3)


def test_lower_pressure_means_higher_altitude():
    altitudes = pressure_to_altitude(np.array([101000.0, 100000.0, 90000.0]))
    assert np.all(np.diff(altitudes) > 0)


def test_pressure_drop_of_12_pa_near_sea_level_is_about_one_metre():
    assert pressure_to_altitude(101325.0 - 12.01) == pytest.approx(1.0, abs=0.01)


def test_ground_pressure_as_reference_gives_height_above_ground():
    assert pressure_to_altitude(95000.0, sea_level_pa=95000.0) == pytest.approx(0.0, abs=1e-9)


def test_altitude_to_pressure_inverts_pressure_to_altitude():
    altitude = np.linspace(-400.0, 20000.0, 50)
    np.testing.assert_allclose(pressure_to_altitude(altitude_to_pressure(altitude)), altitude, atol=1e-6)


def test_pressure_to_altitude_is_vectorised_and_keeps_shape():
    assert pressure_to_altitude(np.full((2, 3), 100000.0)).shape == (2, 3)


def test_nan_pressure_gives_nan_altitude():
    assert np.isnan(pressure_to_altitude(np.nan))


def test_non_positive_pressure_gives_nan():
    assert np.all(np.isnan(pressure_to_altitude(np.array([0.0, -5.0]))))


def test_above_tropopause_the_troposphere_formula_reads_low():
    # Real ISA at 20 km (isothermal 216.65 K above 11 km): 5474.9 Pa.
    assert pressure_to_altitude(5474.9) < 20000.0 - 500.0


# --- vertical acceleration: frames, units, attitude forms --------------------

LEVEL_Q = np.array([1.0, 0.0, 0.0, 0.0])


def test_ned_level_at_rest_is_zero():
    assert vertical_acceleration([0.0, 0.0, -G], LEVEL_Q, frame="NED") == pytest.approx(0.0, abs=1e-12)


def test_ned_level_accelerating_up_at_one_g_is_plus_g():
    # Body z points down: climbing at 1 g, the accelerometer reads −2 g on z.
    assert vertical_acceleration([0.0, 0.0, -2 * G], LEVEL_Q, frame="NED") == pytest.approx(G)


def test_ned_free_fall_is_minus_g():
    assert vertical_acceleration([0.0, 0.0, 0.0], LEVEL_Q, frame="NED") == pytest.approx(-G)


def test_enu_level_at_rest_is_zero():
    assert vertical_acceleration([0.0, 0.0, G], LEVEL_Q, frame="ENU") == pytest.approx(0.0, abs=1e-12)


def test_enu_level_accelerating_up_at_half_g_is_plus_half_g():
    assert vertical_acceleration([0.0, 0.0, 1.5 * G], LEVEL_Q, frame="ENU") == pytest.approx(0.5 * G)


def test_nwu_level_accelerating_down_is_negative():
    assert vertical_acceleration([0.0, 0.0, 0.8 * G], LEVEL_Q, frame="NWU") == pytest.approx(-0.2 * G)


def test_g_units_are_scaled_by_standard_gravity():
    assert vertical_acceleration([0.0, 0.0, 1.25], LEVEL_Q, frame="ENU", accel_units="g") == pytest.approx(0.25 * G)


def test_g_units_at_rest_in_ned_are_zero():
    assert vertical_acceleration([0.0, 0.0, -1.0], LEVEL_Q, frame="NED", accel_units="g") == pytest.approx(0.0, abs=1e-12)


def test_ned_pitched_up_90_degrees_at_rest_is_zero():
    # Nose up 90°: body x points up, so at rest the accelerometer reads +g on x.
    assert vertical_acceleration([G, 0.0, 0.0], [0.0, np.pi / 2, 0.0], frame="NED") == pytest.approx(0.0, abs=1e-9)


def test_ned_rolled_30_degrees_at_rest_with_euler_angles_is_zero():
    roll = np.radians(30.0)
    reading = [0.0, -G * np.sin(roll), -G * np.cos(roll)]
    assert vertical_acceleration(reading, [roll, 0.0, 0.0], frame="NED") == pytest.approx(0.0, abs=1e-9)


def test_enu_tilt_ignored_leaks_gravity_as_negative_acceleration():
    # 10° roll reading interpreted as level: g·(cos 10° − 1) ≈ −0.149 m/s².
    roll = np.radians(10.0)
    reading = [0.0, G * np.sin(roll), G * np.cos(roll)]
    assert vertical_acceleration(reading, LEVEL_Q, frame="ENU") == pytest.approx(G * (np.cos(roll) - 1.0))


def test_quaternion_and_euler_attitudes_agree():
    rng = np.random.default_rng(1)
    angles = rng.uniform(-0.6, 0.6, size=(20, 3))
    accel = rng.normal(0.0, 5.0, size=(20, 3))
    q = euler_to_quaternion(angles[:, 0], angles[:, 1], angles[:, 2])
    np.testing.assert_allclose(vertical_acceleration(accel, q, frame="NED"),
                               vertical_acceleration(accel, angles, frame="NED"), atol=1e-12)


def test_yaw_does_not_change_vertical_acceleration():
    reading = [1.0, 2.0, -G + 0.3]
    values = [vertical_acceleration(reading, [0.1, 0.2, yaw], frame="NED") for yaw in (0.0, 1.0, 3.0)]
    assert np.ptp(values) < 1e-12


def test_vertical_acceleration_is_vectorised():
    accel = np.tile([0.0, 0.0, -G], (7, 1))
    assert vertical_acceleration(accel, np.tile(LEVEL_Q, (7, 1))).shape == (7,)


def test_unknown_frame_is_rejected():
    with pytest.raises(ValueError, match="frame"):
        vertical_acceleration([0, 0, 1], LEVEL_Q, frame="XYZ")


def test_unknown_units_are_rejected():
    with pytest.raises(ValueError, match="accel_units"):
        vertical_acceleration([0, 0, 1], LEVEL_Q, accel_units="ft/s^2")


def test_attitude_of_wrong_length_is_rejected():
    with pytest.raises(ValueError, match="attitude"):
        vertical_acceleration([0, 0, 1], [1.0, 0.0])


# --- quaternions and gyro integration -----------------------------------------

def test_quaternion_matrix_of_yaw_90_maps_x_to_y():
    rotation = quaternion_to_matrix(euler_to_quaternion(0.0, 0.0, np.pi / 2))
    np.testing.assert_allclose(rotation @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-12)


def test_gyro_attitude_levels_initial_attitude_on_gravity():
    # Sensor lying on its side: the specific force at rest is along body −y.
    q = gyro_attitude(np.zeros((1, 3)), 0.01, [0.0, -9.8, 0.0])
    np.testing.assert_allclose(quaternion_to_matrix(q[0]) @ [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], atol=1e-12)


def test_gyro_attitude_integrates_a_constant_rate():
    # 90 °/s about body x for 1 s from level: rolled 90°.
    q = gyro_attitude(np.tile([90.0, 0.0, 0.0], (100, 1)), 0.01, [0.0, 0.0, 1.0])
    np.testing.assert_allclose(q[-1], euler_to_quaternion(np.pi / 2, 0.0, 0.0), atol=1e-9)


def test_gyro_attitude_removes_the_given_bias():
    q = gyro_attitude(np.tile([5.0, -3.0, 2.0], (100, 1)), 0.01, [0.0, 0.0, 1.0], gyro_bias_dps=[5.0, -3.0, 2.0])
    np.testing.assert_allclose(q[-1], [1.0, 0.0, 0.0, 0.0], atol=1e-12)
