"""Recorded logs: one reader module per format, all returning :class:`LogData`.

Every reader returns a :class:`LogData` on one time grid (the accelerometer's
timestamps, possibly irregular): the observer's vertical-acceleration input
(m/s², +up, gravity removed), the baro altitude (m; NaN on steps without a new
baro sample), when the log has them the flight computer's own height estimate
as a reference, GPS, rangefinder, raw IMU, pressure, temperature and flight
state (see :class:`LogData` for units and datums).
:func:`fusion_altitude.runner.run_log` runs an estimator on it.

Formats (:data:`FORMATS`, tried by :func:`sniff_format` in this order)
----------------------------------------------------------------------
* ``ulog`` — PX4 ULog, :func:`read_ulog` (``[logs]`` extra): by the file's
  magic bytes or ``.ulg``.
* ``dataflash`` — ArduPilot DataFlash, :func:`read_dataflash` (``[logs]``
  extra), every generation (``TimeUS`` and ArduCopter ≤ 3.3's ``TimeMS``):
  by its message header bytes or ``.bin``.
* ``altos`` — AltOS CSV of every version (TeleMega, EasyMega, TeleMetrum,
  EasyMini; flight-computer downloads and ground-station telemetry),
  :func:`read_altos_csv`: by its ``#version,serial,flight,…`` header, after
  any ``#`` comment lines; no column options.
* ``raven`` — Featherweight Raven CSV export, :func:`read_raven`: by its
  ``Time…`` / ``Axial Accel (Gs)`` / ``Altitude (Ft-AGL)`` header; two
  time bases merged onto one grid.
* ``rrc3`` — Missile Works RRC3 CSV export, :func:`read_rrc3`: by its
  ``time,altitude,pressure,velocity,…,events`` header; baro only.
* ``cats`` — CATS split CSVs, :func:`read_cats`: ``*baro.csv`` /
  ``*imu.csv`` / ``*flight_info.csv`` (with a ``ts`` column) or a
  directory holding them.
* ``csv`` — anything else: :func:`read_csv_log`, the caller names columns.

Repeated timestamps are merged (numeric columns averaged) and counted in
``LogData.repeated_timestamps`` and a warning; logging gaps are listed in
``LogData.gaps``; time that goes backwards is an error.

Every reader's output goes through the plausibility checks of
:mod:`fusion_altitude.logs._checks` (time in seconds, absurd cells dropped
with a warning naming the line, dead channels never used), each reported in
one line.

Bad input raises :class:`LogError`: one line naming the file, the line (or
message) and the column. Readers never raise anything else on a bad file.
"""

from __future__ import annotations

import functools
import os
import stat
from dataclasses import dataclass
from typing import Callable, Dict, Optional, Tuple

from .._core import installed_extension_folder
from ._data import LogData, LogError, LogWarning, find_gaps, merge_repeated_timestamps, quiet_warnings
from ._table import given_bytes
from .altos import looks_like_altos, read_altos_csv
from .cats import find_cats_files, looks_like_cats, read_cats
from .dataflash import DATAFLASH_MAGIC, read_dataflash
from .generic_csv import read_csv_log
from .raven import looks_like_raven, read_raven
from .rrc3 import looks_like_rrc3, read_rrc3
from .ulog import ULOG_MAGIC, read_ulog

# a source checkout shadowing an installed copy: the compiled decoder (_decode) loads from the installed one
if installed_extension_folder(__file__, "logs", "_decode") is not None:
    __path__.append(installed_extension_folder(__file__, "logs", "_decode"))  # type: ignore[name-defined]  # noqa: F821

__all__ = ["LogError", "LogWarning", "LogData", "Format", "FORMATS", "read_csv_log", "read_ulog",
           "read_dataflash", "read_altos_csv", "read_cats", "read_raven", "read_rrc3", "find_cats_files",
           "sniff_format", "load_log",
           "find_gaps", "merge_repeated_timestamps", "quiet_warnings"]


@dataclass(frozen=True)
class Format:
    """One log format of the registry.

    Attributes
    ----------
    name : str
        Short name (``load_log(format=…)``).
    description : str
        For messages and ``--help``.
    extensions : tuple of str
        Lower-case file extensions that select it when the content does not.
    sniff : callable(path, head_bytes) -> bool
        True if the file's first bytes (≤ 4 kB) are this format.
    read : callable
        The reader; called as ``read(path, **options)``.
    needs_columns : bool
        True if the caller must name the columns (generic CSV).
    """

    name: str
    description: str
    extensions: tuple
    sniff: Callable[[str, bytes], bool]
    read: Callable[..., LogData]
    needs_columns: bool = False


@functools.lru_cache(maxsize=4)
def _text(head: bytes) -> str:
    """The sniffed head as text, decoded once for the four text sniffers."""
    return head.decode("utf-8-sig", errors="replace")


FORMATS: Dict[str, Format] = {f.name: f for f in (
    Format("ulog", "PX4 ULog", (".ulg",), lambda path, head: head.startswith(ULOG_MAGIC), read_ulog),
    Format("dataflash", "ArduPilot DataFlash", (".bin",),
           lambda path, head: head[:2] == DATAFLASH_MAGIC and len(head) > 2 and head[2] == 128, read_dataflash),
    Format("altos", "AltOS CSV", (), lambda path, head: looks_like_altos(_text(head)), read_altos_csv),
    Format("raven", "Featherweight Raven CSV", (), lambda path, head: looks_like_raven(_text(head)), read_raven),
    Format("rrc3", "Missile Works RRC3 CSV", (), lambda path, head: looks_like_rrc3(_text(head)), read_rrc3),
    Format("cats", "CATS CSV set", (), lambda path, head: looks_like_cats(path, _text(head)), read_cats),
    Format("csv", "CSV (columns named by the caller)", (".csv", ".txt"), lambda path, head: True, read_csv_log,
           needs_columns=True),
)}


def sniff_format(path: str) -> str:
    """The name of the format of ``path`` (a key of :data:`FORMATS`), by content first, then extension.

    A directory is a CATS set. Raises :class:`LogError` if the path does not exist.
    """
    if os.path.isdir(path):
        find_cats_files(path)
        return "cats"
    try:
        with open(path, "rb") as handle:
            head = handle.read(4096)
    except OSError as error:
        raise LogError(f"cannot open {path}: {error.strerror}") from None
    return _format_of(path, head)


def _format_of(path: str, head: bytes) -> str:
    """The format of the file ``path`` whose first bytes (≤ 4 kB) are ``head``: by content first, then extension."""
    for name in ("ulog", "dataflash", "altos", "raven", "rrc3", "cats"):
        if FORMATS[name].sniff(path, head):
            return name
    suffix = os.path.splitext(path)[1].lower()
    for format_ in FORMATS.values():
        if suffix in format_.extensions:
            return format_.name
    return "csv"


#: Largest text log (bytes) that :func:`load_log` reads whole while sniffing it, for its reader to take instead of
#: reading it again (an open and a read: about 15 µs, 5 % of reading a 28 kB RRC3 export).
READ_ONCE_MAX = 1 << 22
#: A file of at most this many bytes is read whole at once, whatever its format (a binary log is then read again by
#: its reader: at most 256 kB more, against its decoding's milliseconds).
SMALL_FILE = 1 << 18


def _sniff_and_read(path: str) -> Optional[Tuple[str, Optional[bytes]]]:
    """The format of a regular file and, for a text format of at most :data:`READ_ONCE_MAX` bytes, the whole
    file's bytes (else None), in one open; None when the file cannot be opened or is not a regular file
    (:func:`sniff_format` then decides, with its errors)."""
    try:
        with open(path, "rb") as handle:
            status = os.fstat(handle.fileno())
            if not stat.S_ISREG(status.st_mode):
                return None
            whole = status.st_size <= SMALL_FILE  # read in one call (no second read, no joining)
            raw = handle.read() if whole else handle.read(4096)
            name = _format_of(path, raw[:4096] if whole else raw)
            if name in ("ulog", "dataflash") or status.st_size > READ_ONCE_MAX:
                return name, None
            if whole or len(raw) < 4096:
                return name, raw
            handle.seek(0)  # the whole file in one read: no join of its head and the rest (a copy of it)
            return name, handle.read()
    except OSError:
        return None


#: Decoders of :func:`load_log`: the fast one (default), or the reference library of one format, kept for a release.
DECODERS = {"fast": None, "pymavlink": "dataflash", "pyulog": "ulog"}


def load_log(path: str, format: Optional[str] = None, instance: Optional[int] = None,
             progress: Optional[Callable[[int, int], None]] = None, decoder: str = "fast",
             column_options: Optional[Dict[str, object]] = None, **options) -> LogData:
    """Read a log of any known format.

    Parameters
    ----------
    path : str
        A log file, or a directory holding a CATS set.
    format : str, optional
        Force a format (a key of :data:`FORMATS`); default :func:`sniff_format`.
    instance : int, optional
        Sensor instance for formats with several (DataFlash, ULog, CATS);
        default the primary.
    progress : callable(done, total), optional
        Called while reading.
    decoder : {"fast", "pymavlink", "pyulog"}
        "fast" (default): DataFlash and ULog decoded in C (the extension),
        stray bytes, ULog sync recovery and appended data included; the few
        logs whose reading depends on the reference library's other recovery
        paths are left to it, so results do not depend on the decoder; small
        CSV bodies are scanned in C, larger ones read by pyarrow. "pymavlink":
        DataFlash through pymavlink, "pyulog": ULog through pyulog — the
        references, kept for one release; each only for its own format.
    column_options : dict, optional
        Options for a log whose columns must be named (generic CSV), left
        out for the formats that know their columns: for a caller that reads
        logs of any format with one set of column options (the fleet), with
        the file sniffed and read once. A missing file is then the sniffer's
        LogError (``cannot open …``).
    **options
        Passed to the reader: the column options of :func:`read_csv_log` for
        generic CSV; ``ground_temperature_k`` for AltOS / CATS / CSV.
        Options a format does not take are an error (LogError naming them).

    Raises
    ------
    LogError
        Missing file, unknown format, unreadable or inconsistent content, a
        reference decoder of another format.
    ValueError
        ``decoder`` is not a known decoder.
    """
    if decoder not in DECODERS:
        raise ValueError(f"decoder must be one of {', '.join(DECODERS)}, got {decoder!r}")
    sniffed = None if format else _sniff_and_read(path)
    if sniffed is None:
        if not column_options and not os.path.exists(path):
            raise LogError(f"{path}: no such file")
        sniffed = format or sniff_format(path), None
    name, raw = sniffed
    if name not in FORMATS:
        raise LogError(f"unknown log format {name!r}; known: {', '.join(FORMATS)}")
    if column_options and FORMATS[name].needs_columns:
        options = {**column_options, **options}
    options = {key: value for key, value in options.items() if value is not None}
    _check_options(path, name, options, instance, decoder)
    if name in ("dataflash", "ulog"):
        options["decoder"] = decoder
    given_bytes(path, raw)  # the reader's read_text takes them (a CSV read once)
    try:
        return FORMATS[name].read(path, progress=progress, **options)
    finally:
        given_bytes(path, None)


@functools.lru_cache(maxsize=None)
def _csv_options() -> frozenset:
    """The keyword options of :func:`read_csv_log` (its signature, read once)."""
    import inspect
    return frozenset(inspect.signature(read_csv_log).parameters) - {"path", "progress"}


def _check_options(path: str, name: str, options: dict, instance: Optional[int], decoder: str) -> None:
    """Refuse options the format ``name`` does not take (``options`` gains ``instance`` where it does)."""
    if instance is not None:
        if name in ("altos", "csv", "raven", "rrc3"):
            raise LogError(f"{path}: a {FORMATS[name].description} has one sensor instance; instance not supported")
        options["instance"] = instance
    if name == "csv":
        unknown = sorted(set(options) - _csv_options())
        if unknown:
            raise LogError(f"unknown CSV option{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}")
        if "time_column" not in options:
            raise LogError(f"{path}: not a ULog, DataFlash, AltOS, Raven, RRC3 or CATS log; as a generic CSV it "
                           f"needs its "
                           f"columns named (time_column, accel_column, baro_column or pressure_column)")
    accepted = {"ulog": {"instance", "decoder"}, "dataflash": {"instance", "decoder"},
                "altos": {"ground_temperature_k"}, "raven": set(), "rrc3": set(),
                "cats": {"instance", "ground_temperature_k", "accel_range"}}
    if name in accepted:
        extra = sorted(set(options) - accepted[name])
        if extra:
            raise LogError(f"{path} is a {FORMATS[name].description}, which takes no {', '.join(extra)} option"
                           f"{'s' if len(extra) > 1 else ''} (its columns are known)")
    if DECODERS[decoder] is not None and DECODERS[decoder] != name:
        raise LogError(f"{path}: the {decoder} decoder reads only {FORMATS[DECODERS[decoder]].description} logs; "
                       f"this is a {FORMATS[name].description} log")
