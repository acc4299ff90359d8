# cython: boundscheck=False, wraparound=False, initializedcheck=False
"""CSV rows formatted in C, byte for byte as Python's ``%`` formatting writes them.

Each value goes through CPython's own float formatter
(``PyOS_double_to_string``, the function behind ``repr(float)`` and
``"%.9g" % x``), so the text is the same bytes as the pure-Python writer's
``(row_format * n) % values`` — only the per-value Python objects, the
tuple and the format parsing are gone. Used by :mod:`fusion_altitude._core._csv_write`.
"""

from libc.stdlib cimport free, malloc
from libc.string cimport memcpy, strlen

import numpy as np

cdef extern from "Python.h":
    char *PyOS_double_to_string(double val, char format_code, int precision, int flags, int *type) except NULL
    void PyMem_Free(void *p)
    int Py_DTSF_ADD_DOT_0
    object PyBytes_FromStringAndSize(const char *v, Py_ssize_t len)

#: Column kinds: the printf format each stands for.
KIND_REPR = 0  # "%r": the shortest round-trip repr of a float64 (≤ 17 significant digits)
KIND_G9 = 1  # "%.9g": 9 significant digits (round-trips every float32)
KIND_INT = 2  # "%d": the value truncated to an integer

#: Longest text one value can take, characters ("-2.2250738585072014e-308" is 24; an int64 20).
DEF MAX_CELL = 32


cdef Py_ssize_t _int_text(char *out, double value):
    """``"%d" % value`` into out (value finite and within ±2**63); the count of characters."""
    cdef long long number = <long long>value
    cdef char digits[24]
    cdef Py_ssize_t count = 0, i
    cdef unsigned long long magnitude
    cdef Py_ssize_t start = 0
    if number < 0:
        out[0] = 45  # "-"
        start = 1
        magnitude = <unsigned long long>(-(number + 1)) + 1
    else:
        magnitude = <unsigned long long>number
    while True:
        digits[count] = 48 + <char>(magnitude % 10)
        count += 1
        magnitude //= 10
        if magnitude == 0:
            break
    for i in range(count):
        out[start + i] = digits[count - 1 - i]
    return start + count


def format_rows(double[:, ::1] block, int[::1] kinds):
    """The rows of ``block`` as CSV text (bytes), each cell as its column's kind says.

    Parameters
    ----------
    block : numpy.ndarray of float64, shape (rows, columns), C-contiguous
        The values, each column converted to float64 (float32 values exactly).
    kinds : numpy.ndarray of int32, shape (columns,)
        :data:`KIND_REPR`, :data:`KIND_G9` or :data:`KIND_INT` per column.

    Returns
    -------
    bytes
        ASCII text: cells separated by ``,``, every row ending in ``\\n``.
    """
    cdef Py_ssize_t rows = block.shape[0], columns = block.shape[1]
    if kinds.shape[0] != columns:
        raise ValueError(f"kinds: {kinds.shape[0]} kinds for {columns} columns")
    cdef Py_ssize_t j
    for j in range(columns):
        if kinds[j] < 0 or kinds[j] > 2:
            raise ValueError(f"kinds: column {j} has kind {kinds[j]}, not 0, 1 or 2")
    cdef Py_ssize_t capacity = rows * columns * (MAX_CELL + 1) + 1
    cdef char *out = <char *>malloc(capacity)
    if out == NULL:
        raise MemoryError()
    cdef Py_ssize_t used = 0, i, length
    cdef char *text
    cdef double value
    cdef int kind
    try:
        for i in range(rows):
            for j in range(columns):
                value = block[i, j]
                kind = kinds[j]
                if kind == KIND_INT:
                    if not (-9.2e18 < value < 9.2e18):
                        raise ValueError(f"block: row {i}, column {j}: {value!r} is not an integer")
                    used += _int_text(out + used, value)
                else:
                    if kind == KIND_REPR:
                        text = PyOS_double_to_string(value, b'r', 0, Py_DTSF_ADD_DOT_0, NULL)
                    else:
                        text = PyOS_double_to_string(value, b'g', 9, 0, NULL)
                    length = strlen(text)
                    if length > MAX_CELL:
                        PyMem_Free(text)
                        raise ValueError(f"block: row {i}, column {j}: {length} characters")
                    memcpy(out + used, text, length)
                    PyMem_Free(text)
                    used += length
                out[used] = 44 if j + 1 < columns else 10  # "," or "\n"
                used += 1
        return PyBytes_FromStringAndSize(out, used)
    finally:
        free(out)
