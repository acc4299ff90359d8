"""PX4 ULog (.ulg): decoded in C (the extension), pyulog (the ``[logs]`` extra) as the reference."""

from __future__ import annotations

import contextlib
import io
import os
from typing import Callable, Optional

import numpy as np

from ..sensors import pressure_to_altitude, vertical_acceleration
from ._binary_args import checked_instance
from ._data import LogData, LogError, align, finish, merge_repeated_timestamps, previous, reference_on_grid
from ._truncation import ulog_missing_bytes, warn_if_truncated as _warn_if_truncated

#: First bytes of every ULog file.
ULOG_MAGIC = b"ULog\x01\x12\x35"
_TOPICS = ["vehicle_air_data", "sensor_combined", "vehicle_attitude", "vehicle_local_position", "sensor_baro",
           "sensor_accel", "sensor_gyro", "vehicle_gps_position", "sensor_gps", "distance_sensor", "vehicle_status"]
#: The decoders :func:`read_ulog` takes.
DECODERS = ("fast", "pyulog")
#: ``vehicle_status.vehicle_type`` → vehicle hint.
_VEHICLE_TYPES = {1: "copter", 2: "plane", 3: "rover"}
#: ``vehicle_status.arming_state`` value for "armed".
_ARMED = 2


def _first(topic, *names):
    """The first of ``names`` present in a topic's data, as float64; None if none is."""
    for name in names:
        if name in topic:
            return np.asarray(topic[name], dtype=float)
    return None


def _block(topic, names):
    """The fields ``names`` of a topic side by side as float64 (n × len(names)) when the topic is the C decoder's
    table (:class:`~fusion_altitude.logs._ulog_fast.Topic`) and they are consecutive fields of one type (an array
    field as ``q[0..3]``, or ``x, y, z``): one strided view of the samples converted at once; else None."""
    table = getattr(topic, "table", None)
    if table is None:
        return None
    fields = table.dtype.fields
    kind, offset = fields.get(names[0], (None, 0))[:2]
    if kind is None or any(fields.get(name, ())[:2] != (kind, offset + k * kind.itemsize)
                           for k, name in enumerate(names)):
        return None
    view = np.ndarray((table.shape[0], len(names)), dtype=kind, buffer=table, offset=offset,
                      strides=(table.dtype.itemsize, kind.itemsize))
    return view.astype(np.float64)


def _vector(topic, *stems):
    """The 3-vector ``stem[0..2]`` of the first of ``stems`` the topic has, as float64 (n × 3; each component
    the first of the stems present); None if the topic has no ``stem[0]``."""
    block = _block(topic, [f"{stems[0]}[{i}]" for i in range(3)])
    if block is not None:
        return block
    if _first(topic, *(f"{stem}[0]" for stem in stems)) is None:
        return None
    return np.column_stack([_first(topic, *(f"{stem}[{i}]" for stem in stems)) for i in range(3)])


def read_ulog(path: str, instance: Optional[int] = None,
              progress: Optional[Callable[[int, int], None]] = None, decoder: str = "fast") -> LogData:
    """Read a PX4 ULog (.ulg).

    Topics and fields (older and newer PX4 names both accepted; the grid
    starts at the first IMU sample, 0 s):

    * IMU: ``sensor_combined`` ``accelerometer_m_s2[0..2]`` (m/s², body FRD)
      and ``gyro_rad[0..2]`` (rad/s) for instance 0 (PX4's voted primary);
      ``sensor_accel``/``sensor_gyro`` x, y, z of that ``multi_id`` for
      ``instance`` ≥ 1 (the primary if the log has no such instance: the
      notes say which). Clipping from ``accelerometer_clipping``.
    * attitude ``vehicle_attitude`` ``q`` (body FRD → NED) rotates the
      specific force to ``vertical_acceleration`` (+up, gravity removed).
    * baro: ``vehicle_air_data`` ``baro_alt_meter`` (m, ISA pressure
      altitude, datum "sea level"), ``baro_pressure_pa``,
      ``baro_temp_celcius`` at ``timestamp_sample`` — or, in PX4 < 1.8 logs,
      the ``baro_*`` fields of ``sensor_combined``; for ``instance`` ≥ 1,
      ``sensor_baro`` pressure of that ``multi_id`` through the ISA formula.
    * GPS: ``vehicle_gps_position`` (or ``sensor_gps``) ``alt`` (mm) or
      ``altitude_msl_m`` (m) where ``fix_type`` ≥ 3 → ``gps_altitude``;
      ``epv`` (m) → ``gps_accuracy``; ``satellites_used``.
    * ``distance_sensor`` ``current_distance`` (m, downward-facing ones,
      orientation 25, with ``signal_quality`` ≠ 0) → ``rangefinder``.
    * reference ``vehicle_local_position`` (z, vz NED → −z, −vz).
    * ``vehicle_status`` ``arming_state`` → ``flight_state``
      ("armed"/"disarmed"), ``vehicle_type`` → ``vehicle``.

    ``decoder="fast"`` (default) decodes in C (the extension), walking the
    messages as pyulog does: damaged or unknown messages stepped over,
    reading resumed after a sync sequence, appended data read after the
    flag-bits message's offsets. Logs whose reading depends on what pyulog
    does on an exception (messages it cannot parse, flags it refuses, a
    cut message before the data section) are read with pyulog, so the
    result never depends on the decoder. ``decoder="pyulog"`` always reads with pyulog (the
    ``[logs]`` extra), the reference the fast decoder is tested against.

    Raises
    ------
    LogError
        Not a ULog, a needed topic or instance missing, time going backwards.
    ImportError
        pyulog is not installed.
    ValueError
        ``decoder`` is not "fast" or "pyulog".
    """
    want = checked_instance(path, instance, decoder, DECODERS, "a PX4 ULog")
    topics, missing_bytes = _decode_topics(path, decoder)
    if progress is not None:
        progress(1, 2)
    try:
        return _build(path, want, _topic_lookup(path, topics), progress, missing_bytes)
    except LogError:
        raise
    except (KeyError, IndexError, ValueError) as error:  # a topic with unexpected fields
        raise LogError(f"{path}: unexpected ULog content: {type(error).__name__}: {error}") from None


def _topic_lookup(path: str, topics: dict):
    """``topic(name, multi=0, needed=True)``: the data of one topic instance of ``topics``; a LogError naming the
    topics the log has when a needed one is missing, None for a missing one not needed."""
    names = sorted({name for name, _ in topics})

    def topic(name, multi=0, needed=True):
        if (name, multi) in topics:
            return topics[(name, multi)]
        if needed:
            raise LogError(f"{path}: topic {name!r}" + (f" instance {multi}" if multi else "")
                           + (f" not in the log; topics are {', '.join(names)}" if names
                              else " not in the log; the log has no topic with data"))
        return None

    return topic


def _decode_topics(path: str, decoder: str):
    """The topics of the ULog at ``path``, (name, multi_id) → {field: array}, and the function that tells how
    many bytes its last message lacks: by the C decoder, or by pyulog where the log needs its recovery paths
    (or ``decoder`` is "pyulog")."""
    try:
        with open(path, "rb") as handle:
            blob = handle.read()
    except OSError as error:
        raise LogError(f"cannot read {path} as a PX4 ULog: {type(error).__name__}: {error}") from None
    if blob[:len(ULOG_MAGIC)] != ULOG_MAGIC:
        raise LogError(f"{path}: not a PX4 ULog (it does not start with the ULog magic bytes)")
    if decoder == "fast":
        from ._ulog_fast import NeedsReference, ULogTopics
        try:
            decoded = ULogTopics(blob, _TOPICS)
            return decoded.data, lambda _: decoded.missing_bytes()
        except NeedsReference:
            pass
    return _read_pyulog(path), ulog_missing_bytes


def _read_pyulog(path: str) -> dict:
    """The topics of a ULog through pyulog (the reference decoder): (name, multi_id) → {field: array}."""
    try:
        from pyulog import ULog
    except ImportError as error:
        raise ImportError("reading .ulg logs needs pyulog: pip install 'fusion-altitude[logs]'") from error
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            ulog = ULog(path, _TOPICS)  # pyulog prints what it skips in a damaged file
    except LogError:
        raise
    except Exception as error:  # pyulog raises a variety of errors on a bad file
        raise LogError(f"cannot read {path} as a PX4 ULog: {type(error).__name__}: {error}") from None
    return {(d.name, d.multi_id): d.data for d in ulog.data_list if len(d.data.get("timestamp", ())) > 0}


def _build(path, want, topic, progress, missing_bytes=ulog_missing_bytes) -> LogData:
    """Assemble the LogData of a ULog from ``topic(name, instance=0, needed=True)`` (see :func:`read_ulog`)."""
    notes = []
    accel_instance = want > 0 and topic("sensor_accel", want, needed=False) is not None
    baro_instance = want > 0 and topic("sensor_baro", want, needed=False) is not None
    if want > 0 and not (accel_instance or baro_instance):
        raise LogError(f"{path}: no sensor_accel or sensor_baro instance {want} in the log")
    if not accel_instance:
        stamp, accel_body, gyro, clipped = _imu_combined(path, want, topic, notes)
    else:
        stamp, accel_body, gyro, clipped = _imu_instance(want, topic, notes)
    t0 = float(stamp[0])  # µs; float before subtracting (uint64 would wrap)
    columns = {"accel": accel_body}
    if gyro is not None:
        columns["gyro"] = gyro
    if clipped is not None:
        columns["clipped"] = clipped
    time, columns, repeated = merge_repeated_timestamps((stamp - t0) * 1e-6, columns, path,
                                                        np.arange(stamp.size) + 1, "timestamp", row_word="IMU sample")
    att = topic("vehicle_attitude")
    q = _block(att, [f"q[{i}]" for i in range(4)])
    if q is None:
        q = np.column_stack([att[f"q[{i}]"] for i in range(4)]).astype(float)
    q_grid = previous(time, (att["timestamp"].astype(float) - t0) * 1e-6, q)
    accel = vertical_acceleration(columns["accel"], q_grid, frame="NED")
    if not baro_instance:
        baro, pressure, temperature = _baro_primary(path, want, topic, time, t0, notes)
    else:
        baro, pressure, temperature = _baro_instance(path, want, topic, time, t0, notes)
    data = LogData(f"{os.path.basename(path)} (PX4 ULog)", time, accel, baro, clipped=columns.get("clipped"),
                   notes=notes, accel=columns["accel"], gyro=columns.get("gyro"), imu_frame="FRD",
                   pressure=pressure, temperature=temperature, altitude_reference="sea level",
                   repeated_timestamps=repeated)
    _add_gps(data, topic, time, t0)
    _add_rangefinder(data, topic, time, t0)
    _add_status(data, topic, time, t0)
    position = topic("vehicle_local_position", needed=False)
    if position is not None:
        data.reference_altitude, data.reference_velocity = reference_on_grid(
            time, baro, (position["timestamp"].astype(float) - t0) * 1e-6, -position["z"].astype(float),
            -position["vz"].astype(float))
        data.reference_name = "PX4 EKF (vehicle_local_position)"
    if progress is not None:
        progress(2, 2)
    _warn_if_truncated(data, path, missing_bytes)
    return finish(data)


def _imu_combined(path, want, topic, notes):
    """The primary IMU from ``sensor_combined``: stamps (µs), accelerometer (m/s², n×3 FRD), gyro (rad/s, n×3, or
    None) and clipping flags (or None); appends a note."""
    imu = topic("sensor_combined")
    stamp = imu["timestamp"].astype(float)
    accel_body = _vector(imu, "accelerometer_m_s2", "acc")
    if accel_body is None:
        raise LogError(f"{path}: topic 'sensor_combined' has no accelerometer_m_s2 field")
    gyro = _vector(imu, "gyro_rad", "gyro_rad_s")
    clipped = np.asarray(imu["accelerometer_clipping"]) != 0 if "accelerometer_clipping" in imu else None
    notes.append("sensor_combined.accelerometer_m_s2, vehicle_attitude.q"
                 + (f" (no sensor_accel instance {want}: the primary IMU)" if want else ""))
    return stamp, accel_body, gyro, clipped


def _imu_instance(want, topic, notes):
    """IMU instance ``want`` from ``sensor_accel``/``sensor_gyro``: stamps (µs), accelerometer (m/s², n×3),
    gyro (rad/s, n×3, on the accelerometer's stamps, or None) and None for clipping; appends a note."""
    accel_topic = topic("sensor_accel", want)
    stamp = _first(accel_topic, "timestamp_sample", "timestamp")
    accel_body = _block(accel_topic, list("xyz"))
    if accel_body is None:
        accel_body = np.column_stack([accel_topic[a].astype(float) for a in "xyz"])
    gyro_topic = topic("sensor_gyro", want, needed=False)
    gyro = None
    if gyro_topic is not None:
        gyro = np.column_stack([np.interp(stamp, _first(gyro_topic, "timestamp_sample", "timestamp"),
                                          gyro_topic[a].astype(float)) for a in "xyz"])
    notes.append(f"sensor_accel instance {want}, vehicle_attitude.q")
    return stamp, accel_body, gyro, None


def _baro_primary(path, want, topic, time, t0, notes):
    """The primary baro on the grid ``time`` (s): altitude (m), pressure (Pa, or None), temperature (K, or
    None), from ``vehicle_air_data`` or (PX4 < 1.8) ``sensor_combined``; appends a note."""
    pressure = temperature = None
    if want:
        notes.append(f"no sensor_baro instance {want}: the primary baro")
    air = topic("vehicle_air_data", needed=False)
    if air is not None and "baro_alt_meter" in air:
        air_time = (_first(air, "timestamp_sample", "timestamp") - t0) * 1e-6
        baro = align(time, air_time, air["baro_alt_meter"].astype(float))
        if "baro_pressure_pa" in air:
            pressure = align(time, air_time, air["baro_pressure_pa"].astype(float))
        if "baro_temp_celcius" in air:
            temperature = align(time, air_time, air["baro_temp_celcius"].astype(float) + 273.15)
        notes.append("vehicle_air_data.baro_alt_meter")
    elif "baro_alt_meter" in topic("sensor_combined"):  # PX4 < 1.8: baro inside sensor_combined
        combined = topic("sensor_combined")
        relative = _first(combined, "baro_timestamp_relative")
        baro_stamp = combined["timestamp"].astype(float) + (relative if relative is not None else 0.0)
        baro = align(time, (baro_stamp - t0) * 1e-6, combined["baro_alt_meter"].astype(float))
        if "baro_temp_celcius" in combined:
            temperature = align(time, (baro_stamp - t0) * 1e-6,
                                 combined["baro_temp_celcius"].astype(float) + 273.15)
        notes.append("sensor_combined.baro_alt_meter (PX4 < 1.8)")
    else:
        raise LogError(f"{path}: no baro: neither vehicle_air_data.baro_alt_meter nor "
                       f"sensor_combined.baro_alt_meter in the log")
    return baro, pressure, temperature


def _baro_instance(path, want, topic, time, t0, notes):
    """Baro instance ``want`` of ``sensor_baro`` on the grid ``time`` (s): ISA altitude (m), pressure (Pa;
    mbar of PX4 < 1.12 converted) and temperature (K, or None); appends a note."""
    temperature = None
    sensor = topic("sensor_baro", want)
    baro_time = (_first(sensor, "timestamp_sample", "timestamp") - t0) * 1e-6
    pressure_raw = _first(sensor, "pressure")
    if pressure_raw is None:
        raise LogError(f"{path}: topic 'sensor_baro' instance {want} has no pressure field")
    if np.nanmedian(pressure_raw) < 2000.0:  # PX4 < 1.12 logged mbar
        pressure_raw = pressure_raw * 100.0
    pressure = align(time, baro_time, pressure_raw)
    baro = pressure_to_altitude(pressure)
    if "temperature" in sensor:
        temperature = align(time, baro_time, sensor["temperature"].astype(float) + 273.15)
    notes.append(f"sensor_baro instance {want} pressure (ISA)")
    return baro, pressure, temperature


def _add_gps(data: LogData, topic, time, t0) -> None:
    """GPS altitude (m), vertical accuracy (m) and satellites of fixes ≥ 3D, on the grid ``time`` (s)."""
    gps = topic("vehicle_gps_position", needed=False)
    if gps is None:
        gps = topic("sensor_gps", needed=False)
    if gps is None:
        return
    gps_time = (gps["timestamp"].astype(float) - t0) * 1e-6
    altitude = _first(gps, "altitude_msl_m")
    if altitude is None and "alt" in gps:
        altitude = gps["alt"].astype(float) * 1e-3
    if altitude is None:
        return
    fix = _first(gps, "fix_type")
    good = fix >= 3 if fix is not None else np.ones(altitude.shape, dtype=bool)
    data.gps_altitude = align(time, gps_time, np.where(good, altitude, np.nan))
    if "epv" in gps:
        data.gps_accuracy = align(time, gps_time, np.where(good, gps["epv"].astype(float), np.nan))
    if "satellites_used" in gps:
        data.gps_satellites = align(time, gps_time, np.where(good, gps["satellites_used"].astype(float), np.nan))


def _add_rangefinder(data: LogData, topic, time, t0) -> None:
    """Downward (orientation 25) rangefinder distance, m, with a non-zero signal quality, on the grid ``time``."""
    ranger = topic("distance_sensor", needed=False)
    if ranger is not None and "current_distance" in ranger:
        distance = ranger["current_distance"].astype(float)
        keep = np.ones(distance.shape, dtype=bool)
        if "orientation" in ranger:
            keep &= ranger["orientation"] == 25
        if "signal_quality" in ranger:
            keep &= ranger["signal_quality"] != 0
        if keep.any():
            data.rangefinder = align(time, (ranger["timestamp"].astype(float) - t0) * 1e-6,
                                      np.where(keep, distance, np.nan))


def _add_status(data: LogData, topic, time, t0) -> None:
    """Vehicle type and armed/disarmed state (on the grid ``time``, s) from ``vehicle_status``."""
    status = topic("vehicle_status", needed=False)
    if status is not None:
        status_time = (status["timestamp"].astype(float) - t0) * 1e-6
        if "vehicle_type" in status:
            data.vehicle = _VEHICLE_TYPES.get(int(status["vehicle_type"][-1]), "")
        if "arming_state" in status:
            states = np.where(status["arming_state"] == _ARMED, "armed", "disarmed").astype(object)
            data.flight_state = previous(time, status_time, states)
