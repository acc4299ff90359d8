"""Raw-IMU flights for the inertial navigation filter, built from the simulator.

:func:`simulate_raw_imu` takes a scenario of :mod:`fusion_altitude.scenarios`
(its trajectory, IMU and baro models), puts a stationary start in front of it
(the vehicle at rest on the ground, then a smooth take-off into the scenario's
motion), optionally rocks the attitude, adds a baro offset and a magnetic
disturbance, and returns everything a raw-IMU estimator needs — gyro (rad/s),
accelerometer (m/s²) and magnetometer in the body frame, baro on the IMU grid —
with the truth and the simulated sensor errors next to it. Nothing here is an
estimator; :func:`run_ins` and :func:`run_two_step` run the INS and the
two-step pipeline (imufusion AHRS, then the altitude observer) on a flight.

Frames and units as in :mod:`fusion_altitude.sim`: earth NWU (z up), body
accel +g on z when level at rest. Every random draw comes from one
``numpy.random.Generator`` seeded by ``seed``, in a fixed order (the IMU's,
then the baro's), so a seed gives the same flight bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional, Tuple

import numpy as np

from . import trajectories as sim
from .._core._common import GRAVITY
from ..sensors import euler_to_quaternion

__all__ = ["RawImuFlight", "simulate_raw_imu", "run_ins", "run_two_step", "attitude_error_deg"]


@dataclass
class RawImuFlight(sim.TrajectoryFlight):
    """A simulated flight with a raw IMU.

    Attributes
    ----------
    trajectory : sim.Trajectory
        Truth on the IMU grid (time s, altitude m, vertical velocity m/s, attitude body → NWU).
    imu : sim.ImuStream
        The IMU as :mod:`fusion_altitude.sim` reports it (accel g, gyro °/s, mag), disturbance included.
    gyro : numpy.ndarray
        Angular rate, body, rad/s, shape (n, 3).
    accel : numpy.ndarray
        Specific force, body, m/s², shape (n, 3).
    mag : numpy.ndarray
        Magnetic field, body, arbitrary units, shape (n, 3).
    baro_altitude : numpy.ndarray
        Baro altitude on the IMU grid, m; NaN on steps without a sample.
    dt : float
        IMU period, s.
    rest_duration : float
        Seconds at rest at the start.
    gyro_bias : numpy.ndarray
        Simulated gyro bias, rad/s, body.
    accel_bias : numpy.ndarray
        Simulated accelerometer bias, m/s², body.
    baro_offset : float
        What the baro reads above the truth altitude, m (plus noise and disturbances).
    mag_disturbance : tuple or None
        (start s, end s, field added in the body frame) or None.
    transient : float
        Seconds after the end of the rest excluded from statistics.
    scenario : str
        The scenario the motion comes from.
    """

    trajectory: sim.Trajectory
    imu: sim.ImuStream
    gyro: np.ndarray
    accel: np.ndarray
    mag: np.ndarray
    baro_altitude: np.ndarray
    dt: float
    rest_duration: float
    gyro_bias: np.ndarray
    accel_bias: np.ndarray
    baro_offset: float
    mag_disturbance: Optional[Tuple[float, float, Tuple[float, float, float]]]
    transient: float
    scenario: str

    @property
    def evaluated(self) -> np.ndarray:
        """Steps counted in statistics: after the rest and the scenario's transient."""
        return self.time >= self.rest_duration + self.transient


def _with_rest(trajectory: sim.Trajectory, rest: float, ramp: float) -> sim.Trajectory:
    """The trajectory delayed by ``rest`` s at rest, faded in over ``ramp`` s (raised cosine), h, v, a consistent."""
    rate = trajectory.rate
    extra = int(round(rest * rate))
    n = len(trajectory) + extra
    time = np.arange(n) / rate
    altitude = np.concatenate([np.full(extra, trajectory.altitude[0]), trajectory.altitude])
    weight = np.clip((time - rest) / ramp, 0.0, 1.0) if ramp > 0 else (time >= rest).astype(float)
    weight = 0.5 - 0.5 * np.cos(np.pi * weight)
    altitude = trajectory.altitude[0] + weight * (altitude - trajectory.altitude[0])
    velocity = np.gradient(altitude, time)
    accel = np.gradient(velocity, time)
    altitude, velocity = sim.from_acceleration(time, accel, float(altitude[0]))
    attitude = np.concatenate([np.repeat(trajectory.attitude[:1], extra, axis=0), trajectory.attitude])
    return sim.Trajectory(time, altitude, velocity, accel, attitude, trajectory.name + " with a stationary start")


def _rocking(time: np.ndarray, start: float, amplitude_deg: float) -> np.ndarray:
    """Attitude rocking after ``start``: roll and pitch sinusoids of ``amplitude_deg`` (0.23, 0.17 Hz), slow yaw."""
    on = np.clip((time - start) / 2.0, 0.0, 1.0)
    roll = np.radians(amplitude_deg) * on * np.sin(2 * np.pi * 0.23 * time)
    pitch = np.radians(amplitude_deg) * on * np.sin(2 * np.pi * 0.17 * time + 1.0)
    yaw = np.radians(30.0) * on * np.sin(2 * np.pi * 0.05 * time)
    return euler_to_quaternion(roll, pitch, yaw)


def simulate_raw_imu(scenario: str = "realistic", seed: int = 0, rest_duration: float = 10.0, ramp: float = 2.0,
                     rocking_deg: float = 0.0, baro_offset: float = 2.5,
                     mag_disturbance: Optional[Tuple[float, float, Tuple[float, float, float]]] = None
                     ) -> RawImuFlight:
    """A scenario's flight from a raw IMU, with a stationary start.

    Parameters
    ----------
    scenario : str
        A name of :func:`fusion_altitude.scenarios.scenario_names` (its trajectory, IMU and baro models).
    seed : int
        Seed of every random draw.
    rest_duration : float
        Seconds at rest before the motion, s (≥ 0).
    ramp : float
        Seconds over which the scenario's motion fades in after the rest, s.
    rocking_deg : float
        Roll/pitch rocking amplitude after the rest, degrees (0: the scenario's own attitude).
    baro_offset : float
        Constant baro reading above the truth, m: the baro bias an INS should learn at rest.
    mag_disturbance : (start s, end s, (x, y, z)), optional
        A field added to the magnetometer in the body frame over [start, end).

    Returns
    -------
    RawImuFlight
    """
    from . import scenarios

    if not rest_duration >= 0:
        raise ValueError(f"rest_duration must be >= 0 s, got {rest_duration!r}")
    spec = scenarios.spec(scenario)
    rng = np.random.default_rng(seed)
    trajectory = _with_rest(spec.trajectory(), rest_duration, ramp)
    if rocking_deg:
        trajectory = replace(trajectory, attitude=_rocking(trajectory.time, rest_duration, rocking_deg))
    imu = sim.simulate_imu(trajectory, spec.imu, rng)
    if mag_disturbance is not None:
        start, end, field = mag_disturbance
        window = (imu.time >= start) & (imu.time < end)
        imu.mag = imu.mag + np.where(window[:, None], np.asarray(field, dtype=float), 0.0)
    baro = sim.simulate_baro(trajectory, spec.baro, rng)
    baro.value = baro.value + baro_offset
    return RawImuFlight(
        trajectory=trajectory, imu=imu, gyro=np.radians(imu.gyro), accel=imu.accel * GRAVITY, mag=imu.mag.copy(),
        baro_altitude=sim.align_to(trajectory.time, baro), dt=trajectory.dt, rest_duration=rest_duration,
        gyro_bias=np.radians(np.asarray(spec.imu.gyro_bias, dtype=float)),
        accel_bias=np.asarray(spec.imu.accel_bias, dtype=float) * GRAVITY, baro_offset=baro_offset,
        mag_disturbance=mag_disturbance, transient=spec.transient, scenario=scenario)


def run_ins(flight: RawImuFlight, settings=None, use_magnetometer: bool = True):
    """The INS (C binding) over a flight; returns its :class:`fusion_altitude.InsBatch`."""
    from .._core._ins import InsEstimator

    return InsEstimator(settings).update_batch(flight.gyro, flight.accel, flight.dt, flight.baro_altitude,
                                               flight.mag if use_magnetometer else None)


def run_two_step(flight: RawImuFlight, use_magnetometer: bool = True):
    """The two-step pipeline: imufusion AHRS (defaults, the flight's rate) for the vertical
    acceleration, then the altitude observer (the VTOL preset, scaled to the baro rate).

    Returns
    -------
    (AltitudeBatch, numpy.ndarray)
        The observer's outputs and the AHRS quaternions (w, x, y, z) per step.
    """
    import imufusion

    from .._core._observer import AltitudeEstimator, AltitudeSettings
    from ..tuning import settings_for_baro_rate

    ahrs = imufusion.Ahrs()
    rate = 1.0 / flight.dt
    if abs(rate - 100.0) > 1e-9:
        ahrs.set_settings(imufusion.AhrsSettings(sample_rate=rate))
    n = flight.time.size
    vertical = np.empty(n)
    quaternion = np.empty((n, 4))
    gyro = np.ascontiguousarray(flight.imu.gyro, dtype=float)
    accel = np.ascontiguousarray(flight.imu.accel, dtype=float)
    mag = np.ascontiguousarray(flight.imu.mag, dtype=float)
    for i in range(n):
        if use_magnetometer:
            ahrs.update(gyro[i], accel[i], mag[i])
        else:
            ahrs.update_no_magnetometer(gyro[i], accel[i])
        vertical[i] = ahrs.get_earth_acceleration()[2]
        quaternion[i] = ahrs.get_quaternion()
    steps_per_baro = n / max(int(np.sum(np.isfinite(flight.baro_altitude))), 1)
    observer = AltitudeEstimator(settings_for_baro_rate(AltitudeSettings.preset("vtol"), steps_per_baro))
    return observer.update_batch(vertical * GRAVITY, flight.baro_altitude, flight.dt), quaternion


def attitude_error_deg(estimate, truth, tilt_only: bool = False) -> np.ndarray:
    """Angle between estimated and true attitudes (quaternions (w, x, y, z), body → earth), degrees.

    ``tilt_only`` measures the angle between the estimated and true body up
    directions instead (heading errors excluded).
    """
    q = np.asarray(estimate, dtype=float)
    p = np.asarray(truth, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    p = p / np.linalg.norm(p, axis=-1, keepdims=True)
    if tilt_only:
        def up(x):
            w, a, b, c = x[..., 0], x[..., 1], x[..., 2], x[..., 3]
            return np.stack([2 * (a * c - w * b), 2 * (b * c + w * a), 1 - 2 * (a * a + b * b)], axis=-1)
        cosine = np.clip(np.sum(up(q) * up(p), axis=-1), -1.0, 1.0)
        return np.degrees(np.arccos(cosine))
    dot = np.clip(np.abs(np.sum(q * p, axis=-1)), 0.0, 1.0)
    return np.degrees(2 * np.arccos(dot))
