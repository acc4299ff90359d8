"""ArduPilot DataFlash (.bin) through pymavlink (the ``[logs]`` extra)."""

from __future__ import annotations

import os

import numpy as np

from ..sensors import vertical_acceleration
from ._data import LogData, LogError, _align, _check_grid, _previous, _reference_on_grid


def read_dataflash(path: str) -> LogData:
    """Read an ArduPilot DataFlash log (.bin) through pymavlink (the ``[logs]`` extra).

    Uses ``IMU`` (AccX/Y/Z m/s², body FRD; instance 0), ``ATT`` (Roll, Pitch,
    Yaw in °, NED), ``BARO`` (Alt, m; instance 0) and, as the reference, the
    first of ``XKF1``, ``NKF1``, ``EKF1`` in the log (PD, VD → −PD, −VD; core 0).
    """
    try:
        from pymavlink import mavutil
    except ImportError as error:
        raise ImportError("reading .bin logs needs pymavlink: pip install 'fusion-altitude[logs]'") from error
    kinds = ["IMU", "ATT", "BARO", "XKF1", "NKF1", "EKF1"]
    rows = {kind: [] for kind in kinds}
    try:
        log = mavutil.mavlink_connection(path)
        while True:
            message = log.recv_match(type=kinds)
            if message is None:
                break
            kind = message.get_type()
            fields = message.to_dict()
            instance = fields.get("I", fields.get("C", 0))
            if instance in (0, "0", None):
                rows[kind].append(fields)
    except Exception as error:
        raise LogError(f"cannot read {path} as an ArduPilot DataFlash log: {error}") from None
    for needed in ("IMU", "ATT", "BARO"):
        if not rows[needed]:
            raise LogError(f"{path}: no {needed} messages in the log")

    def column(kind, name):
        return np.array([r[name] for r in rows[kind]], dtype=float)

    t0 = column("IMU", "TimeUS")[0]
    time = (column("IMU", "TimeUS") - t0) * 1e-6
    accel_body = np.column_stack([column("IMU", f"Acc{axis}") for axis in "XYZ"])
    att_time = (column("ATT", "TimeUS") - t0) * 1e-6
    euler = np.radians(np.column_stack([column("ATT", name) for name in ("Roll", "Pitch", "Yaw")]))
    accel = vertical_acceleration(accel_body, _previous(time, att_time, euler), frame="NED")
    baro = _align(time, (column("BARO", "TimeUS") - t0) * 1e-6, column("BARO", "Alt"))
    data = LogData(f"{os.path.basename(path)} (ArduPilot DataFlash)", time, accel, baro,
                   notes=["BARO.Alt, IMU.AccX/Y/Z, ATT.Roll/Pitch/Yaw"])
    for kind in ("XKF1", "NKF1", "EKF1"):
        if rows[kind]:
            ref_time = (column(kind, "TimeUS") - t0) * 1e-6
            velocity = -column(kind, "VD") if "VD" in rows[kind][0] else np.gradient(-column(kind, "PD"), ref_time)
            data.reference_altitude, data.reference_velocity = _reference_on_grid(
                time, baro, ref_time, -column(kind, "PD"), velocity)
            data.reference_name = f"ArduPilot EKF ({kind})"
            break
    _check_grid(time, data.source)
    return data
