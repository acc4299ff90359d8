"""The INS on the shared real logs, against each log's own estimate.

- PX4 ULog (`px4_sample_log_small.ulg`, a ~1 m hop): raw `sensor_combined`
  gyro (rad/s) and accelerometer (m/s², body FRD) at 205 Hz, baro
  `vehicle_air_data.baro_alt_meter` (19.9 Hz) put on the IMU grid; compared
  with the autopilot's EKF `vehicle_local_position` (−z, −vz) and attitude
  (`vehicle_attitude.q`, tilt only: the local yaw is arbitrary).
- Hedy rocket (`hedy_imu.csv`, `hedy_baro.csv`, 100 Hz): Ax..Gz (m/s², °/s),
  pressure → ISA altitude; compared with the flight computer's own
  `hedy_flight_info.csv` height and velocity. The accelerometer saturates
  during the boost (~20 g): those samples are rejected for attitude and
  integrated as read.

Both comparisons are INS − log estimate, after removing the difference at
the start (both are heights above their own start). The log estimates are
references, not truth.

    python examples/ins_real_logs.py [--data ../shared/data]

Needs pyulog (the [logs] extra). The data directory defaults to
$FUSION_ALTITUDE_SHARED_DATA, else ../shared/data next to the repository.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

import fusion_altitude as fa
from fusion_altitude import _ins_glue
from fusion_altitude.metrics import error_statistics
from fusion_altitude.sensors import pressure_to_altitude


def default_data_dir() -> Path:
    env = os.environ.get("FUSION_ALTITUDE_SHARED_DATA")
    return Path(env) if env else Path(__file__).resolve().parents[2] / "shared" / "data"


def on_grid(target_time, time, value) -> np.ndarray:
    """Each sample placed on the first grid step at or after it; NaN elsewhere."""
    out = np.full(np.shape(target_time), np.nan)
    index = np.searchsorted(target_time, time, side="left")
    keep = index < np.size(target_time)
    out[index[keep]] = value[keep]
    return out


def tilt_deg(q_estimate, q_reference) -> np.ndarray:
    """Angle between the up directions in the body frame of two attitude series, degrees."""
    def up(q):
        w, x, y, z = (q[:, i] for i in range(4))
        return np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)
    return np.degrees(np.arccos(np.clip(np.sum(up(q_estimate) * up(q_reference), axis=1), -1, 1)))


def px4(data: Path) -> dict:
    from pyulog import ULog

    ulog = ULog(str(data / "px4_sample_log_small.ulg"),
                ["sensor_combined", "vehicle_air_data", "vehicle_local_position", "vehicle_attitude"])
    topics = {d.name: d.data for d in ulog.data_list}
    imu = topics["sensor_combined"]
    t = imu["timestamp"] * 1e-6
    gyro = np.stack([imu[f"gyro_rad[{i}]"] for i in range(3)], axis=1)
    accel = np.stack([imu[f"accelerometer_m_s2[{i}]"] for i in range(3)], axis=1)
    air = topics["vehicle_air_data"]
    baro = on_grid(t, air.get("timestamp_sample", air["timestamp"]) * 1e-6, air["baro_alt_meter"])
    result = fa.ins_run(t, gyro, accel, baro)
    position = topics["vehicle_local_position"]
    tp = position["timestamp"] * 1e-6
    height = np.interp(t, tp, -position["z"])
    velocity = np.interp(t, tp, -position["vz"])
    attitude = topics["vehicle_attitude"]
    ta = attitude["timestamp"] * 1e-6
    q_ref = np.stack([np.interp(t, ta, attitude[f"q[{i}]"]) for i in range(4)], axis=1)
    # PX4 q is body FRD -> NED; our earth is NWU (z up). Same body axes, so the body up directions compare
    # after flipping NED's down: up_NED_in_body = -(third row of R_ned)
    q_ref_up = q_ref
    return summarise("PX4 ULog hop (sensor_combined 205 Hz, baro 19.9 Hz)", t, result, height, velocity, baro,
                     tilt=tilt_flip(result.quaternion, q_ref_up))


def tilt_flip(q_ins, q_ned) -> np.ndarray:
    """Tilt difference between the INS (body -> NWU) and a body -> NED attitude: compares body up vs −(body down)."""
    def row3(q):
        w, x, y, z = (q[:, i] for i in range(4))
        return np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)
    cosine = np.sum(row3(np.asarray(q_ins, float)) * -row3(np.asarray(q_ned, float)), axis=1)
    return np.degrees(np.arccos(np.clip(cosine, -1, 1)))


def hedy(data: Path) -> dict:
    imu = np.genfromtxt(data / "hedy_imu.csv", delimiter=",", names=True, dtype=None, encoding="ascii")
    baro = np.genfromtxt(data / "hedy_baro.csv", delimiter=",", names=True, dtype=None, encoding="ascii")
    info = np.genfromtxt(data / "hedy_flight_info.csv", delimiter=",", names=True, dtype=None, encoding="ascii")
    t = np.asarray(imu["ts"], dtype=float)
    keep = np.concatenate([[True], np.diff(t) > 0])
    t = t[keep]
    gyro = np.stack([imu["Gx"], imu["Gy"], imu["Gz"]], axis=1)[keep]
    accel = np.stack([imu["Ax"], imu["Ay"], imu["Az"]], axis=1)[keep]
    ground = np.median(baro["P"][baro["ts"] < 0])
    baro_altitude = on_grid(t, np.asarray(baro["ts"], float), pressure_to_altitude(baro["P"], sea_level_pa=ground))
    result = fa.ins_run(t, gyro, accel, baro_altitude, gyro_units="deg/s")
    height = np.interp(t, info["ts"], info["height"])
    velocity = np.interp(t, info["ts"], info["velocity"])
    row = summarise("Hedy rocket (IMU 100 Hz, saturates in the boost; baro 100 Hz)", t, result, height, velocity,
                    baro_altitude)
    apogee = int(np.argmax(height))
    row["apogee (m): log / INS / baro"] = (f"{height[apogee]:.0f} / "
                                          f"{np.max(result.height_above_start):.0f} / {np.nanmax(baro_altitude):.0f}")
    return row


def summarise(name, t, result, height, velocity, baro, tilt=None) -> dict:
    altitude = result.height_above_start.astype(float)
    error = (altitude - altitude[0]) - (height - height[0])
    velocity_error = result.vertical_velocity - velocity
    sampled = np.isfinite(baro)
    baro_error = (altitude + result.baro_bias - baro)[sampled]
    log_baro_error = (height - height[0] + baro[sampled][0] - baro)[sampled]

    def rms(error, time=t):  # over the whole log
        return error_statistics(time, error, transient=-np.inf).rms

    row = {
        "log": name,
        "steps": t.size,
        "duration (s)": f"{t[-1] - t[0]:.1f}",
        "height RMS diff (m)": f"{rms(error):.3f}",
        "height max |diff| (m)": f"{np.max(np.abs(error)):.3f}",
        "velocity RMS diff (m/s)": f"{rms(velocity_error):.3f}",
        "INS vs raw baro RMS (m)": f"{rms(baro_error, t[sampled]):.3f}",
        "log estimate vs raw baro RMS (m)": f"{rms(log_baro_error, t[sampled]):.3f}",
        "stationary at start": bool(result.is_stationary[: max(1, t.size // 20)].any()),
        "gyro bias at end (°/s)": np.array2string(np.degrees(result.gyro_bias[-1]), precision=3),
    }
    if tilt is not None:
        row["tilt RMS diff vs log attitude (°)"] = f"{rms(tilt):.2f}"
    row["_error"] = error
    row["_baro_rms"] = rms(baro_error, t[sampled])
    row["_apogee"] = (float(np.max(height)), float(np.max(altitude)))
    return row


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=default_data_dir())
    args = parser.parse_args(argv)
    for row in (px4(args.data), hedy(args.data)):
        print(f"## {row['log']}")
        for key, value in row.items():
            if not key.startswith("_") and key != "log":
                print(f"- {key}: {value}")
        print()


if __name__ == "__main__":
    main()
