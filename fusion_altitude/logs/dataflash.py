"""ArduPilot DataFlash (.bin) of every generation, through pymavlink (the ``[logs]`` extra)."""

from __future__ import annotations

import contextlib
import io
import os
from typing import Callable, Dict, List, NamedTuple, Optional

import numpy as np

from ..sensors import vertical_acceleration
from . import _dataflash_fast as fast
from ._binary_args import checked_instance
from ._dataflash_fast import time_of as _time_of
from ._data import LogData, LogError, align, finish, merge_repeated_timestamps, previous, reference_on_grid
from ._truncation import dataflash_missing_bytes, warn_if_truncated as _warn_if_truncated

#: First two bytes of every DataFlash message.
DATAFLASH_MAGIC = b"\xa3\x95"
#: Message names of a second / third sensor in logs before the ``I`` instance field (ArduPilot ≤ 3.x).
_OLD_INSTANCE_NAMES = {"IMU": ["IMU", "IMU2", "IMU3"], "BARO": ["BARO", "BAR2", "BAR3"], "GPS": ["GPS", "GPS2"]}
#: GPS ``Status`` at or above this is a 3D fix.
GPS_3D_FIX = 3


@contextlib.contextmanager
def _quiet_file_descriptors(sink):
    """Send what C code writes to fds 1 and 2 (pymavlink's indexer reports bad bytes there) to ``sink``."""
    import sys
    import tempfile
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, ValueError):
            pass
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:  # no real file descriptors (embedded interpreter): nothing to silence
        yield
        return
    with tempfile.TemporaryFile(mode="w+b") as capture:
        try:
            os.dup2(capture.fileno(), 1)
            os.dup2(capture.fileno(), 2)
            yield
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
            capture.seek(0)
            sink.write(capture.read().decode("utf-8", "replace"))


def _time_spikes(time: np.ndarray) -> np.ndarray:
    """Indices of damaged messages: a jump forward of more than max(60 s, 1000 median steps) that is
    the last message or is followed by time going back (a corrupt tail or a bit flip in a stamp)."""
    if time.size < 3:
        return np.zeros(0, dtype=int)
    dt = np.diff(time)
    if not (dt > 60.0).any():  # no step over the lowest limit (60 s): no spike, whatever the median
        return np.zeros(0, dtype=int)
    limit = max(60.0, 1000.0 * float(np.median(dt)))
    jumps = np.flatnonzero(dt > limit) + 1
    return np.array([i for i in jumps if i == time.size - 1 or time[i + 1] < time[i]], dtype=int)


#: Message types the reader asks for.
KINDS = ["IMU", "IMU2", "IMU3", "ATT", "BARO", "BAR2", "BAR3", "GPS", "GPS2", "GPA", "RFND",
         "XKF1", "NKF1", "EKF1", "ARM", "MSG"]
#: Families of rows the reader builds (IMU2 and IMU3 join IMU, and so on).
FAMILIES = ("IMU", "ATT", "BARO", "GPS", "GPA", "RFND", "XKF1", "NKF1", "EKF1", "ARM")
#: Every field the reader reads (the rest are never materialised by the fast decoder).
FIELDS_USED = ("TimeUS", "TimeMS", "T", "Week", "I", "C", "AccX", "AccY", "AccZ", "GyrX", "GyrY", "GyrZ",
               "Roll", "Pitch", "Yaw", "Alt", "Press", "Temp", "Status", "NSats", "VAcc", "Dist", "Dist1",
               "Stat", "PD", "VD", "ArmState")
#: Decoders of ``read_dataflash``: the C decoder, or pymavlink (the reference, kept for one release).
DECODERS = ("fast", "pymavlink")


def read_dataflash(path: str, instance: Optional[int] = None,
                   progress: Optional[Callable[[int, int], None]] = None, decoder: str = "fast") -> LogData:
    """Read an ArduPilot DataFlash log (.bin) of any generation.

    ``decoder="fast"`` (default) decodes in C (the extension), damaged bytes
    stepped over and reported as pymavlink does; logs whose reading depends
    on pymavlink's internals further (types redefined by a second FMT, odd
    formats) are then read with pymavlink, so the result never depends on
    the decoder. ``decoder="pymavlink"`` always reads with pymavlink (the
    ``[logs]`` extra), the reference the fast decoder is tested against.

    Time stamps: ``TimeUS`` (µs) in current logs, ``TimeMS`` (ms) in
    ArduCopter ≤ 3.3 logs (GPS: its ``T`` boot-time field); the grid starts
    at the first IMU sample (0 s).

    Messages used (instance ``instance`` of each sensor, the ``I`` field in
    current logs, ``IMU2``/``BAR2``/``GPS2`` names in old ones; default 0,
    ArduPilot's primary unless the parameters chose another):

    * ``IMU`` AccX/Y/Z (m/s², body FRD) → ``accel``; GyrX/Y/Z (rad/s) → ``gyro``;
    * ``ATT`` Roll, Pitch, Yaw (°, NED) rotate the specific force to
      ``vertical_acceleration`` (+up, gravity removed);
    * ``BARO`` Alt (m above the arming point, datum "") → ``baro_altitude``;
      Press (Pa) → ``pressure``; Temp (°C) → ``temperature`` (K);
    * ``GPS`` Alt (m above sea level) where ``Status`` ≥ 3 (3D fix) →
      ``gps_altitude``; NSats → ``gps_satellites``; ``GPA`` VAcc (m) →
      ``gps_accuracy``;
    * ``RFND`` Dist (or Dist1), m → ``rangefinder`` (readings with ``Stat``
      other than 4 "good", where logged, are dropped);
    * the first of ``XKF1`` (core 0), ``NKF1``, ``EKF1`` → reference (−PD, −VD);
    * ``ARM`` ArmState → ``flight_state`` ("armed"/"disarmed"); the firmware
      name in ``MSG`` → ``vehicle``.

    Raises
    ------
    LogError
        Not a DataFlash log, or no ``IMU``/``ATT``/``BARO`` data (for that
        instance), time going backwards.
    ImportError
        pymavlink is not installed (``decoder="pymavlink"``, or a log the fast decoder leaves to it).
    ValueError
        ``decoder`` is not one of "fast", "pymavlink".
    """
    want = checked_instance(path, instance, decoder, DECODERS, "an ArduPilot DataFlash log")
    if decoder == "fast":
        try:
            return _read_fast(path, want, progress)
        except fast.NeedsReference:
            pass
    return _read_pymavlink(path, want, progress)


def _read_fast(path: str, want: int, progress) -> LogData:
    """``read_dataflash`` with the C decoder; raises NeedsReference for a log it leaves to pymavlink."""
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as error:
        raise LogError(f"cannot read {path} as an ArduPilot DataFlash log: {type(error).__name__}: {error}") \
            from None
    if data[:2] != DATAFLASH_MAGIC:
        raise LogError(f"{path}: not an ArduPilot DataFlash log (it does not start with A3 95)")
    try:
        index = fast.DataFlashIndex(data, path, KINDS, FIELDS_USED)
    except ValueError as error:
        raise LogError(f"cannot read {path} as an ArduPilot DataFlash log: {error}") from None

    def select(kind, columns, count):
        # (family or None, the messages kept: a mask, or None for all)
        for family, names in _OLD_INSTANCE_NAMES.items():
            if kind in names:
                if kind != family:
                    return (family if names.index(kind) == want else None), None
                if "I" in columns:
                    return family, _integer_column(kind, columns, "I") == want
                return (family if want == 0 else None), None
        if kind == "XKF1" and "C" in columns:
            return kind, _integer_column(kind, columns, "C") == 0
        if kind == "GPA":
            if "I" in columns:
                return kind, _integer_column(kind, columns, "I") == want
            return (kind if want == 0 else None), None
        return kind, None

    def _integer_column(kind, columns, name):
        # the reader's int(...) of the value: declined unless every value is a finite number
        values = columns[name]
        if not np.isfinite(values).all():
            raise fast.NeedsReference(f"{kind}.{name} is not finite")
        return np.trunc(values)

    parts, firmware = fast.read_families(index, KINDS, FIELDS_USED, select)
    rows = {family: fast.ArrayRows(parts.get(family, []), FIELDS_USED) for family in FAMILIES}
    size = len(data)
    chatter = _Chatter(bad_headers=index.bad_headers, skipped=index.skipped_runs())
    return _build_checked(path, rows, firmware, chatter, want, progress, size, lambda _: index.missing_bytes(data))


def _read_pymavlink(path: str, want: int, progress) -> LogData:
    """``read_dataflash`` with pymavlink's DFReader (the reference decoder)."""
    try:
        from pymavlink import DFReader
    except ImportError as error:
        raise ImportError("reading .bin logs needs pymavlink: pip install 'fusion-altitude[logs]'") from error
    kinds = KINDS
    rows: Dict[str, List[dict]] = {kind: [] for kind in FAMILIES}
    firmware = ""
    try:
        size = os.path.getsize(path)
        with open(path, "rb") as handle:
            if handle.read(2) != DATAFLASH_MAGIC:
                raise LogError(f"{path}: not an ArduPilot DataFlash log (it does not start with A3 95)")
        chatter = io.StringIO()  # pymavlink prints what it skips; keep it off the user's stdout
        with contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter), \
                _quiet_file_descriptors(chatter):
            log = DFReader.DFReader_binary(path, zero_time_base=True)
        count = 0
        while True:
            with contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
                message = log.recv_match(type=kinds)
            if message is None:
                break
            kind = message.get_type()
            fields = message.to_dict()
            count += 1
            if progress is not None and count % 20000 == 0:
                progress(min(getattr(log, "offset", 0), size), size)
            if kind == "MSG":
                text = str(fields.get("Message", ""))
                if not firmware and text.startswith(("Ardu", "APM:")):
                    firmware = text
                continue
            for family, names in _OLD_INSTANCE_NAMES.items():
                if kind in names:
                    number = names.index(kind) if kind != family else int(fields.get("I", 0))
                    if number == want:
                        rows[family].append(fields)
                    break
            else:
                if kind == "XKF1" and int(fields.get("C", 0)) != 0:
                    continue
                if kind == "GPA" and int(fields.get("I", 0)) != want:
                    continue
                rows[kind].append(fields)
    except LogError:
        raise
    except Exception as error:  # pymavlink raises many kinds of errors on a damaged file
        raise LogError(f"cannot read {path} as an ArduPilot DataFlash log: {type(error).__name__}: {error}") \
            from None
    finally:
        handle = getattr(locals().get("log"), "filehandle", None)
        if handle is not None:
            handle.close()
    return _build_checked(path, {family: DictRows(found) for family, found in rows.items()}, firmware,
                          _Chatter.of(chatter.getvalue()), want, progress, size)


class _Chatter(NamedTuple):
    """What pymavlink prints about damage while reading a log, counted: bytes that start no message ("bad header",
    one line each), runs of them its clock set-up walk skips ("Skipped N bad bytes") and messages its bookkeeping
    fails on ("bad msg")."""

    bad_headers: int = 0
    skipped: int = 0
    bad_messages: int = 0

    @classmethod
    def of(cls, text: str) -> "_Chatter":
        """The counts of pymavlink's printed text."""
        return cls(text.count("bad header"), text.count("Skipped"), text.count("bad msg"))


def _build_checked(path, rows, firmware, chatter, want, progress, size,
                   missing_bytes=dataflash_missing_bytes) -> LogData:
    """:func:`_build`, its errors on odd content as LogError naming the file."""
    try:
        return _build(path, rows, firmware, chatter, want, progress, size, missing_bytes)
    except LogError:
        raise
    except (ValueError, TypeError, IndexError, KeyError, OverflowError) as error:  # a damaged FMT: odd fields
        raise LogError(f"{path}: unexpected DataFlash content: {type(error).__name__}: {error}") from None


class DictRows:
    """The messages of one family as pymavlink's dicts, answering what :class:`_dataflash_fast.ArrayRows` answers."""

    def __init__(self, rows: List[dict]) -> None:
        self.rows = rows

    def __len__(self) -> int:
        return len(self.rows)

    def has(self, field: str) -> bool:
        """Whether the first message has ``field``."""
        return field in self.rows[0]

    def values(self, field: str) -> np.ndarray:
        """``field`` of every message as float64 (NaN where missing); TypeError/ValueError if not numbers."""
        return np.array([r.get(field, np.nan) for r in self.rows], dtype=float)

    def times(self) -> np.ndarray:
        """:func:`_time_of` of every message, s."""
        return np.array([_time_of(r) for r in self.rows], dtype=float)

    def truthy(self, field: str) -> np.ndarray:
        """Whether ``field`` is true in each message."""
        return np.array([bool(r.get(field)) for r in self.rows], dtype=bool)

    def keep(self, mask: np.ndarray) -> "DictRows":
        """Only the messages where ``mask`` is true."""
        self.rows = [r for r, k in zip(self.rows, mask) if k]
        return self


class _Messages:
    """The parsed messages of one log by kind, read as float arrays; bad content → LogError naming the file."""

    def __init__(self, path: str, rows) -> None:
        self.path, self.rows = path, rows

    def times(self, kind: str) -> np.ndarray:
        """The time stamps of the ``kind`` messages, in the log's unit (µs or ms)."""
        try:
            values = self.rows[kind].times()
        except (TypeError, ValueError):
            raise LogError(f"{self.path}: {kind} messages with a time stamp that is not a number") from None
        if not np.isfinite(values).all():
            raise LogError(f"{self.path}: {kind} messages without a TimeUS or TimeMS field")
        return values

    def column(self, kind: str, *names: str) -> np.ndarray:
        """The first of the fields ``names`` that the ``kind`` messages have, as float64."""
        rows = self.rows[kind]
        for name in names:
            if rows.has(name):
                try:
                    return rows.values(name)
                except (TypeError, ValueError):
                    raise LogError(f"{self.path}: {kind}.{name}: not a number in every message") from None
        raise LogError(f"{self.path}: {kind} messages have no field {' or '.join(names)}; "
                       f"fields are {', '.join(_fields_of(rows))}")


def _fields_of(rows) -> List[str]:
    """The field names of the first message of ``rows``."""
    return list(rows.rows[0]) if isinstance(rows, DictRows) else list(rows.first_fields)


def _build(path, rows, firmware, chatter, want, progress, size, missing_bytes=dataflash_missing_bytes) -> LogData:
    """The LogData of the parsed messages (see :func:`read_dataflash`)."""
    for needed in ("IMU", "ATT", "BARO"):
        if not len(rows[needed]):
            raise LogError(f"{path}: no {needed} messages" + (f" for instance {want}" if want else "") + " in the log")
    messages = _Messages(path, rows)
    stamp = "TimeUS" if rows["IMU"].has("TimeUS") else "TimeMS"
    imu_time_raw, damaged = _imu_times_without_spikes(messages)
    t0 = float(imu_time_raw[0])
    imu = {"accel": np.stack([messages.column("IMU", f"Acc{a}") for a in "XYZ"], axis=1),
           "gyro": np.stack([messages.column("IMU", f"Gyr{a}") for a in "XYZ"], axis=1)}
    order = np.arange(imu_time_raw.size) + 1
    time, imu, repeated = merge_repeated_timestamps(imu_time_raw - t0, imu, path, order, stamp,
                                                    row_word="IMU message")
    att_time = messages.times("ATT") - t0
    euler = np.radians(np.stack([messages.column("ATT", name) for name in ("Roll", "Pitch", "Yaw")], axis=1))
    accel = vertical_acceleration(imu["accel"], previous(time, att_time, euler), frame="NED")
    baro_time = messages.times("BARO") - t0
    baro = align(time, baro_time, messages.column("BARO", "Alt"))
    vehicle = ""
    for word, kind in (("copter", "copter"), ("plane", "plane"), ("rover", "rover"), ("sub", "sub")):
        if word in firmware.lower():
            vehicle = kind
            break
    data = LogData(f"{os.path.basename(path)} (ArduPilot DataFlash)", time, accel, baro,
                   notes=[f"BARO.Alt, IMU.AccX/Y/Z, ATT.Roll/Pitch/Yaw (instance {want}, {stamp})"]
                   + ([firmware] if firmware else []),
                   accel=imu["accel"], gyro=imu["gyro"], imu_frame="FRD", vehicle=vehicle, repeated_timestamps=repeated)
    skipped = chatter.bad_messages + chatter.skipped + damaged
    if chatter.bad_headers:
        data.warn(f"{path}: damaged bytes skipped ({chatter.bad_headers} bad message headers)")
    if skipped:
        data.warn(f"{path}: {skipped} damaged message(s) skipped")
    if rows["BARO"].has("Press"):
        data.pressure = align(time, baro_time, messages.column("BARO", "Press"))
    if rows["BARO"].has("Temp"):
        data.temperature = align(time, baro_time, messages.column("BARO", "Temp") + 273.15)
    _add_gps(data, messages, time, t0)
    _add_rangefinder_and_arming(data, messages, time, t0)
    _add_ekf_reference(data, messages, time, t0, baro)
    if progress is not None:
        progress(size, size)
    _warn_if_truncated(data, path, missing_bytes)
    return finish(data)


def _imu_times_without_spikes(messages: _Messages):
    """The IMU time stamps without isolated spikes (those messages dropped from ``messages``) and the count
    dropped."""
    imu_time_raw = messages.times("IMU")
    spikes = _time_spikes(imu_time_raw)
    if not spikes.size:
        return imu_time_raw, 0
    keep = np.ones(imu_time_raw.size, dtype=bool)
    keep[spikes] = False
    messages.rows["IMU"].keep(keep)
    return imu_time_raw[keep], spikes.size


def _add_gps(data: LogData, messages: _Messages, time: np.ndarray, t0: float) -> None:
    """GPS altitude (m) and satellites where Status ≥ 3D fix, and GPA vertical accuracy (m), on the grid."""
    rows = messages.rows
    if not len(rows["GPS"]):
        return
    gps_time = messages.times("GPS") - t0
    status = messages.column("GPS", "Status")
    altitude = np.where(status >= GPS_3D_FIX, messages.column("GPS", "Alt"), np.nan)
    data.gps_altitude = align(time, gps_time, altitude)
    if rows["GPS"].has("NSats"):
        data.gps_satellites = align(time, gps_time, np.where(status >= GPS_3D_FIX, messages.column("GPS", "NSats"),
                                                              np.nan))
    if len(rows["GPA"]) and rows["GPA"].has("VAcc"):
        data.gps_accuracy = align(time, messages.times("GPA") - t0, messages.column("GPA", "VAcc"))
    data.notes.append("GPS.Alt where Status ≥ 3")


def _add_rangefinder_and_arming(data: LogData, messages: _Messages, time: np.ndarray, t0: float) -> None:
    """Rangefinder distance (m, where Stat is 4 = good) and the armed/disarmed state, on the grid."""
    rows = messages.rows
    if len(rows["RFND"]):
        distance = messages.column("RFND", "Dist", "Dist1")
        if rows["RFND"].has("Stat"):
            distance = np.where(messages.column("RFND", "Stat") == 4, distance, np.nan)
        data.rangefinder = align(time, messages.times("RFND") - t0, distance)
    if len(rows["ARM"]) and rows["ARM"].has("ArmState"):
        states = np.where(rows["ARM"].truthy("ArmState"), "armed", "disarmed").astype(object)
        arm_time = messages.times("ARM") - t0
        index = np.searchsorted(arm_time, time, side="right") - 1
        data.flight_state = np.where(index >= 0, states[np.clip(index, 0, None)], "disarmed").astype(object)


def _add_ekf_reference(data: LogData, messages: _Messages, time: np.ndarray, t0: float, baro: np.ndarray) -> None:
    """The EKF's altitude (m, −PD) and vertical velocity (m/s, −VD) as the reference, from the first of XKF1,
    NKF1, EKF1 present."""
    rows = messages.rows
    for kind in ("XKF1", "NKF1", "EKF1"):
        if len(rows[kind]):
            ref_time = messages.times(kind) - t0
            down = messages.column(kind, "PD")
            velocity = -messages.column(kind, "VD") if rows[kind].has("VD") else np.gradient(-down, ref_time)
            if ref_time.size >= 2 and (ref_time[1:] > ref_time[:-1]).all():
                data.reference_altitude, data.reference_velocity = reference_on_grid(
                    time, baro, ref_time, -down, velocity)
                data.reference_name = f"ArduPilot EKF ({kind})"
            break
