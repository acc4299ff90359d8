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
                      extra_columns: Optional[Dict[str, np.ndarray]] = None) -> dict:
    """A generic CSV (``time,accel,baro,reference``) of :func:`profile` with the given oddities.

    ``gravity`` (m/s²) is added to the acceleration (9.80665: gravity left in).
    ``repeat_every`` > 0 repeats every n-th row's timestamp from the row before
    (the values are the truth at the true time). ``bad_cell_row`` writes
    ``oops`` in the accel column of that data row (file line = row + 2);
    ``backwards_row`` writes that row's time 1 s before the previous one.
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
        cells = [repr(float(t)), f"{a:.6f}", baro, f"{altitude[i] / altitude_scale:.4f}"]
        if extra_columns:
            cells += [repr(float(values[i])) for values in extra_columns.values()]
        if bad_cell_row == i:
            cells[1] = "oops"
        if backwards_row == i:
            cells[0] = repr(float(written[i - 1] - 1.0))
        lines.append(",".join(cells))
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
