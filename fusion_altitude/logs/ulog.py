"""PX4 ULog (.ulg) through pyulog (the ``[logs]`` extra)."""

from __future__ import annotations

import os

import numpy as np

from ..sensors import vertical_acceleration
from ._data import LogData, LogError, _align, _check_grid, _previous, _reference_on_grid


def read_ulog(path: str) -> LogData:
    """Read a PX4 ULog (.ulg) through pyulog (the ``[logs]`` extra).

    Uses ``vehicle_air_data`` (baro_alt_meter, m, at timestamp_sample),
    ``sensor_combined`` (accelerometer_m_s2, body FRD, and its clipping flags),
    ``vehicle_attitude`` (q, body FRD → NED) and, as the reference,
    ``vehicle_local_position`` (z, vz NED → −z, −vz), instance 0 of each.
    """
    try:
        from pyulog import ULog
    except ImportError as error:
        raise ImportError("reading .ulg logs needs pyulog: pip install 'fusion-altitude[logs]'") from error
    try:
        ulog = ULog(path, ["vehicle_air_data", "sensor_combined", "vehicle_attitude", "vehicle_local_position"])
    except Exception as error:  # pyulog raises a variety of errors on a bad file
        raise LogError(f"cannot read {path} as a PX4 ULog: {error}") from None
    topics = {d.name: d.data for d in ulog.data_list if d.multi_id == 0}
    for needed in ("vehicle_air_data", "sensor_combined", "vehicle_attitude"):
        if needed not in topics:
            raise LogError(f"{path}: topic {needed!r} not in the log; topics are "
                           f"{', '.join(sorted({d.name for d in ulog.data_list}))}")
    imu = topics["sensor_combined"]
    t0 = float(imu["timestamp"][0])  # µs; float before subtracting (uint64 would wrap)
    time = (imu["timestamp"].astype(float) - t0) * 1e-6
    accel_body = np.column_stack([imu[f"accelerometer_m_s2[{i}]"] for i in range(3)]).astype(float)
    att = topics["vehicle_attitude"]
    q = np.column_stack([att[f"q[{i}]"] for i in range(4)]).astype(float)
    q_grid = _previous(imu["timestamp"].astype(float), att["timestamp"].astype(float), q)
    accel = vertical_acceleration(accel_body, q_grid, frame="NED")
    air = topics["vehicle_air_data"]
    air_time = air["timestamp_sample"] if "timestamp_sample" in air else air["timestamp"]
    baro = _align(time, (air_time.astype(float) - t0) * 1e-6, air["baro_alt_meter"].astype(float))
    clipped = imu["accelerometer_clipping"] != 0 if "accelerometer_clipping" in imu else None
    data = LogData(f"{os.path.basename(path)} (PX4 ULog)", time, accel, baro, clipped=clipped,
                   notes=["vehicle_air_data.baro_alt_meter, sensor_combined.accelerometer_m_s2, vehicle_attitude.q"])
    if "vehicle_local_position" in topics:
        lp = topics["vehicle_local_position"]
        data.reference_altitude, data.reference_velocity = _reference_on_grid(
            time, baro, (lp["timestamp"].astype(float) - t0) * 1e-6, -lp["z"].astype(float), -lp["vz"].astype(float))
        data.reference_name = "PX4 EKF (vehicle_local_position)"
    _check_grid(time, data.source)
    return data
