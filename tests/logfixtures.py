"""Fixture generators: logs with what real logs have, written by code (never copied from ../shared).

* :func:`write_dataflash` — an ArduPilot DataFlash log from its own FMT
  messages, in the ArduCopter ≤ 3.3 style (``TimeMS``, ``IMU2``/``BAR2``,
  GPS with ``T``) or the current style (``TimeUS``, ``I`` instance field),
  with optional gap, repeated timestamps and a corrupt tail.
* :func:`write_altos_csv` — an AltOS CSV export (``#version,…`` header,
  ``altitude`` twice, several rows per time stamp, negative time on the pad).
* :func:`write_cats_set` — CATS split CSVs (``*baro.csv``, ``*imu.csv``,
  ``*flight_info.csv``).
* :func:`write_generic_csv` — a CSV with chosen units, BOM, gap, repeats,
  gravity left in, a cut-short last line.

All of them fly the same simple vertical profile (:func:`profile`): 5 s
on the ground, a smooth climb to 30 m, hover, so tests know the truth.
"""

from __future__ import annotations

import struct
from typing import Dict, List, Optional, Sequence

import numpy as np

G = 9.80665

# --- truth -------------------------------------------------------------------


def profile(time: np.ndarray, start: float = 5.0, climb: float = 10.0, height: float = 30.0):
    """Altitude (m), vertical velocity (m/s) and acceleration (m/s²), +up: rest until ``start``,
    a cosine-smoothed climb of ``height`` over ``climb`` s, then hover."""
    phase = np.clip((time - start) / climb, 0.0, 1.0)
    inside = (time > start) & (time < start + climb)
    altitude = height * (phase - np.sin(2 * np.pi * phase) / (2 * np.pi))
    velocity = np.where(inside, height / climb * (1 - np.cos(2 * np.pi * phase)), 0.0)
    accel = np.where(inside, height / climb ** 2 * 2 * np.pi * np.sin(2 * np.pi * phase), 0.0)
    return altitude, velocity, accel


def drop_gap(time: np.ndarray, gap: Optional[Sequence[float]]) -> np.ndarray:
    """Mask of the rows kept when ``gap`` = (start s, length s) is lost."""
    if gap is None:
        return np.ones(time.shape, dtype=bool)
    return ~((time >= gap[0]) & (time < gap[0] + gap[1]))


# --- DataFlash -----------------------------------------------------------------

_STRUCT = {"b": "b", "B": "B", "h": "h", "H": "H", "i": "i", "I": "I", "f": "f", "d": "d", "n": "4s",
           "N": "16s", "Z": "64s", "c": "h", "C": "H", "e": "i", "E": "I", "L": "i", "M": "B", "q": "q", "Q": "Q"}
_SCALE = {"c": 100.0, "C": 100.0, "e": 100.0, "E": 100.0, "L": 1e7}


class DataFlashWriter:
    """Writes DataFlash messages: FMT first, then data packed by the format string."""

    def __init__(self):
        self.out = bytearray()
        self.formats: Dict[str, tuple] = {}

    def define(self, type_id: int, name: str, fmt: str, columns: str) -> None:
        length = 3 + struct.calcsize("<" + "".join(_STRUCT[c] for c in fmt))
        self.formats[name] = (type_id, fmt)
        self.out += b"\xa3\x95\x80" + struct.pack("<BB4s16s64s", type_id, length, name.encode(), fmt.encode(),
                                                  columns.encode())

    def write(self, name: str, *values) -> None:
        type_id, fmt = self.formats[name]
        packed = []
        for char, value in zip(fmt, values):
            if char in "nNZ":
                packed.append(str(value).encode())
            elif char in _SCALE:
                packed.append(int(round(value * _SCALE[char])))
            elif char in "fd":
                packed.append(float(value))
            else:
                packed.append(int(round(value)))
        self.out += b"\xa3\x95" + bytes([type_id]) + struct.pack("<" + "".join(_STRUCT[c] for c in fmt), *packed)


def write_dataflash(path, style: str = "TimeMS", duration: float = 20.0, imu_rate: float = 50.0,
                    baro_rate: float = 10.0, gps_rate: float = 5.0, gap: Optional[Sequence[float]] = None,
                    repeat_every: int = 0, corrupt_tail: bool = False, second_instance_offset: float = 3.0,
                    gps_fix_from: float = 2.0, firmware: str = "ArduCopter V3.2.1 (36b405fb)") -> dict:
    """Write a DataFlash log of :func:`profile`; return the truth (times are from the first IMU sample).

    ``style="TimeMS"``: ArduCopter ≤ 3.3 (ms stamps, ``IMU2``/``BAR2``
    messages for the second sensor, ``EKF1``, GPS ``TimeMS`` = week time and
    ``T`` = boot ms). ``style="TimeUS"``: current (µs, ``I`` instance field,
    ``XKF1`` with core ``C``). The second baro reads ``second_instance_offset``
    m higher. GPS has no fix (Status 1) before ``gps_fix_from`` s and reads
    100 m above the baro datum after it. ``repeat_every`` > 0 writes every
    n-th IMU message with the previous one's time stamp.
    """
    w = DataFlashWriter()
    old = style == "TimeMS"
    stamp, unit, t_char = ("TimeMS", 1e3, "I") if old else ("TimeUS", 1e6, "Q")
    boot = 12.345  # s since boot at the first sample
    if old:
        w.define(129, "IMU", "Iffffff", "TimeMS,GyrX,GyrY,GyrZ,AccX,AccY,AccZ")
        w.define(130, "IMU2", "Iffffff", "TimeMS,GyrX,GyrY,GyrZ,AccX,AccY,AccZ")
        w.define(131, "ATT", "IccccCCCC", "TimeMS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw")
        w.define(132, "BARO", "Iffcf", "TimeMS,Alt,Press,Temp,CRt")
        w.define(133, "BAR2", "Iffcf", "TimeMS,Alt,Press,Temp,CRt")
        w.define(134, "GPS", "BIHBcLLeeEefI", "Status,TimeMS,Week,NSats,HDop,Lat,Lng,RelAlt,Alt,Spd,GCrs,VZ,T")
        w.define(135, "EKF1", "IccCffffffccc", "TimeMS,Roll,Pitch,Yaw,VN,VE,VD,PN,PE,PD,GX,GY,GZ")
        w.define(136, "MSG", "Z", "Message")
    else:
        w.define(129, "IMU", "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ")
        w.define(131, "ATT", "QccccCC", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw")
        w.define(132, "BARO", "QBffc", "TimeUS,I,Alt,Press,Temp")
        w.define(134, "GPS", "QBBIHBe", "TimeUS,I,Status,GMS,GWk,NSats,Alt")
        w.define(135, "XKF1", "QBff", "TimeUS,C,PD,VD")
        w.define(136, "MSG", "QZ", "TimeUS,Message")
        w.define(137, "RFND", "QBfB", "TimeUS,Instance,Dist,Stat")
        w.define(138, "ARM", "QB", "TimeUS,ArmState")
        w.define(139, "GPA", "QBf", "TimeUS,I,VAcc")
    if old:
        w.write("MSG", firmware)
    else:
        w.write("MSG", boot * unit, firmware)
        w.write("ARM", boot * unit, 1)
    events = []
    imu_time = np.arange(0.0, duration, 1.0 / imu_rate)
    for k, t in enumerate(imu_time):
        events.append((t, 0, "IMU", k))
    for t in np.arange(0.0, duration, 1.0 / baro_rate):
        events.append((t + 0.001, 1, "BARO", 0))
        events.append((t + 0.001, 2, "ATT", 0))
        events.append((t + 0.002, 3, "EKF", 0))
    for t in np.arange(0.0, duration, 1.0 / gps_rate):
        events.append((t + 0.003, 4, "GPS", 0))
    events.sort(key=lambda e: (e[0], e[1]))
    previous_imu = None
    for t, _, kind, k in events:
        if not drop_gap(np.array([t]), gap)[0]:
            continue
        altitude, velocity, accel = (float(v) for v in profile(np.array(t)))
        stamp_value = (boot + t) * unit
        if kind == "IMU":
            if repeat_every and k % repeat_every == 0 and previous_imu is not None:
                stamp_value = previous_imu
            previous_imu = stamp_value
            values = (0.0, 0.0, 0.0, 0.0, 0.0, -(G + accel))
            if old:
                w.write("IMU", stamp_value, *values)
                w.write("IMU2", stamp_value, *values[:5], -(G + accel) - 0.2)
            else:
                w.write("IMU", stamp_value, 0, *values)
                w.write("IMU", stamp_value, 1, *values[:5], -(G + accel) - 0.2)
        elif kind == "ATT":
            w.write("ATT", stamp_value, 0, 0, 0, 0, 0, 90.0, *((0, 0) if old else ()))
        elif kind == "BARO":
            pressure = 101325.0 * (1 - 0.0065 * altitude / 288.15) ** 5.2559
            if old:
                w.write("BARO", stamp_value, altitude, pressure, 25.0, velocity)
                w.write("BAR2", stamp_value, altitude + second_instance_offset, pressure - 36.0, 26.0, velocity)
            else:
                w.write("BARO", stamp_value, 0, altitude, pressure, 25.0)
                w.write("BARO", stamp_value, 1, altitude + second_instance_offset, pressure - 36.0, 26.0)
                w.write("RFND", stamp_value, 0, altitude + 0.1, 4 if altitude < 20 else 1)
        elif kind == "EKF":
            if old:
                w.write("EKF1", stamp_value, 0, 0, 0, 0, 0, -velocity, 0, 0, -altitude, 0, 0, 0)
            else:
                w.write("XKF1", stamp_value, 0, -altitude, -velocity)
                w.write("XKF1", stamp_value, 1, -altitude + 50.0, -velocity)
        elif kind == "GPS":
            status = 3 if t >= gps_fix_from else 1
            if old:
                w.write("GPS", status, 123456789, 1800, 9, 1.2, 47.0, 8.0, altitude, altitude + 100.0, 0, 0, 0,
                        stamp_value)
            else:
                w.write("GPS", stamp_value, 0, status, int(123456789 + t * 1000), 1800, 9, altitude + 100.0)
                w.write("GPA", stamp_value, 0, 1.5)
    data = bytes(w.out)
    if corrupt_tail:
        data = data + b"\xa3\x95" + bytes([129]) + b"\x01\x02\x03" + bytes(range(200, 256)) + b"\x00" * 7
    with open(path, "wb") as handle:
        handle.write(data)
    kept = drop_gap(imu_time, gap)
    altitude, velocity, _ = profile(imu_time[kept])
    return {"time": imu_time[kept], "altitude": altitude, "velocity": velocity}


# --- CSVs --------------------------------------------------------------------

ALTOS_HEADER = ("#version,serial,flight,call,time,state,state_name,acceleration,pressure,altitude,height,speed,"
                "temperature,drogue_voltage,main_voltage,battery_voltage,accel_x,accel_y,accel_z,gyro_roll,"
                "gyro_pitch,gyro_yaw,mag_x,mag_y,mag_z,tilt,pyro,connected,locked,nsat,latitude,longitude,"
                "altitude,year,month,day,hour,minute,second,pdop,hdop,vdop,mode")
_ALTOS_STATES = [(0.0, 2, "pad"), (0.0, 3, "boost"), (2.0, 5, "coast"), (8.0, 6, "drogue"), (20.0, 7, "main"),
                 (40.0, 8, "landed")]
PAD_ALTITUDE = 812.0


def altos_state(time: float):
    """(state number, state name) of the AltOS fixture at ``time`` (s from launch)."""
    current = (1, "pad") if time < 0 else (2, "pad")
    for start, number, name in _ALTOS_STATES:
        if time >= start:
            current = (number, name)
    return current


def write_altos_csv(path, duration: float = 30.0, rate: float = 20.0, pad_time: float = 3.0,
                    rows_per_stamp: int = 2, bom: bool = False, padded: bool = False) -> dict:
    """An AltOS-style CSV of :func:`profile` starting at launch (t = 0), pad at ``PAD_ALTITUDE`` m.

    Each time stamp is written ``rows_per_stamp`` times (one per telemetry
    packet), the copies with accelerations ±0.2 m/s² around the truth so
    the merged mean is the truth. GPS locked from 1 s after launch. ``padded``
    writes fixed-width fields as AltosUI does (``   -3.00``, ``     pad``). Pressure
    and temperature (°C) are the ISA atmosphere's at the altitude.
    """
    time = np.round(np.arange(-pad_time, duration, 1.0 / rate), 6)
    altitude, velocity, accel = profile(time, start=0.0)
    lines = [ALTOS_HEADER]
    for t, h, v, a in zip(time, altitude, velocity, accel):
        number, name = altos_state(t)
        pressure = 101325.0 * (1 - 0.0065 * (h + PAD_ALTITUDE) / 288.15) ** 5.2559
        locked = 1 if t >= 1.0 else 0
        for copy in range(rows_per_stamp):
            delta = 0.2 * (1 if copy % 2 else -1) if rows_per_stamp > 1 else 0.0
            cells = [1, 2718, 7, "N0CALL", f"{t:.2f}", number, name, f"{a + delta:.4f}", f"{pressure:.1f}",
                     f"{h + PAD_ALTITUDE:.3f}", f"{h:.3f}", f"{v:.3f}", f"{15.0 - 0.0065 * (h + PAD_ALTITUDE):.3f}", "3.9", "3.9", "3.8",
                     "0.1", "0.2", f"{a + G:.3f}", "1.0", "-2.0", "0.5", "0.1", "0.2", "0.3", "2", "0", 1, locked,
                     9 if locked else 3, "47.000000", "8.000000", f"{h + PAD_ALTITUDE + 40.0:.1f}" if locked else "0",
                     2024, 6, 1, 12, 0, 0, "1.5", "0.9", "1.2", "N"]
            lines.append(",".join(f"{c:>8}" if padded else str(c) for c in cells))
    text = "\n".join(lines) + "\n"
    with open(path, "w", encoding="utf-8-sig" if bom else "utf-8") as handle:
        handle.write(text)
    return {"time": time, "altitude": altitude + PAD_ALTITUDE, "height": altitude, "velocity": velocity}


def write_cats_set(directory, prefix: str = "flight_", duration: float = 20.0, rate: float = 100.0,
                   pad_time: float = 2.0, info_name: str = "flight_info", second_instance: bool = False) -> dict:
    """CATS-style split CSVs of :func:`profile` from launch (t = 0): the rocket's long axis is the sensor's
    +Y axis pointing down (≈ −9.8 on Y at rest, as on Hedy)."""
    time = np.round(np.arange(-pad_time, duration, 1.0 / rate), 6)
    altitude, velocity, accel = profile(time, start=0.0)
    pressure = 99600.0 * (1 - 0.0065 * altitude / 287.0) ** 5.2559
    imu_lines, baro_lines, info_lines = ["ts,id,Ax,Ay,Az,Gx,Gy,Gz"], ["ts,id,T,P"], ["ts,height,velocity,acceleration"]
    for t, h, v, a, p in zip(time, altitude, velocity, accel, pressure):
        for instance in ((0, 1) if second_instance else (0,)):
            imu_lines.append(f"{t:.3f},IMU{instance},0.0,{-(G + a) + 0.05 * instance:.6f},0.0,0.0,0.0,0.0")
            baro_lines.append(f"{t:.3f},BARO{instance},{30.0 + instance},{p + 12.0 * instance:.2f}")
        info_lines.append(f"{t:.3f},{h:.4f},{v:.4f},{a:.4f}")
    for name, lines in (("imu", imu_lines), ("baro", baro_lines), (info_name, info_lines)):
        with open(f"{directory}/{prefix}{name}.csv", "w") as handle:
            handle.write("\n".join(lines) + "\n")
    return {"time": time, "altitude": altitude, "velocity": velocity}


def write_generic_csv(path, duration: float = 20.0, rate: float = 100.0, baro_every: int = 5,
                      accel_units: str = "m/s^2", altitude_units: str = "m", gravity: float = 0.0,
                      gap: Optional[Sequence[float]] = None, repeat_every: int = 0, bom: bool = False,
                      cut_tail: bool = False, bad_cell_row: Optional[int] = None, backwards_row: Optional[int] = None,
                      extra_columns: Optional[Dict[str, np.ndarray]] = None, time_scale: float = 1.0,
                      cells: Optional[Dict[int, Dict[str, str]]] = None) -> dict:
    """A generic CSV (``time,accel,baro,reference``) of :func:`profile` with the given oddities.

    ``gravity`` (m/s²) is added to the acceleration (9.80665: gravity left in).
    ``repeat_every`` > 0 repeats every n-th row's timestamp from the row before
    (the values are the truth at the true time). ``bad_cell_row`` writes
    ``oops`` in the accel column of that data row (file line = row + 2);
    ``backwards_row`` writes that row's time 1 s before the previous one. ``time_scale`` multiplies the written
    time (1000: milliseconds). ``cells`` = {row: {column: text}} overwrites cells (e.g. a ``1e30`` baro).
    """
    time = np.arange(0.0, duration, 1.0 / rate)
    keep = drop_gap(time, gap)
    time = time[keep]
    altitude, velocity, accel = profile(time)
    accel_scale = G if accel_units == "g" else 1.0
    altitude_scale = 0.3048 if altitude_units == "ft" else 1.0
    written = time.copy()
    if repeat_every:
        for i in range(repeat_every, written.size, repeat_every):
            written[i] = written[i - 1]
    names = ["time", "accel", "baro", "reference"] + list(extra_columns or {})
    lines = [",".join(names)]
    for i, t in enumerate(written):
        a = (accel[i] + gravity) / accel_scale
        baro = f"{altitude[i] / altitude_scale:.4f}" if i % baro_every == 0 else ""
        row = [repr(float(t * time_scale)), f"{a:.6f}", baro, f"{altitude[i] / altitude_scale:.4f}"]
        if extra_columns:
            row += [repr(float(values[i])) for values in extra_columns.values()]
        if bad_cell_row == i:
            row[1] = "oops"
        if backwards_row == i:
            row[0] = repr(float(written[i - 1] - 1.0))
        for name, text in (cells or {}).get(i, {}).items():
            row[names.index(name)] = text
        lines.append(",".join(row))
    text = "\n".join(lines) + "\n"
    if cut_tail:
        text = text + lines[-1][: len(lines[-1]) // 3]  # the logger died mid-line: no newline at the end
    with open(path, "w", encoding="utf-8-sig" if bom else "utf-8", newline="") as handle:
        handle.write(text)
    return {"time": time, "written_time": written, "altitude": altitude, "velocity": velocity, "accel": accel}


def write_bytes(path, data: bytes) -> str:
    with open(path, "wb") as handle:
        handle.write(data)
    return str(path)


def mutations(data: bytes, rng: np.random.Generator, count: int) -> List[bytes]:
    """Truncations and bit flips of ``data`` (for the reader fuzz)."""
    out = []
    for _ in range(count):
        kind = rng.integers(4)
        if kind == 0 and len(data) > 1:
            out.append(data[: int(rng.integers(0, len(data)))])
        else:
            buffer = bytearray(data)
            for _ in range(int(rng.integers(1, 9))):
                if not buffer:
                    break
                position = int(rng.integers(len(buffer)))
                if kind == 1:
                    buffer[position] ^= 1 << int(rng.integers(8))
                elif kind == 2:
                    buffer[position] = int(rng.integers(256))
                else:
                    del buffer[position: position + int(rng.integers(1, 64))]
            out.append(bytes(buffer))
    return out


# --- PX4 ULog ------------------------------------------------------------------------

_ULOG_TYPES = {"uint64_t": "Q", "int32_t": "i", "uint8_t": "B", "float": "f", "double": "d"}


class ULogWriter:
    """Writes a ULog: file header, FORMAT ('F') definitions, then ADD_LOGGED ('A') and DATA ('D')."""

    def __init__(self, start_us: int = 1_000_000):
        self.definitions = bytearray(b"ULog\x01\x12\x35\x01" + struct.pack("<Q", start_us))
        self.data = bytearray()
        self.fields: Dict[str, list] = {}
        self.ids: Dict[tuple, int] = {}

    @staticmethod
    def _message(kind: bytes, payload: bytes) -> bytes:
        return struct.pack("<HB", len(payload), kind[0]) + payload

    def define(self, name: str, fields: Sequence[tuple]) -> None:
        """``fields``: (type, name, count) with the first one ``("uint64_t", "timestamp", 1)``."""
        self.fields[name] = list(fields)
        text = name + ":" + "".join(f"{t}[{n}] {f};" if n > 1 else f"{t} {f};" for t, f, n in fields)
        self.definitions += self._message(b"F", text.encode())

    def subscribe(self, name: str, multi_id: int = 0) -> None:
        msg_id = len(self.ids)
        self.ids[(name, multi_id)] = msg_id
        self.data += self._message(b"A", struct.pack("<BH", multi_id, msg_id) + name.encode())

    def write(self, name: str, values: dict, multi_id: int = 0) -> None:
        packed = b""
        for type_, field, count in self.fields[name]:
            value = values.get(field, 0)
            items = list(value) if count > 1 else [value]
            code = _ULOG_TYPES[type_]
            packed += struct.pack("<" + code * count, *[int(round(v)) if code in "QiB" else float(v) for v in items])
        self.data += self._message(b"D", struct.pack("<H", self.ids[(name, multi_id)]) + packed)

    def bytes(self) -> bytes:
        return bytes(self.definitions + self.data)


def write_ulog(path, style: str = "new", duration: float = 10.0, imu_rate: float = 100.0,
               baro_rate: float = 20.0, gps_rate: float = 5.0, gap: Optional[Sequence[float]] = None,
               second_baro_offset_pa: float = -24.0, gps_fix_from: float = 2.0) -> dict:
    """A PX4 ULog of :func:`profile` (level, FRD/NED), ``style="new"`` (``vehicle_air_data``,
    ``sensor_gps.altitude_msl_m``, two ``sensor_baro`` and ``sensor_accel`` instances) or ``"old"`` (PX4 < 1.8: baro
    inside ``sensor_combined``, ``vehicle_gps_position.alt`` in mm). GPS reads 100 m above the
    baro datum, without a fix before ``gps_fix_from`` s."""
    w = ULogWriter()
    start = 1_000_000
    combined = [("uint64_t", "timestamp", 1), ("float", "gyro_rad", 3), ("float", "accelerometer_m_s2", 3),
                ("uint8_t", "accelerometer_clipping", 1)]
    if style == "old":
        combined += [("float", "baro_alt_meter", 1), ("float", "baro_temp_celcius", 1),
                     ("int32_t", "baro_timestamp_relative", 1)]
    w.define("sensor_combined", combined)
    w.define("vehicle_attitude", [("uint64_t", "timestamp", 1), ("float", "q", 4)])
    w.define("vehicle_local_position", [("uint64_t", "timestamp", 1), ("float", "z", 1), ("float", "vz", 1)])
    if style == "old":
        w.define("vehicle_gps_position", [("uint64_t", "timestamp", 1), ("int32_t", "alt", 1), ("float", "epv", 1),
                                          ("uint8_t", "fix_type", 1), ("uint8_t", "satellites_used", 1)])
        topics = ["sensor_combined", "vehicle_attitude", "vehicle_local_position", "vehicle_gps_position"]
    else:
        w.define("vehicle_air_data", [("uint64_t", "timestamp", 1), ("uint64_t", "timestamp_sample", 1),
                                      ("float", "baro_alt_meter", 1), ("float", "baro_temp_celcius", 1),
                                      ("float", "baro_pressure_pa", 1)])
        w.define("sensor_baro", [("uint64_t", "timestamp", 1), ("uint64_t", "timestamp_sample", 1),
                                 ("float", "pressure", 1), ("float", "temperature", 1)])
        w.define("sensor_accel", [("uint64_t", "timestamp", 1), ("uint64_t", "timestamp_sample", 1),
                                  ("float", "x", 1), ("float", "y", 1), ("float", "z", 1)])
        w.define("sensor_gps", [("uint64_t", "timestamp", 1), ("double", "altitude_msl_m", 1), ("float", "epv", 1),
                                ("uint8_t", "fix_type", 1), ("uint8_t", "satellites_used", 1)])
        topics = ["sensor_combined", "vehicle_attitude", "vehicle_local_position", "vehicle_air_data",
                  "sensor_gps"]
    for topic in topics:
        w.subscribe(topic)
    if style != "old":
        w.subscribe("sensor_baro", 0)
        w.subscribe("sensor_baro", 1)
        w.subscribe("sensor_accel", 0)
        w.subscribe("sensor_accel", 1)
    imu_time = np.arange(0.0, duration, 1.0 / imu_rate)
    baro_every = int(round(imu_rate / baro_rate))
    gps_every = int(round(imu_rate / gps_rate))
    kept = drop_gap(imu_time, gap)
    for k, t in enumerate(imu_time):
        if not kept[k]:
            continue
        altitude, velocity, accel = (float(v) for v in profile(np.array(t)))
        stamp = start + int(round(t * 1e6))
        pressure = 101325.0 * (1 - 0.0065 * altitude / 288.15) ** 5.2559
        sample = {"timestamp": stamp, "gyro_rad": (0, 0, 0), "accelerometer_m_s2": (0, 0, -(G + accel)),
                  "accelerometer_clipping": 0}
        if style == "old" and k % baro_every == 0:
            sample.update(baro_alt_meter=altitude, baro_temp_celcius=25.0, baro_timestamp_relative=0)
        elif style == "old" and k > 0:
            sample.update(baro_alt_meter=np.nan, baro_temp_celcius=np.nan, baro_timestamp_relative=0)
        w.write("sensor_combined", sample)
        w.write("vehicle_attitude", {"timestamp": stamp, "q": (1, 0, 0, 0)})
        if style != "old":
            for multi in (0, 1):  # the second accelerometer reads 0.3 m/s² more on z (a bias)
                w.write("sensor_accel", {"timestamp": stamp, "timestamp_sample": stamp, "x": 0.0, "y": 0.0,
                                         "z": -(G + accel) + 0.3 * multi}, multi)
        if k % 2 == 0:
            w.write("vehicle_local_position", {"timestamp": stamp, "z": -altitude, "vz": -velocity})
        if k % baro_every == 0 and style != "old":
            w.write("vehicle_air_data", {"timestamp": stamp, "timestamp_sample": stamp, "baro_alt_meter": altitude,
                                         "baro_temp_celcius": 25.0, "baro_pressure_pa": pressure})
            w.write("sensor_baro", {"timestamp": stamp, "timestamp_sample": stamp, "pressure": pressure,
                                    "temperature": 25.0}, 0)
            w.write("sensor_baro", {"timestamp": stamp, "timestamp_sample": stamp,
                                    "pressure": pressure + second_baro_offset_pa, "temperature": 26.0}, 1)
        if k % gps_every == 0:
            fix = 3 if t >= gps_fix_from else 1
            if style == "old":
                w.write("vehicle_gps_position", {"timestamp": stamp, "alt": (altitude + 100.0) * 1000.0, "epv": 2.0,
                                                 "fix_type": fix, "satellites_used": 10})
            else:
                w.write("sensor_gps", {"timestamp": stamp, "altitude_msl_m": altitude + 100.0, "epv": 2.0,
                                       "fix_type": fix, "satellites_used": 10})
    with open(path, "wb") as handle:
        handle.write(w.bytes())
    altitude, velocity, _ = profile(imu_time[kept])
    return {"time": imu_time[kept], "altitude": altitude, "velocity": velocity}


#: The ULog sync sequence (the payload of PX4's S messages), which pyulog searches for after damaged bytes.
ULOG_SYNC = bytes([0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12])


def _ulog_messages(data: bytes) -> List[tuple]:
    """(offset, type) of each whole message of a sound ULog, after its 16-byte file header."""
    out, offset = [], 16
    while offset + 3 <= len(data):
        size = struct.unpack_from("<H", data, offset)[0]
        out.append((offset, data[offset + 2]))
        offset += 3 + size
    return out


def write_ulog_damaged(path, kind: str, **options) -> str:
    """The ULog of :func:`write_ulog` (``options``) damaged the way real logs are, for pyulog's recovery paths.

    ``kind="sync"``: two damaged stretches (a zero header and stray bytes, as a bad SD-card write leaves) in the
    data section, a third and two thirds of the way in, each followed by a sync message (S), as PX4 writes them;
    and a message of a type pyulog does not know (``X``) in between.
    ``kind="appended"``: the log cut inside a data message 60 % of the way in (a crash), then data appended at that
    offset (the flag-bits message first, with incompatible bit 0 and the offset): the subscriptions again, but for
    ``vehicle_local_position``, and the data messages from 40 % on."""
    write_ulog(path, **options)
    with open(path, "rb") as handle:
        log = handle.read()
    messages = _ulog_messages(log)
    data = [offset for offset, kind_ in messages if kind_ == ord("D")]
    if kind == "sync":
        stray = b"\x00\x00\x00" + bytes(range(1, 30))
        sync = struct.pack("<HB", len(ULOG_SYNC), ord("S")) + ULOG_SYNC
        unknown = struct.pack("<HB", 6, ord("X")) + b"newer!"
        first, middle, second = data[len(data) // 3], data[len(data) // 2], data[2 * len(data) // 3]
        damaged = (log[:first] + stray + sync + log[first:middle] + unknown + log[middle:second] + stray[:11] + sync
                   + log[second:])
    elif kind == "appended":
        cut = data[6 * len(data) // 10] + 9
        spans = [(offset, following) for (offset, kind_), (following, _) in zip(messages, messages[1:])
                 if kind_ == ord("A")]
        subscriptions = b"".join(log[a:b] for a, b in spans if b"vehicle_local_position" not in log[a:b])
        flags = struct.pack("<HB", 40, ord("B")) + bytes(8) + bytes([1]) + bytes(7) + struct.pack("<3Q", cut + 43, 0, 0)
        damaged = log[:16] + flags + log[16:cut] + subscriptions + log[data[4 * len(data) // 10]:]
    else:
        raise ValueError(f"kind must be 'sync' or 'appended', got {kind!r}")
    return write_bytes(path, damaged)


# --- rocket flight-computer exports (issue 20: "never silently wrong on a real log") -----------------------------
#
# Each ``*_csv(directory, …)`` function writes one file into ``directory`` (e.g. pytest's ``tmp_path``), written the
# way the real export is, and returns its path as a str, for the reader tests and end-to-end checks.

#: AltOS CSV version 5 header (AltosUI 1.4–1.6, ``altoslib/AltosCSV.java``): ``clock, rssi, lqi`` after ``time``,
#: ``accel_speed, baro_speed`` instead of ``speed``, ``gyro_x/y/z``.
ALTOS_V5_HEADER = ("#version,serial,flight,call,time,clock,rssi,lqi,state,state_name,acceleration,pressure,altitude,"
                   "height,accel_speed,baro_speed,temperature,drogue_voltage,main_voltage,battery_voltage,accel_x,"
                   "accel_y,accel_z,gyro_x,gyro_y,gyro_z,connected,locked,nsat,latitude,longitude,altitude,year,"
                   "month,day,hour,minute,second,pad_dist,pad_range,pad_az,pad_el,pdop,hdop,vdop")
#: AltOS 1.4.1's header as written: the advanced-sensor names follow ``main_voltage`` without a comma
#: (25 names; the rows have 26 cells).
ALTOS_14_HEADER = ("#version,serial,flight,call,time,clock,rssi,lqi,state,state_name,acceleration,pressure,altitude,"
                   "height,accel_speed,baro_speed,temperature,battery_voltage,drogue_voltage,main_voltageaccel_x,"
                   "accel_y,accel_z,gyro_x,gyro_y,gyro_z")
ALTOS_14_PREAMBLE = ("# Config version: 1.18", "# Serial number: 2718", "# Flight number: 7",
                     "# Software version: 1.4.1")
#: TeleMega IMU accelerometer full scale, m/s² (±16 g).
IMU_FULL_SCALE = 16 * G
#: Net boost acceleration of :func:`rocket_profile`, m/s² (the along-axis accelerometer reads this + g).
BOOST = 12 * G
BOOST_HIGH = 18 * G
BURN_TIME = 1.0
DESCENT_RATE = 20.0


def rocket_profile(time: np.ndarray, boost: float = BOOST, burn: float = BURN_TIME):
    """A vertical rocket flight: height (m above the pad), velocity (m/s), acceleration (m/s², +up, gravity removed).

    On the pad before t = 0; ``boost`` m/s² net for ``burn`` s; then ballistic (−g, no drag) until falling at
    ``DESCENT_RATE`` m/s, then a steady descent under the drogue."""
    t = np.asarray(time, dtype=float)
    vb, hb = boost * burn, 0.5 * boost * burn ** 2
    tc = t - burn
    t_drogue = (vb + DESCENT_RATE) / G  # coast time until −DESCENT_RATE
    h_drogue = hb + vb * t_drogue - 0.5 * G * t_drogue ** 2
    height = np.where(t < 0, 0.0, np.where(t < burn, 0.5 * boost * t ** 2, np.where(
        tc < t_drogue, hb + vb * tc - 0.5 * G * tc ** 2, h_drogue - DESCENT_RATE * (tc - t_drogue))))
    velocity = np.where(t < 0, 0.0, np.where(t < burn, boost * t, np.where(tc < t_drogue, vb - G * tc,
                                                                           -DESCENT_RATE)))
    accel = np.where(t < 0, 0.0, np.where(t < burn, boost, np.where(tc < t_drogue, -G, 0.0)))
    return height, velocity, accel


def _rocket_state(t: float, velocity: float):
    if t < 0:
        return 2, "pad"
    if t < BURN_TIME:
        return 3, "boost"
    if velocity > 0:
        return 5, "coast"
    return 6, "drogue"


def _isa_pressure(altitude):
    return 101325.0 * (1 - 0.0065 * np.asarray(altitude, dtype=float) / 288.15) ** 5.2559


def _telemetry_time(pad_time: float, duration: float, step: float = 0.1):
    """Ground-station packet times: every ``step`` s, with packets lost in runs of 0.5–4 s (fixed pattern)."""
    time = np.round(np.arange(-pad_time, duration, step), 6)
    keep = np.ones(time.shape, dtype=bool)
    for start, length in ((-1.5, 0.5), (3.0, 1.2), (6.0, 4.0), (12.0, 0.8), (16.0, 2.0)):
        keep &= ~((time > start) & (time < start + length))
    return time[keep]


def write_altos_rocket_csv(path, style: str = "current", duration: float = 25.0, rate: float = 20.0,
                           pad_time: float = 2.0, imu: str = "live", boost: float = BOOST, telemetry: bool = False,
                           acceleration: bool = True) -> dict:
    """An AltOS CSV of :func:`rocket_profile` (pad at ``PAD_ALTITUDE`` m), one row per time stamp.

    ``style``: ``"current"`` (:data:`ALTOS_HEADER`), ``"v5"`` (:data:`ALTOS_V5_HEADER`: clock, rssi, lqi,
    accel_speed, baro_speed) or ``"1.4"`` (:data:`ALTOS_14_PREAMBLE` comment lines, then the defective
    :data:`ALTOS_14_HEADER`; no GPS). ``imu``: ``"live"`` (accel_x = the along-axis specific force, ±16 g
    clipped), ``"dead"`` (accel_x/y/z all 0.00 on every row, as a TeleMega with a failed IMU writes) or
    ``"none"`` (no IMU columns: TeleMetrum). ``telemetry``: packet times of :func:`_telemetry_time` (0.1 s with
    0.5–4 s losses) instead of ``rate``. ``acceleration=False``: an EasyMini (the column holds AltOS's
    "missing" value 2147483647.00). The ``acceleration`` column is gravity-removed (≈ 0 on the pad), as AltOS
    writes it; it never saturates.
    """
    time = _telemetry_time(pad_time, duration) if telemetry else np.round(np.arange(-pad_time, duration, 1 / rate), 6)
    height, velocity, accel = rocket_profile(time, boost=boost)
    specific = accel + G  # along the axis, +nose: +1 g on the pad
    imu_x = np.clip(specific, -IMU_FULL_SCALE, IMU_FULL_SCALE)
    header = {"current": ALTOS_HEADER, "v5": ALTOS_V5_HEADER, "1.4": ALTOS_14_HEADER}[style]
    lines = list(ALTOS_14_PREAMBLE) if style == "1.4" else []
    lines.append(header)
    for i, (t, h, v, a) in enumerate(zip(time, height, velocity, accel)):
        number, name = _rocket_state(t, v)
        altitude = h + PAD_ALTITUDE
        pressure = float(_isa_pressure(altitude))
        temperature = 15.0 - 0.0065 * altitude
        acc = f"{a:.2f}" if acceleration else "2147483647.00"
        if imu == "dead":
            axes = ["0.00"] * 3
        else:
            axes = [f"{imu_x[i]:.2f}", f"{0.3 + 0.01 * np.sin(7 * t):.2f}", f"{-0.2 + 0.01 * np.cos(5 * t):.2f}"]
        gyros = [f"{0.5 * np.sin(t):.2f}", f"{0.4 * np.cos(t):.2f}", f"{120.0 if 0 <= t < 5 else 3.0:.2f}"]
        locked = 1 if t >= 1.0 else 0
        gps = [1, locked, 9 if locked else 3, "47.0000000", "8.0000000", f"{altitude + 40.0:.1f}" if locked else "0.0",
               2024, 6, 1, 12, 0, 0]
        rssi, lqi = -70 - int(20 * abs(np.sin(t))), 40 + int(t) % 7
        if style == "current":
            cells = [1, 2718, 7, "N0CALL", f"{t:.2f}", number, name, acc, f"{pressure:.1f}", f"{altitude:.2f}",
                     f"{h:.2f}", f"{v:.2f}", f"{temperature:.1f}", "3.9", "3.9", "3.8", *axes, *gyros, "0.1", "0.2",
                     "0.3", "2", "0", *gps, "1.5", "0.9", "1.2", "N"]
        elif style == "v5":
            cells = [5, 2718, 7, "N0CALL", f"{t:.2f}", f"{t + 100.0:.2f}", rssi, lqi, number, name, acc,
                     f"{pressure:.2f}", f"{altitude:.2f}", f"{h:.2f}", f"{v:.2f}", f"{v:.2f}", f"{temperature:.1f}",
                     "3.9", "3.9", "3.8", *axes, *gyros, *gps, 0, 0, 0, 0, "1.5", "0.9", "1.2"]
        else:
            cells = [5, 2718, 7, "N0CALL", f"{t:.2f}", f"{t + 100.0:.2f}", 0, 0, number, name, acc,
                     f"{pressure:.2f}", f"{altitude:.2f}", f"{h:.2f}", f"{v:.2f}", f"{v:.2f}", f"{temperature:.1f}",
                     "3.8", "3.9", "3.9", *axes, *gyros]
        if imu == "none":  # a TeleMetrum: no IMU cells
            cells = [c for j, c in enumerate(cells) if header.lstrip("#").split(",")[j]
                     not in _IMU_NAMES] if style != "1.4" else cells[:-6]
        lines.append(",".join(str(c) for c in cells))
    if imu == "none":
        names = [n for n in lines[-len(time) - 1].lstrip("#").split(",") if n not in _IMU_NAMES]
        if style == "1.4":
            names = ALTOS_14_HEADER.lstrip("#").split(",")[:19] + ["main_voltage"]
        lines[-len(time) - 1] = "#" + ",".join(names)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines) + "\n")
    return {"time": time, "height": height, "velocity": velocity, "accel": accel, "specific": specific,
            "imu_x": imu_x, "altitude": height + PAD_ALTITUDE}


_IMU_NAMES = {"accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z", "gyro_roll", "gyro_pitch", "gyro_yaw",
              "mag_x", "mag_y", "mag_z"}


def altos_telemetry_csv(directory) -> str:
    """A TeleMega ground-station telemetry export (AltOS CSV v5: clock, rssi, lqi, accel_speed, baro_speed):
    packets every 0.1 s (median step) with losses of 0.5, 0.8, 1.2, 2 and 4 s."""
    path = f"{directory}/telemetry.csv"
    write_altos_rocket_csv(path, style="v5", telemetry=True)
    return path


def altos_14_csv(directory) -> str:
    """An AltOS 1.4.1 export: ``# Config version`` / ``# Serial number`` / ``# Software version`` comment lines
    before the header, and the header's missing comma (``main_voltageaccel_x``: 25 names for 26 cells)."""
    path = f"{directory}/altos-1.4.csv"
    write_altos_rocket_csv(path, style="1.4")
    return path


def telemega_dead_imu_csv(directory) -> str:
    """A TeleMega export whose IMU is dead (accel_x/y/z 0.00 on every row) while ``acceleration`` is alive."""
    path = f"{directory}/telemega-dead-imu.csv"
    write_altos_rocket_csv(path, imu="dead")
    return path


def telemega_saturating_imu_csv(directory) -> str:
    """A TeleMega export of an 18 g boost: the IMU's accel_x saturates at +16 g, ``acceleration`` does not."""
    path = f"{directory}/telemega-saturating.csv"
    write_altos_rocket_csv(path, boost=BOOST_HIGH)
    return path


def easymini_csv(directory) -> str:
    """An EasyMini export: no accelerometer (``acceleration`` holds AltOS's missing value), no IMU columns."""
    path = f"{directory}/easymini.csv"
    write_altos_rocket_csv(path, imu="none", acceleration=False)
    return path


#: The data row (0-based) and so the file line (row + 2) of the 1e30 baro cell of :func:`csv_with_absurd_baro`.
ABSURD_BARO_ROW = 700


def csv_with_absurd_baro(directory) -> str:
    """A generic CSV (:func:`write_generic_csv`: ``time,accel,baro,reference``) whose baro cell on data row
    :data:`ABSURD_BARO_ROW` (file line ``ABSURD_BARO_ROW + 2``) reads ``1e30``."""
    path = f"{directory}/absurd-baro.csv"
    write_generic_csv(path, baro_every=5, cells={ABSURD_BARO_ROW: {"baro": "1e30"}})
    return path


def csv_with_millisecond_time(directory) -> str:
    """A generic CSV (100 Hz, 20 s) whose time column is in milliseconds (0, 10, 20, …)."""
    path = f"{directory}/ms-time.csv"
    write_generic_csv(path, time_scale=1000.0)
    return path


RAVEN_HEADER = "Time-Axial Accel (Gs), Axial Accel (Gs), bILBA, Time (s), Altitude (Ft-AGL), bILBA"


def raven_csv(directory, duration: float = 30.0, accel_seconds: float = 4.5) -> str:
    """A Featherweight Raven export of :func:`rocket_profile` (pad at t = 0.5 s): ``Axial Accel (Gs)`` at 400 Hz
    for the first ``accel_seconds`` s on its own time column, ``Altitude (Ft-AGL)`` at 20 Hz on ``Time (s)``
    (starting at 0.04375 s, as the real export), ``bILBA`` status bits; the shorter channel's cells are empty on
    the rows after its end."""
    path = f"{directory}/raven.csv"
    accel_time = np.round(np.arange(0.0, accel_seconds, 0.0025), 6)
    alt_time = np.round(np.arange(0.04375, duration, 0.05), 6)
    _, _, accel = rocket_profile(accel_time - 0.5)
    height, _, _ = rocket_profile(alt_time - 0.5)
    rows = max(accel_time.size, alt_time.size)
    lines = [RAVEN_HEADER]
    for i in range(rows):
        left = (f"{accel_time[i]:.4f},{(accel[i] + G) / G:.2f},b{'1' if accel_time[i] >= 0.5 else '0'}000"
                if i < accel_time.size else ",,")
        right = (f"{alt_time[i]:.5f},{height[i] / 0.3048:.5f},b{'1' if alt_time[i] >= 0.5 else '0'}000"
                 if i < alt_time.size else ",,")
        lines.append(f"{left},{right}")
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines))  # the real export ends without a newline
    return path


RRC3_HEADER = "time,altitude,pressure,velocity,temperature,events,voltages"
#: Data rows (0-based; file line = row + 2) of the RRC3 fixture's quirks.
RRC3_SPIKE_ROW = 300
RRC3_GARBAGE_ROWS = (451, 452)
RRC3_SHIFT_FROM_ROW = 440


def rrc3_csv(directory) -> str:
    """A Missile Works RRC3 export of :func:`rocket_profile` (launch at 1 s), 20 Hz, 22.6 s, with the real
    export's quirks: from data row :data:`RRC3_SHIFT_FROM_ROW` the temperature cell is missing (the events and
    an empty voltage one column left), a +54 m one-sample spike on row :data:`RRC3_SPIKE_ROW`, and two garbage
    rows (10.7 km, −2.5 km) on :data:`RRC3_GARBAGE_ROWS`, the first carrying the ``Drogue`` event."""
    path = f"{directory}/rrc3.csv"
    time = np.round(np.arange(0.0, 22.65, 0.05), 2)
    height, velocity, _ = rocket_profile(time - 1.0)
    lines = [RRC3_HEADER]
    for i, (t, h, v) in enumerate(zip(time, height, velocity)):
        if i == RRC3_SPIKE_ROW:
            h = h + 54.0
        pressure = float(_isa_pressure(h + 1400.0)) / 100.0
        if i == RRC3_GARBAGE_ROWS[0]:
            lines.append(f"{t:.2f},10700.59,191.25,7215.777, Drogue,,")
            continue
        if i == RRC3_GARBAGE_ROWS[1]:
            lines.append(f"{t:.2f},-2490.543,1158.70,-5345.959, -,,")
            continue
        if i >= RRC3_SHIFT_FROM_ROW:
            lines.append(f"{t:.2f},{h:.6g},{pressure:.2f},{v:.6g}, -,,")
        else:
            lines.append(f"{t:.2f},{h:.6g},{pressure:.2f},{v:.6g},31.9, -,3.811746")
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines) + "\n")
    return path
