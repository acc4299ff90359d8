"""Fleets of logs on Dask: run, summarise and fit over thousands of flights.

Reading a log (pyulog, pymavlink, the CSV parser) costs far more than running
an estimator on it, so fleet work scales with cores and machines. This module
puts the logs, a batch of consecutive logs per task, on a :mod:`dask.distributed`
cluster — a ``LocalCluster`` sized to the machine when no client is given, or any
existing cluster (``Client("tcp://HOST:8786")``) unchanged. Needs the
``[fleet]`` extra (``dask[distributed]``, ``pyarrow``; ``bokeh`` for the dashboard).

Functions
---------
:func:`run_many`
    Run an estimator over every log; per-log estimates as Parquet, one summary
    table (Parquet and CSV), failed logs as rows with their one-line error,
    resume by settings hash.
:func:`fit_many`
    One set of observer gains for many logs: per-log sweeps on the workers,
    their sums reduced on the client, refined; scored on held-out logs.
:func:`summary`
    The summary table of an output directory.

Output directory
----------------
``OUT/logs/<log_id>.parquet``
    Per grid step, the columns ``fusion-altitude run -o`` writes, in its order
    (time s, altitude m, vertical_velocity m/s, the estimator's other outputs —
    the observer's accel_bias m/s² and baro_residual m —, baro_altitude m,
    vertical_acceleration m/s², reference_altitude m when the log has one),
    in their native dtypes (the estimates float32, as computed), plus ``log_id``. The file's key-value metadata ``fusion_altitude.fleet``
    holds the settings hash, the source fingerprint and the log's summary row.
``OUT/csv/<log_id>.csv`` (``write_csv=True``)
    The very file ``fusion-altitude run -o`` writes.
``OUT/failed/<log_id>.json``
    A log that cannot be used (a reader or estimator error): its summary row.
``OUT/summary.parquet``, ``OUT/summary.csv``
    One row per log of the run (:data:`SUMMARY_FIELDS`).

Every file is written to a temporary name, made durable (``fsync``) and renamed
into place (local disks; :class:`_Publisher`: on a thread of its own, overlapping
the next log, with one directory ``fsync`` per task before the task reports, while
the worker already runs its next task), or
uploaded as one object (object stores), so a worker that dies mid-write leaves
either the complete old file or none; Dask reruns its task.

Paths may be local files, directories (searched recursively for
:data:`LOG_EXTENSIONS`), globs, or any fsspec URL (``s3://bucket/logs/*.ulg``)
that the workers can read; remote logs are copied to a local temporary file
for the readers. ``OUT`` may be an fsspec URL too; on a multi-machine cluster
it must be storage every worker and the client see.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import dataclasses
import hashlib
import json
import math
import os
import socket
import tempfile
import time as _time
import uuid
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterator, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import health, runner, tuning
from ._core._observer import AltitudeSettings
from .estimators import estimator_names
from .outputs import atomic_output, csv_columns, write_csv, write_temporary
from ._version import __version__

__all__ = ["FORMAT_VERSION", "LOG_EXTENSIONS", "SUMMARY_FIELDS", "FleetRun", "FleetFit", "expand_paths", "log_id",
           "settings_hash", "run_many", "fit_many", "summary", "worst_logs", "open_client"]

#: Version of the output layout; part of the settings hash.
FORMAT_VERSION = 2  # 2: the health columns of the summary and the flags column of the estimates

#: File name endings searched for in a directory (case-insensitive).
LOG_EXTENSIONS = (".ulg", ".bin", ".csv")

_METADATA_KEY = b"fusion_altitude.fleet"

#: Columns of the summary table, in order: (name, pyarrow type name, meaning).
SUMMARY_FIELDS: Tuple[Tuple[str, str, str], ...] = (
    ("log_id", "string", "basename of the log and 8 hex digits of the SHA-1 of its full path or URL"),
    ("path", "string", "path or URL of the log"),
    ("status", "string", "'ok', or 'failed' with the error in `error`"),
    ("error", "string", "one-line error of a failed log ('' when ok)"),
    ("source", "string", "file name and format, as the reader names it"),
    ("estimator", "string", "estimator run"),
    ("settings_hash", "string", "hash of estimator, settings, CSV options, package and format version"),
    ("bytes", "int64", "size of the log file, bytes"),
    ("samples", "int64", "grid steps (IMU samples)"),
    ("duration_s", "float64", "last − first grid time, s"),
    ("imu_rate_hz", "float64", "(samples − 1) / duration, Hz"),
    ("baro_samples", "int64", "grid steps carrying a baro sample"),
    ("baro_rate_hz", "float64", "(baro samples − 1) / (last − first baro time), Hz"),
    ("imu_gaps", "int64", "grid steps longer than twice the median step"),
    ("max_dt_s", "float64", "longest grid step, s"),
    ("baro_gaps", "int64", "intervals between baro samples longer than twice the median interval"),
    ("max_baro_interval_s", "float64", "longest interval between baro samples, s"),
    ("clipped_samples", "int64", "samples with the accelerometer at its range limit"),
    ("reference", "string", "the log's own estimate the metrics compare with ('' if none)"),
    ("mean_error_m", "float64", "mean of altitude − reference, m (whole log)"),
    ("rms_error_m", "float64", "RMS of altitude − reference, m"),
    ("max_abs_error_m", "float64", "max |altitude − reference|, m"),
    ("p95_abs_error_m", "float64", "95th percentile of |altitude − reference|, m"),
    ("baro_rms_error_m", "float64", "RMS of baro − reference, m"),
    ("final_altitude_m", "float64", "last altitude estimate, m"),
    ("final_accel_bias_m_s2", "float64", "last accelerometer-bias estimate, m/s²"),
    # the health report of `run` (fusion_altitude.health), as columns
    ("baro_first_s", "float64", "time of the first baro sample, s"),
    ("baro_last_s", "float64", "time of the last baro sample, s"),
    ("baro_longest_outage_s", "float64", "longest time without a baro sample, to the log's end included, s"),
    ("stopped_streams", "string", "sensor streams that stop before the log's end (';'-separated; '' if none)"),
    ("dead_channels", "string", "sensor streams that are constant or empty (';'-separated; '' if none)"),
    ("gps_samples", "int64", "GPS altitude samples (0 without GPS)"),
    ("rangefinder_samples", "int64", "rangefinder samples (0 without a rangefinder)"),
    ("estimator_gaps", "int64", "updates the estimator treated as gaps (-1: it has no gap counter)"),
    ("not_baro_aided_s", "float64", "time the baro was silent for longer than its timeout (rows flagged in -o), s"),
    ("truncated", "bool_", "the file ends inside a message: cut short (warned)"),
    ("reader_warnings", "int64", "warnings the reader issued"),
    ("warnings", "string", "the reader's warnings, one line each, joined by ' | ' ('' if none)"),
)
# then, for estimators that report them, final_<name> of their other bias/offset outputs (e.g. the Kalman
# filter's final_baro_offset, m)


# ----------------------------------------------------------------------------
# one log, as `fusion-altitude run` reads and runs it


#: Exceptions that mean "this log cannot be used", as opposed to a problem of
#: the machine (a missing package, a full disk): the first kind is recorded and
#: not retried with the same settings, the second is reported and retried.
LOG_ERRORS: Tuple[type, ...] = (ValueError,)  # logs.LogError is a ValueError


def resolve_settings(estimator: str, settings: Any) -> Any:
    """The settings object for ``estimator``: None (its default), a preset name, or a settings object."""
    if estimator not in estimator_names():
        raise ValueError(f"estimator must be one of {', '.join(estimator_names())}, got {estimator!r}")
    if estimator == "observer":
        from ._core._observer import AltitudeSettings
        if settings is None:
            return AltitudeSettings()
        if isinstance(settings, str):
            return AltitudeSettings.preset(settings)
        if not isinstance(settings, AltitudeSettings):
            raise TypeError(f"settings must be an AltitudeSettings or a preset name, got {type(settings).__name__}")
        return settings
    if isinstance(settings, str):
        raise ValueError(f"settings: presets by name exist for the observer only, got {settings!r} for {estimator}")
    return settings


def run_columns(run) -> List[Tuple[str, np.ndarray]]:
    """The per-step columns ``run -o`` writes (:func:`fusion_altitude.outputs.csv_columns`), each in its native dtype."""
    return [(name, np.asarray(values)) for name, values in csv_columns(run)]


def _jsonable(value: Any) -> Any:
    if isinstance(value, float):
        return value.hex() if math.isfinite(value) else repr(value)
    if isinstance(value, (np.floating,)):
        return float(value).hex()
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in sorted(value.items())}
    if value is None or isinstance(value, (bool, int, str)):
        return value
    return repr(value)


def settings_key(estimator: str, settings: Any) -> Dict[str, Any]:
    """A JSON-able, exact description of the settings (floats as hex), for the settings hash."""
    if settings is None:
        values: Any = None
    elif hasattr(settings, "as_tuple"):
        values = list(settings.as_tuple())
    elif dataclasses.is_dataclass(settings):
        values = dataclasses.asdict(settings)
    else:
        values = repr(settings)
    return {"estimator": estimator, "type": type(settings).__name__, "values": _jsonable(values)}


def read_log(path: str, csv_options: Optional[Dict[str, Any]] = None):
    """Read one local log file as ``fusion-altitude run`` does (``LogData``); ``csv_options``
    go to the logs that need column names (generic CSV) only.

    A CSV log without the column options its reader needs raises ``ValueError``
    (a property of the log and the options, like any reader error).
    """
    from . import logs

    try:
        with logs.quiet_warnings():  # the warnings are in LogData.warnings: the summary and the CLI report them
            # the column options go to the formats that need them only: load_log sniffs and reads the file once
            return logs.load_log(path, column_options=dict(csv_options) if csv_options else None)
    except TypeError as error:
        raise ValueError(f"{path}: this log needs csv_options ({error})") from None


def require_fleet_packages():
    """Raise ImportError naming the [fleet] extra when Dask distributed or pyarrow is missing."""
    try:
        import distributed  # noqa: F401  (pyflakes)
        import pyarrow  # noqa: F401
    except ImportError as error:
        raise ImportError("fleet processing needs dask.distributed and pyarrow: "
                          "pip install 'fusion-altitude[fleet]'") from error


# ----------------------------------------------------------------------------
# Paths, ids, hashes


def _is_url(path: str) -> bool:
    return "://" in path and not path.startswith("file://")


def expand_paths(paths_or_globs: Union[str, Sequence[str]]) -> List[str]:
    """Log paths from files, directories (recursive, :data:`LOG_EXTENSIONS`), globs and fsspec URLs.

    Local paths come back absolute, URLs with their protocol; sorted, without
    duplicates. A plain path that does not exist is kept (it becomes a failed
    row); a glob or directory that matches nothing raises ``ValueError``.
    """
    import fsspec

    if isinstance(paths_or_globs, (str, os.PathLike)):
        paths_or_globs = [paths_or_globs]
    found = set()
    for item in paths_or_globs:
        item = os.fspath(item)
        fs, path = fsspec.core.url_to_fs(item)
        local = not _is_url(item)

        def name(p: str) -> str:
            return os.path.abspath(p) if local else fs.unstrip_protocol(p)

        if any(ch in path for ch in "*?["):
            matches = [p for p in fs.glob(path) if fs.isfile(p)]
            if not matches:
                raise ValueError(f"paths_or_globs: {item!r} matches no file")
            found.update(name(p) for p in matches)
        elif fs.isdir(path):
            matches = [p for p in fs.find(path) if p.lower().endswith(LOG_EXTENSIONS)]
            if not matches:
                raise ValueError(f"paths_or_globs: directory {item!r} holds no {', '.join(LOG_EXTENSIONS)} file")
            found.update(name(p) for p in matches)
        else:
            found.add(name(path))
    return _flights(sorted(found))


def _output_folders(output_dir: str):
    """The file system and root of ``output_dir``, with its ``logs/`` and ``failed/`` folders made."""
    import fsspec

    out_fs, root = fsspec.core.url_to_fs(output_dir)
    for sub in ("logs", "failed"):
        out_fs.makedirs(f"{root}/{sub}", exist_ok=True)
    return out_fs, root


def _inside(path: str, directory: str, directory_is_real: bool = False) -> bool:
    """``path`` is ``directory`` or lies in it, symlinks resolved (``directory_is_real``: it already is)."""
    path = os.path.realpath(path)
    directory = directory if directory_is_real else os.path.realpath(directory)
    return path == directory or path.startswith(directory.rstrip(os.sep) + os.sep)


def check_output_apart(paths_or_globs: Union[str, Sequence[str]], logs: Sequence[str], output_dir: str) -> None:
    """Refuse an output directory that holds a log or lies inside a directory of logs (symlinks resolved).

    Its ``summary.csv``, ``logs/`` and ``csv/`` would otherwise replace a file of the same name among the
    logs, and the next run would read the fleet's own outputs as logs.

    Raises
    ------
    ValueError
        Naming ``output_dir`` and the log or directory it clashes with.
    """
    if _is_url(output_dir):
        return
    if isinstance(paths_or_globs, (str, os.PathLike)):
        paths_or_globs = [paths_or_globs]
    for item in map(os.fspath, paths_or_globs):
        if not _is_url(item) and os.path.isdir(item) and _inside(output_dir, item):
            raise ValueError(f"output_dir {output_dir!r} is inside the log directory {item!r}: the fleet would "
                             "read its own outputs as logs; choose a directory outside it")
    real_output = os.path.realpath(output_dir)  # once, not once per log (240 logs: 5.2 → 2.9 ms of CPU)
    for log in logs:
        if not _is_url(log) and _inside(log, real_output, directory_is_real=True):
            raise ValueError(f"output_dir {output_dir!r} holds the log {log!r}: the fleet's outputs could "
                             "replace it; choose a directory that holds no log")


def _flights(paths: List[str]) -> List[str]:
    """``paths`` with one path per flight: the IMU and flight-info files of a CATS set whose baro file is in the
    list are dropped (the reader opens them with it), so a flight is one row, never three."""
    from .logs import cats

    baro_sets = set()
    for path in paths:
        split = cats._split_name(path)
        if split is not None and split[2] == "baro":
            baro_sets.add((split[0], split[1].lower()))
    kept = []
    for path in paths:
        split = cats._split_name(path)
        if split is not None and split[2] != "baro" and (split[0], split[1].lower()) in baro_sets:
            continue
        kept.append(path)
    return kept


def log_id(path: str) -> str:
    """The id of a log in the outputs: its basename and 8 hex digits of the SHA-1 of its full path or URL."""
    base = os.path.basename(path.rstrip("/")) or "log"
    safe = "".join(ch if ch.isalnum() or ch in "._-" else "_" for ch in base)
    return f"{safe}-{hashlib.sha1(path.encode()).hexdigest()[:8]}"


def settings_hash(estimator: str, settings: Any, csv_options: Optional[Dict[str, Any]] = None) -> str:
    """16 hex digits identifying what a run computes: estimator, exact settings, CSV options,
    package version and output format version. Equal hashes ⇒ equal outputs for the same log."""
    key = {"format": FORMAT_VERSION, "version": __version__, "settings": settings_key(estimator, settings),
           "csv_options": _jsonable(dict(csv_options or {}))}
    return hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16]


def _fingerprint(fs, path: str) -> Tuple[str, int]:
    """(unique key of the file's current version, size in bytes)."""
    info = fs.info(path)
    return fs.ukey(path), int(info.get("size") or 0)


# ----------------------------------------------------------------------------
# Atomic writes


def _atomic_write(fs, path: str, payload: bytes) -> None:
    """Write ``payload`` so that ``path`` is either absent, its old content, or all of ``payload``."""
    if _is_local(fs):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with atomic_output(path) as temporary, open(temporary, "wb") as handle:
            handle.write(payload)
            handle.flush()
            os.fsync(handle.fileno())
    else:
        fs.pipe_file(path, payload)  # an object store publishes an object only once it is complete


def _write_if_changed(fs, path: str, payload: bytes) -> bool:
    """Atomically write ``payload`` unless ``path`` already holds exactly it; True if written."""
    if fs.exists(path) and fs.cat_file(path) == payload:
        return False
    _atomic_write(fs, path, payload)
    return True


class _Publisher:
    r"""Publishes the output files of one Dask task, each atomically and durably, overlapping the disk's waits.

    On a local file system the task's thread writes each file to a temporary name
    (:func:`fusion_altitude.outputs.write_temporary`); one background thread then ``fsync``\ s it, renames it
    into place and removes the file it supersedes, if any, while the next log is read and run (an ``fsync``
    waits about 4 ms for the disk and costs 0.2 ms of CPU). :meth:`close` waits for every file and
    ``fsync``\ s each directory renamed into once, so when a task returns its results, every file it wrote is
    complete and durable, name included (a task on a Dask worker waits for that after leaving its slot to the
    next task: :func:`_leave_worker_slot`). A worker killed before that leaves the complete old file or none
    (and temporary files, which :func:`run_many` removes at the end); Dask reruns the task, which reuses every
    output already in place. Object stores get each file as one object, at once.
    """

    def __init__(self) -> None:
        self._pending: List[Future] = []
        self._paths: set = set()  # of the files not yet known to be in place
        self._directories: set = set()

    def write(self, fs, path: str, payload: bytes, supersedes: Optional[str] = None) -> None:
        """Publish ``payload`` at ``path``; then remove ``supersedes`` (a file ``path`` replaces) if it exists."""
        if not _is_local(fs):
            fs.pipe_file(path, payload)  # an object store publishes an object only once it is complete
            if supersedes is not None and fs.exists(supersedes):
                fs.rm_file(supersedes)
            return
        directory = os.path.dirname(os.path.abspath(path))
        os.makedirs(directory, exist_ok=True)
        descriptor, temporary = write_temporary(path, payload)
        self._pending.append(_publish_thread().submit(_publish, descriptor, temporary, path, supersedes))
        self._paths.update((path, supersedes))
        self._directories.add(directory)

    def settle(self, *paths: str) -> None:
        """Wait until the files this publisher writes or removes are in place, if any of ``paths`` is among them
        (a log met twice in one task reads back what its first run wrote)."""
        if self._paths.intersection(paths):
            for pending in self._pending:
                pending.result()
            self._paths = set()

    def close(self) -> None:
        """Wait for every file to be in place; fsync each directory renamed into; raise the first error."""
        try:
            for pending in self._pending:
                pending.result()
        finally:
            concurrent.futures.wait(self._pending)  # every file settled, even after an error
            self._pending, self._paths = [], set()
        for directory in sorted(self._directories):
            _fsync_directory(directory)
        self._directories = set()


_PUBLISH_THREAD: Dict[int, ThreadPoolExecutor] = {}


def _publish_thread() -> ThreadPoolExecutor:
    """This process's one publish thread (started on first use; a worker process keeps it between tasks)."""
    pid = os.getpid()  # a forked child starts its own
    if pid not in _PUBLISH_THREAD:
        _PUBLISH_THREAD.clear()
        _PUBLISH_THREAD[pid] = ThreadPoolExecutor(1, thread_name_prefix="fleet-publish")
    return _PUBLISH_THREAD[pid]


def _publish(descriptor: int, temporary: str, path: str, supersedes: Optional[str]) -> None:
    """Make the temporary file durable, rename it onto ``path``, remove ``supersedes`` (on the publish thread)."""
    try:
        try:
            os.fsync(descriptor)
        finally:
            os.close(descriptor)
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
    if supersedes is not None:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(supersedes)


def _fsync_directory(directory: str) -> None:
    """Make the renames into ``directory`` durable (POSIX; elsewhere a rename is as durable as the OS makes it)."""
    if os.name != "posix":
        return
    descriptor = os.open(directory, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def _is_temporary(name: str) -> bool:
    """A temporary file of an interrupted write: ``outputs.atomic_output``'s ``.NAME.XXXX.part.EXT``, or the
    ``.NAME.tmp-HEX`` of earlier versions."""
    return ".tmp-" in name or (name.startswith(".") and ".part" in name)


def _remove_leftovers(fs, root: str) -> int:
    """Remove temporary files of interrupted writes under ``root``; returns how many."""
    removed = 0
    for sub in ("logs", "csv", "failed"):
        directory = f"{root}/{sub}"
        if not fs.exists(directory):
            continue
        for path in fs.ls(directory, detail=False):
            if _is_temporary(os.path.basename(path)):
                fs.rm_file(path)
                removed += 1
    return removed


# ----------------------------------------------------------------------------
# One log (runs on a worker)


def _one_line(error: BaseException) -> str:
    text = str(error).strip().splitlines()
    return f"{type(error).__name__}: {text[0] if text else ''}".rstrip(": ")


def _gaps(times: np.ndarray) -> Tuple[int, float]:
    """(intervals longer than twice the median interval, longest interval s)."""
    if times.size < 2:
        return 0, math.nan
    steps = np.diff(times)
    return int(np.sum(steps > 2.0 * np.median(steps))), float(np.max(steps))


def _describe(data, run, columns: Dict[str, np.ndarray]) -> Dict[str, Any]:
    """Summary-row fields of a good log (see :data:`SUMMARY_FIELDS`); ``columns`` are its :func:`run_columns`."""
    time = np.asarray(data.time, dtype=float)
    baro = np.asarray(data.baro_altitude, dtype=float)
    duration = float(time[-1] - time[0]) if time.size else math.nan
    baro_time = time[np.isfinite(baro)]
    baro_span = float(baro_time[-1] - baro_time[0]) if baro_time.size > 1 else math.nan
    imu_gaps, max_dt = _gaps(time)
    baro_gaps, max_baro_interval = _gaps(baro_time)
    row = {
        "source": data.source,
        "samples": int(time.size),
        "duration_s": duration,
        "imu_rate_hz": (time.size - 1) / duration if duration > 0 else math.nan,
        "baro_samples": int(baro_time.size),
        "baro_rate_hz": (baro_time.size - 1) / baro_span if baro_span > 0 else math.nan,
        "imu_gaps": imu_gaps, "max_dt_s": max_dt, "baro_gaps": baro_gaps, "max_baro_interval_s": max_baro_interval,
        "clipped_samples": int(np.sum(data.clipped)) if data.clipped is not None else 0,
        "reference": data.reference_name if data.reference_altitude is not None else "",
        **_error_fields(run),
        "final_altitude_m": float(columns["altitude"][-1]) if time.size else math.nan,
        **_health_fields(data, run, columns["flags"]),
    }
    for name, values in columns.items():  # every bias or offset the estimator reports
        if ("bias" in name or "offset" in name) and values.size:
            row["final_accel_bias_m_s2" if name == "accel_bias" else f"final_{name}"] = float(values[-1])
    return {key: float(value) if isinstance(value, np.floating) else value for key, value in row.items()}


def _error_fields(run) -> Dict[str, Any]:
    """The error columns of a summary row against the log's own estimate, m (NaN without one)."""
    fused, raw = run.comparison(), run.baro_comparison()
    good = fused is not None and fused.count
    return {
        "mean_error_m": fused.mean if good else math.nan,
        "rms_error_m": fused.rms if good else math.nan,
        "max_abs_error_m": fused.max if good else math.nan,
        "p95_abs_error_m": fused.p95 if good else math.nan,
        "baro_rms_error_m": raw.rms if raw is not None and raw.count else math.nan,
    }


def _health_fields(data, run, flags: np.ndarray) -> Dict[str, Any]:
    """The health columns of a good log's summary row (see :data:`SUMMARY_FIELDS`); ``flags`` is its ``run -o``
    flags column, whose not-baro-aided bit is :func:`fusion_altitude.health.not_baro_aided` of the log."""
    streams = {stream.name: stream for stream in health.sensor_health(data)}
    baro = streams["baro"]
    time = np.asarray(data.time, dtype=float)
    unaided = (flags & health.FLAG_BITS["not_baro_aided"]) != 0
    return {
        "baro_first_s": baro.first, "baro_last_s": baro.last, "baro_longest_outage_s": baro.longest_outage,
        "stopped_streams": ";".join(s.name for s in health.stopped_streams(streams.values())),
        "dead_channels": ";".join(s.name for s in streams.values() if s.dead),
        "gps_samples": streams["gps"].samples if "gps" in streams else 0,
        "rangefinder_samples": streams["rangefinder"].samples if "rangefinder" in streams else 0,
        "estimator_gaps": int(run.gap_count) if getattr(run, "gap_count", None) is not None else -1,
        "not_baro_aided_s": float(np.sum(np.diff(time, prepend=time[0])[unaided])),
        "truncated": bool(getattr(data, "truncated", False)),
        "reader_warnings": len(getattr(data, "warnings", [])),
        "warnings": " | ".join(" ".join(str(w).split()) for w in getattr(data, "warnings", [])),
    }


def _estimates_table(identifier: str, columns: List[Tuple[str, np.ndarray]], metadata: Dict[str, Any]):
    import pyarrow as pa

    n = columns[0][1].size if columns else 0
    ids = pa.DictionaryArray.from_arrays(pa.array(np.zeros(n, np.int32)), pa.array([identifier]))
    table = pa.table({"log_id": ids, **{name: pa.array(values) for name, values in columns}})
    return table.replace_schema_metadata({_METADATA_KEY: json.dumps(metadata).encode()})


def _estimates_parquet_options(table) -> Dict[str, Any]:
    """Writer options of a per-log estimates file: the float columns byte-stream-split, without a dictionary.

    A dictionary of float samples (pyarrow's default) cost 80 % of the write (9.0 → 1.8 ms of CPU for the
    245 s Hedy log's 24,564 rows) and made the file larger (1.19 → 0.83 MB, snappy either way).
    Statistics (min/max per row group) are kept for ``log_id`` and ``time``, the columns a reader filters on.
    """
    import pyarrow as pa

    floats = [column.name for column in table.schema if pa.types.is_floating(column.type)]
    return {"use_dictionary": [name for name in table.column_names if name not in floats],
            "column_encoding": {name: "BYTE_STREAM_SPLIT" for name in floats},
            "write_statistics": [name for name in ("log_id", "time") if name in table.column_names]}


def _parquet_bytes(table, **options) -> bytes:
    """``table`` as the bytes of a Parquet file; ``options`` go to ``pyarrow.parquet.write_table``."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, **options)
    return sink.getvalue().to_pybytes()


def _stored_metadata(fs, path: str) -> Optional[Dict[str, Any]]:
    """The fleet metadata of an output file, or None if it is missing or unreadable."""
    try:
        if path.endswith(".json"):
            return json.loads(fs.cat_file(path))
        import pyarrow.parquet as pq
        with fs.open(path, "rb") as handle:
            metadata = pq.read_schema(handle).metadata or {}
        return json.loads(metadata[_METADATA_KEY])
    except Exception:  # missing, truncated by a crash of another tool, not ours: recompute
        return None


def _is_local(fs) -> bool:
    return "file" in (fs.protocol if isinstance(fs.protocol, tuple) else (fs.protocol,))


@contextlib.contextmanager
def _local_copy(fs, path: str) -> Iterator[str]:
    """A local file path for ``path``: itself when local, else a temporary copy (same suffix)."""
    if _is_local(fs):
        yield path
        return
    suffix = os.path.splitext(path)[1]
    with tempfile.TemporaryDirectory(prefix="fusion-altitude-fleet-") as directory:
        local = os.path.join(directory, f"log{suffix}")
        fs.get_file(path, local)
        yield local


class _Job(NamedTuple):
    url: str
    log_id: str
    output_dir: str
    estimator: str
    settings: Any
    csv_options: Dict[str, Any]
    settings_hash: str
    write_csv: bool
    retry_failed: bool


class _Outputs(NamedTuple):
    """Where one log's outputs go: the output file system and the three paths of :func:`run_many`'s layout."""

    fs: Any
    parquet: str
    failed: str
    csv: str

    @classmethod
    def of(cls, job: _Job) -> "_Outputs":
        import fsspec

        out_fs, root = fsspec.core.url_to_fs(job.output_dir)
        return cls(out_fs, f"{root}/logs/{job.log_id}.parquet", f"{root}/failed/{job.log_id}.json",
                   f"{root}/csv/{job.log_id}.csv")


def _process_batch(jobs: Sequence[_Job]) -> List[Dict[str, Any]]:
    """Run consecutive logs (one Dask task): the :func:`_process_log` result of each, in order, returned once
    every file they wrote is in place and durable (:class:`_Publisher`). The wait for the last files' disk
    happens after the task has handed its worker slot to the next task (:func:`_leave_worker_slot`)."""
    publisher = _Publisher()
    try:
        return [_process_log(job, publisher) for job in jobs]
    finally:
        _leave_worker_slot()
        publisher.close()


def _leave_worker_slot() -> None:
    """In a Dask worker's task thread, hand the worker's slot to its next task (:func:`distributed.secede`).

    What is left of a task after its last log is waiting: for the ``fsync`` of the last file and of the
    directories (an ``fsync`` waits about 4 ms for the development machine's disk). Holding the slot meanwhile
    left the worker's core idle. After seceding, the worker starts its next task at once, and this thread only
    waits and then returns the results as before (a task still reports once its files are durable). The wait
    holding the slot fell from 0.46–0.48 to 0.26–0.28 ms a log with one worker, and from 1.42–1.45 to
    0.72–0.78 ms with two (``benchmarks/fleet_bench.py --copies 60``'s slot table, at load 8; what is left is
    the ``secede`` call, which starts the pool's next thread). Elsewhere (a plain call, ``client.run``) it does
    nothing.
    """
    try:
        from distributed import secede
        from distributed.threadpoolexecutor import thread_state as pool_thread
        from distributed.worker import thread_state as task_thread
    except ImportError:
        return
    if getattr(task_thread, "key", None) is not None and getattr(pool_thread, "executor", None) is not None:
        secede()  # a task on a thread of the worker's pool (not a client.run call, not a plain call)


def _process_log(job: _Job, publisher: Optional[_Publisher] = None) -> Dict[str, Any]:
    """Run one log. Returns {"row": summary row, "action": computed/reused/failed, costs}; its files go through
    ``publisher`` (default: one of its own, closed before returning).

    Never raises for a bad log: its error becomes the row's ``error``.
    """
    if publisher is None:
        own = _Publisher()
        try:
            return _process_log(job, own)
        finally:
            own.close()
    import fsspec

    outputs = _Outputs.of(job)
    row: Dict[str, Any] = {"log_id": job.log_id, "path": job.url, "status": "failed", "error": "", "source": "",
                           "estimator": job.estimator, "settings_hash": job.settings_hash, "bytes": 0}
    costs = {"read_s": 0.0, "estimate_s": 0.0, "write_s": 0.0, "cpu_s": 0.0}
    cpu_start = _time.thread_time()
    try:
        log_fs, log_path = fsspec.core.url_to_fs(job.url)
        fingerprint, row["bytes"] = _fingerprint(log_fs, log_path)
    except Exception as error:  # missing file, no access: retried next time
        row["error"] = _one_line(error)
        return {"row": row, "action": "failed", **costs}
    publisher.settle(outputs.parquet, outputs.failed)
    stored = _reusable_row(job, outputs, fingerprint)
    if stored is not None:
        return {"row": stored, "action": "reused", **costs}
    record = {"settings_hash": job.settings_hash, "fingerprint": fingerprint, "row": row}
    try:
        run, columns = _read_and_run(job, log_fs, log_path, row, costs)
    except LOG_ERRORS as error:  # the log itself is bad: record it, do not retry
        row["error"] = _one_line(error)
        publisher.write(outputs.fs, outputs.failed, json.dumps(record, indent=1).encode())
        return {"row": row, "action": "failed", **costs}
    except Exception as error:  # a problem of this machine (missing package...): report, retry next run
        row["error"] = _one_line(error)
        return {"row": row, "action": "failed", **costs}
    tick = _time.perf_counter()
    row["status"] = "ok"
    _write_outputs(job, outputs, run, columns, record, publisher)
    costs["write_s"] = _time.perf_counter() - tick
    costs["cpu_s"] = _time.thread_time() - cpu_start
    return {"row": row, "action": "computed", **costs}


def _reusable_row(job: _Job, outputs: _Outputs, fingerprint: str) -> Optional[Dict[str, Any]]:
    """The stored summary row of this version of the log with the same settings (resume), or None to compute."""
    for path, wanted in ((outputs.parquet, True), (outputs.failed, not job.retry_failed)):
        stored = _stored_metadata(outputs.fs, path) if wanted else None
        if stored and stored.get("settings_hash") == job.settings_hash and stored.get("fingerprint") == fingerprint:
            if path == outputs.parquet and job.write_csv and not outputs.fs.exists(outputs.csv):
                return None  # the CSV was asked for this time: recompute
            return stored["row"]
    return None


def _read_and_run(job: _Job, log_fs, log_path: str, row: Dict[str, Any], costs: Dict[str, float]):
    """Read and run one log, filling ``row`` (its summary) and the read and estimate times of ``costs``.

    Returns (the run, its :func:`run_columns` as a dict). Raises ValueError for a log that cannot be used,
    including one whose estimate is not finite."""
    tick = _time.perf_counter()
    with _local_copy(log_fs, log_path) as local:
        data = read_log(local, job.csv_options)
    costs["read_s"] = _time.perf_counter() - tick
    tick = _time.perf_counter()
    run = runner.run_log(data, estimator=job.estimator, settings=job.settings)
    problem = health.check_estimate(run, run.estimate.altitude, run.estimate.vertical_velocity)
    if problem is not None:  # never an "ok" row with an estimate that cannot be trusted
        raise ValueError(f"{data.source}: estimator {job.estimator}: {problem}: the estimate cannot be trusted")
    columns = dict(run_columns(run))
    row.update(_describe(data, run, columns))
    costs["estimate_s"] = _time.perf_counter() - tick
    return run, columns


def _write_outputs(job: _Job, outputs: _Outputs, run, columns: Dict[str, np.ndarray], record: Dict[str, Any],
                   publisher: _Publisher):
    """Write a good log's estimates (Parquet, and the ``run -o`` CSV when asked) and drop its old failure record
    (it failed with other settings or an older file) once the Parquet file is in place."""
    if job.write_csv:
        _write_run_csv(outputs.fs, outputs.csv, run)
    table = _estimates_table(job.log_id, list(columns.items()), record)
    publisher.write(outputs.fs, outputs.parquet, _parquet_bytes(table, **_estimates_parquet_options(table)),
                    supersedes=outputs.failed)


def _write_run_csv(fs, path: str, run) -> None:
    """The ``fusion-altitude run -o`` CSV of ``run`` at ``path``, atomically."""
    if _is_local(fs):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_csv(run, path)  # through outputs.atomic_output: a temporary file renamed into place
        return
    with tempfile.TemporaryDirectory() as directory:
        write_csv(run, os.path.join(directory, "run.csv"))
        with open(os.path.join(directory, "run.csv"), "rb") as handle:
            _atomic_write(fs, path, handle.read())


# ----------------------------------------------------------------------------
# Clients


@contextlib.contextmanager
def open_client(client: Any = None, workers: Optional[int] = None, threads_per_worker: int = 1,
                processes: bool = True, **cluster_options) -> Iterator[Any]:
    """A Dask client: ``client`` itself (a ``Client``), one connected to a scheduler address
    (``"tcp://HOST:8786"``), or, with None, a ``LocalCluster`` of ``workers`` processes (default: one
    per core) closed on exit. ``cluster_options`` go to ``LocalCluster``.

    The local cluster runs with :data:`LOCAL_CLUSTER_CONFIG` (no ``MALLOC_TRIM_THRESHOLD_`` in the workers'
    environment unless this process's sets it, no statistical profiler, slower monitors), on top of the
    Dask configuration in force.
    """
    require_fleet_packages()
    import dask
    from distributed import Client, LocalCluster

    if client is not None and not isinstance(client, str):
        yield client
        return
    if isinstance(client, str):
        with Client(client) as connected:
            yield connected
        return
    _check_workers(workers)
    options = {"dashboard_address": _dashboard_address(), "silence_logs": 40}
    options.update(cluster_options)
    with dask.config.set(LOCAL_CLUSTER_CONFIG), \
            LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=threads_per_worker,
                         processes=processes, **options) as cluster, Client(cluster) as local:
        yield local


#: Dask configuration of the local cluster :func:`open_client` starts (the CPU figures: ``docs/fleet.md``).
#:
#: - No ``MALLOC_TRIM_THRESHOLD_`` in the workers' environment (None removes Dask's default of 65536): with
#:   it, glibc's malloc maps and unmaps every array over 128 kB afresh, and a fleet log cost about twice the
#:   CPU (the bench's logs in one process: 7.3 → 14.2 ms a log); without it, a worker keeps freed memory
#:   for the next log instead of returning it to the system at once.
#: - No statistical profiler in the workers (it samples every thread's stack every 10 ms, for the
#:   dashboard's profile page), the event loop's responsiveness tick every 1 s instead of 20 ms, the
#:   system monitor every 5 s instead of 0.5 s and the memory monitor every 1 s instead of 0.1 s: an idle
#:   2-worker cluster used 58 ms of CPU a second in its workers and 40 ms in the client's process
#:   (scheduler, nannies), 6 and 8 ms with these.
LOCAL_CLUSTER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                        "distributed.worker.profile.enabled": False,
                        "distributed.admin.tick.interval": "1s",
                        "distributed.admin.system-monitor.interval": "5s",
                        "distributed.worker.memory.monitor-interval": "1s"}


def _check_workers(workers: Optional[int]) -> None:
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers must be a positive integer, got {workers!r}")


def _dashboard_address() -> str:
    """Dask's usual dashboard port 8787 where bokeh is installed and the port is free; otherwise a free port
    (``:0``: no warning about a busy 8787 from parallel clusters; the CLI prints the link it got)."""
    if not _has_dashboard():
        return ":0"
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        try:
            probe.bind(("", 8787))
        except OSError:
            return ":0"
    return ":8787"


def _has_dashboard() -> bool:
    try:
        import bokeh  # noqa: F401
    except ImportError:
        return False
    return True


def dashboard_link(client: Any) -> Optional[str]:
    """The dashboard URL of a client's cluster, or None when no dashboard is up (the dashboard
    needs bokeh; its presence is judged on this machine)."""
    try:
        info = client.scheduler_info()
        return client.dashboard_link if info.get("services", {}).get("dashboard") and _has_dashboard() else None
    except Exception:
        return None


# ----------------------------------------------------------------------------
# run_many


@dataclass
class FleetRun:
    """What :func:`run_many` returns.

    Attributes
    ----------
    summary : pyarrow.Table
        One row per log (:data:`SUMMARY_FIELDS`, then any further final biases), in path order.
    output_dir : str
        Where the outputs are.
    settings_hash : str
        Hash of what was computed (:func:`settings_hash`).
    computed, reused, failed : list of str
        Log ids computed now, skipped because their outputs matched, and failed
        (now or before).
    costs : pyarrow.Table
        Per log of this run: log_id, action, bytes, read_s, estimate_s, write_s
        (wall-clock s on its worker; write_s up to the file's hand-over to the
        publish thread, whose ``fsync`` and rename overlap the next log) and cpu_s
        (CPU time of the task's thread, s, computed logs only); 0 for reused logs.
    """

    summary: Any
    output_dir: str
    settings_hash: str
    computed: List[str] = field(default_factory=list)
    reused: List[str] = field(default_factory=list)
    failed: List[str] = field(default_factory=list)
    costs: Any = None


def _summary_table(rows: List[Dict[str, Any]]):
    import pyarrow as pa

    extra = sorted({key for row in rows for key in row} - {name for name, _, _ in SUMMARY_FIELDS})
    fields = [pa.field(name, getattr(pa, kind)()) for name, kind, _ in SUMMARY_FIELDS]
    fields += [pa.field(name, pa.float64()) for name in extra]
    schema = pa.schema(fields)
    return pa.Table.from_pylist([{name: row.get(name) for name in schema.names} for row in rows], schema=schema)


def _csv_bytes(table) -> bytes:
    import pyarrow as pa
    import pyarrow.csv as pcsv

    sink = pa.BufferOutputStream()
    pcsv.write_csv(table, sink)
    return sink.getvalue().to_pybytes()


def run_many(paths_or_globs: Union[str, Sequence[str]], estimator: str = "observer", settings: Any = None,
             client: Any = None, output_dir: str = "fleet-out", csv_options: Optional[Dict[str, Any]] = None,
             workers: Optional[int] = None, write_csv: bool = False, retry_failed: bool = False,
             progress: bool = False, on_result: Optional[Callable[[Dict[str, Any]], None]] = None) -> FleetRun:
    """Run an estimator over many logs on Dask, several logs per task (:func:`_batches`).

    Parameters
    ----------
    paths_or_globs : str or sequence of str
        Log files, directories, globs or fsspec URLs (:func:`expand_paths`).
    estimator : str
        Estimator to run (``"observer"``; more where ``fusion_altitude.runner`` offers them).
    settings : settings object or str, optional
        The estimator's settings, or an observer preset name; default its default.
    client : distributed.Client or str, optional
        An existing client, or a scheduler address (``"tcp://HOST:8786"``). Default:
        a ``LocalCluster`` with ``workers`` processes (one per core), closed afterwards.
    output_dir : str
        Output directory or fsspec URL (see the module documentation).
    csv_options : dict, optional
        ``load_log`` keyword arguments for CSV logs (``time_column``, ``accel_column``,
        ``baro_column`` or ``pressure_column``, ...); ignored by .ulg/.bin.
    workers : int, optional
        Size of the local cluster when ``client`` is None.
    write_csv : bool
        Also write each log's ``fusion-altitude run -o`` CSV to ``OUT/csv/``.
    retry_failed : bool
        Recompute logs recorded as failed with the same settings.
    progress : bool
        Draw Dask's text progress bar (on stdout, erased when done).
    on_result : callable(dict), optional
        Called on the client as each log finishes, with its summary row and ``action``.

    Returns
    -------
    FleetRun

    Raises
    ------
    ValueError, TypeError
        Bad estimator, settings or workers, or a glob matching nothing (before any work).
    """
    require_fleet_packages()
    _check_workers(workers)
    jobs = _jobs(paths_or_globs, estimator, settings, output_dir, csv_options, write_csv, retry_failed)
    out_fs, root = _output_folders(output_dir)
    with open_client(client, workers) as dask_client:
        results = _run_jobs(dask_client, jobs, progress, on_result)
    _remove_leftovers(out_fs, root)
    ids = [job.log_id for job in jobs]
    table = _summary_table([results[i]["row"] for i in ids])
    _write_if_changed(out_fs, f"{root}/summary.parquet", _parquet_bytes(table))
    _write_if_changed(out_fs, f"{root}/summary.csv", _csv_bytes(table))
    return FleetRun(table, output_dir, jobs[0].settings_hash,
                    computed=[i for i in ids if results[i]["action"] == "computed"],
                    reused=[i for i in ids if results[i]["action"] == "reused" and results[i]["row"]["status"] == "ok"],
                    failed=[i for i in ids if results[i]["row"]["status"] != "ok"], costs=_costs_table(ids, results))


def _jobs(paths_or_globs, estimator: str, settings: Any, output_dir: str, csv_options: Optional[Dict[str, Any]],
          write_csv: bool, retry_failed: bool) -> List[_Job]:
    """One :class:`_Job` per log of :func:`run_many`, in path order; ValueError or TypeError (before any work)
    for no log, an output directory among the logs, or a bad estimator or settings."""
    urls = expand_paths(paths_or_globs)
    if not urls:
        raise ValueError("paths_or_globs is empty")
    check_output_apart(paths_or_globs, urls, output_dir)
    resolved = resolve_settings(estimator, settings)
    csv_options = dict(csv_options or {})
    digest = settings_hash(estimator, resolved, csv_options)
    return [_Job(url, log_id(url), output_dir, estimator, resolved, csv_options, digest, write_csv, retry_failed)
            for url in urls]


#: The most logs one Dask task runs (see :func:`_batches`).
BATCH_LOGS = 64

#: The fewest logs a Dask task runs while the fleet has that many per worker left (see :func:`_batches`).
MIN_BATCH_LOGS = 8


def _batches(jobs: Sequence[_Job], workers: int) -> List[List[_Job]]:
    """Consecutive logs grouped into Dask tasks, the first tasks long and the last ones short.

    Each batch takes 1/(4·workers) of the logs not yet given out ("guided" scheduling), at most
    :data:`BATCH_LOGS` and at least :data:`MIN_BATCH_LOGS` (fewer only when the logs left, shared out
    over the workers, are fewer). Dask's cost per task is paid for a few tasks instead of every log — on
    the 2-CPU development machine, under load, about 3–4 ms of CPU in the client's process (client and
    scheduler) and 3 ms in the worker per task, against 7–10 ms of work in a bench log —, and the
    short tasks at the end keep the workers finishing together (at most a :data:`MIN_BATCH_LOGS` task
    apart).
    """
    batches: List[List[_Job]] = []
    start = 0
    while start < len(jobs):
        left = len(jobs) - start
        floor = min(MIN_BATCH_LOGS, -(-left // workers))  # a worker's share of the logs left, rounded up
        size = min(BATCH_LOGS, max(floor, left // (4 * workers)))
        batches.append(list(jobs[start:start + size]))
        start += size
    return batches


def _run_jobs(dask_client, jobs: Sequence[_Job], progress: bool,
              on_result: Optional[Callable[[Dict[str, Any]], None]]) -> Dict[str, Dict[str, Any]]:
    """Run the jobs on the cluster in batches; each log's :func:`_process_log` result by log id."""
    from distributed import as_completed

    batches = _batches(jobs, max(1, sum(dask_client.nthreads().values())))
    # keys unique per call: a finished run's keys may linger on the scheduler, and a reused key returns
    # the old result instead of running the task
    token = uuid.uuid4().hex[:8]
    futures = dask_client.map(_process_batch, batches, key=[f"fleet-run-{token}-{k}" for k in range(len(batches))],
                              pure=False)
    if progress:
        from distributed import progress as dask_progress
        dask_progress(futures)
    results: Dict[str, Dict[str, Any]] = {}
    for future in as_completed(futures):
        for result in future.result():
            results[result["row"]["log_id"]] = result
            if on_result is not None:
                on_result({**result["row"], "action": result["action"]})
    return results


def _costs_table(ids: Sequence[str], results: Dict[str, Dict[str, Any]]):
    """:attr:`FleetRun.costs`: per log, its action, size and the times of its task."""
    import pyarrow as pa

    return pa.Table.from_pylist([{"log_id": i, "action": results[i]["action"], "bytes": results[i]["row"]["bytes"],
                                  "read_s": results[i]["read_s"], "estimate_s": results[i]["estimate_s"],
                                  "write_s": results[i]["write_s"], "cpu_s": results[i]["cpu_s"]} for i in ids])


# ----------------------------------------------------------------------------
# summary


def summary(output_dir: str):
    """The summary table (``pyarrow.Table``) of a :func:`run_many` output directory."""
    require_fleet_packages()
    import fsspec
    import pyarrow.parquet as pq

    out_fs, root = fsspec.core.url_to_fs(output_dir)
    path = f"{root}/summary.parquet"
    if not out_fs.exists(path):
        raise ValueError(f"output_dir: {output_dir!r} holds no summary.parquet (run `fleet run` first)")
    with out_fs.open(path, "rb") as handle:
        return pq.read_table(handle)


def worst_logs(table, count: int = 10) -> List[Dict[str, Any]]:
    """Rows of a summary table, worst first: failed logs, then by RMS error against the reference (m)."""
    rows = table.to_pylist()

    def badness(row):
        rms = row.get("rms_error_m")
        return (row["status"] == "ok", -(rms if rms is not None and math.isfinite(rms) else -math.inf))

    return sorted(rows, key=badness)[:count]


# ----------------------------------------------------------------------------
# fit_many


class _FitInputs(NamedTuple):
    log_id: str
    path: str
    accel: np.ndarray
    baro_altitude: np.ndarray
    dt: np.ndarray
    reference: np.ndarray
    mask: np.ndarray
    steps_per_baro: float  # grid steps per baro sample: the gains run multiplied by it, as `fit` runs them
    stability_dt: float  # s, the period tuning.fit checks stability at on this log (median dt · steps per baro)


class _FitMeta(NamedTuple):
    log_id: str
    path: str
    error: str
    samples: int
    stability_dt: float


def _fit_inputs(url: str, csv_options: Dict[str, Any], skip: float) -> Union[_FitInputs, _FitMeta]:
    """Read one log for fitting (a Dask task, kept in worker memory); a _FitMeta with the error if unusable."""
    import fsspec

    identifier = log_id(url)
    try:
        fs, path = fsspec.core.url_to_fs(url)
        with _local_copy(fs, path) as local:
            data = read_log(local, csv_options)
        if data.reference_altitude is None:
            raise ValueError(f"{data.source} has no reference altitude")
        time = np.asarray(data.time, dtype=float)
        dt = tuning.sample_periods(time)
        steps = tuning.steps_per_baro(data.baro_altitude)
        inputs = _FitInputs(identifier, url, data.vertical_acceleration, data.baro_altitude, dt,
                            data.reference_altitude, tuning.without_gap_transients(dt, tuning.training_mask(time, skip)), steps,
                            tuning.stability_period(dt, steps))
        tuning.sweep(inputs.accel, inputs.baro_altitude, inputs.dt, [AltitudeSettings()], reference=inputs.reference,
                     mask=inputs.mask, threads=1)  # checks the inputs once, naming the problem (a worker is one core)
        return inputs
    except Exception as error:
        return _FitMeta(identifier, url, _one_line(error), 0, math.nan)


def _fit_meta(inputs: Union[_FitInputs, _FitMeta]) -> _FitMeta:
    if isinstance(inputs, _FitMeta):
        return inputs
    return _FitMeta(inputs.log_id, inputs.path, "", int(np.asarray(inputs.dt).size), inputs.stability_dt)


def _sweep_sums(inputs: _FitInputs, gains: np.ndarray) -> Tuple[int, np.ndarray]:
    """(metric samples, float32 sums of squared altitude − reference per setting, m²) of one log, for designed
    gains (K, 3): tuning.fit's own metric (tuning.score: the gains times the log's steps per baro sample)."""
    result = tuning.score(inputs.accel, inputs.baro_altitude, inputs.dt, inputs.reference, inputs.mask, gains,
                          inputs.steps_per_baro, threads=1)
    return result.metric_samples, result.sum_squared_error


def _pooled_rms(parts: Sequence[Tuple[int, np.ndarray]]) -> np.ndarray:
    """RMS over all logs' samples from per-log sums, summed in log order in float64.

    With one log this is exactly ``SweepResult.rms_error``: sqrt(float64(sum) / count)."""
    count = sum(samples for samples, _ in parts)
    total = np.zeros_like(parts[0][1], dtype=np.float64)
    for _, sums in parts:
        total = total + sums.astype(np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.sqrt(total / float(count))


#: FleetFit's fields: tuning.FitResult's, then the fleet's own.
_FLEET_FIT_FIELDS = [(name, tuning.FitResult.__annotations__[name]) for name in tuning.FitResult._fields] + [
    ("logs", List[str]), ("excluded", List[Tuple[str, str]]), ("metric_samples", int),
    ("holdout", List[Dict[str, Any]]), ("holdout_rms_error", float), ("holdout_default_rms_error", float)]


class FleetFit(NamedTuple("FleetFit", _FLEET_FIT_FIELDS)):  # type: ignore[misc]  (fields computed)
    """What :func:`fit_many` returns.

    Attributes
    ----------
    settings : AltitudeSettings
        The gains that minimise the RMS altitude error over all training logs pooled.
    omega, zeta, omega_b : float
        Their bandwidth parameters (rad/s, 1, rad/s).
    rms_error, default_rms_error : float
        Pooled RMS of altitude − reference on the training logs, m, for the fit
        and the default (VTOL) gains.
    landscape : numpy.ndarray
        Every evaluated candidate, best first, as :attr:`fusion_altitude.tuning.FitResult.landscape`.
    logs : list of str
        Ids of the training logs used.
    excluded : list of (str, str)
        (path, one-line reason) of logs left out (unreadable, no reference).
    metric_samples : int
        Samples in the training metric.
    holdout : list of dict
        Per held-out log: log_id, path, samples, rms_error_m (fit), default_rms_error_m, error.
    holdout_rms_error, holdout_default_rms_error : float
        Pooled RMS over the held-out logs, m, for the fit and the default gains (NaN without any).
    """

    __slots__ = ()


def fit_many(paths_or_globs: Union[str, Sequence[str]], holdout: Union[None, str, Sequence[str]] = None,
             client: Any = None, workers: Optional[int] = None, csv_options: Optional[Dict[str, Any]] = None,
             skip: float = 5.0, omega_range: Tuple[float, float] = (0.05, 20.0),
             zetas: Sequence[float] = (0.5, 0.7, 1.0, 1.4),
             bias_ratios: Sequence[float] = (0.0, 0.05, 0.1, 0.2, 0.35), refinements: int = 3) -> FleetFit:
    """One set of observer gains for many logs (a vehicle type), scored on held-out logs.

    Each log is read once by a worker and kept there. The search is
    :func:`fusion_altitude.tuning.search`, the one :func:`fusion_altitude.tuning.fit`
    runs (a coarse grid over ω, ζ, ω_b = ratio·ω, then ``refinements`` finer
    grids around the best point); a candidate is kept when it is stable at
    every log's own check period (:func:`fusion_altitude.tuning.stability_period`:
    the log's median dt times its grid steps per baro sample; the largest over
    the logs). For every round each worker scores all candidate gains on its
    logs with :func:`fusion_altitude.tuning.score` (fit's metric: the gains
    multiplied by the log's steps per baro sample, as ``run`` and ``fit`` run
    them) and returns only the per-candidate sum of squared altitude −
    reference (float32, as the sweep kernel accumulates it) and the sample
    count; the client adds them in log order in float64 and ranks by pooled
    RMS. The result does not depend on the cluster; with one log it is exactly
    the result of ``fusion-altitude fit LOG --skip SKIP`` (``tuning.fit`` with
    the log's steps per baro sample and :func:`fusion_altitude.tuning.training_mask`).

    Parameters
    ----------
    paths_or_globs : str or sequence of str
        Training logs (with a reference altitude: the autopilot's estimate of a
        .ulg/.bin, or ``csv_options["reference_column"]``).
    holdout : str or sequence of str, optional
        Held-out logs to score the fit on (not used to fit).
    client, workers
        As for :func:`run_many`.
    csv_options : dict, optional
        ``load_log`` keyword arguments for CSV logs.
    skip : float
        Seconds at the start of each log left out of the metric (start-up transient), s: the
        samples after ``time[0] + skip`` count, as ``fusion-altitude fit --skip``.
    omega_range, zetas, bias_ratios, refinements
        The search grid, as :func:`fusion_altitude.tuning.fit`.

    Returns
    -------
    FleetFit

    Raises
    ------
    ValueError
        No usable training log, a glob matching nothing, a bad search range.
    """
    require_fleet_packages()
    _check_workers(workers)
    train_urls, holdout_urls = _fit_paths(paths_or_globs, holdout)
    csv_options = dict(csv_options or {})
    if not math.isfinite(skip) or skip < 0:
        raise ValueError(f"skip must be finite and >= 0 (s), got {skip!r}")
    with open_client(client, workers) as dask_client:
        training = _Training(dask_client, train_urls, csv_options, skip)
        fit = training.fit(omega_range, zetas, bias_ratios, refinements)
        held, pooled = _score_holdout(dask_client, holdout_urls, csv_options, skip, fit.settings)
    return FleetFit(*fit, training.log_ids, training.excluded, training.metric_samples, held, *pooled)


def _fit_paths(paths_or_globs, holdout) -> Tuple[List[str], List[str]]:
    """The training and held-out log paths of :func:`fit_many`; ValueError when there is no training log or
    a log is in both."""
    train_urls = expand_paths(paths_or_globs)
    if not train_urls:
        raise ValueError("paths_or_globs is empty")
    holdout_urls = expand_paths(holdout) if holdout else []
    overlap = sorted(set(train_urls) & set(holdout_urls))
    if overlap:
        raise ValueError(f"holdout: {overlap[0]!r} is also a training log")
    return train_urls, holdout_urls


class _Training:
    """The training logs of a fleet fit, each read once by a worker and kept in its memory, and the search.

    For every round of :func:`fusion_altitude.tuning.search` each worker scores all candidate gains on its logs
    (:func:`_sweep_sums`) and returns only per-candidate sums and the sample count; the client adds them in log
    order in float64 (:func:`_pooled_rms`), so the result does not depend on the cluster.
    """

    def __init__(self, dask_client, urls: Sequence[str], csv_options: Dict[str, Any], skip: float):
        self.client = dask_client
        inputs = dask_client.map(_fit_inputs, urls, csv_options=csv_options, skip=skip, pure=False)
        metas = dask_client.gather(dask_client.map(_fit_meta, inputs, pure=False))
        self.inputs = [future for future, meta in zip(inputs, metas) if not meta.error]
        self.excluded = [(meta.path, meta.error) for meta in metas if meta.error]
        usable = [meta for meta in metas if not meta.error]
        self.log_ids = [meta.log_id for meta in usable]
        if not usable:
            raise ValueError("paths_or_globs: no usable training log"
                             + (f"; first: {self.excluded[0][0]}: {self.excluded[0][1]}" if self.excluded else ""))
        # every log's own check period (tuning.fit's: median dt · steps per baro); the gains must be stable on all
        self.dt_check = max(meta.stability_dt for meta in usable)
        self.metric_samples = 0

    def evaluate_rms(self, gains: np.ndarray) -> np.ndarray:
        """Pooled RMS of altitude − reference over all training logs, m, per row of designed gains (K, 3)."""
        parts = self.client.gather([self.client.submit(_sweep_sums, future, gains, pure=False)
                                    for future in self.inputs])
        self.metric_samples = sum(samples for samples, _ in parts)
        return _pooled_rms(parts)

    def fit(self, omega_range, zetas, bias_ratios, refinements: int) -> tuning.FitResult:
        """The best stable gains of the search, the default gains' RMS, and the landscape (best first)."""
        ranked = tuning.search(self.evaluate_rms, self.dt_check, omega_range, zetas, bias_ratios, refinements)
        default_rms = float(self.evaluate_rms(np.array([AltitudeSettings().as_tuple()], dtype=np.float64))[0])
        return tuning.fit_result(ranked, default_rms)


def _score_holdout(dask_client, urls: Sequence[str], csv_options: Dict[str, Any], skip: float,
                   fitted: AltitudeSettings) -> Tuple[List[Dict[str, Any]], List[float]]:
    """Per held-out log its row (log_id, path, samples, rms_error_m, default_rms_error_m, error), and the
    pooled RMS over them, m, of the fitted and the default gains (NaN without any)."""
    if not urls:
        return [], [math.nan, math.nan]
    gains = np.array([fitted.as_tuple(), AltitudeSettings().as_tuple()], dtype=np.float64)
    inputs = dask_client.map(_fit_inputs, urls, csv_options=csv_options, skip=skip, pure=False)
    metas = dask_client.gather(dask_client.map(_fit_meta, inputs, pure=False))
    parts = dask_client.gather([dask_client.submit(_sweep_sums, future, gains, pure=False)
                                if not meta.error else None for future, meta in zip(inputs, metas)])
    held = []
    for meta, part in zip(metas, parts):
        rms = _pooled_rms([part]) if part is not None else (math.nan, math.nan)
        held.append({"log_id": meta.log_id, "path": meta.path, "samples": part[0] if part else 0,
                     "rms_error_m": float(rms[0]), "default_rms_error_m": float(rms[1]), "error": meta.error})
    good = [part for part in parts if part is not None]
    return held, ([float(value) for value in _pooled_rms(good)] if good else [math.nan, math.nan])
