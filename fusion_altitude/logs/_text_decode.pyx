# cython: boundscheck=False, wraparound=False
"""The C scan of a plain numeric CSV body (``_csv_scan.h``) for :mod:`fusion_altitude.logs._csv_fast`: the numeric
columns as float64 and the text columns as distinct cells and an index per row, in one pass without pyarrow's
fixed set-up; or where the body stops being plain, which the readers' other paths then read."""

import numpy as np

from cpython.bytes cimport PyBytes_AS_STRING, PyBytes_FromStringAndSize
from libc.stdint cimport int64_t
from libc.string cimport memchr, memcpy

cdef extern from "Python.h":
    const char *PyUnicode_AsUTF8AndSize(object text, Py_ssize_t *size) except NULL
    ctypedef struct PyObject
    double PyOS_string_to_double(const char *text, char **end, PyObject *overflow_exception)
    PyObject *PyErr_Occurred()
    void PyErr_Clear()

cdef extern from "_csv_scan.h":
    ctypedef enum CsvScanStatus:
        CsvScanOk
        CsvScanNotPlainText
        CsvScanRagged
        CsvScanNotNumber
        CsvScanFull
    ctypedef struct CsvScanArguments:
        const char *body
        size_t size
        const int *numeric
        size_t numericCount
        const int *text
        size_t textCount
        const char *missing
        size_t missingSize
        size_t capacity
        double *numbers
        int64_t *textIndex
        int64_t *distinctStart
        int64_t *distinctLength
        int64_t *hashSlots
        size_t hashSize
        double (*toDouble)(const char *text, char **end)
    ctypedef struct CsvScanResult:
        size_t rows
        size_t distinct[64]
        size_t line
        size_t cell
    int CSV_SCAN_MAX_COLUMNS
    CsvScanStatus CsvScan(const CsvScanArguments *arguments, CsvScanResult *result) nogil
    size_t CsvScanNewlines(const char *text, size_t size) nogil
    size_t CsvScanLongestDigitRun(const char *text, size_t size) nogil

cdef double _python_float(const char *text, char **end) noexcept:
    """Python's own conversion (``float``'s, correctly rounded on every platform) for the scan's numbers off
    Clinger's fast path; a text it refuses ends at its start (the scan then hands the body on). Needs the GIL."""
    cdef double value = PyOS_string_to_double(text, end, NULL)
    if PyErr_Occurred() != NULL:
        PyErr_Clear()
        end[0] = <char *> text
    return value


#: Status names of :func:`scan_csv`.
STATUS = {0: "ok", 1: "not plain text", 2: "ragged", 3: "not a number", 4: "full"}


def scan_csv(body, numeric, text, str missing, Py_ssize_t start=0):
    """The numeric and text columns of a plain CSV body (``_csv_scan.h``'s rules), in one C pass.

    Parameters
    ----------
    body : str or bytes
        The data lines (no header), ``\\n``-separated: text, or the file's bytes (the scan takes ASCII only, so
        bytes it reads are the text's characters one for one; a reader need not decode a body it scans).
    numeric, text : sequence of int
        Cell positions of the numeric columns and of the text columns, in output order.
    missing : str
        The cells meaning "no value" (lower case; matched in any case), each followed by ``\\n``.
    start : int
        Where the body starts in ``body`` (a whole file's bytes read in place, without copying its body).

    Returns
    -------
    status : str
        "ok", or why the body is not plain: "not plain text", "ragged", "not a number", "full".
    numbers : numpy.ndarray or None
        float64, shape (rows, len(numeric)), each column contiguous (Fortran order: a reader's column is a view,
        not a copy) (None unless "ok").
    text_columns : list of (numpy.ndarray, numpy.ndarray) or None
        Per text column: its distinct cells, stripped of spaces and tabs (object array of str, in order of first
        appearance), and the index of each row's cell among them (int64).
    line, cell : int
        "ok": the body's lines (blank ones too; a last line without a newline counts), so ``rows == line`` when
        no line is blank. Otherwise the body line (0-based) and cell position where the scan stopped (-1 for a
        text body that is not ASCII).
    """
    cdef Py_ssize_t size = 0
    cdef const char *data
    if isinstance(body, bytes):
        data = PyBytes_AS_STRING(body)
        size = len(body)
    elif isinstance(body, str):
        if not body.isascii():
            return "not plain text", None, None, -1, -1
        data = PyUnicode_AsUTF8AndSize(body, &size)
    else:
        raise TypeError(f"body must be str or bytes, got {type(body).__name__}")
    if not 0 <= start <= size:
        raise ValueError(f"start must be within the body's {size} characters, got {start}")
    data += start
    size -= start
    cdef Py_ssize_t missing_size = 0
    cdef const char *missing_data = PyUnicode_AsUTF8AndSize(missing, &missing_size)
    cdef size_t numeric_count = len(numeric), text_count = len(text)
    if numeric_count + text_count > <size_t> CSV_SCAN_MAX_COLUMNS or numeric_count + text_count == 0:
        return "full", None, None, 0, 0
    cdef size_t capacity = _rows_guess(data, <size_t> size)
    status, numbers, columns, line, cell = _scan(body, start, data, <size_t> size, numeric, text, missing_data,
                                                 <size_t> missing_size, capacity)
    if status == "more rows":  # than guessed: count them and scan again
        capacity = CsvScanNewlines(data, <size_t> size) + 1
        status, numbers, columns, line, cell = _scan(body, start, data, <size_t> size, numeric, text, missing_data,
                                                     <size_t> missing_size, capacity)
    return status, numbers, columns, line, cell


cdef size_t _rows_guess(const char *data, size_t size) noexcept:
    """Rows to make room for without a pass over the body: its size over its first line's length, a quarter more
    and 64 rows spare (a body of shorter lines fills it: :func:`scan_csv` then counts its lines and scans again)."""
    cdef const char *found = <const char *> memchr(data, 10, size)
    cdef size_t first = <size_t> (found - data) + 1 if found != NULL else size + 1
    return size // first + size // (4 * first) + 64


cdef tuple _scan(body, Py_ssize_t start, const char *data, size_t size, numeric, text, const char *missing_data, size_t missing_size,
                 size_t capacity):
    """One scan of ``data`` (``body`` from ``start`` on) with room for ``capacity`` rows: :func:`scan_csv`'s answer, or "more rows" when they
    did not fit."""
    cdef size_t numeric_count = len(numeric), text_count = len(text)
    cdef size_t hash_size = 1
    while text_count and hash_size < 2 * capacity:
        hash_size *= 2
    cdef int positions[64]
    cdef size_t k
    for k in range(numeric_count):
        positions[k] = numeric[k]
    for k in range(text_count):
        positions[numeric_count + k] = text[k]
    numbers = np.empty((max(numeric_count, 1), capacity), dtype=np.float64)  # column-major: each column contiguous
    cdef double[:, ::1] numbers_view = numbers
    # one int64 workspace: each row's text index, each column's distinct starts and lengths, the hash slots
    cdef size_t words = text_count * (3 * capacity + hash_size)
    work = np.empty(max(words, 1), dtype=np.int64)
    cdef int64_t[::1] work_view = work
    cdef CsvScanArguments arguments
    cdef CsvScanResult result
    cdef CsvScanStatus status
    arguments.body = data
    arguments.size = size
    arguments.numeric = &positions[0]
    arguments.numericCount = numeric_count
    arguments.text = &positions[numeric_count]
    arguments.textCount = text_count
    arguments.missing = missing_data
    arguments.missingSize = missing_size
    arguments.capacity = capacity
    arguments.numbers = &numbers_view[0, 0]
    arguments.textIndex = &work_view[0]
    arguments.distinctStart = &work_view[0] + text_count * capacity
    arguments.distinctLength = &work_view[0] + 2 * text_count * capacity
    arguments.hashSlots = &work_view[0] + 3 * text_count * capacity
    arguments.hashSize = hash_size
    arguments.toDouble = _python_float
    status = CsvScan(&arguments, &result)  # with the GIL: Python's float conversion needs it (a body is small)
    if status == CsvScanFull and result.rows == capacity:
        return "more rows", None, None, int(result.line), int(result.cell)
    if status != CsvScanOk:
        return STATUS[<int> status], None, None, int(result.line), int(result.cell)
    rows = result.rows
    columns = []
    for k in range(text_count):
        found = result.distinct[k]
        starts = work[(text_count + k) * capacity:(text_count + k) * capacity + found].tolist()
        lengths = work[(2 * text_count + k) * capacity:(2 * text_count + k) * capacity + found].tolist()
        cells = np.empty(found, dtype=object)
        if isinstance(body, bytes):
            cells[:] = [body[start + first:start + first + length].decode("ascii")
                        for first, length in zip(starts, lengths)]
        else:
            cells[:] = [body[start + first:start + first + length] for first, length in zip(starts, lengths)]
        columns.append((cells, work[k:rows * text_count:text_count].copy()))
    return "ok", numbers[:numeric_count, :rows].T, columns, int(result.line), -1



def newlines(const unsigned char[::1] data):
    """``data`` with every ``\\r\\n`` and every other ``\\r`` made ``\\n`` (bytes): what ``str.replace`` does to the
    decoded text, for UTF-8 and Latin-1 alike (their ``\\r`` and ``\\n`` are those bytes and no others), in one pass
    (runs between carriage returns copied whole)."""
    cdef Py_ssize_t size = data.shape[0], n = 0, run
    if size == 0:
        return b""
    out = PyBytes_FromStringAndSize(NULL, size)
    cdef char *target = PyBytes_AS_STRING(out)
    cdef const unsigned char *source = &data[0]
    cdef const unsigned char *end = source + size
    cdef const unsigned char *found
    with nogil:
        while source < end:
            found = <const unsigned char *> memchr(source, 13, <size_t> (end - source))
            run = (found if found != NULL else end) - source
            memcpy(target + n, source, <size_t> run)
            n += run
            if found == NULL:
                break
            target[n] = 10
            n += 1
            source = found + (2 if found + 1 < end and found[1] == 10 else 1)
    return out if n == size else out[:n]


def longest_digit_run(const unsigned char[::1] data):
    """The longest run of digits in ``data`` with the decimal points left out (``"12.345"`` is a run of 5): what
    ``re.search("[0-9]{16}", text.replace(".", ""))`` asks of a sample, in one C pass (a fortieth of the time)."""
    if data.shape[0] == 0:
        return 0
    return CsvScanLongestDigitRun(<const char *> &data[0], <size_t> data.shape[0])


def newline_count(str text):
    """``text.count("\\n")``: in C over an ASCII string's bytes (a quarter of the time on a 28 kB body)."""
    if not text.isascii():
        return text.count("\n")
    cdef Py_ssize_t size = 0
    cdef const char *data = PyUnicode_AsUTF8AndSize(text, &size)
    return CsvScanNewlines(data, <size_t> size)
