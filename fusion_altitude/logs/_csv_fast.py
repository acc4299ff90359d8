"""Read the numeric and text columns of a CSV table in one columnar pass (a C scan or pyarrow), or say it cannot.

:func:`read_numbers_and_text` is the first try of
:func:`fusion_altitude.logs._table.read_columns` (and of the RRC3 reader).
A body of at most :data:`SCAN_MAX_CHARS` characters goes to the C scan of the
extension first (:func:`fusion_altitude.logs._text_decode.scan_csv` over
``_csv_scan.h``): one pass, no set-up, the numbers correctly rounded as
Python's ``float`` reads them, the text cells as distinct cells and an index
per row; it takes only a plain body (ASCII, no quote, rows of one length, cells
that are numbers or missing words) and hands anything else on. The generic CSV
reader gives it the file's bytes, read in place and never decoded
(:func:`scan_bytes`). Then
pyarrow's C++ CSV reader (``pyarrow.csv.read_csv``; pyarrow is in the
``[fleet]`` extra) parses the body of the table once, only the columns asked
for: the numeric ones as float64 — correctly rounded, the same bits as
Python's ``float`` — with the "no value" cells of
:data:`fusion_altitude.logs._table.MISSING` as NaN, the text ones as strings,
each distinct cell stripped once. Whenever the text is anything but plain (a
row with another number of cells, a cell pyarrow will not read as a number:
spaces, ``1_000``, a cut last line, a quote in a table with text columns …)
it returns None and the existing numpy and pure-Python passes run, with their
line-numbered errors: the fast path never decides an error or a warning, so
they stay exactly as before. pyarrow's native threads start with SIGTERM and
SIGINT blocked (:func:`native_threads_without_signals`).

``engine("python")`` turns the fast paths off, ``engine("pyarrow")`` the C scan
only (the tests compare the three ways).
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import re
import signal
import types
from typing import Iterator, List, Optional, Sequence, Tuple

import numpy as np

#: Parser in use: "auto" (the C scan for small bodies, then pyarrow when installed, else numpy), "pyarrow" (no
#: C scan) or "python" (numpy and pure Python only).
ENGINE = "auto"
ENGINES = ("auto", "pyarrow", "python")
#: Characters of text per pyarrow call (progress granularity).
CHUNK_CHARS = 64_000_000
#: Largest body (characters) the C scan reads first whatever its numbers. Below it pyarrow's fixed set-up (about
#: 0.2 ms a parse) is most of a read; above it pyarrow is the faster on long numbers (more than 15 significant
#: digits go to Python's own conversion in the scan: the CATS IMU file, 2.9 MB, 34 ms against pyarrow's 8 ms; the
#: 72 kB Raven export 0.12 against 0.36 ms). A larger body goes to the scan too when its first
#: :data:`SAMPLE_CHARS` characters hold no run of more than 15 digits (:func:`_short_numbers`): numbers the scan
#: reads on its exact fast path, where it is about twice pyarrow's speed (a 1 MB CSV of ``%.9g`` numbers, 24 500
#: rows: 2.75 against 5.38 ms for the whole ``load_log``). Either way the values are the same bits.
SCAN_MAX_CHARS = 262_144
#: Characters of a large body looked at by :func:`_short_numbers`.
SAMPLE_CHARS = 8192
_LONG_DIGITS = re.compile(r"[0-9]{16}")


@contextlib.contextmanager
def engine(name: str) -> Iterator[None]:
    """Parse CSV logs with ``name`` ("auto" or "python") inside the ``with`` block."""
    if name not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)}, got {name!r}")
    global ENGINE
    _OUTER_ENGINES.append(ENGINE)
    ENGINE = name
    try:
        yield
    finally:
        ENGINE = _OUTER_ENGINES.pop()


#: The engines of the enclosing ``engine`` blocks, innermost last.
_OUTER_ENGINES: List[str] = []


def text_chunks(body: str, size: int) -> Iterator[Tuple[str, int]]:
    """``body`` in pieces of about ``size`` characters that end at a line end: (piece, characters done)."""
    total, start = len(body), 0
    while start < total:
        stop = body.find("\n", min(start + size, total))
        stop = total if stop < 0 else stop + 1
        yield body[start:stop], stop
        start = stop


@contextlib.contextmanager
def native_threads_without_signals() -> Iterator[None]:
    """SIGTERM and SIGINT blocked in this thread while pyarrow starts its native threads, which inherit the
    mask: those threads must never take a process signal, or the CLI's hold on signals around creating an
    output file (runner._atomic_output, which blocks them in the main thread only) would not hold. A signal
    that arrives meanwhile is delivered when the mask is restored."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    try:
        previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM, signal.SIGINT})
    except (OSError, ValueError):
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


@functools.lru_cache(maxsize=8)
def _null_values(missing: Tuple[str, ...]) -> List[str]:
    """Every upper/lower-case spelling of each word of ``missing`` ("na" → na, nA, Na, NA)."""
    spellings = set()
    for word in missing:
        options = [(c.lower(), c.upper()) if c.isalpha() else (c,) for c in word]
        spellings.update("".join(p) for p in itertools.product(*options))
    return sorted(spellings)


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
    both = read_numbers_and_text(body, columns, (), missing, progress)
    return None if both is None else both[0]


def read_numbers_and_text(body: str, columns: Sequence[int], text: Sequence[int], missing: Sequence[str],
                          progress=None, encoded: bool = False) -> Optional[Tuple[np.ndarray, list]]:
    """The numeric ``columns`` (float64, rows × columns) and the stripped cells of the ``text`` columns (one
    object array of str each) of the CSV ``body``, in one pass; None if not plain.

    As :func:`read_columns`, and with text columns asked for, also None when ``body`` holds a quote
    character (the Python path splits such lines with :mod:`csv`): a plain body splits at every comma, as
    ``line.split(",")`` does. Each distinct text cell (pyarrow's dictionary encoding) is stripped with
    ``str.strip`` once; with ``encoded``, each text column comes as those stripped cells and the index of
    each row's cell among them (``cells[indices]`` is the column), for a reader that maps each distinct
    cell once.
    """
    if ENGINE == "python" or (text and '"' in body):
        return None
    scanned = _scan(body, columns, text, missing) if ENGINE == "auto" and (
        len(body) <= SCAN_MAX_CHARS or _short_numbers(body)) else None
    if scanned is not None:
        if progress is not None:
            progress(len(body), len(body))
        numbers, columns_text, _ = scanned
        return numbers, columns_text if encoded else [cells[indices] for cells, indices in columns_text]
    pacsv = _pyarrow()
    if pacsv is None:
        return None
    import pyarrow as pa

    parts, texts = [], [[] for _ in text]
    with native_threads_without_signals():
        for chunk, done in text_chunks(body, CHUNK_CHARS):
            table = _parse(pacsv, chunk, columns, text, missing)
            if table is None:
                return None
            part = np.empty((table.num_rows, len(columns)), dtype=np.float64)
            for j, position in enumerate(columns):
                part[:, j] = table.column(f"f{position}").to_numpy(zero_copy_only=False)  # null → NaN
            parts.append(part)
            for cells, position in zip(texts, text):
                cells += table.column(f"f{position}").chunks
            if progress is not None:
                progress(done, len(body))
    numbers = np.zeros((0, len(columns))) if not parts else parts[0] if len(parts) == 1 else np.concatenate(parts)
    columns_text = [_stripped(pa.chunked_array(cells, type=pa.string())) for cells in texts]
    return numbers, columns_text if encoded else [cells[indices] for cells, indices in columns_text]


def scan_bytes(raw: bytes, start: int, columns: Sequence[int], text: Sequence[int], missing: Sequence[str],
               progress=None) -> Optional[Tuple[np.ndarray, list, int]]:
    """:func:`read_numbers_and_text`'s C scan of a body given as the file's bytes ``raw`` from ``start`` on, read
    in place and not decoded (the scan reads ASCII only, whose bytes are its characters): the numbers, the text
    columns as (distinct cells, indices) and the body's line count (blank lines and a last line without a newline
    included: the rows when equal); None when the scan is off or the body not for it (as for text: the size rule,
    a body not plain, no row), and the caller reads the decoded body the other ways."""
    size = len(raw) - start
    if ENGINE != "auto" or not (size <= SCAN_MAX_CHARS or _short_numbers(raw[start:start + SAMPLE_CHARS])):
        return None
    scanned = _scan(raw, columns, text, missing, start)
    if scanned is not None and progress is not None:
        progress(size, size)
    return scanned


def _short_numbers(body) -> bool:
    """True if the first :data:`SAMPLE_CHARS` characters of ``body`` (str or bytes) hold no run of more than 15
    digits (decimal points left out): numbers of at most 15 significant digits, which the C scan converts on its
    exact fast path. In C when the extension is built (8 kB: 5 against 200 µs for the regular expression)."""
    sample = body[:SAMPLE_CHARS]
    extension = text_decode()
    if extension is not None:
        return extension.longest_digit_run(sample if isinstance(sample, bytes) else
                                           sample.encode("utf-8", "surrogatepass")) <= 15
    if isinstance(sample, bytes):
        sample = sample.decode("latin-1")  # digits and points are the same bytes
    return _LONG_DIGITS.search(sample.replace(".", "")) is None


@functools.lru_cache(maxsize=None)
def text_decode():
    """The functions of the extension's :mod:`fusion_altitude.logs._text_decode` (``scan_csv``, ``newlines``,
    ``newline_count``, ``longest_digit_run``), or None when it is not built; imported once (an
    import statement costs about 1 µs a call, three calls a read). Not at module import: a source checkout finds
    the installed extension only once :mod:`fusion_altitude.logs` has extended its path."""
    try:
        from ._text_decode import longest_digit_run, newline_count, newlines, scan_csv
    except ImportError:
        return None
    return types.SimpleNamespace(newline_count=newline_count, newlines=newlines, scan_csv=scan_csv,
                                 longest_digit_run=longest_digit_run)


def _scan(body, columns: Sequence[int], text: Sequence[int], missing: Sequence[str], start: int = 0):
    """The C scan's numbers, (distinct cells, indices) per text column and the body's line count; None when the
    extension is not built, or the body (str, or bytes from ``start`` on) is not plain or has no row
    (:func:`fusion_altitude.logs._text_decode.scan_csv`)."""
    extension = text_decode()
    if extension is None:
        return None
    status, numbers, columns_text, lines, _ = extension.scan_csv(body, columns, text, _missing_words(tuple(missing)),
                                                                 start)
    if status != "ok" or numbers.shape[0] == 0:
        return None
    return numbers, columns_text, lines


def newline_count(text: str) -> int:
    """``text.count("\\n")``, in C when the extension is built (a 28 kB export: 3.6 against 9 µs)."""
    extension = text_decode()
    return text.count("\n") if extension is None else extension.newline_count(text)


@functools.lru_cache(maxsize=8)
def _missing_words(missing: Tuple[str, ...]) -> str:
    """The missing words for the C scan: lower case, each followed by a newline."""
    return "".join(word.lower() + "\n" for word in missing)


def _parse(pacsv, chunk: str, columns: Sequence[int], text: Sequence[int], missing: Sequence[str]):
    """pyarrow's table of one chunk: ``columns`` as float64 (``missing`` → null), ``text`` as strings (no null);
    None if pyarrow refuses the text."""
    import pyarrow as pa

    types = {f"f{i}": pa.float64() for i in columns}
    types.update({f"f{i}": pa.string() for i in text})
    data = chunk.encode("utf-8")
    convert = pacsv.ConvertOptions(column_types=types, include_columns=list(types),
                                   null_values=_null_values(tuple(missing)), strings_can_be_null=False,
                                   quoted_strings_can_be_null=False)
    parse = pacsv.ParseOptions(delimiter=",", quote_char='"' if not text else False, newlines_in_values=False)
    read = pacsv.ReadOptions(autogenerate_column_names=True, use_threads=False,
                             block_size=max(1 << 20, min(len(data) + 1, 1 << 30)))
    try:
        return pacsv.read_csv(pa.py_buffer(data), read_options=read, parse_options=parse, convert_options=convert)
    except (pa.ArrowException, KeyError, ValueError, TypeError):
        return None


def _stripped(cells) -> Tuple[np.ndarray, np.ndarray]:
    """A pyarrow string column as its distinct cells, each stripped (object array of str), and the index of each
    row's cell among them (int64)."""
    encoded = cells.combine_chunks().dictionary_encode()
    stripped = np.empty(len(encoded.dictionary), dtype=object)
    stripped[:] = [cell.strip() for cell in encoded.dictionary.to_pylist()]
    return stripped, encoded.indices.to_numpy(zero_copy_only=False).astype(np.int64, copy=False)
