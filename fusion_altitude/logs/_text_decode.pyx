# cython: boundscheck=False, wraparound=False
"""The C scan of a plain numeric CSV body (``_csv_scan.h``) for :mod:`fusion_altitude.logs._csv_fast`: the numeric
columns as float64 and the text columns as distinct cells and an index per row, in one pass without pyarrow's
fixed set-up; or where the body stops being plain, which the readers' other paths then read."""

import numpy as np

from libc.stdint cimport int64_t

cdef extern from "Python.h":
    const char *PyUnicode_AsUTF8AndSize(object text, Py_ssize_t *size) except NULL

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
    ctypedef struct CsvScanResult:
        size_t rows
        size_t distinct[64]
        size_t line
        size_t cell
    int CSV_SCAN_MAX_COLUMNS
    CsvScanStatus CsvScan(const CsvScanArguments *arguments, CsvScanResult *result) nogil

#: Status names of :func:`scan_csv`.
STATUS = {0: "ok", 1: "not plain text", 2: "ragged", 3: "not a number", 4: "full"}


def scan_csv(str body, numeric, text, str missing):
    """The numeric and text columns of a plain CSV body (``_csv_scan.h``'s rules), in one C pass.

    Parameters
    ----------
    body : str
        The data lines (no header), ``\\n``-separated.
    numeric, text : sequence of int
        Cell positions of the numeric columns and of the text columns, in output order.
    missing : str
        The cells meaning "no value" (lower case; matched in any case), each followed by ``\\n``.

    Returns
    -------
    status : str
        "ok", or why the body is not plain: "not plain text", "ragged", "not a number", "full".
    numbers : numpy.ndarray or None
        float64, shape (rows, len(numeric)) (None unless "ok").
    text_columns : list of (numpy.ndarray, numpy.ndarray) or None
        Per text column: its distinct cells, stripped of spaces and tabs (object array of str, in order of first
        appearance), and the index of each row's cell among them (int64).
    line, cell : int
        Body line (0-based) and cell position where a scan that is not "ok" stopped (-1 for a non-ASCII body).
    """
    if not body.isascii():
        return "not plain text", None, None, -1, -1
    cdef Py_ssize_t size = 0
    cdef const char *data = PyUnicode_AsUTF8AndSize(body, &size)
    cdef Py_ssize_t missing_size = 0
    cdef const char *missing_data = PyUnicode_AsUTF8AndSize(missing, &missing_size)
    cdef size_t numeric_count = len(numeric), text_count = len(text)
    if numeric_count + text_count > <size_t> CSV_SCAN_MAX_COLUMNS or numeric_count + text_count == 0:
        return "full", None, None, 0, 0
    cdef size_t capacity = body.count("\n") + 1
    cdef size_t hash_size = 1
    while text_count and hash_size < 2 * capacity:
        hash_size *= 2
    positions = np.array(list(numeric) + list(text) + [0], dtype=np.intc)
    numbers = np.empty((capacity, max(numeric_count, 1)), dtype=np.float64)
    index = np.empty((capacity, max(text_count, 1)), dtype=np.int64)
    starts = np.empty((max(text_count, 1), capacity), dtype=np.int64)
    lengths = np.empty((max(text_count, 1), capacity), dtype=np.int64)
    slots = np.empty(max(text_count, 1) * hash_size, dtype=np.int64)
    cdef int[::1] positions_view = positions
    cdef double[:, ::1] numbers_view = numbers
    cdef int64_t[:, ::1] index_view = index
    cdef int64_t[:, ::1] starts_view = starts
    cdef int64_t[:, ::1] lengths_view = lengths
    cdef int64_t[::1] slots_view = slots
    cdef CsvScanArguments arguments
    cdef CsvScanResult result
    cdef CsvScanStatus status
    arguments.body = data
    arguments.size = <size_t> size
    arguments.numeric = &positions_view[0]
    arguments.numericCount = numeric_count
    arguments.text = &positions_view[numeric_count]
    arguments.textCount = text_count
    arguments.missing = missing_data
    arguments.missingSize = <size_t> missing_size
    arguments.capacity = capacity
    arguments.numbers = &numbers_view[0, 0]
    arguments.textIndex = &index_view[0, 0]
    arguments.distinctStart = &starts_view[0, 0]
    arguments.distinctLength = &lengths_view[0, 0]
    arguments.hashSlots = &slots_view[0]
    arguments.hashSize = hash_size
    with nogil:
        status = CsvScan(&arguments, &result)
    if status != CsvScanOk:
        return STATUS[<int> status], None, None, int(result.line), int(result.cell)
    rows = result.rows
    columns = []
    for k in range(text_count):
        cells = np.empty(result.distinct[k], dtype=object)
        cells[:] = [body[start:start + length] for start, length in
                    zip(starts[k, :result.distinct[k]].tolist(), lengths[k, :result.distinct[k]].tolist())]
        columns.append((cells, np.ascontiguousarray(index[:rows, k])))
    return "ok", numbers[:rows, :numeric_count], columns, int(result.line), -1


def newlines(const unsigned char[::1] data):
    """``data`` with every ``\\r\\n`` and every other ``\\r`` made ``\\n`` (bytes): what ``str.replace`` does to the
    decoded text, for UTF-8 and Latin-1 alike (their ``\\r`` and ``\\n`` are those bytes and no others), in one pass."""
    cdef Py_ssize_t size = data.shape[0], i, n = 0
    out = bytearray(size)
    cdef unsigned char[::1] view = out
    with nogil:
        i = 0
        while i < size:
            if data[i] == 13:
                view[n] = 10
                if i + 1 < size and data[i + 1] == 10:
                    i += 1
            else:
                view[n] = data[i]
            n += 1
            i += 1
    del view
    del out[n:]
    return bytes(out)
