"""Seeded, deterministic flight simulator: truth trajectories and sensor streams.

A simulation has three layers, each a plain function of numpy arrays:

1. a **trajectory** (:class:`Trajectory`): truth altitude h (m), vertical
   velocity v (m/s) and vertical acceleration a (m/s²), +up, with a truth
   attitude, on a base time grid (the IMU rate);
2. **sensor models** that turn the truth into what a sensor would report, each
   at its own rate with its own errors (:class:`ImuModel`, :class:`BaroModel`,
   :class:`RangefinderModel` over a :class:`Terrain`, :class:`GpsModel`);
3. the **attitude pipeline** (:func:`ahrs_vertical_acceleration`) that runs
   the IMU stream through a real AHRS (``imufusion``, the ``[ahrs]`` extra) so
   that tilt errors reach the vertical channel as in a real pipeline.

Every random draw comes from one ``numpy.random.Generator`` built from the
seed, in a fixed order, so the same seed gives the same streams bit for bit.

Frames: the simulator's earth frame is NWU (x north, y west, z **up**), the
convention of the ``imufusion`` AHRS defaults; accelerometers report specific
force in g (+1 g on body z when level and at rest), gyroscopes °/s,
magnetometers arbitrary units. All altitudes are m, +up.
"""

from __future__ import annotations

from dataclasses import InitVar, dataclass, field, replace
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from .._core._common import GRAVITY
from ..sensors import euler_to_quaternion, quaternion_multiply, quaternion_to_matrix

__all__ = [
    "Trajectory",
    "hover",
    "sinusoid",
    "climb_cruise_descend",
    "takeoff_landing",
    "balloon_ascent",
    "rocket",
    "TRAJECTORIES",
    "ImuModel",
    "ImuStream",
    "BaroModel",
    "BaroStream",
    "RangefinderModel",
    "Terrain",
    "GpsModel",
    "SensorStream",
    "simulate_imu",
    "simulate_baro",
    "simulate_rangefinder",
    "simulate_gps",
    "ahrs_vertical_acceleration",
    "truth_vertical_acceleration",
    "align_to",
    "LogFaultModel",
    "apply_log_faults",
    "write_log_csv",
]


# ----------------------------------------------------------------------------
# Trajectories


@dataclass
class Trajectory:
    """Truth of a flight on a uniform time grid.

    Attributes
    ----------
    time : numpy.ndarray
        Sample times, s, uniform, starting at 0.
    altitude : numpy.ndarray
        Truth altitude h, m, +up.
    vertical_velocity : numpy.ndarray
        Truth vertical velocity v = dh/dt, m/s, +up.
    vertical_acceleration : numpy.ndarray
        Truth vertical acceleration a = dv/dt, m/s², +up (gravity not included).
    attitude : numpy.ndarray
        Truth attitude, quaternion (w, x, y, z) body → earth (NWU), shape (n, 4).
    name : str
        Short description.
    """

    time: np.ndarray
    altitude: np.ndarray
    vertical_velocity: np.ndarray
    vertical_acceleration: np.ndarray
    attitude: np.ndarray
    name: str = ""

    @property
    def rate(self) -> float:
        """Sample rate of the grid, Hz."""
        return 1.0 / float(self.time[1] - self.time[0])

    @property
    def dt(self) -> float:
        """Sample period of the grid, s."""
        return float(self.time[1] - self.time[0])

    def __len__(self) -> int:
        return int(self.time.shape[0])


class TrajectoryFlight:
    """Base of a simulated flight that keeps its truth as ``trajectory`` (a :class:`Trajectory` on the
    flight's sample grid)."""

    @property
    def time(self) -> np.ndarray:
        """Sample times of the flight (its truth trajectory's grid), s."""
        return self.trajectory.time  # type: ignore[attr-defined]


def _grid(duration: float, rate: float) -> np.ndarray:
    if not (duration > 0 and rate > 0):
        raise ValueError(f"duration (s) and rate (Hz) must be > 0, got {duration!r}, {rate!r}")
    return np.arange(int(round(duration * rate))) / rate


def level_trajectory(n: int) -> np.ndarray:
    """Attitude quaternions (w, x, y, z) of a level vehicle for n samples: the identity, shape (n, 4)."""
    q = np.zeros((n, 4))
    q[:, 0] = 1.0
    return q


def from_acceleration(time: np.ndarray, accel: np.ndarray, altitude0: float = 0.0,
                       velocity0: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
    """Integrate a (m/s²) twice with the trapezoid rule: (h m, v m/s), consistent to O(dt²)."""
    dt = np.diff(time)
    velocity = velocity0 + np.concatenate([[0.0], np.cumsum(0.5 * (accel[1:] + accel[:-1]) * dt)])
    altitude = altitude0 + np.concatenate([[0.0], np.cumsum(0.5 * (velocity[1:] + velocity[:-1]) * dt)])
    return altitude, velocity


def _smooth_step(time: np.ndarray, start: float, duration: float) -> np.ndarray:
    """0 before start, 1 after start + duration, raised-cosine in between (dimensionless)."""
    x = np.clip((time - start) / duration, 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * x)


def _velocity_profile(time: np.ndarray, legs: Sequence[Tuple[float, float]], ramp: float,
                      altitude0: float = 0.0, name: str = "") -> Trajectory:
    """Trajectory whose vertical velocity moves between (start s, velocity m/s) legs with raised-cosine ramps."""
    velocity = np.zeros_like(time)
    previous = 0.0
    for start, target in legs:
        velocity += (target - previous) * _smooth_step(time, start, ramp)
        previous = target
    accel = np.gradient(velocity, time)
    altitude, velocity = from_acceleration(time, accel, altitude0)
    return Trajectory(time, altitude, velocity, accel, level_trajectory(time.size), name)


def hover(duration: float = 60.0, rate: float = 100.0, altitude: float = 10.0) -> Trajectory:
    """Stationary hover at ``altitude`` (m) for ``duration`` (s), sampled at ``rate`` (Hz)."""
    t = _grid(duration, rate)
    return Trajectory(t, np.full_like(t, altitude), np.zeros_like(t), np.zeros_like(t), level_trajectory(t.size), "hover")


def sinusoid(duration: float = 60.0, rate: float = 100.0, amplitude: float = 5.0,
             frequency: float = 0.1) -> Trajectory:
    """h = amplitude·sin(2π·frequency·t): amplitude m, frequency Hz, duration s, rate Hz.

    The reference motion of the published ``clean`` and ``realistic`` runs.
    """
    t = _grid(duration, rate)
    w = 2 * np.pi * frequency
    return Trajectory(t, amplitude * np.sin(w * t), amplitude * w * np.cos(w * t),
                      -amplitude * w * w * np.sin(w * t), level_trajectory(t.size), "sinusoid")


def climb_cruise_descend(duration: float = 120.0, rate: float = 100.0, climb_rate: float = 3.0,
                         cruise_altitude: float = 60.0, ramp: float = 2.0) -> Trajectory:
    """Climb at ``climb_rate`` (m/s) to ``cruise_altitude`` (m), cruise, descend back to 0.

    The climb and descent take cruise_altitude/climb_rate s each, the cruise
    the rest of ``duration`` (s). Velocity changes follow raised-cosine ramps
    of ``ramp`` s so the acceleration is continuous.
    """
    t = _grid(duration, rate)
    leg = cruise_altitude / climb_rate
    if 2 * (leg + ramp) + 2 > duration:
        raise ValueError(f"duration {duration} s is too short to climb {cruise_altitude} m and descend "
                         f"at {climb_rate} m/s")
    cruise_end = duration - leg - ramp - 1.0
    legs = [(1.0, climb_rate), (1.0 + leg, 0.0), (cruise_end, -climb_rate), (cruise_end + leg, 0.0)]
    return _velocity_profile(t, legs, ramp, name="climb-cruise-descend")


def takeoff_landing(duration: float = 40.0, rate: float = 100.0, hover_altitude: float = 5.0,
                    climb_rate: float = 1.5, ground_time: float = 3.0, tilt_deg: float = 5.0) -> Trajectory:
    """VTOL hop: ``ground_time`` s on the ground, climb to ``hover_altitude`` (m), hover, land, rest.

    While airborne the vehicle rocks in roll and pitch (±``tilt_deg`` °, 0.3
    and 0.23 Hz) as a multirotor holding position does; on the ground it is
    level. Climb and descent at ``climb_rate`` m/s.
    """
    t = _grid(duration, rate)
    ramp = 1.0
    leg = hover_altitude / climb_rate
    land_start = duration - ground_time - leg - ramp
    legs = [(ground_time, climb_rate), (ground_time + leg, 0.0), (land_start, -climb_rate),
            (land_start + leg, 0.0)]
    trajectory = _velocity_profile(t, legs, ramp, name="takeoff-landing")
    airborne = _smooth_step(t, ground_time, ramp) * (1 - _smooth_step(t, land_start + leg, ramp))
    tilt = np.radians(tilt_deg) * airborne
    trajectory.attitude = euler_to_quaternion(tilt * np.sin(2 * np.pi * 0.3 * t),
                                              tilt * np.sin(2 * np.pi * 0.23 * t + 1.0), 0.1 * t * airborne)
    return trajectory


def balloon_ascent(rate: float = 10.0, ceiling: float = 30000.0, ascent_rate: float = 5.0,
                   hold: float = 60.0) -> Trajectory:
    """Weather balloon: ascend at ``ascent_rate`` (m/s) to ``ceiling`` (m), then hold ``hold`` s.

    At the default 5 m/s to 30 km the flight lasts 100 min; sampled at
    ``rate`` Hz (10 by default to keep it small). The gondola swings
    (±3° at 0.5 Hz).
    """
    duration = ceiling / ascent_rate + 20.0 + hold
    t = _grid(duration, rate)
    trajectory = _velocity_profile(t, [(5.0, ascent_rate), (5.0 + ceiling / ascent_rate, 0.0)], 10.0,
                                   name="balloon")
    swing = np.radians(3.0) * np.sin(2 * np.pi * 0.5 * t)
    trajectory.attitude = euler_to_quaternion(swing, 0.5 * swing, 0.0 * t)
    return trajectory


def rocket(duration: float = 60.0, rate: float = 100.0, boost_accel: float = 150.0, burn_time: float = 2.5,
           pad_time: float = 2.0, drag_coefficient: float = 2.5e-4, drogue_velocity: float = -25.0) -> Trajectory:
    """Sounding rocket: pad, boost, coast with drag to apogee, drogue descent.

    Parameters
    ----------
    duration, rate : float
        Length s and sample rate Hz.
    boost_accel : float
        Net upward acceleration during the burn, m/s² (150 ≈ 15 g).
    burn_time, pad_time : float
        Motor burn s, time on the pad before ignition s.
    drag_coefficient : float
        Quadratic drag k (1/m): drag deceleration = k·v².
    drogue_velocity : float
        Descent rate under drogue, m/s (negative), reached 2 s after apogee.

    Notes
    -----
    The rocket points up the whole flight (attitude level: body z = up), so
    the vertical channel sees the full boost; the accelerometer range of the
    IMU model decides whether it clips.
    """
    t = _grid(duration, rate)
    dt = 1.0 / rate
    h = np.zeros_like(t)
    v = np.zeros_like(t)
    a = np.zeros_like(t)
    apogee_time = None
    for i in range(1, t.size):
        ti = t[i - 1]
        if ti < pad_time:
            ai = 0.0
        elif ti < pad_time + burn_time:
            ai = boost_accel - drag_coefficient * v[i - 1] * abs(v[i - 1])
        elif v[i - 1] > 0 and apogee_time is None:
            ai = -GRAVITY - drag_coefficient * v[i - 1] * abs(v[i - 1])
        else:
            if apogee_time is None:
                apogee_time = ti
            ai = (drogue_velocity - v[i - 1]) / 1.0  # first-order approach to the drogue rate (τ = 1 s)
        a[i - 1] = ai
        v[i] = v[i - 1] + ai * dt
        h[i] = h[i - 1] + 0.5 * (v[i] + v[i - 1]) * dt
        if h[i] < 0 and ti > pad_time + burn_time:
            h[i] = 0.0
            v[i] = 0.0
    a[-1] = a[-2]
    # Re-derive v, h from a with the same trapezoid rule as the other trajectories.
    h, v = from_acceleration(t, a)
    landed = np.maximum.accumulate((h < 0) & (t > pad_time + burn_time))
    h[landed], v[landed], a[landed] = 0.0, 0.0, 0.0
    return Trajectory(t, h, v, a, level_trajectory(t.size), "rocket")


#: Trajectory builders by name, for the simulator's scenario table and CLI.
TRAJECTORIES = {
    "hover": hover,
    "sinusoid": sinusoid,
    "climb-cruise-descend": climb_cruise_descend,
    "takeoff-landing": takeoff_landing,
    "balloon": balloon_ascent,
    "rocket": rocket,
}


# ----------------------------------------------------------------------------
# Sensor streams


@dataclass
class SensorStream:
    """One scalar sensor at its own rate.

    Attributes
    ----------
    time : numpy.ndarray
        Sample times, s.
    value : numpy.ndarray
        Reported values (m for altitudes); NaN where the sensor gave nothing.
    """

    time: np.ndarray
    value: np.ndarray


@dataclass
class BaroStream(SensorStream):
    """Barometer samples: ``value`` is baro altitude (m), ``pressure`` the same in Pa."""

    pressure: np.ndarray = field(default_factory=lambda: np.zeros(0))


@dataclass
class ImuStream:
    """IMU samples on the trajectory's grid.

    Attributes
    ----------
    time : numpy.ndarray
        Sample times, s.
    accel : numpy.ndarray
        Specific force, body frame (NWU: +1 g on z when level at rest), g, shape (n, 3).
    gyro : numpy.ndarray
        Angular rate, body frame, °/s, shape (n, 3).
    mag : numpy.ndarray
        Magnetic field, body frame, arbitrary units, shape (n, 3).
    clipped : numpy.ndarray
        True where any accelerometer axis hit the range limit.
    """

    time: np.ndarray
    accel: np.ndarray
    gyro: np.ndarray
    mag: np.ndarray
    clipped: np.ndarray


@dataclass
class ImuModel:
    """Accelerometer, gyroscope and magnetometer errors.

    Attributes
    ----------
    accel_bias : tuple of float
        Constant accelerometer bias per body axis, g.
    accel_noise : float
        Accelerometer white noise, standard deviation per axis per sample, g.
    accel_range : float
        Full-scale range, g; readings are clipped to ±range. ``inf`` disables.
    vibration_amplitude : tuple of float
        Amplitude of a sinusoidal vibration per axis, g (props / motor).
    vibration_frequency : float
        Vibration frequency, Hz (aliases against the sample rate as it would).
    gyro_bias : tuple of float
        Constant gyro bias per axis, °/s.
    gyro_noise : float
        Gyro white noise, standard deviation per axis per sample, °/s.
    mag_field : tuple of float
        Earth magnetic field in the earth frame (NWU), arbitrary units.
    mag_noise : float
        Magnetometer white noise, standard deviation per axis, same units.
    """

    accel_bias: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    accel_noise: float = 0.0
    accel_range: float = float("inf")
    vibration_amplitude: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    vibration_frequency: float = 0.0
    gyro_bias: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    gyro_noise: float = 0.0
    mag_field: Tuple[float, float, float] = (1.0, 0.0, 0.0)
    mag_noise: float = 0.0


def _body_rates(attitude: np.ndarray, dt: float) -> np.ndarray:
    """Body angular rate (rad/s) that takes attitude[i-1] to attitude[i]; the first sample gets 0."""
    conj = attitude * np.array([1.0, -1.0, -1.0, -1.0])
    delta = quaternion_multiply(conj[:-1], attitude[1:])  # q_{i-1}^-1 ⊗ q_i, body frame
    delta *= np.sign(delta[:, :1] + (delta[:, :1] == 0))
    vector = delta[:, 1:]
    norm = np.linalg.norm(vector, axis=1)
    angle = 2 * np.arctan2(norm, delta[:, 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        axis = np.where(norm[:, None] > 0, vector / norm[:, None], 0.0)
    rates = axis * (angle / dt)[:, None]
    return np.vstack([np.zeros((1, 3)), rates])


def simulate_imu(trajectory: Trajectory, model: ImuModel, rng: np.random.Generator) -> ImuStream:
    """IMU readings for a trajectory (on its grid).

    Random draws, in order: accel noise (n, 3), gyro noise (n, 3), mag noise (n, 3).

    Parameters
    ----------
    trajectory : Trajectory
        Truth; its attitude is body → earth (NWU).
    model : ImuModel
        Errors (g, °/s).
    rng : numpy.random.Generator
        Source of every random draw.

    Returns
    -------
    ImuStream
    """
    n = len(trajectory)
    rotation = quaternion_to_matrix(trajectory.attitude)  # body → earth
    specific_force_earth = np.zeros((n, 3))
    specific_force_earth[:, 2] = (trajectory.vertical_acceleration + GRAVITY) / GRAVITY  # g, NWU
    accel = np.einsum("nji,nj->ni", rotation, specific_force_earth)  # Rᵀ f: earth → body
    accel += np.asarray(model.accel_bias, dtype=float)
    accel += model.accel_noise * rng.standard_normal((n, 3))
    if model.vibration_frequency > 0:
        phase = 2 * np.pi * model.vibration_frequency * trajectory.time
        accel += np.outer(np.sin(phase), np.asarray(model.vibration_amplitude, dtype=float))
    clipped = np.any(np.abs(accel) >= model.accel_range, axis=1)
    accel = np.clip(accel, -model.accel_range, model.accel_range)
    gyro = np.degrees(_body_rates(trajectory.attitude, trajectory.dt))
    gyro += np.asarray(model.gyro_bias, dtype=float)
    gyro += model.gyro_noise * rng.standard_normal((n, 3))
    mag = np.einsum("nji,j->ni", rotation, np.asarray(model.mag_field, dtype=float))
    mag += model.mag_noise * rng.standard_normal((n, 3))
    return ImuStream(trajectory.time, accel, gyro, mag, clipped)


@dataclass
class BaroModel:
    """Barometer errors, in altitude terms (m) unless stated.

    Attributes
    ----------
    rate : float or None
        Sample rate, Hz; None samples on the trajectory grid.
    noise : float
        White noise standard deviation, m.
    prop_wash_amplitude, prop_wash_frequency : float
        Periodic pressure disturbance from propellers: amplitude m, frequency Hz.
    quantization : float
        Output resolution, m (0 = none). Applied to the altitude.
    lag : float
        First-order lag time constant, s (sensor + IIR filter), 0 = none.
    drift_rate : float
        Slow thermal drift, m/s (a ramp), plus ``drift_walk`` random walk.
    drift_walk : float
        Random-walk drift intensity, m/√s.
    spike_probability, spike_magnitude : float
        Per-sample probability of a spike and its standard deviation, m.
    stuck_probability, stuck_duration : float
        Per-sample probability that the reading freezes, and for how long, s.
    dropout_probability : float
        Per-sample probability of a missing sample (NaN).
    sea_level_pa : float
        Reference pressure for the ``pressure`` output, Pa.
    ground_effect_amplitude, ground_effect_height : float
        Rotor ground effect while the vehicle moves or flies: the baro reads
        ``amplitude · exp(−h / height)`` m low at height h above the start
        (m, m; amplitude 0 = off). No random draws.
    """

    rate: Optional[float] = None
    noise: float = 0.0
    prop_wash_amplitude: float = 0.0
    prop_wash_frequency: float = 0.0
    quantization: float = 0.0
    lag: float = 0.0
    drift_rate: float = 0.0
    drift_walk: float = 0.0
    spike_probability: float = 0.0
    spike_magnitude: float = 0.0
    stuck_probability: float = 0.0
    stuck_duration: float = 0.0
    dropout_probability: float = 0.0
    sea_level_pa: float = 101325.0
    ground_effect_amplitude: float = 0.0
    ground_effect_height: float = 1.0


def _sample_times(trajectory: Trajectory, rate: Optional[float]) -> np.ndarray:
    if rate is None:
        return trajectory.time.copy()
    return np.arange(0.0, trajectory.time[-1] + 1e-12, 1.0 / rate)


def simulate_baro(trajectory: Trajectory, model: BaroModel, rng: np.random.Generator) -> BaroStream:
    """Barometer readings (altitude m and pressure Pa) at the model's rate.

    Random draws, in order: noise, drift walk, spike occurrence, spike size,
    stuck occurrence, dropout occurrence (each of length n_baro).

    Parameters
    ----------
    trajectory : Trajectory
        Truth.
    model : BaroModel
        Errors.
    rng : numpy.random.Generator

    Returns
    -------
    BaroStream
        ``value``: baro altitude, m (NaN on a dropout); ``pressure``: the
        same through the ISA troposphere model, Pa.
    """
    from ..sensors import altitude_to_pressure

    time = _sample_times(trajectory, model.rate)
    n = time.size
    truth = np.interp(time, trajectory.time, trajectory.altitude)
    if model.lag > 0:
        dt = np.diff(time, prepend=time[0])
        alpha = 1.0 - np.exp(-dt / model.lag)
        lagged = np.empty_like(truth)
        state = truth[0]
        for i in range(n):
            state += alpha[i] * (truth[i] - state)
            lagged[i] = state
        truth = lagged
    value = truth + model.noise * rng.standard_normal(n)
    if model.prop_wash_amplitude:
        value += model.prop_wash_amplitude * np.sin(2 * np.pi * model.prop_wash_frequency * time)
    walk_steps = rng.standard_normal(n) * model.drift_walk * np.sqrt(np.diff(time, prepend=time[0]))
    value += model.drift_rate * time + np.cumsum(walk_steps)
    spikes = rng.random(n) < model.spike_probability
    value += np.where(spikes, model.spike_magnitude * rng.standard_normal(n), 0.0)
    stuck_start = rng.random(n) < model.stuck_probability
    if model.stuck_duration > 0:
        i = 0
        while i < n:
            if stuck_start[i]:
                end = np.searchsorted(time, time[i] + model.stuck_duration)
                value[i:end] = value[i]
                i = max(end, i + 1)
            else:
                i += 1
    if model.ground_effect_amplitude:
        value -= _ground_effect(trajectory, time, model.ground_effect_amplitude, model.ground_effect_height)
    if model.quantization > 0:
        value = np.round(value / model.quantization) * model.quantization
    value[rng.random(n) < model.dropout_probability] = np.nan
    return BaroStream(time, value, altitude_to_pressure(value, model.sea_level_pa))


def _ground_effect(trajectory: Trajectory, time: np.ndarray, amplitude: float, height: float) -> np.ndarray:
    """Baro under-read (m) from rotor ground effect: amplitude·exp(−h/height) from 1 s before the
    first motion to 1 s after the last (rotors on), 0 otherwise; h = height above the start, m."""
    moving = np.flatnonzero(np.abs(trajectory.vertical_velocity) > 1e-3)
    if moving.size == 0:
        return np.zeros_like(time)
    on = (time >= trajectory.time[moving[0]] - 1.0) & (time <= trajectory.time[moving[-1]] + 1.0)
    h = np.interp(time, trajectory.time, trajectory.altitude) - trajectory.altitude[0]
    return np.where(on, amplitude * np.exp(-np.maximum(h, 0.0) / height), 0.0)


@dataclass(frozen=True)
class Terrain:
    """The ground under the vehicle: what a downward rangefinder measures its height above.

    Attributes
    ----------
    ground_altitude : float
        Altitude of the ground at the start, m (the trajectory's datum).
    steps : tuple of (float, float)
        (time s, change m): the ground under the vehicle rises by ``change``
        from ``time`` on (a roof, a table, a ditch when negative).
    """

    ground_altitude: float = 0.0
    steps: Tuple[Tuple[float, float], ...] = ()

    def height_above(self, time: np.ndarray, altitude: np.ndarray) -> np.ndarray:
        """Height above the ground, m, of a vehicle at ``altitude`` (m) at ``time`` (s): the altitude less the
        ground altitude, less each step's change from its time on (in the order of :attr:`steps`)."""
        height = altitude - self.ground_altitude
        for step_time, change in self.steps:
            height = height - np.where(time >= step_time, change, 0.0)
        return height


@dataclass
class RangefinderModel:
    """Downward rangefinder (lidar / sonar) measuring height above the ground along the body z axis.

    Attributes
    ----------
    rate : float
        Sample rate, Hz.
    min_range, max_range : float
        Valid range, m; readings outside give NaN.
    noise : float
        White noise standard deviation, m.
    dropout_probability : float
        Per-sample probability of no echo (NaN).
    terrain : Terrain
        The ground it measures from (flat, at altitude 0 m, by default).

    Other Parameters
    ----------------
    ground_altitude : float, optional
        Sets ``terrain.ground_altitude``, m (the keyword of the model before
        :class:`Terrain`; read back as ``model.ground_altitude``).
    terrain_steps : tuple of (float, float), optional
        Sets ``terrain.steps`` (likewise; read back as ``model.terrain_steps``).
    """

    rate: float = 20.0
    min_range: float = 0.1
    max_range: float = 12.0
    noise: float = 0.02
    dropout_probability: float = 0.02
    terrain: Terrain = field(default_factory=Terrain)
    ground_altitude: InitVar[Optional[float]] = None
    terrain_steps: InitVar[Optional[Tuple[Tuple[float, float], ...]]] = None

    def __post_init__(self, ground_altitude: Optional[float],
                      terrain_steps: Optional[Tuple[Tuple[float, float], ...]]) -> None:
        if ground_altitude is not None:
            self.terrain = replace(self.terrain, ground_altitude=ground_altitude)
        if terrain_steps is not None:
            self.terrain = replace(self.terrain, steps=tuple(terrain_steps))


# The keywords' values, read through the terrain (set after the class: a property in its body would be taken for
# the InitVar's default).
RangefinderModel.ground_altitude = property(lambda model: model.terrain.ground_altitude,
                                            doc="The terrain's ground altitude, m (``terrain.ground_altitude``).")
RangefinderModel.terrain_steps = property(lambda model: model.terrain.steps,
                                          doc="The terrain's steps, (time s, change m) (``terrain.steps``).")


def simulate_rangefinder(trajectory: Trajectory, model: RangefinderModel, rng: np.random.Generator) -> SensorStream:
    """Slant range to the ground, m (NaN: out of range or no echo).

    The beam points along body −z, so the slant range is the height above
    ``model.terrain`` / cos(tilt). Random draws, in order: noise, dropout
    occurrence.
    """
    time = _sample_times(trajectory, model.rate)
    height = model.terrain.height_above(time, np.interp(time, trajectory.time, trajectory.altitude))
    rotation = quaternion_to_matrix(trajectory.attitude)
    cos_tilt = np.interp(time, trajectory.time, rotation[:, 2, 2])
    with np.errstate(divide="ignore", invalid="ignore"):
        slant = np.where(cos_tilt > 0.1, height / cos_tilt, np.nan)
    value = slant + model.noise * rng.standard_normal(time.size)
    value[(slant < model.min_range) | (slant > model.max_range) | ~np.isfinite(slant)] = np.nan
    value[rng.random(time.size) < model.dropout_probability] = np.nan
    return SensorStream(time, value)


@dataclass
class GpsModel:
    """GNSS altitude.

    Attributes
    ----------
    rate : float
        Fix rate, Hz.
    satellites : tuple of int
        Satellite count at the start and the end (linear in between, rounded).
    noise_at_10_satellites : float
        Vertical noise standard deviation with 10 satellites, m; scales as
        10 / satellites. No fix (NaN) below ``min_satellites``.
    min_satellites : int
        Fewer satellites give no fix.
    jump_probability, jump_magnitude : float
        Per-fix probability of a step change in the bias (multipath /
        constellation change) and its standard deviation, m.
    offset : float
        Constant offset of GPS altitude from the baro reference (geoid vs
        ISA), m.
    outages : tuple of (float, float)
        (start s, end s) windows without a fix (NaN).
    """

    rate: float = 5.0
    satellites: Tuple[int, int] = (12, 12)
    noise_at_10_satellites: float = 1.5
    min_satellites: int = 5
    jump_probability: float = 0.002
    jump_magnitude: float = 3.0
    offset: float = 0.0
    outages: Tuple[Tuple[float, float], ...] = ()


def simulate_gps(trajectory: Trajectory, model: GpsModel, rng: np.random.Generator) -> Tuple[SensorStream, np.ndarray]:
    """GPS altitude, m (NaN: no fix), and the satellite count per fix.

    Random draws, in order: noise, jump occurrence, jump size.
    """
    time = _sample_times(trajectory, model.rate)
    n = time.size
    satellites = np.rint(np.linspace(model.satellites[0], model.satellites[1], n)).astype(int)
    sigma = model.noise_at_10_satellites * 10.0 / np.maximum(satellites, 1)
    value = np.interp(time, trajectory.time, trajectory.altitude) + model.offset + sigma * rng.standard_normal(n)
    jumps = rng.random(n) < model.jump_probability
    value += np.cumsum(np.where(jumps, model.jump_magnitude * rng.standard_normal(n), 0.0))
    value[satellites < model.min_satellites] = np.nan
    for start, end in model.outages:
        value[(time >= start) & (time < end)] = np.nan
    return SensorStream(time, value), satellites


# ----------------------------------------------------------------------------
# Attitude pipeline


def ahrs_vertical_acceleration(imu: ImuStream, gain: float = 0.5, use_magnetometer: bool = True,
                               settings: Optional[object] = None) -> np.ndarray:
    """Vertical acceleration (m/s², +up, gravity removed) through the imufusion AHRS.

    Runs ``imufusion.Ahrs`` (defaults: NWU, gain 0.5, 100 Hz sample rate)
    sample by sample on the IMU stream and returns ``earth_acceleration.z · g``,
    exactly as a firmware pipeline would feed the altitude observer. Attitude
    errors from gyro bias and accelerometer noise therefore tilt the specific
    force and leak gravity into the vertical channel.

    Parameters
    ----------
    imu : ImuStream
        Readings in g, °/s and arbitrary magnetometer units.
    gain : float
        AHRS gain (only used when ``settings`` is None and differs from 0.5).
    use_magnetometer : bool
        Use ``update`` (True) or ``update_no_magnetometer``.
    settings : imufusion.AhrsSettings, optional
        Full AHRS settings; its sample rate should match the IMU's.

    Raises
    ------
    ImportError
        imufusion is not installed (``pip install fusion-altitude[ahrs]``).
    """
    try:
        import imufusion
    except ImportError as error:  # pragma: no cover - exercised only without the extra
        raise ImportError("the AHRS pipeline needs imufusion: pip install 'fusion-altitude[ahrs]'") from error
    ahrs = imufusion.Ahrs()
    rate = 1.0 / float(imu.time[1] - imu.time[0])
    if settings is not None:
        ahrs.set_settings(settings)
    elif gain != 0.5 or abs(rate - 100.0) > 1e-9:
        ahrs.set_settings(imufusion.AhrsSettings(sample_rate=rate, gain=gain))
    out = np.empty(imu.time.size)
    gyro = np.ascontiguousarray(imu.gyro, dtype=float)
    accel = np.ascontiguousarray(imu.accel, dtype=float)
    mag = np.ascontiguousarray(imu.mag, dtype=float)
    if use_magnetometer:
        for i in range(out.size):
            ahrs.update(gyro[i], accel[i], mag[i])
            out[i] = ahrs.get_earth_acceleration()[2]
    else:
        for i in range(out.size):
            ahrs.update_no_magnetometer(gyro[i], accel[i])
            out[i] = ahrs.get_earth_acceleration()[2]
    return out * GRAVITY


def truth_vertical_acceleration(imu: ImuStream, trajectory: Trajectory) -> np.ndarray:
    """Vertical acceleration (m/s², +up) from the IMU with the *truth* attitude (no AHRS).

    Used when imufusion is not installed, and to separate attitude errors from
    sensor errors.
    """
    from ..sensors import vertical_acceleration

    return vertical_acceleration(imu.accel, trajectory.attitude, frame="NWU", accel_units="g")


def align_to(target_time: np.ndarray, stream: SensorStream) -> np.ndarray:
    """Put a slower stream onto a faster grid: each sample at the first target time at or after it, NaN elsewhere.

    Parameters
    ----------
    target_time : numpy.ndarray
        Grid times, s (sorted).
    stream : SensorStream
        Samples at their own times, s.

    Returns
    -------
    numpy.ndarray
        Same length as ``target_time``: the sensor's value on the grid step
        where it became available, NaN on the others (the observer's "no
        sample this step"). If several samples fall in one step the newest wins.
    """
    out = np.full(target_time.shape, np.nan)
    index = np.searchsorted(target_time, stream.time - 1e-9, side="left")
    keep = index < target_time.size
    out[index[keep]] = stream.value[keep]
    return out


# ----------------------------------------------------------------------------
# Logging faults: what a recorder does to the samples (all streams at once)


@dataclass
class LogFaultModel:
    """Faults of the *logger*, not of a sensor: applied to every column of a log at once.

    Attributes
    ----------
    gap_start : float or None
        Start of a logging gap, s (SD-card stall, brown-out): every row with
        ``gap_start ≤ t < gap_start + gap_duration`` is lost. None = no gap.
    gap_duration : float
        Length of the gap, s.
    repeat_probability : float
        Per-row probability that a row is written with the previous row's
        timestamp (a coarse or stalled logger clock); the values are kept.
    timestamp_resolution : float
        Written timestamps are truncated to this step, s (0 = exact); rows
        faster than it share timestamps (e.g. 0.01 s for a 200 Hz log).
    stops : dict of str → float
        Streams that stop mid-log: column name → time (s) from which the
        column is NaN (a baro that stops, a GPS that is unplugged). No random
        draws.
    dead_columns : tuple of str
        Channels that are dead for the whole log: written as 0 on every row,
        as real exports write a sensor that never answered. No random draws.
    """

    gap_start: Optional[float] = None
    gap_duration: float = 2.0
    repeat_probability: float = 0.0
    timestamp_resolution: float = 0.0
    stops: Dict[str, float] = field(default_factory=dict)
    dead_columns: Tuple[str, ...] = ()


def apply_log_faults(time, columns: Dict[str, np.ndarray], model: LogFaultModel,
                     rng: Optional[np.random.Generator] = None):
    """Apply :class:`LogFaultModel` to a log given as a time column and named columns.

    Random draws (only if ``repeat_probability`` > 0): one uniform per row
    left after the gap.

    Parameters
    ----------
    time : array_like
        Row times, s, increasing.
    columns : dict of str → array_like
        Columns with one entry (or row) per time.
    model : LogFaultModel
    rng : numpy.random.Generator, optional
        Needed when ``repeat_probability`` > 0.

    Returns
    -------
    time : numpy.ndarray
        Written timestamps, s (non-decreasing: repeats are equal to the row
        before, never smaller).
    columns : dict of str → numpy.ndarray
        The kept rows.
    repeated : int
        Number of rows whose timestamp equals the row before.

    Raises
    ------
    ValueError
        Bad model values (naming the field) or a column whose length is not
        that of ``time`` (naming the column).
    """
    time = np.asarray(time, dtype=float)
    _check_log_fault_model(model)
    columns = _log_columns(time, columns, model)
    for name, stop in model.stops.items():
        values = columns[name].astype(float)
        values[time >= stop] = np.nan
        columns[name] = values
    for name in model.dead_columns:
        columns[name] = np.zeros_like(columns[name], dtype=float)
    keep = np.ones(time.shape, dtype=bool)
    if model.gap_start is not None:
        keep &= ~((time >= model.gap_start) & (time < model.gap_start + model.gap_duration))
    time = time[keep]
    columns = {name: values[keep] for name, values in columns.items()}
    written = _written_timestamps(time, model, rng)
    repeated = int(np.sum(np.diff(written) == 0))
    return written, columns, repeated


def _check_log_fault_model(model: LogFaultModel) -> None:
    """ValueError naming the first field of ``model`` out of range."""
    if model.gap_duration < 0 or not np.isfinite(model.gap_duration):
        raise ValueError(f"gap_duration must be a non-negative number of s, got {model.gap_duration}")
    if not 0.0 <= model.repeat_probability <= 1.0:
        raise ValueError(f"repeat_probability must be in [0, 1], got {model.repeat_probability}")
    if model.timestamp_resolution < 0:
        raise ValueError(f"timestamp_resolution must be ≥ 0 s, got {model.timestamp_resolution}")


def _log_columns(time: np.ndarray, columns: Dict[str, np.ndarray], model: LogFaultModel) -> Dict[str, np.ndarray]:
    """The columns as arrays, each one row per time, holding every column ``model`` names (else ValueError)."""
    columns = {name: np.asarray(values) for name, values in columns.items()}
    for name, values in columns.items():
        if values.shape[:1] != time.shape:
            raise ValueError(f"column {name!r} has {values.shape[0] if values.ndim else 0} rows, time {time.size}")
    for name in list(model.stops) + list(model.dead_columns):
        if name not in columns:
            raise ValueError(f"LogFaultModel names column {name!r}, not in the log ({', '.join(columns)})")
    return columns


def _written_timestamps(time: np.ndarray, model: LogFaultModel, rng: Optional[np.random.Generator]) -> np.ndarray:
    """The timestamps the logger writes, s: truncated to ``timestamp_resolution``, and a row's repeated from the row
    before with ``repeat_probability`` (one uniform draw of ``rng`` per row)."""
    written = time.copy()
    if model.timestamp_resolution > 0:
        written = np.floor(written / model.timestamp_resolution + 1e-9) * model.timestamp_resolution
    if model.repeat_probability > 0:
        if rng is None:
            raise ValueError("rng is needed when repeat_probability > 0")
        repeat = rng.random(written.size) < model.repeat_probability
        repeat[0] = False
        for i in np.flatnonzero(repeat):
            written[i] = written[i - 1]
    return written


def write_log_csv(path: str, time, columns: Dict[str, np.ndarray], time_column: str = "time") -> None:
    """Write a log as a CSV (header row, full float64 precision; NaN written as an empty cell).

    Parameters
    ----------
    path : str
        Output file.
    time : array_like
        Row times, s.
    columns : dict of str → array_like
        Column name → one value per row.
    time_column : str
        Name of the time column.
    """
    names = [time_column] + list(columns)
    table = np.column_stack([np.asarray(time, dtype=float)]
                            + [np.asarray(values, dtype=float) for values in columns.values()])
    with open(path, "w", newline="") as handle:
        handle.write(",".join(names) + "\n")
        for row in table:
            handle.write(",".join("" if v != v else repr(float(v)) for v in row) + "\n")
