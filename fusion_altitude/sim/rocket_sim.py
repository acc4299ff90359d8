"""Simulated high-power rocket flights with the sensor errors real flight computers see.

Built on :mod:`fusion_altitude.sim` (its :class:`~fusion_altitude.sim.Trajectory`
and trapezoid integration); adds what the plain ``rocket`` trajectory lacks:

- a transonic flight (≈ 300 m/s, ≈ 5 km apogee, as the Hedy flight in the shared data)
  with density-dependent drag, a drogue descent and a main parachute opened at a
  set height, then landing and rest;
- a **static-port error proportional to dynamic pressure**: the static pressure
  reads high by ``c·q`` (q = ½ρv²), i.e. the baro altitude reads low by
  ``c·v²/(2g)`` m, plus a transonic bump around Mach 1;
- **pyro spikes**: single samples off by 150–500 m at the drogue (1 s after apogee) and main charges;
- **accelerometer saturation** (the long-axis reading clips at ±``saturation``)
  during the thrust peak at ignition;
- a **tumbling descent**: from the drogue charge on the long-axis accelerometer reads the
  projection of gravity and drag on a tumbling airframe, not the vertical.

The accelerometer output follows the library's rocket convention: long-axis
specific force minus g (m/s², ≈ 0 at rest on the pad, +up while the nose is up).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from .trajectories import GRAVITY, Trajectory, TrajectoryFlight, from_acceleration, level_trajectory

#: Speed of sound at the pad (15 °C), m/s; the simulator uses it for the Mach number.
SPEED_OF_SOUND = 340.3


@dataclass
class RocketFlightModel:
    """Parameters of one simulated flight (SI units).

    Attributes
    ----------
    rate : float
        Sample rate of accelerometer and baro, Hz.
    pad_time : float
        s at rest on the pad before ignition.
    thrust_accel : float
        Thrust per unit mass, m/s² (net of gravity at lift-off: thrust_accel − g).
    burn_time : float
        s.
    drag_k : float
        Drag deceleration k·v²·ρ/ρ0, 1/m.
    drogue_velocity, main_velocity : float
        Descent rates, m/s (negative).
    main_altitude : float
        Height above the pad where the main opens, m.
    static_port_coefficient : float
        c: the static pressure reads high by c·q (baro altitude low by c·v²/(2g)).
    transonic_bump : float
        Extra baro error near Mach 1, m (Gaussian in Mach, σ 0.05).
    baro_noise : float
        m, white.
    pyro_spike : tuple of float
        Range of the spike magnitude at each pyro charge, m.
    accel_bias : float
        m/s², constant (learned on the pad).
    accel_scale_error : float
        Fractional scale error of the accelerometer.
    accel_noise : float
        m/s², white.
    saturation : float
        Long-axis reading clips at ±saturation, m/s² (specific force); the thrust
        peak at ignition (≈ 2 × thrust_accel) exceeds it.
    tumble_amplitude : float
        m/s²: amplitude of the tumbling long-axis reading after apogee.
    pad_altitude : float
        Pad pressure altitude, m.
    ejection_delay : float
        s from the true apogee to the drogue charge (free fall over the top,
        then the drogue and the tumbling start).
    """

    rate: float = 100.0
    pad_time: float = 3.0
    thrust_accel: float = 70.0
    burn_time: float = 6.0
    drag_k: float = 4.0e-4
    drogue_velocity: float = -25.0
    main_velocity: float = -6.0
    main_altitude: float = 250.0
    static_port_coefficient: float = 0.064
    transonic_bump: float = 60.0
    baro_noise: float = 1.0
    pyro_spike: tuple = (150.0, 500.0)
    accel_bias: float = 0.2
    accel_scale_error: float = 0.005
    accel_noise: float = 1.0
    saturation: float = 12.0 * GRAVITY
    tumble_amplitude: float = 8.0
    pad_altitude: float = 1400.0
    ejection_delay: float = 1.0


@dataclass
class RocketFlight(TrajectoryFlight):
    """One simulated flight.

    Attributes
    ----------
    trajectory : Trajectory
        Truth (altitude is the height above the pad, m).
    accel : numpy.ndarray
        Long-axis accelerometer minus g, m/s² (saturated, tumbling after apogee).
    baro_altitude : numpy.ndarray
        Pressure altitude, m (static-port error, transonic bump, pyro spikes, noise).
    static_port_error : numpy.ndarray
        The deterministic part of the baro error, m (≤ 0).
    apogee_time, apogee_height : float
        True apogee, s and m above the pad.
    main_time : float
        True main-deployment time (height crosses main_altitude going down), s.
    launch_time, burnout_time : float
        s.
    landed_time : float
        s; ``inf`` when the rocket is still moving at the end of a ``duration`` too short to land.
    model : RocketFlightModel
    """

    trajectory: Trajectory
    accel: np.ndarray
    baro_altitude: np.ndarray
    static_port_error: np.ndarray
    apogee_time: float
    apogee_height: float
    main_time: float
    launch_time: float
    burnout_time: float
    landed_time: float
    model: RocketFlightModel

    @property
    def dt(self) -> float:
        return self.trajectory.dt


def _density_ratio(height: np.ndarray, pad_altitude: float) -> np.ndarray:
    """ρ/ρ0 of the ISA troposphere at pressure altitude pad_altitude + height."""
    return np.maximum(1.0 - 2.25577e-5 * (pad_altitude + height), 0.05) ** 4.2559


def rocket_trajectory(model: RocketFlightModel, duration: Optional[float] = None) -> Trajectory:
    """Truth of the flight: pad, boost, coast with drag, drogue, main, landing, rest."""
    dt = 1.0 / model.rate
    n = int(round((duration if duration is not None else 400.0) * model.rate))
    a = np.zeros(n)
    v = 0.0
    h = 0.0
    phase = "pad"
    landed_at = None
    for i in range(n):
        t = i * dt
        drag = model.drag_k * float(_density_ratio(np.array(h), model.pad_altitude)) * v * abs(v)
        if phase == "pad":
            ai = 0.0
            if t >= model.pad_time:
                phase = "boost"
        if phase == "boost":  # thrust peaks at twice its mean level at ignition (time constant 0.4 s)
            ai = model.thrust_accel * (0.75 + np.exp(-(t - model.pad_time) / 0.4)) - GRAVITY - drag
            if t >= model.pad_time + model.burn_time:
                phase = "coast"
        if phase == "coast":
            ai = -GRAVITY - drag
            if v + ai * dt <= 0.0:
                phase = "arc"
                ejection = t + model.ejection_delay
        if phase == "arc":  # free fall over the top until the drogue charge
            ai = -GRAVITY - drag
            if t >= ejection:
                phase = "drogue"
        if phase == "drogue":
            ai = (model.drogue_velocity - v) / 1.0
            if h <= model.main_altitude:
                phase = "main"
        if phase == "main":
            ai = (model.main_velocity - v) / 1.0
            if h + v * dt <= 0.0:
                phase = "landed"
                landed_at = i
        if phase == "landed":
            ai = 0.0
        a[i] = ai
        v += ai * dt
        h += v * dt
        if phase == "landed":
            v = 0.0
    t = np.arange(n) * dt
    height, velocity = from_acceleration(t, a)
    if landed_at is not None:
        height[landed_at:] = height[landed_at]
        velocity[landed_at:] = 0.0
        a[landed_at:] = 0.0
    return Trajectory(t, height, velocity, a, level_trajectory(n), "rocket (transonic)")


def simulate_rocket_flight(seed: int = 0, model: Optional[RocketFlightModel] = None, randomise: bool = True,
                           duration: Optional[float] = None) -> RocketFlight:
    """A simulated flight with the sensor errors of the module docstring.

    Parameters
    ----------
    seed : int
        Seeds the noise, spikes and (with ``randomise``) the flight parameters.
    model : RocketFlightModel, optional
        Base parameters; defaults if omitted.
    randomise : bool, default True
        Draw thrust (±15 %), burn time (±15 %), drag (±20 %), static-port
        coefficient (0.04–0.08: 0.064 fitted on the Hedy flight), accel bias (±0.5 m/s²) and scale error (±0.5 %) from ``seed``.
    duration : float, optional
        s; long enough to land and rest 10 s if omitted. A shorter one ends the flight in the air
        (``landed_time`` is then ``inf``).
    """
    rng = np.random.default_rng(seed)
    model = _drawn_model(RocketFlightModel() if model is None else model, rng if randomise else None)
    trajectory = rocket_trajectory(model, duration)
    if duration is None:  # trim to 10 s after landing
        still = np.nonzero((trajectory.vertical_velocity != 0.0) | (trajectory.time < model.pad_time + 1.0))[0]
        end = min(len(trajectory), int(still[-1] + 10 * model.rate))
        trajectory = Trajectory(trajectory.time[:end], trajectory.altitude[:end], trajectory.vertical_velocity[:end],
                                trajectory.vertical_acceleration[:end], trajectory.attitude[:end], trajectory.name)
    t = trajectory.time
    h = trajectory.altitude
    v = trajectory.vertical_velocity
    n = t.size
    k_apogee = int(np.argmax(h))
    apogee_time, apogee_height = float(t[k_apogee]), float(h[k_apogee])
    descending = np.arange(n) > k_apogee
    below_main = descending & (h <= model.main_altitude)
    k_main = int(np.argmax(below_main)) if below_main.any() else n - 1
    moving = np.nonzero(v != 0.0)[0]
    k_landed = int(moving[-1] + 1) if moving.size else n - 1
    landed_time = float(t[k_landed]) if k_landed < n else math.inf  # still moving when the run ends
    burnout_time = model.pad_time + model.burn_time
    ejection_time = apogee_time + model.ejection_delay
    accel = _accelerometer(trajectory, model, ejection_time, landed_time, rng)

    # barometer: static-port error ∝ dynamic pressure, transonic bump, pyro spikes, noise
    mach = np.abs(v) / SPEED_OF_SOUND
    static_error = -(model.static_port_coefficient * v * v / (2 * GRAVITY)
                     + model.transonic_bump * np.exp(-0.5 * ((mach - 1.0) / 0.05) ** 2))
    baro = model.pad_altitude + h + static_error + model.baro_noise * rng.standard_normal(n)
    k_ejection = int(np.searchsorted(t, ejection_time))
    for k in (k_ejection, k_main + 1):
        if k < n:
            baro[k] += rng.choice((-1.0, 1.0)) * rng.uniform(*model.pyro_spike)
    return RocketFlight(trajectory, accel, baro, static_error, apogee_time, apogee_height, float(t[k_main]),
                        model.pad_time, burnout_time, landed_time, model)


def _drawn_model(base: RocketFlightModel, rng: Optional[np.random.Generator]) -> RocketFlightModel:
    """``base`` with thrust, burn time, drag, static-port coefficient, accel bias and scale error drawn from ``rng``
    (in that order), as :func:`simulate_rocket_flight`'s ``randomise`` describes; ``base`` itself without ``rng``."""
    params = dict(base.__dict__)
    if rng is not None:
        params["thrust_accel"] = base.thrust_accel * rng.uniform(0.85, 1.15)
        params["burn_time"] = base.burn_time * rng.uniform(0.85, 1.15)
        params["drag_k"] = base.drag_k * rng.uniform(0.8, 1.2)
        params["static_port_coefficient"] = rng.uniform(0.04, 0.08)
        params["accel_bias"] = rng.uniform(-0.5, 0.5)
        params["accel_scale_error"] = rng.uniform(-0.005, 0.005)
    return RocketFlightModel(**params)


def _accelerometer(trajectory: Trajectory, model: RocketFlightModel, ejection_time: float, landed_time: float,
                   rng: np.random.Generator) -> np.ndarray:
    """Long-axis accelerometer minus g, m/s²: the specific force (a + g along the axis; from the drogue charge at
    ``ejection_time`` to ``landed_time``, s, a tumbling airframe's) with scale error, bias, noise (one normal draw
    per sample) and saturation."""
    t = trajectory.time
    specific = trajectory.vertical_acceleration + GRAVITY
    tumble_phase = 2 * np.pi * 0.7 * (t - ejection_time)
    tumbling = GRAVITY * np.cos(tumble_phase) + model.tumble_amplitude * np.sin(2.3 * tumble_phase)
    specific = np.where((t >= ejection_time) & (t < landed_time), tumbling, specific)
    noise = model.accel_noise * rng.standard_normal(t.size)
    reading = specific * (1.0 + model.accel_scale_error) + model.accel_bias + noise
    reading = np.clip(reading, -model.saturation, model.saturation)
    return reading - GRAVITY


def telemetry_indices(flight: RocketFlight, seed: int = 0, step: float = 0.1, gap_probability: float = 0.07,
                      longest: float = 4.0, quiet: Tuple[float, ...] = (), quiet_margin: float = 2.0) -> np.ndarray:
    """Sample indices of a ground-station telemetry log drawn from a simulated flight.

    Packets every ``step`` s, and with probability ``gap_probability`` per
    packet a gap drawn uniformly from 0.6 s to ``longest`` s instead (lost
    packets), as an AltOS telemetry CSV (median step 0.1 s, 154 steps over
    0.5 s, the longest 4 s, over a 3-minute flight). No gap starts or ends
    within ``quiet_margin`` s of the times in ``quiet`` (e.g. the true apogee,
    to test the event timing apart from the data a gap removes).

    Returns
    -------
    numpy.ndarray of int
        Increasing indices into ``flight.time``, starting at 0.
    """
    rng = np.random.default_rng(seed)
    rate = flight.model.rate
    times = flight.time
    indices = [0]
    k = 0
    while True:
        gap = rng.random() < gap_probability
        length = rng.uniform(0.6, longest) if gap else step
        end = k + max(1, int(round(length * rate)))
        if gap and any(times[k] - quiet_margin - length <= q <= times[k] + length + quiet_margin for q in quiet):
            end = k + max(1, int(round(step * rate)))
        if end >= times.size:
            break
        indices.append(end)
        k = end
    return np.asarray(indices)


#: Kinds of :func:`flight_log`.
LOG_KINDS = ("imu", "dead_imu", "saturating_imu", "baro_only", "axial", "axial_ends")


def flight_log(flight: RocketFlight, kind: str = "imu", indices: Optional[np.ndarray] = None,
               imu_range: float = 6.0 * GRAVITY):
    """A :class:`~fusion_altitude.logs.LogData` of a simulated flight, as a flight computer's log reader gives it.

    Parameters
    ----------
    flight : RocketFlight
    kind : str
        ``"imu"``: a raw IMU (N, 3), the long axis +Z (reads +g on the pad);
        ``"dead_imu"``: the IMU's columns all zero (a TeleMega export with a dead IMU);
        ``"saturating_imu"``: the IMU clips at ±``imu_range`` (m/s², specific
        force; the thrust peak exceeds it) and the reader's ``clipped`` flag is not set;
        ``"baro_only"``: no accelerometer (``baro_only``, zeros as vertical acceleration);
        ``"axial"``: the flight computer's along-axis accelerometer
        (``axial_acceleration``) and a dead IMU;
        ``"axial_ends"``: the along-axis accelerometer stops 4.5 s after
        launch (a Raven's) and there is no IMU.
    indices : numpy.ndarray of int, optional
        Samples to keep (e.g. :func:`telemetry_indices`); all if omitted.
    imu_range : float
        m/s², the saturating IMU's range.

    Returns
    -------
    fusion_altitude.logs.LogData
        ``time`` s, ``baro_altitude`` m (the flight's), vertical acceleration
        as a reader without an attitude would give it (the long axis minus g;
        zeros for ``baro_only``); ``vehicle`` "rocket".
    """
    from ..logs import LogData

    if kind not in LOG_KINDS:
        raise ValueError(f"kind must be one of {', '.join(LOG_KINDS)}, got {kind!r}")
    k = np.arange(flight.time.size) if indices is None else np.asarray(indices)
    time = flight.time[k]
    specific = flight.accel[k] + GRAVITY  # long-axis specific force, m/s², +nose
    n = time.size
    accel = axial = None
    vertical = flight.accel[k].copy()
    if kind in ("imu", "dead_imu", "saturating_imu", "axial"):
        accel = np.zeros((n, 3))
        if kind != "dead_imu" and kind != "axial":
            accel[:, 2] = specific if kind == "imu" else np.clip(specific, -imu_range, imu_range)
            accel[:, 0] = 0.3 + 0.05 * np.sin(time)
            accel[:, 1] = -0.2 + 0.05 * np.cos(time)
    if kind in ("axial", "axial_ends"):
        axial = specific.copy()
        if kind == "axial_ends":
            axial[time > flight.launch_time + 4.5] = np.nan
    if kind in ("dead_imu", "baro_only", "axial"):
        vertical = np.zeros(n)
    return LogData(source=f"simulated flight ({kind})", time=time, vertical_acceleration=vertical,
                   baro_altitude=flight.baro_altitude[k].copy(), accel=accel, imu_frame="sensor" if accel is not None else "",
                   vehicle="rocket", axial_acceleration=axial, baro_only=kind == "baro_only")
