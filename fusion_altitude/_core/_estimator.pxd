# cython: language_level=3
"""The base class of every binding estimator (cimported by each ``_<module>.pyx``)."""


cdef class Estimator:
    pass
