"""Named simulation scenarios, including two that reproduce published figures.

``clean`` and ``realistic`` are the two examples published with the Rust crate
``fusion-altitude`` (the design this package follows): the same motion, sensor
budget and AHRS, so our error figures must agree with theirs within the spread
of the noise. :data:`PUBLISHED` holds their numbers.

Run one with :func:`run_scenario`; :func:`scenario_names` lists them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Dict, Optional, Tuple

import numpy as np

from .._core._common import GRAVITY
from .._core._observer_glue import AltitudeBatch
from .._core._observer import AltitudeEstimator, AltitudeSettings
from ..metrics import ErrorStatistics, error_statistics
from . import trajectories as sim

__all__ = ["PUBLISHED", "PUBLISHED_SOURCE", "export_csv", "ScenarioResult", "ScenarioSpec", "scenario_names", "spec", "run_scenario", "describe"]

#: Published figures of the Rust crate's examples (errors in m, after 5 s).
#: ``clean``: ``with_fusion_ahrs``; ``realistic``: ``realistic_noise``.
PUBLISHED = {
    "clean": {"max": 0.105},
    "realistic": {"mean": 0.009, "rms": 0.036, "max": 0.15, "final_bias": 0.012 * GRAVITY},
}
#: Where :data:`PUBLISHED` comes from (its documentation states no version number).
PUBLISHED_SOURCE = ("the Rust crate fusion-altitude (pre-1.0, the version its documentation describes; "
                    "examples realistic_noise and with_fusion_ahrs)")


@dataclass
class ScenarioResult:
    """Everything a scenario run produced.

    Attributes
    ----------
    name : str
        Scenario name.
    seed : int
        Seed of the random generator.
    trajectory : sim.Trajectory
        Truth (time s, altitude m, vertical velocity m/s, acceleration m/s²).
    imu : sim.ImuStream
        IMU readings (g, °/s).
    baro : sim.BaroStream
        Baro readings at their own rate (altitude m, pressure Pa).
    vertical_acceleration : numpy.ndarray
        Observer input on the IMU grid, m/s², +up (through the AHRS, or the
        truth attitude when ``attitude="truth"``).
    baro_altitude : numpy.ndarray
        Baro altitude on the IMU grid, m; NaN on steps without a new sample.
    estimate : AltitudeBatch
        Observer outputs per IMU step.
    true_bias : float
        Vertical accelerometer bias of the scenario, m/s², +up (what the
        observer's bias estimate should approach on a level platform).
    transient : float
        Seconds excluded from the statistics.
    attitude : str
        ``"ahrs"`` or ``"truth"``.
    rangefinder, gps : sim.SensorStream or None
        Extra streams (not used by this observer; for a later Kalman filter).
    description : str
        One line about the scenario.
    fault_end : float or None
        Time (s) at which the scenario's sensor fault ends (baro glitch, GPS
        outage, terrain step, leaving ground effect), for recovery times.
    """

    name: str
    seed: int
    trajectory: sim.Trajectory
    imu: sim.ImuStream
    baro: sim.BaroStream
    vertical_acceleration: np.ndarray
    baro_altitude: np.ndarray
    estimate: AltitudeBatch
    true_bias: float
    transient: float
    attitude: str
    rangefinder: Optional[sim.SensorStream] = None
    gps: Optional[sim.SensorStream] = None
    description: str = ""
    fault_end: Optional[float] = None

    @property
    def time(self) -> np.ndarray:
        """IMU-grid times, s."""
        return self.trajectory.time

    @property
    def altitude_error(self) -> np.ndarray:
        """Fused estimate − truth, m, per IMU step."""
        return self.estimate.altitude.astype(float) - self.trajectory.altitude

    @property
    def baro_error(self) -> np.ndarray:
        """Raw baro − truth, m, per IMU step (NaN where there is no baro sample)."""
        return self.baro_altitude - self.trajectory.altitude

    def statistics(self) -> ErrorStatistics:
        """Error statistics of the fused estimate after the transient (m)."""
        return error_statistics(self.time, self.altitude_error, self.transient)

    def baro_statistics(self) -> ErrorStatistics:
        """Error statistics of the raw baro after the transient (m)."""
        return error_statistics(self.time, self.baro_error, self.transient)

    @property
    def final_bias(self) -> float:
        """Bias estimate at the end of the run, m/s²."""
        return float(self.estimate.accel_bias[-1])


@dataclass
class ScenarioSpec:
    """How a scenario is built: description, trajectory, sensor models, preset, transient (s), faults."""

    description: str
    trajectory: Callable[[], sim.Trajectory]
    imu: sim.ImuModel
    baro: sim.BaroModel = field(default_factory=sim.BaroModel)
    preset: str = "vtol"
    transient: float = 5.0
    baro_override: Optional[Callable[[sim.Trajectory], np.ndarray]] = None
    rangefinder: Optional[sim.RangefinderModel] = None
    gps: Optional[sim.GpsModel] = None
    baro_fault: Optional[Tuple[float, float, float]] = None
    fault_end: Optional[float] = None


_REALISTIC_IMU = sim.ImuModel(accel_bias=(0.005, -0.008, 0.012), accel_noise=0.005,
                              gyro_bias=(0.20, -0.15, 0.10), gyro_noise=0.10,
                              mag_field=(1.0, 0.0, 0.0), mag_noise=0.05)


def _specs() -> Dict[str, ScenarioSpec]:
    return {**_vehicle_specs(), **_comparison_specs()}


def _vehicle_specs() -> Dict[str, ScenarioSpec]:
    """The published examples and one scenario per vehicle."""
    return {
        "realistic": ScenarioSpec(
            "published realistic_noise: 60 s of h = 5 sin(2π·0.1·t) at 100 Hz, MEMS biases and noise, "
            "8 Hz prop-wash on the baro",
            lambda: sim.sinusoid(60.0, 100.0), _REALISTIC_IMU,
            sim.BaroModel(noise=0.10, prop_wash_amplitude=0.30, prop_wash_frequency=8.0)),
        "clean": ScenarioSpec(
            "published with_fusion_ahrs: 30 s of h = 5 sin(2π·0.1·t) at 100 Hz, ideal IMU, "
            "baro = truth + 0.05 sin(0.41 i)",
            lambda: sim.sinusoid(30.0, 100.0), sim.ImuModel(),
            baro_override=lambda trajectory: trajectory.altitude + 0.05 * np.sin(0.41 * np.arange(len(trajectory)))),
        "hover": ScenarioSpec(
            "60 s hover at 10 m, MEMS IMU, 50 Hz baro with noise, quantization and slow thermal drift",
            lambda: sim.hover(60.0, 100.0, 10.0), _REALISTIC_IMU,
            sim.BaroModel(rate=50.0, noise=0.10, quantization=0.02, drift_rate=0.002, drift_walk=0.01,
                          prop_wash_amplitude=0.2, prop_wash_frequency=8.0)),
        "climb-cruise-descend": ScenarioSpec(
            "120 s: climb at 3 m/s to 60 m, cruise, descend; fixed-wing gains, 25 Hz lagged baro",
            lambda: sim.climb_cruise_descend(120.0, 100.0), _REALISTIC_IMU,
            sim.BaroModel(rate=25.0, noise=0.2, lag=0.05, drift_rate=0.003), preset="fixed_wing", transient=20.0),
        "takeoff-landing": ScenarioSpec(
            "40 s VTOL hop to 5 m with rocking attitude, vibration, 50 Hz baro with prop-wash and glitches; "
            "rangefinder and GPS streams",
            lambda: sim.takeoff_landing(40.0, 200.0),
            sim.ImuModel(accel_bias=(0.005, -0.008, 0.012), accel_noise=0.01, vibration_amplitude=(0.05, 0.05, 0.1),
                         vibration_frequency=87.0, accel_range=16.0, gyro_bias=(0.2, -0.15, 0.1), gyro_noise=0.1,
                         mag_noise=0.05),
            sim.BaroModel(rate=50.0, noise=0.1, prop_wash_amplitude=0.3, prop_wash_frequency=8.0, quantization=0.01,
                          spike_probability=0.002, spike_magnitude=3.0, stuck_probability=0.0005,
                          stuck_duration=0.5, dropout_probability=0.01),
            rangefinder=sim.RangefinderModel(), gps=sim.GpsModel(satellites=(7, 14))),
        "balloon": ScenarioSpec(
            "weather balloon to 30 km at 5 m/s, 10 Hz IMU and 1 Hz baro; balloon gains",
            lambda: sim.balloon_ascent(10.0), _REALISTIC_IMU,
            sim.BaroModel(rate=1.0, noise=0.5, quantization=0.1, drift_walk=0.05),
            preset="balloon", transient=120.0, gps=sim.GpsModel(rate=1.0)),
        "rocket": ScenarioSpec(
            "transonic high-power rocket (fusion_altitude.rocket_sim, seeded): ≈ 7 g boost with a clipped thrust "
            "peak, ≈ 250 m/s, apogee ≈ 2-3.5 km, static-port baro error ∝ dynamic pressure, pyro spikes, tumbling "
            "long-axis accel after apogee, drogue, main at 250 m, landing; 100 Hz",
            lambda: sim.rocket(60.0, 100.0),
            sim.ImuModel(accel_bias=(0.005, -0.008, 0.012), accel_noise=0.01, accel_range=16.0,
                         gyro_noise=0.1, mag_noise=0.05),
            sim.BaroModel(noise=0.5, lag=0.02), preset="racing", transient=2.0),
    }


def _comparison_specs() -> Dict[str, ScenarioSpec]:
    """The estimator comparison's scenarios."""
    return {
        "fixed-wing": ScenarioSpec(
            "180 s fixed wing: climb at 4 m/s to 100 m, cruise, descend; 25 Hz lagged drifting baro, 5 Hz GPS; "
            "fixed-wing gains",
            lambda: sim.climb_cruise_descend(180.0, 100.0, climb_rate=4.0, cruise_altitude=100.0), _REALISTIC_IMU,
            sim.BaroModel(rate=25.0, noise=0.25, lag=0.05, drift_rate=0.005, drift_walk=0.02),
            preset="fixed_wing", transient=20.0, gps=sim.GpsModel(jump_probability=0.0)),
        "ground-effect": ScenarioSpec(
            "40 s VTOL hop to 5 m: rotor ground effect makes the 50 Hz baro read up to 1.5 m low near the ground; "
            "rangefinder and GPS streams",
            lambda: sim.takeoff_landing(40.0, 100.0), _REALISTIC_IMU,
            sim.BaroModel(rate=50.0, noise=0.1, prop_wash_amplitude=0.2, prop_wash_frequency=8.0,
                          ground_effect_amplitude=1.5, ground_effect_height=0.7),
            rangefinder=sim.RangefinderModel(), gps=sim.GpsModel(jump_probability=0.0), fault_end=7.0),
        "baro-glitches": ScenarioSpec(
            "60 s: climb at 1 m/s to a 5 m hover and back down; 50 Hz baro with spikes (1 %, 4 m), freezes, and an 8 m "
            "pressure glitch from 30 to 32 s; rangefinder",
            lambda: sim.climb_cruise_descend(60.0, 100.0, climb_rate=1.0, cruise_altitude=5.0), _REALISTIC_IMU,
            sim.BaroModel(rate=50.0, noise=0.1, spike_probability=0.01, spike_magnitude=4.0,
                          stuck_probability=0.002, stuck_duration=0.5),
            rangefinder=sim.RangefinderModel(), baro_fault=(30.0, 32.0, 8.0), fault_end=32.0),
        "terrain-step": ScenarioSpec(
            "60 s at 3 m over ground that rises 1 m at 20 s (a roof) and drops back at 40 s; 50 Hz baro, 20 Hz lidar",
            lambda: sim.climb_cruise_descend(60.0, 100.0, climb_rate=1.0, cruise_altitude=3.0), _REALISTIC_IMU,
            sim.BaroModel(rate=50.0, noise=0.15, prop_wash_amplitude=0.2, prop_wash_frequency=8.0),
            rangefinder=sim.RangefinderModel(terrain_steps=((20.0, 1.0), (40.0, -1.0)), dropout_probability=0.0),
            fault_end=40.0),
        "gps-outage": ScenarioSpec(
            "120 s at 30-50 m: 25 Hz baro drifting 3 cm/s, 5 Hz GPS with a 20 s outage from 50 to 70 s",
            lambda: sim.climb_cruise_descend(120.0, 100.0, climb_rate=2.0, cruise_altitude=40.0), _REALISTIC_IMU,
            sim.BaroModel(rate=25.0, noise=0.2, drift_rate=0.03, drift_walk=0.02),
            transient=10.0, gps=sim.GpsModel(jump_probability=0.0, outages=((50.0, 70.0),)), fault_end=70.0),
    }


def scenario_names() -> list:
    """Names accepted by :func:`run_scenario`."""
    return list(_specs())


def describe(name: str) -> str:
    """One-line description of a scenario."""
    return spec(name).description


def spec(name: str) -> ScenarioSpec:
    """The :class:`ScenarioSpec` of a scenario.

    Raises
    ------
    ValueError
        Unknown ``name`` (the message lists the scenarios).
    """
    specs = _specs()
    if name not in specs:
        raise ValueError(f"unknown scenario {name!r}; choose one of {', '.join(specs)}")
    return specs[name]


def run_scenario(name: str = "realistic", seed: int = 0, settings: Optional[AltitudeSettings] = None,
                 attitude: str = "auto") -> ScenarioResult:
    """Simulate a scenario and run the observer on it.

    Parameters
    ----------
    name : str
        One of :func:`scenario_names`.
    seed : int
        Seed of ``numpy.random.default_rng``; same seed, same result.
    settings : AltitudeSettings, optional
        Observer gains; default the scenario's preset. When the baro is
        slower than the IMU they are scaled by the rate ratio
        (:func:`fusion_altitude.tuning.settings_for_baro_rate`) so the designed
        bandwidth holds.
    attitude : {"auto", "ahrs", "truth"}
        ``"ahrs"`` runs the IMU through imufusion (the ``[ahrs]`` extra);
        ``"truth"`` rotates it with the truth attitude; ``"auto"`` uses the
        AHRS when imufusion is installed.

    Returns
    -------
    ScenarioResult
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
    scenario = spec(name)
    attitude = _attitude_source(attitude)
    if name == "rocket":
        return _run_rocket_scenario(scenario, seed, settings, attitude)
    rng = np.random.default_rng(seed)
    trajectory = scenario.trajectory()
    imu = sim.simulate_imu(trajectory, scenario.imu, rng)
    baro = _scenario_baro(scenario, trajectory, rng)
    rangefinder = sim.simulate_rangefinder(trajectory, scenario.rangefinder, rng) if scenario.rangefinder else None
    gps = sim.simulate_gps(trajectory, scenario.gps, rng)[0] if scenario.gps else None
    if attitude == "ahrs":
        accel = sim.ahrs_vertical_acceleration(imu)
    else:
        accel = sim.truth_vertical_acceleration(imu, trajectory)
    baro_altitude = sim.align_to(trajectory.time, baro)
    from ..tuning import settings_for_baro_rate, steps_per_baro

    gains = settings if settings is not None else AltitudeSettings.preset(scenario.preset)
    estimator = AltitudeEstimator(settings_for_baro_rate(gains, steps_per_baro(baro_altitude)))
    estimate = estimator.update_batch(accel, baro_altitude, trajectory.dt)
    return ScenarioResult(name, seed, trajectory, imu, baro, accel, baro_altitude, estimate,
                          scenario.imu.accel_bias[2] * GRAVITY, scenario.transient, attitude, rangefinder, gps,
                          scenario.description, scenario.fault_end)


def _attitude_source(attitude: str) -> str:
    """``"ahrs"`` or ``"truth"`` for :func:`run_scenario`'s ``attitude`` (``"auto"``: the AHRS if imufusion is
    installed)."""
    if attitude == "auto":
        try:
            import imufusion  # noqa: F401
            attitude = "ahrs"
        except ImportError:
            attitude = "truth"
    if attitude not in ("ahrs", "truth"):
        raise ValueError(f"attitude must be 'auto', 'ahrs' or 'truth'; got {attitude!r}")
    return attitude


def _scenario_baro(scenario: ScenarioSpec, trajectory: sim.Trajectory, rng: np.random.Generator) -> sim.BaroStream:
    """The scenario's baro (altitude m, pressure Pa): simulated from ``rng`` (the draws after the IMU's) or the
    scenario's override, plus its pressure glitch (``baro_fault``: start s, end s, offset m)."""
    if scenario.baro_override is not None:
        value = scenario.baro_override(trajectory)
        from ..sensors import altitude_to_pressure
        baro = sim.BaroStream(trajectory.time.copy(), value, altitude_to_pressure(value))
    else:
        baro = sim.simulate_baro(trajectory, scenario.baro, rng)
    if scenario.baro_fault is not None:
        start, end, offset = scenario.baro_fault
        baro.value = baro.value + np.where((baro.time >= start) & (baro.time < end), offset, 0.0)
    return baro


def _run_rocket_scenario(scenario: ScenarioSpec, seed: int, settings: Optional[AltitudeSettings],
                         attitude: str) -> ScenarioResult:
    """The ``rocket`` scenario: one :func:`fusion_altitude.rocket_sim.simulate_rocket_flight` (seeded, randomised).

    Altitudes are on the baro's datum (the pad's pressure altitude + the height
    above the pad). The flight simulator models the long-axis accelerometer only:
    ``imu`` holds it on body z (g), x and y 0, a still gyro, a constant
    magnetometer, ``clipped`` where it saturates; ``vertical_acceleration`` is the
    long-axis reading minus g (the rocket convention of :mod:`fusion_altitude.rocket`),
    which after apogee is the tumbling airframe's, not the vertical; ``attitude``
    changes nothing here. The true bias is the simulated long-axis bias.
    """
    from .rocket_sim import simulate_rocket_flight
    from ..tuning import settings_for_baro_rate, steps_per_baro

    flight = simulate_rocket_flight(seed=seed)
    model = flight.model
    truth = flight.trajectory
    trajectory = sim.Trajectory(truth.time, truth.altitude + model.pad_altitude, truth.vertical_velocity,
                                truth.vertical_acceleration, truth.attitude, "rocket")
    n = truth.time.size
    reading = (flight.accel + GRAVITY) / GRAVITY
    imu = sim.ImuStream(truth.time.copy(), np.column_stack([np.zeros(n), np.zeros(n), reading]), np.zeros((n, 3)),
                        np.tile([0.4, 0.0, -0.3], (n, 1)),
                        np.abs(flight.accel + GRAVITY) >= model.saturation * (1 - 1e-9))
    from ..sensors import altitude_to_pressure
    baro = sim.BaroStream(truth.time.copy(), flight.baro_altitude.copy(), altitude_to_pressure(flight.baro_altitude))
    gains = settings if settings is not None else AltitudeSettings.preset(scenario.preset)
    accel = np.asarray(flight.accel, dtype=float)
    estimate = AltitudeEstimator(settings_for_baro_rate(gains, steps_per_baro(flight.baro_altitude))).update_batch(
        accel, flight.baro_altitude, truth.dt)
    return ScenarioResult("rocket", seed, trajectory, imu, baro, accel, np.asarray(flight.baro_altitude, float),
                          estimate, float(model.accel_bias), scenario.transient, attitude, None, None,
                          scenario.description, None)


def export_csv(result: ScenarioResult, path: str) -> None:
    """Write a scenario run as a log that ``fusion-altitude run`` reads, atomically.

    Columns: ``time`` (s), ``vertical_acceleration`` (m/s², +up, gravity
    removed), ``baro_altitude`` (m; empty on steps without a baro sample) and
    ``true_altitude`` (m, the simulator's truth, for ``--reference``). Floats
    are written at full precision (shortest round-trip repr).

    Run it with ``fusion-altitude run PATH --time time --accel vertical_acceleration --baro baro_altitude
    --reference true_altitude``.
    """
    from ..outputs import atomic_output

    columns = (result.time, result.vertical_acceleration, result.baro_altitude, result.trajectory.altitude)
    table = np.column_stack([np.asarray(c, dtype=np.float64) for c in columns])
    with atomic_output(path) as temporary, open(temporary, "w", newline="") as stream:
        stream.write("time,vertical_acceleration,baro_altitude,true_altitude\n")
        for row in table.tolist():
            stream.write(",".join("" if value != value else repr(value) for value in row) + "\n")


#: Former private name of :func:`spec`, kept for one release.
_spec = spec
