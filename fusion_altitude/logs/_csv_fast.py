"""Read the numeric columns of a CSV table with pyarrow's columnar parser, or say it cannot.

:func:`read_columns` is the first try of
:func:`fusion_altitude.logs._table.numeric_columns`: pyarrow's multi-threaded
C++ CSV reader (``pyarrow.csv.read_csv``; pyarrow is in the ``[fleet]``
extra) parses the body of the table, only the columns asked for, as float64
— correctly rounded, the same bits as Python's ``float`` — with the
"no value" cells of :data:`fusion_altitude.logs._table.MISSING` as NaN.
Whenever the text is anything but plain (a row with another number of
cells, a cell pyarrow will not read as a number: spaces, ``1_000``, a cut
last line …) it returns None and the existing numpy and pure-Python passes
run, with their line-numbered errors: the fast path never decides an error
or a warning, so they stay exactly as before.

``engine("python")`` turns the fast path off (the tests compare both ways).
"""

from __future__ import annotations

import contextlib
import itertools
from typing import Iterator, List, Optional, Sequence

import numpy as np

#: Parser in use: "auto" (pyarrow when installed, else numpy) or "python" (numpy and pure Python only).
ENGINE = "auto"
ENGINES = ("auto", "python")
#: Characters of text per pyarrow call (progress granularity).
CHUNK_CHARS = 64_000_000


@contextlib.contextmanager
def engine(name: str) -> Iterator[None]:
    """Parse CSV logs with ``name`` ("auto" or "python") inside the ``with`` block."""
    global ENGINE
    if name not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)}, got {name!r}")
    previous, ENGINE = ENGINE, name
    try:
        yield
    finally:
        ENGINE = previous


def _case_variants(word: str) -> List[str]:
    """Every upper/lower-case spelling of ``word`` ("na" → na, nA, Na, NA)."""
    options = [(c.lower(), c.upper()) if c.isalpha() else (c,) for c in word]
    return sorted({"".join(p) for p in itertools.product(*options)})


def _null_values(missing: Sequence[str]) -> List[str]:
    return [spelling for word in missing for spelling in _case_variants(word)]


def _pyarrow():
    """pyarrow's csv module, or None when pyarrow is not installed."""
    try:
        import pyarrow.csv as pacsv
    except ImportError:
        return None
    return pacsv


def read_columns(body: str, columns: Sequence[int], missing: Sequence[str], progress=None) -> Optional[np.ndarray]:
    """The ``columns`` (positions) of the CSV ``body`` as float64, shape (rows, columns); None if not plain.

    Parameters
    ----------
    body : str
        The data lines (no header), ``\\n``-separated.
    columns : sequence of int
        Cell positions wanted, in output order.
    missing : sequence of str
        Cells meaning "no value" (any case) → NaN.
    progress : callable(done, total), optional
        Called after each chunk (characters of ``body``).

    Returns
    -------
    numpy.ndarray or None
        The values (blank lines skipped), or None when the fast path is off,
        pyarrow is missing, or it refuses any of the text.
    """
    if ENGINE != "auto":
        return None
    pacsv = _pyarrow()
    if pacsv is None:
        return None
    import pyarrow as pa

    names = [f"f{i}" for i in columns]
    convert = pacsv.ConvertOptions(column_types={name: pa.float64() for name in names}, include_columns=names,
                                   null_values=_null_values(missing), strings_can_be_null=True,
                                   quoted_strings_can_be_null=True)
    parse = pacsv.ParseOptions(delimiter=",", quote_char='"', newlines_in_values=False)
    total = len(body)
    parts = []
    start = 0
    while start < total:
        stop = body.find("\n", min(start + CHUNK_CHARS, total))
        stop = total if stop < 0 else stop + 1
        chunk = body[start:stop].encode("utf-8")
        read = pacsv.ReadOptions(autogenerate_column_names=True, use_threads=False,
                                 block_size=max(1 << 20, min(len(chunk) + 1, 1 << 26)))
        try:
            table = pacsv.read_csv(pa.py_buffer(chunk), read_options=read, parse_options=parse,
                                   convert_options=convert)
        except (pa.ArrowException, KeyError, ValueError, TypeError):
            return None
        part = np.empty((table.num_rows, len(names)), dtype=np.float64)
        for j, name in enumerate(names):
            part[:, j] = table.column(name).to_numpy(zero_copy_only=False)  # null → NaN
        parts.append(part)
        start = stop
        if progress is not None:
            progress(start, total)
    if not parts:
        return np.zeros((0, len(columns)))
    return parts[0] if len(parts) == 1 else np.concatenate(parts, axis=0)


def read_text_column(body: str, column: int, rows: int) -> Optional[np.ndarray]:
    """The stripped cells of column ``column`` of the first ``rows`` lines of ``body`` (object array of str).

    Only for a plain body whose first ``rows`` lines are its data rows: no
    quote character, no empty line among them, and pyarrow finding exactly
    ``rows`` rows, each with the same number of cells (else None, and the
    caller splits the lines in Python). Each distinct cell (pyarrow's dictionary encoding) is stripped with
    ``str.strip`` once, so the result is what splitting each line gives.
    """
    if ENGINE != "auto" or '"' in body or rows == 0:
        return None
    pacsv = _pyarrow()
    if pacsv is None:
        return None
    import pyarrow as pa

    name = f"f{column}"
    data = body.encode("utf-8")
    read = pacsv.ReadOptions(autogenerate_column_names=True, use_threads=False,
                             block_size=max(1 << 20, min(len(data) + 1, 1 << 30)))
    convert = pacsv.ConvertOptions(column_types={name: pa.string()}, include_columns=[name], null_values=[],
                                   strings_can_be_null=False, quoted_strings_can_be_null=False)
    parse = pacsv.ParseOptions(delimiter=",", quote_char=False, newlines_in_values=False)
    try:
        table = pacsv.read_csv(pa.py_buffer(data), read_options=read, parse_options=parse, convert_options=convert)
    except (pa.ArrowException, KeyError, ValueError, TypeError):
        return None
    if table.num_rows != rows:
        return None
    encoded = table.column(name).combine_chunks().dictionary_encode()
    stripped = np.empty(len(encoded.dictionary), dtype=object)
    stripped[:] = [cell.strip() for cell in encoded.dictionary.to_pylist()]
    return stripped[encoded.indices.to_numpy(zero_copy_only=False)]
