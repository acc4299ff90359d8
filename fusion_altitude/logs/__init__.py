"""Recorded logs: one reader module per format, all returning :class:`LogData`.

Every reader returns a :class:`LogData` on one time grid (the accelerometer's
timestamps, possibly irregular): the observer's vertical-acceleration input
(m/s², +up, gravity removed), the baro altitude (m; NaN on steps without a new
baro sample) and, when the log has one, the autopilot's own height estimate
as a reference. :func:`fusion_altitude.runner.run_log` runs an estimator on it.

Readers
-------
* :func:`read_csv_log`: columns named by the caller.
* :func:`read_ulog` (PX4, needs the ``[logs]`` extra): baro altitude from
  ``vehicle_air_data.baro_alt_meter``, specific force from
  ``sensor_combined.accelerometer_m_s2`` rotated by ``vehicle_attitude.q``
  (NED), reference ``vehicle_local_position`` (−z, −vz).
* :func:`read_dataflash` (ArduPilot, ``[logs]``): ``BARO.Alt``, ``IMU.Acc*``
  rotated by ``ATT`` roll/pitch/yaw (NED), reference ``−PD`` of the first of
  ``XKF1``, ``NKF1``, ``EKF1`` present (core 0).

Autopilot heights are relative to their own origin; the reference is shifted
by the median of (baro − reference) over the first 2 s with both, so that it
shares the baro's datum. Differences are therefore about shape, not datum.

Bad input raises :class:`LogError` naming the file, column or row.
"""

from __future__ import annotations

import os

from ._data import LogData, LogError
from .dataflash import read_dataflash
from .generic_csv import read_csv_log
from .ulog import read_ulog

__all__ = ["LogError", "LogData", "read_csv_log", "read_ulog", "read_dataflash", "load_log"]


def load_log(path: str, **csv_options) -> LogData:
    """Read a log by its extension: ``.ulg`` PX4, ``.bin`` ArduPilot, anything else CSV (``csv_options``)."""
    if not os.path.exists(path):
        raise LogError(f"{path}: no such file")
    suffix = os.path.splitext(path)[1].lower()
    if suffix == ".ulg":
        return read_ulog(path)
    if suffix == ".bin":
        return read_dataflash(path)
    return read_csv_log(path, **csv_options)
