# cython: boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Strapdown attitude integration in C: the loop of :func:`fusion_altitude.sensors.gyro_attitude`.

:func:`integrate_steps` chains per-sample rotation quaternions onto an
initial attitude and renormalises after each step, in float64 and in exactly
the operation order of the pure-Python loop
(``fusion_altitude.sensors._integrate_steps_python``), compiled without FMA
contraction (``setup.py``: ``-ffp-contract=off``): the same bits, about a
hundred times faster, with the GIL released. Not part of the MCU core (the
flight computer's log is float64 data on a host).
"""

from libc.math cimport sqrt

import numpy as np


cdef void _integrate(double w, double x, double y, double z, const double[:, ::1] steps,
                     double[:, ::1] out) noexcept nogil:
    """out[i] = normalise(q[i-1] ⊗ steps[i]) with q[-1] = (w, x, y, z) (Hamilton product, w first)."""
    cdef Py_ssize_t i
    cdef double w2, x2, y2, z2, nw, nx, ny, nz, norm
    for i in range(steps.shape[0]):
        w2 = steps[i, 0]
        x2 = steps[i, 1]
        y2 = steps[i, 2]
        z2 = steps[i, 3]
        nw = w * w2 - x * x2 - y * y2 - z * z2
        nx = w * x2 + x * w2 + y * z2 - z * y2
        ny = w * y2 - x * z2 + y * w2 + z * x2
        nz = w * z2 + x * y2 - y * x2 + z * w2
        norm = sqrt(nw * nw + nx * nx + ny * ny + nz * nz)  # |q|, renormalised every step
        w = nw / norm
        x = nx / norm
        y = ny / norm
        z = nz / norm
        out[i, 0] = w
        out[i, 1] = x
        out[i, 2] = y
        out[i, 3] = z


def integrate_steps(initial, steps):
    """Attitude after each step: the running product of ``steps`` onto ``initial``, renormalised.

    Parameters
    ----------
    initial : array_like, shape (4,)
        Attitude before the first step, unit quaternion (w, x, y, z).
    steps : array_like, shape (n, 4)
        Rotation of each sample, unit quaternion (w, x, y, z), applied on the
        right (body frame).

    Returns
    -------
    numpy.ndarray, shape (n, 4)
        float64 quaternions (w, x, y, z), one per step.

    Raises
    ------
    ValueError
        ``initial`` not 4 values, or ``steps`` not of shape (n, 4).
    """
    start = np.asarray(initial, dtype=np.float64)
    if start.shape != (4,):
        raise ValueError(f"initial must be a quaternion of 4 values, got shape {start.shape}")
    rows = np.ascontiguousarray(steps, dtype=np.float64)
    if rows.ndim != 2 or rows.shape[1] != 4:
        raise ValueError(f"steps must have shape (n, 4), got {rows.shape}")
    out = np.empty((rows.shape[0], 4), dtype=np.float64)
    cdef const double[:, ::1] step_view = rows
    cdef double[:, ::1] out_view = out
    cdef double w = start[0], x = start[1], y = start[2], z = start[3]
    with nogil:
        _integrate(w, x, y, z, step_view, out_view)
    return out
