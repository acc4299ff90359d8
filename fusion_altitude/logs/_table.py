"""Fast CSV tables with line-accurate errors, shared by the CSV readers (generic, AltOS, CATS, Raven, RRC3).

The fast path hands the numeric (and text) columns a reader needs to pyarrow's columnar
CSV parser when pyarrow is installed and the text is plain
(:mod:`._csv_fast`), else the numbers to numpy's C parser (:func:`numpy.loadtxt`, C since numpy 1.23) in chunks, so a
progress callback can follow. Only if that parser refuses the text does a slow pure-Python
pass run, to find the first bad line and name it — or to accept what the
fast path cannot (``NA`` cells, spaces around empty cells).
"""

from __future__ import annotations

import csv
import io
import os
import threading
from dataclasses import dataclass, field
from typing import Callable, Dict, Iterator, List, Optional, Sequence, Tuple

import numpy as np

from . import _csv_fast
from ._data import LogError

#: Cells that mean "no value" (case-insensitive, after stripping spaces).
MISSING = ("", "nan", "na", "n/a", "null", "none", "-")
#: Characters of text per fast-parser chunk (progress granularity).
_CHUNK_CHARS = 4_000_000


#: The bytes of a file already read in this thread (:func:`given_bytes`), as ``(path, bytes)``, or None.
_GIVEN = threading.local()


def given_bytes(path: str, raw: Optional[bytes]) -> None:
    """The next :func:`read_text` of ``path`` in this thread takes ``raw`` (the whole file, read once by
    :func:`fusion_altitude.logs.load_log` to sniff it) instead of reading the file again; None forgets it."""
    _GIVEN.file = None if raw is None else (path, raw)


def read_text(path: str, what: str = "CSV log") -> str:
    """The whole file as text: UTF-8 (a BOM is dropped), newlines normalised; LogError if unreadable.

    The file's bytes given by :func:`given_bytes` for ``path`` are taken once instead of reading it again."""
    return _decoded(path, read_bytes(path, what))


def read_bytes(path: str, what: str = "CSV log") -> bytes:
    """The whole file's bytes, newlines normalised (``\\r\\n`` and ``\\r`` made ``\\n``); LogError if unreadable
    or binary (a NUL byte in the first 4 kB). Those given by :func:`given_bytes` for ``path`` are taken once."""
    given = getattr(_GIVEN, "file", None)
    if given is not None and given[0] == path:
        _GIVEN.file = None
        raw = given[1]
    else:
        raw = _read_bytes(path, what)
    if raw.find(b"\x00", 0, 4096) >= 0:
        raise LogError(f"{path}: binary data, not a {what} (NUL bytes in the first 4 kB)")
    if b"\r" in raw:  # before decoding: UTF-8 and Latin-1 spell \r and \n as those bytes and no others
        raw = _unix_newlines(raw)
    return raw


def _decoded(path: str, raw: bytes) -> str:
    """:func:`read_bytes`'s ``raw`` as text: UTF-8 (a BOM dropped), else Latin-1 (legacy names; numbers are ASCII)."""
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = raw[:error.start].count(b"\n") + 1
        try:
            return raw.decode("latin-1")  # accept legacy encodings for names; numbers are ASCII anyway
        except UnicodeDecodeError:  # pragma: no cover - latin-1 decodes every byte
            raise LogError(f"{path}: line {line}: not UTF-8 text") from None


#: The ASCII characters ``str.strip`` removes (``str.isspace``): a line of only these is blank.
_ASCII_SPACE = bytes(c for c in range(128) if chr(c).isspace())


def read_table(path: str, what: str = "CSV log") -> "Table":
    """``split_header(path, read_text(path, what))`` without decoding the body: the lines up to the header (the
    first non-blank one) are decoded, and the body stays the file's bytes (``Table.raw`` from ``Table.body_start``
    on, which the C scan reads in place), decoded only when a reader asks for ``Table.body``. Where the header part is not ASCII (a BOM, a
    legacy encoding: its decoding depends on the whole file) the whole file is decoded as :func:`read_text` does.
    Header, line numbers, body text and errors are :func:`split_header`'s."""
    raw = read_bytes(path, what)
    position = 0
    while True:
        end = raw.find(b"\n", position)
        end = len(raw) if end < 0 else end
        if raw[position:end].translate(None, _ASCII_SPACE) or end >= len(raw):
            break
        position = end + 1
    head = raw[:end]
    if not head.isascii():
        return split_header(path, _decoded(path, raw))
    table = split_header(path, head.decode("ascii"))
    return Table(path, table.header, None, table.first_line, table.preamble, raw, min(end + 1, len(raw)))


def _read_bytes(path: str, what: str) -> bytes:
    """The file's bytes; LogError if unreadable."""
    try:
        with open(path, "rb") as handle:
            return handle.read()
    except OSError as error:
        if os.path.isdir(path):
            raise LogError(f"{path}: is a directory, not a {what}") from None
        raise LogError(f"cannot open {path}: {error.strerror}") from None


def _unix_newlines(raw: bytes) -> bytes:
    """``raw`` with ``\\r\\n`` and ``\\r`` made ``\\n``: in one C pass when the extension is built (``replace`` twice
    costs 50 µs on a 28 kB export)."""
    extension = _csv_fast.text_decode()
    if extension is None:
        return raw.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    return extension.newlines(raw)


@dataclass
class Table:
    """A CSV file split into its header and its body.

    Attributes
    ----------
    path : str
        File path, for messages.
    header : list of str
        Column names (stripped; a leading ``#`` of the header line removed).
    body : str
        The data lines, ``\\n``-separated (a property: a table of :func:`read_table` decodes its body on first
        use).
    first_line : int
        File line number (1-based) of the body's first line.
    preamble : tuple of str
        Comment lines before the header (``split_header(…, header_start=…)``),
        stripped.
    raw : bytes or None
        The whole file's bytes (newlines normalised) of a table of :func:`read_table` (its header part ASCII),
        the body from ``body_start`` on, for the C scan; None for a table split from text.
    body_start : int
        Where the body starts in ``raw`` (bytes, and characters of the decoded file alike).
    """

    path: str
    header: List[str]
    text: Optional[str]
    first_line: int
    preamble: Tuple[str, ...] = ()
    raw: Optional[bytes] = field(default=None, repr=False)
    body_start: int = 0

    @property
    def body(self) -> str:
        if self.text is None:  # an ASCII header part: the body is the decoded file's characters from body_start on
            self.text = _decoded(self.path, self.raw)[self.body_start:]
        return self.text

    def index(self, name: str, occurrence: int = 0) -> int:
        """Position of column ``name`` (its ``occurrence``-th copy); LogError listing the columns if absent."""
        positions = [i for i, column in enumerate(self.header) if column == name]
        if len(positions) <= occurrence:
            raise LogError(f"{self.path}: column {name!r} not found; columns are {', '.join(self.header)}")
        return positions[occurrence]

    def has(self, name: str) -> bool:
        return name in self.header


def split_header(path: str, text: str, header_prefix: str = "", header_start: Optional[str] = None) -> Table:
    """The first non-empty line is the header (after ``header_prefix``, e.g. ``#``).

    With ``header_start`` (e.g. ``"#version,"``), comment lines starting with
    ``header_prefix`` before the line that starts with it are skipped and kept
    in ``Table.preamble`` (AltOS 1.4 writes ``# Config version: 1.18`` … there).
    """
    position, line = 0, 1
    preamble = []
    while True:
        end = text.find("\n", position)
        end = len(text) if end < 0 else end
        stripped = text[position:end].strip()
        if stripped:
            if header_start is None or stripped.startswith(header_start) or not (
                    header_prefix and stripped.startswith(header_prefix)):
                break
            preamble.append(stripped)
        if end >= len(text):
            raise LogError(f"{path}: empty file (no header line)")
        position, line = end + 1, line + 1
    header_line = text[position:end].strip()
    if header_prefix and header_line.startswith(header_prefix):
        header_line = header_line[len(header_prefix):]
    header = [name.strip().strip('"').strip() for name in next(csv.reader([header_line]))]
    return Table(path, header, text[end + 1:], line + 1, tuple(preamble))


def _row_lines(table: Table) -> np.ndarray:
    """File line of every non-blank body line (the rows numpy returns, in order)."""
    lines = np.array([i for i, line in enumerate(table.body.split("\n")) if line.strip()], dtype=np.int64)
    return lines + table.first_line


def _numpy_columns(table: Table, columns: Sequence[int], progress) -> Optional[np.ndarray]:
    """The numeric ``columns`` by numpy's C parser (:func:`numpy.loadtxt`) in chunks; None if it refuses."""
    parts = []
    for chunk, done in _csv_fast.text_chunks(table.body, _CHUNK_CHARS):
        if ",," in chunk or ",\n" in chunk or chunk.startswith(",") or "\n," in chunk or chunk.endswith(","):
            chunk = chunk.replace(",,", ",nan,").replace(",,", ",nan,")
            chunk = chunk.replace("\n,", "\nnan,").replace(",\n", ",nan\n")
            if chunk.startswith(","):
                chunk = "nan" + chunk
            if chunk.endswith(","):
                chunk = chunk + "nan"
        try:
            part = np.loadtxt(io.StringIO(chunk), delimiter=",", usecols=tuple(columns), dtype=float,
                              comments=None, ndmin=2, quotechar='"')
        except (ValueError, IndexError, TypeError):
            return None
        parts.append(part)
        if progress is not None:
            progress(done, len(table.body))
    if not parts:
        return np.zeros((0, len(columns)))
    return np.concatenate(parts, axis=0)


def data_lines(table: Table) -> Iterator[Tuple[int, int, str]]:
    """(position in the body, file line number, text) of every line of the body that is not blank."""
    for i, line in enumerate(table.body.split("\n")):
        if line.strip():
            yield i, table.first_line + i, line


def _python_columns(table: Table, columns: Sequence[int], progress, allow_truncated_tail: bool):
    """Pure-Python parse of the needed columns; LogError at the first bad line."""
    names = [table.header[i] for i in columns]
    total = table.body.count("\n") + 1
    ends_cleanly = table.body.endswith("\n") or not table.body
    last = max((i for i, _, _ in data_lines(table)), default=-1)
    rows, row_lines = [], []
    dropped = None
    for i, number, line in data_lines(table):
        try:
            cells = next(csv.reader([line]))
            values = []
            for column, name in zip(columns, names):
                if column >= len(cells):
                    raise LogError(f"{table.path}: line {number}, column {name!r}: missing (the line has "
                                   f"{len(cells)} cells, the header {len(table.header)})")
                cell = cells[column].strip()
                if cell.lower() in MISSING:
                    values.append(np.nan)
                    continue
                try:
                    values.append(float(cell))
                except ValueError:
                    shown = cell if len(cell) <= 40 else cell[:37] + "..."
                    raise LogError(f"{table.path}: line {number}, column {name!r}: {shown!r} is not a number") \
                        from None
        except (LogError, csv.Error) as error:
            if allow_truncated_tail and i == last and not ends_cleanly:
                dropped = number
                break
            if isinstance(error, csv.Error):
                raise LogError(f"{table.path}: line {number}: not CSV ({error})") from None
            raise
        rows.append(values)
        row_lines.append(number)
        if progress is not None and i % 100_000 == 0:
            progress(i, total)
    data = np.array(rows, dtype=float).reshape(len(rows), len(columns))
    return data, np.array(row_lines, dtype=np.int64), dropped


@dataclass
class Columns:
    """Columns of a table's rows (blank lines skipped).

    Attributes
    ----------
    numbers : numpy.ndarray, shape (rows, numeric columns)
        float64; NaN for empty / ``nan`` / ``NA`` cells.
    lines : numpy.ndarray of int
        File line of every row.
    dropped : int or None
        File line of a last line cut short and dropped.
    text : list of numpy.ndarray
        The stripped cells of each text column (object arrays of str).
    """

    numbers: np.ndarray
    lines: np.ndarray
    dropped: Optional[int]
    text: List[np.ndarray]


def read_columns(table: Table, numeric: Sequence[int], text: Sequence[int] = (),
                 progress: Optional[Callable[[int, int], None]] = None, allow_truncated_tail: bool = True) -> Columns:
    """Parse the ``numeric`` columns (positions) of a table as numbers and the ``text`` ones as stripped cells.

    pyarrow parses both in one pass (:func:`._csv_fast.read_numbers_and_text`); where it cannot, numpy's
    parser reads the numbers, and where that cannot either, the pure-Python pass, which names the first bad
    line. A last line cut short (the file does not end with a newline and its last line does not parse) is
    dropped, and its number returned.

    Raises
    ------
    LogError
        The first line with a bad cell, naming file line and column.
    """
    if table.raw is not None:
        scanned = _csv_fast.scan_bytes(table.raw, table.body_start, numeric, text, MISSING, progress)  # undecoded
        if scanned is not None:
            numbers, cells, line_count = scanned
            rows = numbers.shape[0]
            lines = np.arange(rows, dtype=np.int64) + table.first_line if rows == line_count else _row_lines(table)
            return Columns(numbers, lines, None, [distinct[indices] for distinct, indices in cells])
    fast = _csv_fast.read_numbers_and_text(table.body, numeric, text, MISSING, progress)  # pyarrow (issue 25)
    data = fast[0] if fast is not None else _numpy_columns(table, numeric, progress)
    lines = None if data is None else lines_of_rows(table, data.shape[0])
    if lines is None:
        data, lines, dropped = _python_columns(table, numeric, progress, allow_truncated_tail)
        return Columns(data, lines, dropped, [text_column(table, column, lines) for column in text])
    cells = fast[1] if fast is not None else [text_column(table, column, lines) for column in text]
    return Columns(data, lines, None, cells)


def numeric_columns(table: Table, columns: Sequence[int],
                    progress: Optional[Callable[[int, int], None]] = None,
                    allow_truncated_tail: bool = True):
    """Parse the numeric ``columns`` (positions) of a table: :func:`read_columns` without text columns.

    Returns
    -------
    data : numpy.ndarray, shape (rows, len(columns))
        float64; NaN for empty / ``nan`` / ``NA`` cells.
    lines : numpy.ndarray of int
        File line of every row.
    dropped_line : int or None
        A last line cut short (the file does not end with a newline and its
        last line does not parse) is dropped, and its number returned.
    """
    read = read_columns(table, columns, (), progress, allow_truncated_tail)
    return read.numbers, read.lines, read.dropped


def lines_of_rows(table: Table, rows: int) -> Optional[np.ndarray]:
    """File line of each of ``rows`` rows a parser found (blank lines skipped), or None if they do not match."""
    body = table.body
    expected = _csv_fast.newline_count(body) + (1 if body and not body.endswith("\n") else 0)
    if rows == expected:
        return np.arange(expected, dtype=np.int64) + table.first_line
    lines = _row_lines(table)
    return lines if lines.size == rows else None


def text_column(table: Table, column: int, lines: np.ndarray) -> np.ndarray:
    """The raw (stripped) cells of one column for the given file lines (object array of str)."""
    rows = lines.size
    if rows and int(lines[0]) == table.first_line and int(lines[-1]) == table.first_line + rows - 1:
        fast = _csv_fast.read_numbers_and_text(table.body, (), (column,), MISSING)  # pyarrow, or None (issue 25)
        if fast is not None and fast[1][0].size == rows:
            return fast[1][0]
    body = table.body.split("\n")
    quoted = '"' in table.body
    out = []
    for number in lines:
        line = body[int(number) - table.first_line]
        cells = next(csv.reader([line])) if quoted else line.split(",")
        out.append(cells[column].strip() if column < len(cells) else "")
    return np.array(out, dtype=object)


def check_finite(path: str, name: str, values: np.ndarray, lines: np.ndarray, what: str = "a number") -> None:
    """LogError naming the first line where a required column is empty or not finite."""
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise LogError(f"{path}: line {int(lines[bad[0]])}, column {name!r}: needs {what} on every row "
                       f"(empty or not finite)")


def columns_by_name(table: Table, names: Dict[str, Optional[str]]) -> Dict[str, int]:
    """Positions of the named columns (roles with None are skipped)."""
    return {role: table.index(name) for role, name in names.items() if name is not None}
