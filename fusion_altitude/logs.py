"""Recorded logs: read CSV, PX4 ULog and ArduPilot DataFlash, run the observer on them.

Every reader returns a :class:`LogData` on one time grid (the accelerometer's
timestamps, possibly irregular): the observer's vertical-acceleration input
(m/s², +up, gravity removed), the baro altitude (m; NaN on steps without a new
baro sample) and, when the log has one, the autopilot's own height estimate
as a reference. :func:`run_log` runs the observer on it.

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

import csv
import os
from dataclasses import dataclass, field
from typing import Callable, List, Optional

import numpy as np

from ._common import GRAVITY
from ._observer_glue import AltitudeBatch
from ._observer import AltitudeEstimator, AltitudeSettings
from .metrics import ErrorStatistics, error_statistics
from .sensors import pressure_to_altitude, vertical_acceleration

__all__ = [
    "LogError",
    "LogData",
    "LogRun",
    "read_csv_log",
    "read_ulog",
    "read_dataflash",
    "load_log",
    "run_observer",
    "sample_periods",
    "settings_for_baro_rate",
    "run_log",
    "write_csv",
]


class LogError(ValueError):
    """A log cannot be read or used; the message names the file, column or row."""


@dataclass
class LogData:
    """A log on the observer's time grid.

    Attributes
    ----------
    source : str
        File name and format.
    time : numpy.ndarray
        Sample times, s, strictly increasing (irregular allowed).
    vertical_acceleration : numpy.ndarray
        Observer input, m/s², earth frame, +up, gravity removed.
    baro_altitude : numpy.ndarray
        Baro altitude, m; NaN on steps without a new baro sample.
    reference_altitude, reference_velocity : numpy.ndarray or None
        The autopilot's own height (m, baro datum) and vertical velocity
        (m/s, +up) on the same grid, if the log has them.
    reference_name : str
        Where the reference came from.
    clipped : numpy.ndarray or None
        True on samples where the accelerometer was at its range limit.
    notes : list of str
        What the reader chose (topics, instances), for the report.
    """

    source: str
    time: np.ndarray
    vertical_acceleration: np.ndarray
    baro_altitude: np.ndarray
    reference_altitude: Optional[np.ndarray] = None
    reference_velocity: Optional[np.ndarray] = None
    reference_name: str = ""
    clipped: Optional[np.ndarray] = None
    notes: List[str] = field(default_factory=list)


@dataclass
class LogRun(LogData):
    """A :class:`LogData` with the observer's outputs (``estimate``, per grid step)."""

    estimate: Optional[AltitudeBatch] = None

    def comparison(self, transient: float = 0.0) -> Optional[ErrorStatistics]:
        """Statistics of fused − reference altitude (m) after ``transient`` s; None without a reference."""
        if self.reference_altitude is None:
            return None
        return error_statistics(self.time, self.estimate.altitude - self.reference_altitude, transient)

    def baro_comparison(self, transient: float = 0.0) -> Optional[ErrorStatistics]:
        """Statistics of baro − reference altitude (m) after ``transient`` s; None without a reference."""
        if self.reference_altitude is None:
            return None
        return error_statistics(self.time, self.baro_altitude - self.reference_altitude, transient)


# ----------------------------------------------------------------------------
# Helpers


def _align(target_time: np.ndarray, source_time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Each source sample on the first target step at or after it; NaN on other steps (newest wins)."""
    out = np.full(target_time.shape, np.nan)
    index = np.searchsorted(target_time, source_time, side="left")
    keep = (index < target_time.size) & np.isfinite(values)
    out[index[keep]] = values[keep]
    return out


def _previous(target_time: np.ndarray, source_time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The latest source sample at or before each target time (the first one before it starts)."""
    index = np.clip(np.searchsorted(source_time, target_time, side="right") - 1, 0, source_time.size - 1)
    return values[index]


def _reference_on_grid(time, baro_altitude, ref_time, ref_altitude, ref_velocity):
    altitude = np.interp(time, ref_time, ref_altitude, left=np.nan, right=np.nan)
    velocity = np.interp(time, ref_time, ref_velocity, left=np.nan, right=np.nan)
    both = np.isfinite(altitude) & np.isfinite(baro_altitude)
    early = both & (time <= time[both][0] + 2.0) if both.any() else both
    if early.any():
        altitude = altitude + float(np.median(baro_altitude[early] - altitude[early]))
    return altitude, velocity


def _check_grid(time: np.ndarray, source: str) -> None:
    bad = np.flatnonzero(~(np.diff(time) > 0))
    if bad.size:
        raise LogError(f"{source}: time must increase strictly; sample {bad[0] + 1} "
                       f"({time[bad[0] + 1]!r} s) follows {time[bad[0]]!r} s")


# ----------------------------------------------------------------------------
# CSV


def read_csv_log(path: str, time_column: str, accel_column: str, baro_column: Optional[str] = None,
                 pressure_column: Optional[str] = None, accel_units: str = "m/s^2",
                 sea_level_pa: float = 101325.0, reference_column: Optional[str] = None) -> LogData:
    """Read a CSV log with a header row.

    Parameters
    ----------
    path : str
        CSV file (comma separated, header on the first line).
    time_column : str
        Time, s; must increase strictly (irregular steps are fine).
    accel_column : str
        Vertical acceleration, earth frame, +up, gravity removed, in
        ``accel_units``; every row needs one.
    baro_column : str, optional
        Baro altitude, m; an empty cell or ``nan`` means no baro that row.
    pressure_column : str, optional
        Static pressure, Pa, converted with the ISA troposphere formula
        (:func:`fusion_altitude.sensors.pressure_to_altitude`) relative to
        ``sea_level_pa``. Give ``baro_column`` or this, not both.
    accel_units : {"m/s^2", "g"}
        Units of the acceleration column.
    sea_level_pa : float
        Reference pressure for ``pressure_column``, Pa.
    reference_column : str, optional
        A better altitude for (part of) the log, m (RTK GPS, motion capture);
        an empty cell or ``nan`` means unknown. Becomes ``reference_altitude``.

    Raises
    ------
    LogError
        Missing file or column, a cell that is not a number (naming column
        and line), time not increasing (naming the line).
    """
    if (baro_column is None) == (pressure_column is None):
        raise LogError("give exactly one of a baro altitude column or a pressure column")
    if accel_units not in ("m/s^2", "g"):
        raise LogError(f"accel units must be 'm/s^2' or 'g', got {accel_units!r}")
    try:
        handle = open(path, newline="")
    except OSError as error:
        raise LogError(f"cannot open {path}: {error.strerror}") from None
    with handle:
        reader = csv.reader(handle)
        try:
            header = [name.strip() for name in next(reader)]
        except StopIteration:
            raise LogError(f"{path} is empty") from None
        wanted = {"time": time_column, "accel": accel_column, "baro": baro_column or pressure_column}
        if reference_column is not None:
            wanted["reference"] = reference_column
        index = {}
        for role, name in wanted.items():
            if name not in header:
                raise LogError(f"{path}: column {name!r} not found; columns are {', '.join(header)}")
            index[role] = header.index(name)
        columns = {role: [] for role in wanted}
        for line_number, row in enumerate(reader, start=2):
            if not row or all(not cell.strip() for cell in row):
                continue
            for role, name in wanted.items():
                cell = row[index[role]].strip() if index[role] < len(row) else ""
                if role in ("baro", "reference") and cell.lower() in ("", "nan", "na", "null"):
                    columns[role].append(np.nan)
                    continue
                try:
                    value = float(cell)
                except ValueError:
                    raise LogError(f"{path}: line {line_number}, column {name!r}: {cell!r} is not a number") from None
                if role in ("time", "accel") and not np.isfinite(value):
                    raise LogError(f"{path}: line {line_number}, column {name!r}: {cell!r} must be finite")
                columns[role].append(value)
    time = np.asarray(columns["time"], dtype=float)
    if time.size < 2:
        raise LogError(f"{path}: need at least 2 data rows, got {time.size}")
    bad = np.flatnonzero(~(np.diff(time) > 0))
    if bad.size:
        raise LogError(f"{path}: line {bad[0] + 3}, column {time_column!r}: time {time[bad[0] + 1]!r} s does not "
                       f"increase (previous row {time[bad[0]]!r} s)")
    accel = np.asarray(columns["accel"], dtype=float) * (GRAVITY if accel_units == "g" else 1.0)
    baro = np.asarray(columns["baro"], dtype=float)
    if pressure_column is not None:
        baro = pressure_to_altitude(baro, sea_level_pa)
    reference = np.asarray(columns["reference"], dtype=float) if reference_column is not None else None
    return LogData(f"{os.path.basename(path)} (CSV)", time, accel, baro, reference_altitude=reference,
                   reference_name=f"column {reference_column!r}" if reference_column is not None else "",
                   notes=[f"time {time_column!r}, accel {accel_column!r} ({accel_units}), "
                          + (f"baro {baro_column!r} (m)" if baro_column else f"pressure {pressure_column!r} (Pa)")])


# ----------------------------------------------------------------------------
# PX4 ULog


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


# ----------------------------------------------------------------------------
# ArduPilot DataFlash


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


# ----------------------------------------------------------------------------
# Running the observer


def run_observer(time, vertical_acceleration, baro_altitude, settings: Optional[AltitudeSettings] = None,
                 clipped=None, clipped_settings: Optional[AltitudeSettings] = None,
                 progress: Optional[Callable[[int, int], None]] = None, chunk: int = 50_000,
                 compensate_baro_rate: bool = True) -> AltitudeBatch:
    """Run the observer over a log with irregular timestamps and missing baro samples.

    Parameters
    ----------
    time : array_like
        Sample times, s, strictly increasing; dt[i] = time[i] − time[i−1]
        (the first step uses the second step's dt; it only sets the reference).
    vertical_acceleration : array_like
        m/s², +up, gravity removed.
    baro_altitude : array_like
        m; NaN where there is no baro sample.
    settings : AltitudeSettings, optional
        Gains; default the VTOL preset.
    clipped : array_like of bool, optional
        Samples whose accelerometer reading hit its range. See Notes.
    clipped_settings : AltitudeSettings, optional
        Gains on clipped samples; default ``settings`` with the position loop
        4× faster (ω·4, ζ 0.7) and **bias estimation off** (Kb = 0).
    progress : callable(done, total), optional
        Called after each chunk of samples.
    compensate_baro_rate : bool, default True
        Scale the gains by (samples / baro samples) when the baro is slower
        than the grid (:func:`settings_for_baro_rate`), so ``settings`` keeps
        its designed bandwidth.

    Returns
    -------
    AltitudeBatch

    Notes
    -----
    **Clipping.** A clipped accelerometer under-reports the acceleration, and
    the observer would integrate that error and push it into its bias
    estimate. On clipped samples the observer therefore (1) still uses the
    clipped reading (a lower bound of the true magnitude), (2) switches to
    baro-trusting gains so the baro pulls the estimate back quickly, and
    (3) freezes the bias estimate (Kb = 0) so the bias learned before the
    clipping survives it. The normal gains return on the first unclipped
    sample, with the state carried over.
    """
    time = np.asarray(time, dtype=float)
    accel = np.asarray(vertical_acceleration, dtype=float)
    baro = np.asarray(baro_altitude, dtype=float)
    n = time.size
    dt = sample_periods(time)
    settings = settings or AltitudeSettings()
    n_baro = int(np.sum(np.isfinite(baro)))
    if compensate_baro_rate and n_baro > 0:
        settings = settings_for_baro_rate(settings, n / n_baro)
    estimator = AltitudeEstimator(settings)
    normal = estimator.settings
    if clipped is None:
        clipped = np.zeros(n, dtype=bool)
    clipped = np.asarray(clipped, dtype=bool)
    if clipped.any() and clipped_settings is None:
        omega = _bandwidth_of(normal)
        clipped_settings = AltitudeSettings.from_bandwidth(4 * omega, 0.7, 0.0)
    out = AltitudeBatch(*(np.empty(n, dtype=np.float32) for _ in range(4)))
    # Segments of constant clipping state, further cut into chunks for progress.
    edges = np.flatnonzero(np.diff(clipped.astype(np.int8))) + 1
    bounds = np.unique(np.concatenate([[0], edges, np.arange(0, n, chunk), [n]]))
    for start, stop in zip(bounds[:-1], bounds[1:]):
        estimator.settings = clipped_settings if clipped[start] else normal
        views = AltitudeBatch(*(array[start:stop] for array in out))
        estimator.update_batch(accel[start:stop], baro[start:stop], dt[start:stop], out=views)
        if progress is not None:
            progress(int(stop), n)
    return out


def sample_periods(time) -> np.ndarray:
    """Per-sample dt, s, from timestamps: dt[i] = time[i] − time[i−1], and dt[0] = dt[1]
    (the first sample only sets the reference)."""
    time = np.asarray(time, dtype=float)
    dt = np.empty(time.size)
    dt[1:] = np.diff(time)
    dt[:1] = dt[1] if time.size > 1 else 0.01
    return dt


def settings_for_baro_rate(settings: AltitudeSettings, steps_per_baro: float) -> AltitudeSettings:
    """Gains that keep the designed bandwidth when baro samples arrive on only 1 of ``steps_per_baro`` steps.

    The C core applies the baro correction ``K·r·dt`` with the dt of the step
    that carries the baro sample; steps without baro only integrate. With the
    baro at 1/N of the IMU rate the corrections are therefore N times too
    small and every loop runs N times slower than designed (the balloon
    scenario: 10 Hz IMU, 1 Hz baro). Multiplying all three gains by N makes
    each correction ``K·r·(N·dt)``, the designed observer sampled at the baro
    rate. ``steps_per_baro`` ≤ 1 returns ``settings`` unchanged.
    """
    if steps_per_baro <= 1.0:
        return settings
    kh, kv, kb = settings.as_tuple()
    return AltitudeSettings(kh * steps_per_baro, kv * steps_per_baro, kb * steps_per_baro)


def _bandwidth_of(settings: AltitudeSettings) -> float:
    """Position-loop bandwidth ω (rad/s) of gains built with ζ = 0.7, ω_b = ω/5 (inverts Kh = 1.6·ω)."""
    return settings.position_gain / 1.6


def run_log(data: LogData, settings: Optional[AltitudeSettings] = None,
            progress: Optional[Callable[[int, int], None]] = None) -> LogRun:
    """Run the observer on a :class:`LogData` (clipped samples handled as in :func:`run_observer`)."""
    estimate = run_observer(data.time, data.vertical_acceleration, data.baro_altitude, settings,
                            clipped=data.clipped, progress=progress)
    return LogRun(**{name: getattr(data, name) for name in LogData.__dataclass_fields__}, estimate=estimate)


def write_csv(run: LogRun, path: str) -> None:
    """Write the run per grid step: time s, baro_altitude m, vertical_acceleration m/s², altitude m,
    vertical_velocity m/s, accel_bias m/s², baro_residual m and, if present, reference_altitude m."""
    columns = [("time", run.time), ("baro_altitude", run.baro_altitude),
               ("vertical_acceleration", run.vertical_acceleration), ("altitude", run.estimate.altitude),
               ("vertical_velocity", run.estimate.vertical_velocity), ("accel_bias", run.estimate.accel_bias),
               ("baro_residual", run.estimate.baro_residual)]
    if run.reference_altitude is not None:
        columns.append(("reference_altitude", run.reference_altitude))
    table = np.column_stack([np.asarray(values, dtype=float) for _, values in columns])
    np.savetxt(path, table, delimiter=",", header=",".join(name for name, _ in columns), comments="", fmt="%.6g")
