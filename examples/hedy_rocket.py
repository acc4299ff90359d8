"""Real rocket flight end to end: TU Wien "Hedy" (EuRoC 2025, CATS flight computer).

Pipeline, all with library functions:

1. pressure (Pa) → height above the pad with the ISA troposphere formula,
   referenced to the median pre-launch pressure
   (:func:`fusion_altitude.sensors.pressure_to_altitude`);
2. attitude by gyro integration from the on-rail attitude, levelled on the
   pre-launch specific force, with the pre-launch mean rate removed as gyro
   bias (:func:`fusion_altitude.sensors.gyro_attitude`);
3. body specific force → vertical acceleration, +up, gravity removed
   (:func:`fusion_altitude.sensors.vertical_acceleration`);
4. the observer (:func:`fusion_altitude.runner.run_observer`) with rocket gains,
   where accelerometer clipping is handled explicitly (see below);
5. comparison with the flight computer's own height estimate.

Clipping: a sample counts as clipped when any axis reads at or beyond
``ACCEL_RANGE`` (m/s²). On clipped samples the observer keeps the (too small)
reading, switches to baro-trusting gains and freezes its bias estimate
(:func:`fusion_altitude.runner.run_observer`). The script prints how many
samples were clipped.

Run::

    python examples/hedy_rocket.py [--data ../shared/data] [--plot hedy.png]

The data directory defaults to $FUSION_ALTITUDE_SHARED_DATA, else
../shared/data relative to the repository root.
"""

from __future__ import annotations

import argparse
import os
from dataclasses import dataclass

import numpy as np

from fusion_altitude import AltitudeSettings
from fusion_altitude.runner import run_observer
from fusion_altitude.sensors import gyro_attitude, pressure_to_altitude, vertical_acceleration

#: Accelerometer full scale assumed for clip detection, m/s² (±16 g).
ACCEL_RANGE = 16 * 9.80665
#: Samples before this time (s, 0 = launch) are taken as "on the rail, at rest".
REST_END = -0.2
#: Observer gains for the rocket: position-loop ω (rad/s); ζ 0.7, ω_b = ω/5 (the fixed_wing preset).
#: Slower than VTOL so transonic baro errors during boost are not followed (measured: RMS 11.6 m
#: at 0.5 vs 16.5 m at 1.5 rad/s).
OMEGA = 0.5


@dataclass
class HedyRun:
    """Hedy flight on the 100 Hz grid: time s, baro altitude m, vertical acceleration m/s², the
    observer's estimate, the flight computer's height m and velocity m/s, and the clipped mask."""

    time: np.ndarray
    baro_altitude: np.ndarray
    vertical_acceleration: np.ndarray
    estimate: object
    reference_altitude: np.ndarray
    reference_velocity: np.ndarray
    clipped: np.ndarray


def default_data_dir() -> str:
    """$FUSION_ALTITUDE_SHARED_DATA, else ../shared/data relative to the repository root."""
    here = os.path.dirname(os.path.abspath(__file__))
    return os.environ.get("FUSION_ALTITUDE_SHARED_DATA", os.path.join(here, "..", "..", "shared", "data"))


def _read(path: str) -> dict:
    table = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    return {name: np.asarray(table[name]) for name in table.dtype.names}


def run_hedy(data_dir: str, omega: float = OMEGA, accel_range: float = ACCEL_RANGE) -> HedyRun:
    """Run the pipeline of this module's docstring on the Hedy CSVs in ``data_dir``."""
    baro = _read(os.path.join(data_dir, "hedy_baro.csv"))
    imu = _read(os.path.join(data_dir, "hedy_imu.csv"))
    info = _read(os.path.join(data_dir, "hedy_flight_info.csv"))
    time = imu["ts"].astype(float)
    if not np.array_equal(baro["ts"], imu["ts"]):
        raise ValueError("hedy_baro.csv and hedy_imu.csv are expected on the same timestamps")
    rest = time < REST_END
    ground_pa = float(np.median(baro["P"][rest]))
    baro_altitude = pressure_to_altitude(baro["P"].astype(float), sea_level_pa=ground_pa)
    accel_body = np.column_stack([imu["Ax"], imu["Ay"], imu["Az"]]).astype(float)
    gyro = np.column_stack([imu["Gx"], imu["Gy"], imu["Gz"]]).astype(float)
    dt = np.diff(time, prepend=time[0] - 0.01)
    attitude = gyro_attitude(gyro, dt, accel_body[rest].mean(axis=0), gyro[rest].mean(axis=0))
    accel = vertical_acceleration(accel_body, attitude, frame="ENU")
    clipped = np.any(np.abs(accel_body) >= accel_range, axis=1)
    estimate = run_observer(time, accel, baro_altitude, AltitudeSettings.from_bandwidth(omega), clipped=clipped)
    reference_altitude = np.interp(time, info["ts"], info["height"])
    reference_velocity = np.interp(time, info["ts"], info["velocity"])
    return HedyRun(time, baro_altitude, accel, estimate, reference_altitude, reference_velocity, clipped)


def summary(run: HedyRun) -> dict:
    """RMS and max |estimate − flight computer| (m) after launch to the end, apogee heights (m) and times (s)."""
    from fusion_altitude.metrics import error_statistics

    flight = run.time >= 0
    difference = run.estimate.altitude[flight] - run.reference_altitude[flight]
    statistics = error_statistics(run.time[flight], difference, transient=0.0)
    i_est = int(np.argmax(run.estimate.altitude))
    i_ref = int(np.argmax(run.reference_altitude))
    i_baro = int(np.nanargmax(run.baro_altitude))
    return {
        "rms_difference": statistics.rms,
        "max_difference": statistics.max,
        "apogee_estimate": float(run.estimate.altitude[i_est]),
        "apogee_reference": float(run.reference_altitude[i_ref]),
        "apogee_baro": float(run.baro_altitude[i_baro]),
        "apogee_error": float(run.estimate.altitude[i_est] - run.reference_altitude[i_ref]),
        "apogee_time_estimate": float(run.time[i_est]),
        "apogee_time_reference": float(run.time[i_ref]),
        "clipped_samples": int(run.clipped.sum()),
    }


def plot(run: HedyRun, path: str) -> None:
    """Write a PNG: heights, difference to the flight computer, vertical velocity (the [plot] extra)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as error:
        raise SystemExit("plotting needs matplotlib: pip install 'fusion-altitude[plot]'") from error
    fig, axes = plt.subplots(3, 1, figsize=(10, 9), sharex=True, constrained_layout=True)
    axes[0].plot(run.time, run.baro_altitude, color="0.6", lw=0.8, label="baro (ISA, pad reference)")
    axes[0].plot(run.time, run.reference_altitude, color="k", lw=1.2, label="CATS flight computer")
    axes[0].plot(run.time, run.estimate.altitude, color="C0", lw=1.0, label="fusion-altitude")
    axes[0].set_ylabel("height above pad (m)")
    axes[0].legend(fontsize=8)
    axes[0].set_title("Hedy (TU Wien Space Team, EuRoC 2025)")
    axes[1].plot(run.time, run.baro_altitude - run.reference_altitude, color="0.6", lw=0.8, label="baro − CATS")
    axes[1].plot(run.time, run.estimate.altitude - run.reference_altitude, color="C0", lw=1.0,
                 label="fusion-altitude − CATS")
    if run.clipped.any():
        axes[1].fill_between(run.time, -50, 50, where=run.clipped, color="C3", alpha=0.2, label="accel clipped")
    axes[1].set_ylim(-60, 60)
    axes[1].set_ylabel("difference (m)")
    axes[1].legend(fontsize=8)
    axes[2].plot(run.time, run.reference_velocity, color="k", lw=1.2, label="CATS")
    axes[2].plot(run.time, run.estimate.vertical_velocity, color="C0", lw=1.0, label="fusion-altitude")
    axes[2].set_ylabel("vertical velocity (m/s)")
    axes[2].set_xlabel("time since launch (s)")
    axes[2].legend(fontsize=8)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=default_data_dir(), help="directory with the hedy_*.csv files")
    parser.add_argument("--plot", metavar="OUT.png", help="write a plot")
    args = parser.parse_args(argv)
    run = run_hedy(args.data)
    result = summary(run)
    print(f"clipped accelerometer samples (any axis ≥ {ACCEL_RANGE:.1f} m/s²): {result['clipped_samples']}")
    print(f"RMS |fusion-altitude − CATS| from launch: {result['rms_difference']:.2f} m "
          f"(max {result['max_difference']:.2f} m)")
    print(f"apogee: fusion-altitude {result['apogee_estimate']:.1f} m at {result['apogee_time_estimate']:.2f} s, "
          f"CATS {result['apogee_reference']:.1f} m at {result['apogee_time_reference']:.2f} s, "
          f"raw baro {result['apogee_baro']:.1f} m; error {result['apogee_error']:+.1f} m")
    if args.plot:
        plot(run, args.plot)
        print(f"plot written to {args.plot}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
