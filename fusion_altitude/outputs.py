"""Writing results: files replaced atomically (a crash leaves the old file), devices and FIFOs written in place,
and a run of :func:`fusion_altitude.runner.run_log` as CSV or Parquet, one row per grid step at full precision.

A bottom layer (numpy and the standard library only): the simulators, the plots, the runner and the CLI write
through it.
"""

from __future__ import annotations

import contextlib
import os
import signal
import stat
import tempfile
from typing import TYPE_CHECKING, Callable, Iterator, List, Optional, Tuple

import numpy as np

from .health import row_flags

if TYPE_CHECKING:
    from .runner import LogRun

__all__ = ["atomic_output", "is_special_output", "csv_columns", "write_csv"]


def _output_mode(path: str) -> int:
    """Permission bits for a new output ``path``: those of the file it replaces, else 0o666 less the umask."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def is_special_output(path: str) -> bool:
    """True for an output that must be opened and written in place, never replaced by a rename: an existing
    character device (``/dev/null``, ``/dev/full``, a terminal), FIFO or socket, symlinks followed
    (``/dev/stdout``)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return not stat.S_ISREG(mode) and not stat.S_ISDIR(mode)


@contextlib.contextmanager
def atomic_output(path: str) -> Iterator[str]:
    """Yield a temporary path next to ``path`` (same extension); rename it onto ``path`` only on success.

    A crash or an exception while writing leaves ``path`` as it was and no
    temporary file behind. A device or FIFO (:func:`is_special_output`) is
    yielded as it is and written in place: a rename would replace it with a
    regular file. An ``OSError`` about the temporary file names ``path``.
    """
    if is_special_output(path):
        try:
            yield path
        except OSError as error:
            if error.filename is None:  # a write to the device failed (ENOSPC on /dev/full): name it
                raise type(error)(error.errno, error.strerror, path) from None
            raise
        return
    try:
        with _atomic_output(path) as temporary:
            try:
                yield temporary
            except OSError as error:
                if error.filename == temporary:  # name the user's path, never a temporary one
                    raise type(error)(error.errno, error.strerror, path) from None
                raise
    except OSError as error:
        if error.filename is not None and os.path.basename(str(error.filename)).startswith("."):
            if os.path.dirname(os.path.abspath(str(error.filename))) == os.path.dirname(os.path.abspath(path)):
                raise type(error)(error.errno, error.strerror, path) from None
        raise


@contextlib.contextmanager
def _atomic_output(path: str) -> Iterator[str]:
    directory = os.path.dirname(os.path.abspath(path))
    base, extension = os.path.splitext(os.path.basename(path))
    # SIGTERM/SIGINT are held back from the file's creation until the cleanup below is in place: a signal
    # that arrived in between (the CLI turns SIGTERM into an exception) would otherwise leave the file behind
    held = _hold_signals()
    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{base}.", suffix=f".part{extension}", dir=directory)
        try:
            try:
                # mkstemp creates the file with mode 0600: give it the mode open() would (0666 less the umask),
                # or the mode of the file it replaces
                os.fchmod(handle, _output_mode(path))
            finally:
                os.close(handle)
            _release_signals(held)  # a signal held back is delivered here, inside the cleanup
            held = None
            yield temporary
            os.replace(temporary, path)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(temporary)
            raise
    finally:
        _release_signals(held)


def write_temporary(path: str, payload: bytes) -> Tuple[int, str]:
    """Write ``payload`` to a new temporary file next to ``path``, named as :func:`atomic_output` names its
    own (``.NAME.XXXX.part.EXT``) and with the mode ``path`` would get; returns (its open descriptor, its path).

    The caller publishes it: ``os.fsync`` and ``os.close`` the descriptor, then ``os.replace`` the file onto
    ``path`` (or unlinks it). Until then ``path`` is untouched. On an error nothing is left behind.
    """
    directory = os.path.dirname(os.path.abspath(path))
    base, extension = os.path.splitext(os.path.basename(path))
    handle, temporary = tempfile.mkstemp(prefix=f".{base}.", suffix=f".part{extension}", dir=directory)
    try:
        os.fchmod(handle, _output_mode(path))
        view = memoryview(payload)
        while view:
            view = view[os.write(handle, view):]
    except BaseException:
        os.close(handle)
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
    return handle, temporary


def _hold_signals():
    """Block SIGTERM and SIGINT for this thread (POSIX); the previous mask, or None where not possible."""
    if not hasattr(signal, "pthread_sigmask"):
        return None
    return signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM, signal.SIGINT})


def _release_signals(previous) -> None:
    """Restore the signal mask :func:`_hold_signals` returned (pending signals are then delivered)."""
    if previous is not None:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def csv_columns(run: LogRun) -> List[Tuple[str, np.ndarray]]:
    """The columns :func:`write_csv` writes, in order: ``time``, ``altitude``, ``vertical_velocity``, the
    estimator's other 1-D outputs, ``baro_altitude``, ``vertical_acceleration``, if present
    ``reference_altitude``, and ``flags`` (:func:`fusion_altitude.health.row_flags`: bit 1 not baro-aided, 2 the
    step before was a logging gap, 4 accelerometer clipped, 8 after the baro's last sample)."""
    columns: List[Tuple[str, np.ndarray]] = [("time", run.time)]
    estimate = run.estimate
    names = ["altitude", "vertical_velocity"] + [n for n in estimate._fields if n not in ("altitude", "vertical_velocity")]
    for name in names:
        values = np.asarray(getattr(estimate, name))
        if values.ndim == 1 and values.dtype.kind in "fiub" and values.size == run.time.size:
            columns.append((name, values))
    columns.append(("baro_altitude", run.baro_altitude))
    columns.append(("vertical_acceleration", run.vertical_acceleration))
    if run.reference_altitude is not None:
        columns.append(("reference_altitude", run.reference_altitude))
    columns.append(("flags", row_flags(run, run.gap_period)))
    return columns


def _format(values: np.ndarray) -> str:
    """printf format that round-trips the column: 9 significant digits for float32, the shortest
    round-trip repr for float64, a plain integer for integer and boolean columns (e.g. a flight phase)."""
    if values.dtype.kind in "iub":
        return "%d"
    return "%.9g" if values.dtype == np.float32 else "%r"


def write_csv(run: LogRun, path: str, progress: Optional[Callable[[int, int], None]] = None,
              chunk: int = 100_000) -> None:
    """Write the run per grid step at full precision, atomically (see :func:`atomic_output`).

    ``path`` ``"-"`` writes to standard output; a ``.parquet`` path writes
    the same columns as Parquet (needs pyarrow); a device or FIFO is written
    in place.

    Columns as :func:`csv_columns`: time s, altitude m, vertical_velocity m/s,
    the estimator's other outputs (observer: accel_bias m/s², baro_residual m),
    baro_altitude m, vertical_acceleration m/s², reference_altitude m and
    flags (the row's health bits, :data:`fusion_altitude.health.FLAG_BITS`).
    float64 columns (time, the log's inputs) are written as their shortest
    round-trip repr (≤ 17 significant digits) and float32 estimates with 9
    significant digits, so every value reads back bit for bit; a missing
    value is ``nan``.
    """
    columns = csv_columns(run)
    if path == "-":  # standard output
        import sys

        _write_csv_stream(columns, sys.stdout, run.time.size, progress, chunk)
        sys.stdout.flush()
        return
    if os.path.splitext(path)[1].lower() == ".parquet":
        _write_parquet(columns, path)
        if progress is not None:
            progress(run.time.size, run.time.size)
        return
    with atomic_output(path) as temporary, open(temporary, "w", newline="") as stream:
        _write_csv_stream(columns, stream, run.time.size, progress, chunk)


def _write_csv_stream(columns: List[Tuple[str, np.ndarray]], stream, n: int,
                      progress: Optional[Callable[[int, int], None]], chunk: int) -> None:
    from ._core import _csv_write  # the same bytes, formatted in C (issue 25); engine("python") selects the loop below

    fast = _csv_write.ENGINE == "c" and _csv_write.available()
    writer = _csv_write.write_csv_stream if fast else _write_csv_stream_python
    writer(columns, stream, n, progress, chunk)


def _write_csv_stream_python(columns: List[Tuple[str, np.ndarray]], stream, n: int,
                             progress: Optional[Callable[[int, int], None]], chunk: int) -> None:
    arrays = [np.asarray(values) for _, values in columns]
    arrays = [a if a.dtype in (np.float32, np.float64) or a.dtype.kind in "iub" else a.astype(np.float64)
              for a in arrays]
    row_format = ",".join(_format(a) for a in arrays) + "\n"
    stream.write(",".join(name for name, _ in columns) + "\n")
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        block = np.column_stack([a[start:stop].astype(np.float64) for a in arrays])
        stream.write((row_format * (stop - start)) % tuple(block.ravel().tolist()))
        if progress is not None:
            progress(stop, n)


def _write_parquet(columns: List[Tuple[str, np.ndarray]], path: str) -> None:
    """The same columns as a Parquet file (each in its native dtype), atomically; needs pyarrow."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.table({name: pa.array(np.asarray(values)) for name, values in columns})
    with atomic_output(path) as temporary:
        pq.write_table(table, temporary)
