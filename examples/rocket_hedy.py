"""The rocket estimator on the real Hedy flight (CATS flight computer, EuRoC 2025), against CATS's own estimate.

    FUSION_ALTITUDE_SHARED_DATA=/path/to/shared/data python examples/rocket_hedy.py

Prints the events table (ours vs the CATS events, found as `fusion-altitude run`
finds them: the log read by fusion_altitude.logs.read_cats, its events by
fusion_altitude.rocket.flight_computer_events, i.e. events_from_estimates on
the CATS height and velocity on the IMU's time grid, its acceleration the
time derivative of that velocity) and our height minus the CATS
height per flight phase; with --ins, the accelerometer is first rotated to the
vertical by plain gyro integration (fusion_altitude.sensors.gyro_attitude) and
passed as a trusted vertical acceleration. With --fit, the static-port coefficient c of
baro − inertial = d0 + d1·t − c·v²/(2g), fitted over the coast (9.5–25 s)
and the boost (0.5–6.5 s, without the drift term), from the raw long-axis
integration (no pad calibration: the pad part of the log is ignition shake).
"""

import os
import sys
from pathlib import Path

import numpy as np

from fusion_altitude import rocket
from fusion_altitude.logs import read_cats
from fusion_altitude.metrics import error_statistics
from fusion_altitude.sensors import gyro_attitude, pressure_to_altitude, vertical_acceleration

DATA = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", Path(__file__).resolve().parents[2] / "shared" / "data"))


def read(name):
    return np.genfromtxt(DATA / name, delimiter=",", names=True, dtype=None, encoding=None)


def main(use_ins: bool) -> None:
    baro, imu, info = read("hedy_baro.csv"), read("hedy_imu.csv"), read("hedy_flight_info.csv")
    time = baro["ts"].astype(np.float64)
    accel_body = np.column_stack([imu["Ax"], imu["Ay"], imu["Az"]])
    if use_ins:
        gyro = np.column_stack([imu["Gx"], imu["Gy"], imu["Gz"]])
        pad = time < -0.2
        dt = np.diff(time, prepend=time[0] - 0.01)
        attitude = gyro_attitude(gyro, dt, accel_body[pad].mean(axis=0), gyro_bias_dps=gyro[pad].mean(axis=0))
        accel = vertical_acceleration(accel_body, attitude, frame="ENU")
    else:
        accel = rocket.long_axis_accel(accel_body, axis=1, sign=-1)
    batch, events = rocket.run_rocket(time, accel, pressure_to_altitude(baro["P"].astype(np.float64)),
                                      accel_is_vertical=use_ins)
    cats, _ = rocket.flight_computer_events(read_cats(str(DATA / "hedy_baro.csv")))
    print("| event | ours: time (s) | ours: height (m) | CATS estimate: time (s) | CATS estimate: height (m) |")
    print("|---|---|---|---|---|")
    for ours, theirs in zip(events, cats):
        cell = lambda e: (f"{e.time:.3f}", f"{e.height:.1f}") if e.occurred else ("—", "—")
        print(f"| {ours.name} | " + " | ".join(cell(ours) + cell(theirs)) + " |")
    difference = batch.height - np.interp(time, info["ts"], info["height"])
    launch, burnout, apogee = (events[name].sample for name in ("launch", "burnout", "apogee"))
    print()
    print("| ours − CATS height (m) | mean | RMS | max abs |")
    print("|---|---|---|---|")
    for name, part in (("pad", slice(0, launch)), ("boost", slice(launch, burnout)), ("coast", slice(burnout, apogee)),
                       ("descent (apogee to end of log)", slice(apogee, None))):
        d = error_statistics(time[part], difference[part].astype(np.float64), transient=-np.inf)
        print(f"| {name} | {d.mean:+.1f} | {d.rms:.1f} | {d.max:.1f} |")


def fit() -> None:
    baro, imu = read("hedy_baro.csv"), read("hedy_imu.csv")
    time = baro["ts"].astype(np.float64)
    altitude = pressure_to_altitude(baro["P"].astype(np.float64))
    altitude -= altitude[:60].mean()
    accel = rocket.long_axis_accel(np.column_stack([imu["Ax"], imu["Ay"], imu["Az"]]), axis=1, sign=-1)
    start = int(np.argmax(time > -0.12))
    velocity = np.zeros_like(time)
    height = np.zeros_like(time)
    for k in range(start + 1, time.size):
        dt = time[k] - time[k - 1]
        velocity[k] = velocity[k - 1] + accel[k] * dt
        height[k] = height[k - 1] + velocity[k] * dt
    difference = altitude - height
    pressure_term = -velocity ** 2 / (2 * 9.80665)
    coast = (time > 9.5) & (time < 25.0)
    design = np.column_stack([np.ones(coast.sum()), time[coast], pressure_term[coast]])
    (d0, d1, c), *_ = np.linalg.lstsq(design, difference[coast], rcond=None)
    residual = error_statistics(time[coast], design @ (d0, d1, c) - difference[coast], transient=-np.inf).rms
    print(f"coast: c = {c:.4f}, d0 = {d0:.1f} m, d1 = {d1:.2f} m/s, residual RMS {residual:.1f} m")
    boost = (time > 0.5) & (time < 6.5)
    design = np.column_stack([np.ones(boost.sum()), pressure_term[boost]])
    (_, c_boost), *_ = np.linalg.lstsq(design, difference[boost], rcond=None)
    print(f"boost: c = {c_boost:.4f}")
    for speed in (50, 100, 150, 200, 236, 300):
        print(f"  {speed} m/s: baro low by {c * speed ** 2 / (2 * 9.80665):.0f} m")


if __name__ == "__main__":
    if "--fit" in sys.argv[1:]:
        fit()
    else:
        main("--ins" in sys.argv[1:])
