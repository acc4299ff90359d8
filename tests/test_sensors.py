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



def _random_steps(count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    steps = rng.standard_normal((count, 4)) * [[50.0, 1.0, 1.0, 1.0]]  # mostly small rotations, as from a gyro
    return steps / np.linalg.norm(steps, axis=1)[:, None]


def test_gyro_attitude_integrates_in_c_with_the_python_loops_bits():
    """Bit for bit, not a bound: the C loop has the Python loop's operation order and no FMA contraction."""
    from fusion_altitude._core._strapdown import integrate_steps
    from fusion_altitude.sensors import _integrate_steps_python
    steps = _random_steps(50_000, 3)
    initial = np.array([0.5, -0.5, 0.5, 0.5])
    assert integrate_steps(initial, steps).tobytes() == _integrate_steps_python(initial, steps).tobytes()


def test_gyro_attitude_uses_the_c_loop_where_the_extension_is_built(monkeypatch):
    import fusion_altitude.sensors as sensors
    gyro = np.tile([30.0, -10.0, 5.0], (500, 1))
    expected = gyro_attitude(gyro, 0.01, [0.0, 0.0, 1.0])
    monkeypatch.setattr(sensors, "_integrate_steps_python", None)  # would fail if called
    assert gyro_attitude(gyro, 0.01, [0.0, 0.0, 1.0]).tobytes() == expected.tobytes()


def test_gyro_attitude_of_no_samples_is_empty():
    from fusion_altitude._core._strapdown import integrate_steps
    from fusion_altitude.sensors import _integrate_steps_python
    assert integrate_steps([1.0, 0.0, 0.0, 0.0], np.zeros((0, 4))).shape == (0, 4)
    assert _integrate_steps_python(np.array([1.0, 0.0, 0.0, 0.0]), np.zeros((0, 4))).shape == (0, 4)


@pytest.mark.parametrize("initial, steps, name", [([1.0, 0.0, 0.0], np.zeros((2, 4)), "initial"),
                                                  ([1.0, 0.0, 0.0, 0.0], np.zeros((2, 3)), "steps")])
def test_the_c_integration_refuses_a_wrong_shape_by_name(initial, steps, name):
    from fusion_altitude._core._strapdown import integrate_steps
    with pytest.raises(ValueError, match=name):
        integrate_steps(initial, steps)


# --- atmosphere: 1976 U.S. Standard Atmosphere values, other lapse rates, hypsometric ----------

# U.S. Standard Atmosphere 1976, geopotential altitude (m) → pressure (Pa), troposphere layer.
US_STANDARD_ATMOSPHERE_1976 = [(-500.0, 107477.0), (0.0, 101325.0), (1000.0, 89874.6), (2000.0, 79495.2),
                               (3000.0, 70108.5), (5000.0, 54019.9), (8000.0, 35599.8), (11000.0, 22632.1)]


@pytest.mark.parametrize("altitude, pressure", US_STANDARD_ATMOSPHERE_1976)
def test_pressure_to_altitude_matches_the_1976_standard_atmosphere_table(altitude, pressure):
    assert pressure_to_altitude(pressure) == pytest.approx(altitude, abs=1.0)


@pytest.mark.parametrize("altitude, pressure", US_STANDARD_ATMOSPHERE_1976)
def test_altitude_to_pressure_matches_the_1976_standard_atmosphere_table(altitude, pressure):
    assert altitude_to_pressure(altitude) == pytest.approx(pressure, rel=2e-5)


def test_isa_temperature_matches_the_1976_table_at_5_km():
    from fusion_altitude.sensors import isa_temperature
    assert isa_temperature(5000.0) == pytest.approx(255.65)


def _hydrostatic_altitude(pressure, p0, t0, lapse_rate, steps=200_000):
    """Integrate dh/dp = −R·T(h)/(g·p) from p0 down to pressure with T = t0 − L·h (independent of the closed form)."""
    pressures = np.linspace(p0, pressure, steps)
    h = 0.0
    for p_from, p_to in zip(pressures[:-1], pressures[1:]):
        def slope(p, h_):
            return -287.05287 * (t0 - lapse_rate * h_) / (9.80665 * p)
        dp = p_to - p_from
        k1 = slope(p_from, h)
        k2 = slope(p_from + dp / 2, h + dp / 2 * k1)
        k3 = slope(p_from + dp / 2, h + dp / 2 * k2)
        k4 = slope(p_to, h + dp * k3)
        h += dp / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return h


def test_lapse_rate_other_than_isa_follows_the_hydrostatic_equation():
    # 0.0098 K/m (dry adiabatic): the exponent must follow the lapse rate (issue: 1202 m instead of ~1794 m).
    pressure = 81366.0
    expected = _hydrostatic_altitude(pressure, 101325.0, 288.15, 0.0098, steps=20_000)
    assert pressure_to_altitude(pressure, lapse_rate_k_per_m=0.0098) == pytest.approx(expected, abs=0.05)
    assert expected == pytest.approx(1794.0, abs=2.0)


def test_zero_lapse_rate_is_the_isothermal_atmosphere():
    assert pressure_to_altitude(101325.0 / np.e, lapse_rate_k_per_m=0.0) == pytest.approx(
        287.05287 * 288.15 / 9.80665)


def test_altitude_to_pressure_with_another_lapse_rate_inverts_it():
    assert pressure_to_altitude(altitude_to_pressure(1500.0, lapse_rate_k_per_m=0.0098),
                                lapse_rate_k_per_m=0.0098) == pytest.approx(1500.0)


def test_non_positive_sea_level_pressure_is_refused_by_name():
    with pytest.raises(ValueError, match="sea_level_pa must be a positive number, got -5"):
        pressure_to_altitude(100000.0, sea_level_pa=-5.0)


def test_height_above_a_high_pad_uses_the_pads_temperature_not_288_k():
    from fusion_altitude.sensors import height_above_ground
    # Pad at 1300 m in the ISA atmosphere; 500 m above it the table pressure is that of 1800 m.
    pad, above = altitude_to_pressure(1300.0), altitude_to_pressure(1800.0)
    assert height_above_ground(above, pad) == pytest.approx(500.0, abs=0.01)
    # The QFE shortcut (pad pressure as "sea level" at 288.15 K) is off by T_pad/288.15 ≈ 3 %.
    assert pressure_to_altitude(above, sea_level_pa=pad) == pytest.approx(500.0 * 288.15 / 279.7, rel=1e-3)


def test_height_above_ground_with_a_measured_ground_temperature():
    from fusion_altitude.sensors import height_above_ground
    pressure = 90000.0 * np.exp(-9.80665 * 200.0 / (287.05287 * 300.0))  # isothermal 300 K layer, 200 m
    assert height_above_ground(pressure, 90000.0, 300.0, temperature_k=300.0) == pytest.approx(200.0, abs=1e-6)


def test_height_above_ground_refuses_a_non_positive_temperature_by_index():
    from fusion_altitude.sensors import height_above_ground
    with pytest.raises(ValueError, match=r"temperature_k\[1\] must be positive"):
        height_above_ground([90000.0, 89000.0], 90000.0, 290.0, temperature_k=[290.0, -3.0])
