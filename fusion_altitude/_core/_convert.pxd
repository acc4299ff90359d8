# cython: language_level=3
"""Argument conversion shared by every binding (inline, so no module of its own).

Not a header declaration: the ``c*.pxd`` files declare the C headers; this one
holds the single Python-to-C conversion every ``update`` call makes.
"""

from cpython.float cimport PyFloat_AS_DOUBLE, PyFloat_AsDouble, PyFloat_CheckExact


cdef inline double as_double(object value, str name) except? -1.0:
    """A Python real number as a C double, or TypeError naming the argument.

    An exact ``float`` (the per-sample hot path) is read in place, inlined at the
    call site; anything else goes through :func:`_as_double_other`, which holds the
    ``try`` and so stays out of the caller's code.
    """
    if PyFloat_CheckExact(value):
        return PyFloat_AS_DOUBLE(value)
    return _as_double_other(value, name)


cdef inline double _as_double_other(object value, str name) except? -1.0:
    """``float(value)`` as CPython's PyFloat_AsDouble does it (``__float__``, ``__index__``), or TypeError naming it."""
    try:
        return PyFloat_AsDouble(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}") from None
