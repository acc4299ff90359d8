"""Glue of the complementary observer shared by its binding (``_observer.pyx``)
and its reference (``reference/observer.py``): presets, statuses, error
messages that name the argument, batch argument conversion and the result type.
"""

from __future__ import annotations

import math
import warnings
from typing import NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ._c_tables import FUSION_ALTITUDE_MAXIMUM_GAIN, OBSERVER_PRESET_OMEGA, Preset, Status
from ._common import (ACCEL_FINITE, BARO_SAMPLE_OR_NAN, DT_POSITIVE, input_rules, output_arrays as _output_arrays,
                      prepare_inputs, raise_input_error)

__all__ = ["AltitudeBatch", "DiscretisationWarning", "Status", "prepare_inputs", "prepare_batch", "output_arrays"]


#: Preset names accepted by ``AltitudeSettings.preset`` and their position-loop
#: bandwidth ω (rad/s); each uses ζ = 0.7 and ω_b = ω/5 (the rocket ω_b = 0). From the header's
#: ``FusionAltitudePreset`` comments, through the generated tables.
PRESET_OMEGA = dict(OBSERVER_PRESET_OMEGA)


#: The C settings functions the settings classes call instead of the reference's arithmetic twins, once the
#: binding (``_observer.pyx``) registers them at import: ``"from_bandwidth"`` → ``c_settings_from_bandwidth``,
#: ``"check_gains"`` → ``c_gains_check`` (also the rocket settings' observer check). Without the compiled
#: extension it stays empty and the reference's twins compute (``tests/test_settings_checks.py`` and
#: ``tests/test_observer.py`` hold the twins equal to C).
C_SETTINGS_FUNCTIONS: dict = {}


#: Index of each preset in the C enum ``FusionAltitudePreset``.
PRESET_INDEX = {preset.name.lower(): int(preset) for preset in Preset}


#: ``ω·dt`` at or above this gets a :class:`DiscretisationWarning`.
OMEGA_DT_ADVICE = 0.1


class DiscretisationWarning(UserWarning):
    """The sample period is long for the observer's bandwidth (ω·dt ≥ 0.1).

    The semi-implicit Euler step then no longer follows the continuous-time
    response closely, although it may still be stable.
    """


class AltitudeBatch(NamedTuple):
    """Per-sample outputs of ``update_batch``, each a float32 array.

    Attributes
    ----------
    altitude : numpy.ndarray
        Altitude estimate h after each sample, m.
    vertical_velocity : numpy.ndarray
        Vertical velocity estimate v after each sample, m/s, +up.
    accel_bias : numpy.ndarray
        Accelerometer bias estimate b after each sample, m/s², +up.
    baro_residual : numpy.ndarray
        Baro residual z − h of each sample before its correction, m; NaN where
        the sample had no baro altitude, 0 where it set the reference.
    """

    altitude: np.ndarray
    vertical_velocity: np.ndarray
    accel_bias: np.ndarray
    baro_residual: np.ndarray


UPDATE_RULES = input_rules(Status, accel=ACCEL_FINITE, baro_altitude=BARO_SAMPLE_OR_NAN, dt=DT_POSITIVE)


def raise_update_error(status: int, accel: float, baro_altitude: float, dt: float, index: Optional[int] = None,
                       dt_is_array: bool = False) -> None:
    """Raise the ValueError for a rejected update, naming the argument (and index)."""
    raise_input_error(UPDATE_RULES, status, {"accel": accel, "baro_altitude": baro_altitude, "dt": dt}, index,
                      {"dt": dt_is_array})


def raise_reset_error(status: int, baro_altitude: float, accel_bias: float) -> None:
    """Raise the ValueError for a rejected reset, naming the argument."""
    if status == Status.INVALID_BARO_ALTITUDE:
        raise ValueError(f"baro_altitude must be finite (m), got {baro_altitude!r}")
    raise ValueError(f"accel_bias must be finite (m/s²), got {accel_bias!r}")


def raise_settings_error(status: int, gains: Tuple[float, float, float], dt: Optional[float] = None) -> None:
    """Raise the ValueError for rejected gains."""
    kh, kv, kb = gains
    if status == Status.INVALID_GAIN:
        for name, value in zip(("position_gain", "velocity_gain", "bias_gain"), gains):
            if not math.isfinite(value) or value < 0 or value > FUSION_ALTITUDE_MAXIMUM_GAIN:
                raise ValueError(f"{name} must be finite, >= 0 and <= {FUSION_ALTITUDE_MAXIMUM_GAIN:g}, got {value!r}")
    if status == Status.UNSTABLE_GAINS:
        raise ValueError(
            "gains are unstable: Routh-Hurwitz needs position_gain * velocity_gain > bias_gain "
            f"(and position_gain > 0 when velocity_gain > 0), got {kh!r} * {kv!r} vs {kb!r}")
    if status == Status.UNSTABLE_DISCRETE:
        raise ValueError(f"gains ({kh!r}, {kv!r}, {kb!r}) make the discrete update unstable at dt = {dt!r} s")
    if status == Status.INVALID_DT:
        raise ValueError(f"dt must be finite and > 0 (s), got {dt!r}")
    if status == Status.INVALID_GAP_PERIOD:
        raise ValueError("gap_period must be > 0 s (inf: never a gap)")
    if status == Status.INVALID_BARO_TIMEOUT:
        raise ValueError("baro_timeout must be > 0 s (inf: never times out)")
    if status == Status.INVALID_BANDWIDTH:
        raise ValueError("omega and zeta must be finite and > 0, omega_b finite and >= 0, "
                         "and the resulting gains finite")
    raise ValueError(f"invalid settings (status {status})")


def check_preset(name: object) -> int:
    """Return the C preset index of ``name`` or raise ValueError listing the presets."""
    if not isinstance(name, str):
        raise TypeError(f"name must be a str, got {type(name).__name__}")
    try:
        return PRESET_INDEX[name]
    except KeyError:
        raise ValueError(f"name must be one of {', '.join(PRESET_OMEGA)}; got {name!r}") from None


def fastest_pole(position_gain: float, velocity_gain: float, bias_gain: float) -> float:
    """Largest magnitude of the roots of s³ + Kh·s² + Kv·s + Kb, rad/s."""
    roots = np.roots([1.0, position_gain, velocity_gain, bias_gain])
    return float(np.max(np.abs(roots))) if roots.size else 0.0


def warn_if_coarse(gains: Tuple[float, float, float], dt: float, stacklevel: int = 3) -> None:
    """Warn (DiscretisationWarning) when ω·dt ≥ 0.1 for the fastest observer pole ω."""
    omega = fastest_pole(*gains)
    if omega * dt >= OMEGA_DT_ADVICE:
        warnings.warn(
            f"omega * dt = {omega:.3g} * {dt:.3g} s = {omega * dt:.3g} >= {OMEGA_DT_ADVICE}: the discrete "
            "update departs from the continuous-time design; sample faster or lower the gains",
            DiscretisationWarning, stacklevel=stacklevel)


def prepare_batch(accel: object, baro_altitude: object, dt: object,
                  out: Optional[Sequence[np.ndarray]]) -> Tuple[np.ndarray, np.ndarray, np.ndarray, bool, AltitudeBatch]:
    """Convert batch inputs to contiguous float32 and check their shapes.

    Returns
    -------
    accel, baro_altitude : numpy.ndarray
        Contiguous float32 vectors of one length n.
    dt : numpy.ndarray
        Contiguous float32 vector of length n, or of length 1 for a scalar dt.
    dt_is_array : bool
        Whether ``dt`` was given per sample.
    out : AltitudeBatch
        The caller's arrays, checked, or new ones.
    """
    accel32, baro32, dt32, dt_is_array = prepare_inputs(accel, baro_altitude, dt)
    n = accel32.shape[0]
    return accel32, baro32, dt32, dt_is_array, output_arrays((n,), out)


def output_arrays(shape: Tuple[int, ...], out: Optional[Sequence[np.ndarray]]) -> AltitudeBatch:
    """New float32 output arrays of ``shape``, or the caller's ``out`` after checking it."""
    return _output_arrays(AltitudeBatch, [(shape, np.float32)] * 4, out)


class AltitudeContract:
    """The public methods whose signature (and docstring) the AltitudeEstimator binding and reference share, written
    once here: ``_common.share_signatures``/``share_docstrings`` give them to both classes."""

    def update(self, accel: float, baro_altitude: float, dt: float) -> None:
        """Process one sample.

        Parameters
        ----------
        accel : float
            Vertical acceleration, m/s², earth frame, +up, gravity removed.
        baro_altitude : float
            Barometric altitude, m; NaN when no baro sample arrived this step
            (the filter then integrates the acceleration only).
        dt : float
            Time since the previous sample, s.

        Notes
        -----
        Once the reference is set, a ``dt`` above ``settings.gap_period`` is a
        gap: it is not integrated, :attr:`gap_count` goes up, the bias is held
        and the next baro sample (this one's if present) restarts the altitude
        at the baro and the velocity at the mean velocity over the gap
        ((z − h_before) / time since h_before); :attr:`reference_set` is
        False until then. After the restart the bias is held for 8/Kh s
        (while the velocity error is corrected). A step carrying a baro
        sample that the gains cannot integrate stably (Jury's test fails at
        1.5 times the step and the baro interval it ends; default gains with
        a baro every step: dt > 0.413 s) is a gap too.

        With no baro sample for more than ``settings.baro_timeout`` s the
        observer stops dead-reckoning: :attr:`baro_timeouts` goes up,
        :attr:`baro_timed_out` is True until the next baro sample, the
        acceleration is no longer integrated and the velocity decays to 0
        (v ·= T/(T + dt), T = baro_timeout), so the altitude moves at most
        |v|·T further; the next baro sample restarts the altitude at the baro.

        Raises
        ------
        ValueError
            accel not finite, baro_altitude infinite, dt not finite or <= 0;
            the state is unchanged.
        """
        raise NotImplementedError
