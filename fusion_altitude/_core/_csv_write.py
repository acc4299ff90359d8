"""Write ``run -o out.csv`` at parse speed: the same bytes as the pure-Python writer.

:func:`write_csv_stream` formats each chunk of rows in C
(:func:`fusion_altitude._core._csv_format.format_rows`, CPython's own float
formatter per value), so the text is byte for byte what
:func:`fusion_altitude.outputs._write_csv_stream_python` writes —
``repr`` (shortest round trip) for float64, ``%.9g`` for float32, ``%d`` for
integer and boolean columns — at tens of MB/s instead of about 7 MB/s.
``engine("python")`` — or an unbuilt extension — selects the old writer (kept for one release, and for
the tests and ``benchmarks/csv_bench.py`` that compare the two).
"""

from __future__ import annotations

import contextlib
from typing import Callable, Iterator, List, Optional, Tuple

import numpy as np

#: Writer in use: "c" (the extension) or "python" (the original % formatting).
ENGINE = "c"
ENGINES = ("c", "python")


@contextlib.contextmanager
def engine(name: str) -> Iterator[None]:
    """Use the CSV writer ``name`` ("c" or "python") inside the ``with`` block."""
    global ENGINE
    if name not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)}, got {name!r}")
    previous, ENGINE = ENGINE, name
    try:
        yield
    finally:
        ENGINE = previous


def available() -> bool:
    """True when the extension's formatter (``fusion_altitude._core._csv_format``) is built."""
    try:
        from ._csv_format import format_rows  # noqa: F401
    except ImportError:
        return False
    return True


def column_kinds(arrays: List[np.ndarray]) -> np.ndarray:
    """The format kind of each column (int32): 2 ``%d`` integer/boolean, 1 ``%.9g`` float32, 0 ``%r``."""
    from ._csv_format import KIND_G9, KIND_INT, KIND_REPR

    return np.array([KIND_INT if a.dtype.kind in "iub" else KIND_G9 if a.dtype == np.float32 else KIND_REPR
                     for a in arrays], dtype=np.int32)


def write_csv_stream(columns: List[Tuple[str, np.ndarray]], stream, n: int,
                     progress: Optional[Callable[[int, int], None]], chunk: int) -> None:
    """Write the header and ``n`` rows of ``columns`` (name, values) to the text ``stream``, ``chunk`` rows at a time.

    Parameters
    ----------
    columns : list of (str, numpy.ndarray)
        Column names and their values (length ≥ ``n``), as
        :func:`fusion_altitude.runner.csv_columns` returns them.
    stream : text file
        Where the text goes (``write(str)``).
    n : int
        Rows to write.
    progress : callable(done, total), optional
        Called after each chunk with rows written and ``n``.
    chunk : int
        Rows formatted per call (bounds the memory used: about 33 bytes per cell).
    """
    from ._csv_format import format_rows

    arrays = [np.asarray(values) for _, values in columns]
    arrays = [a if a.dtype in (np.float32, np.float64) or a.dtype.kind in "iub" else a.astype(np.float64)
              for a in arrays]
    kinds = column_kinds(arrays)
    stream.write(",".join(name for name, _ in columns) + "\n")
    block = np.empty((min(chunk, n), len(arrays)), dtype=np.float64)
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        rows = block[:stop - start]
        for j, values in enumerate(arrays):
            rows[:, j] = values[start:stop]
        stream.write(format_rows(rows, kinds).decode("ascii"))
        if progress is not None:
            progress(stop, n)
