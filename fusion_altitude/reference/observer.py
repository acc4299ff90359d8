"""The 3rd-order complementary altitude observer, in plain Python.

State (all float32): altitude h (m), vertical velocity v (m/s, +up), accel
bias b (m/s², +up), last baro residual r (m), the time since h was last
updated while a restart after a gap is pending (s), the time since the last
restart after a gap or a baro timeout (s, −1 before any; the bias is held while it times Kh is
below 8), the time since the latest baro sample (s), the gap and baro-timeout counts, whether the
reference is set and whether the baro timed out. Gains: position Kh (1/s), velocity Kv (1/s²),
bias Kb (1/s³); gap period (s); baro timeout (s).

Each function below mirrors the C function named in its docstring, statement
for statement, so that the results agree bit for bit.
"""

from __future__ import annotations

import copy
from typing import Optional, Sequence, Tuple

import numpy as np

from .._core import _c_tables, _common, _observer_glue
from .._core._observer_glue import AltitudeBatch, Status

from ._checkpoint import Checkpointable
from ._diagnostics import BaroGapDiagnostics, settings_property, state_property
from ._settings import GainSettings

f32 = np.float32
#: FUSION_ALTITUDE_MAXIMUM_GAIN: the largest gain the settings check accepts (1/s, 1/s², 1/s³).
MAXIMUM_GAIN = f32(_c_tables.FUSION_ALTITUDE_MAXIMUM_GAIN)
_NAN = f32("nan")

#: FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, s.
DEFAULT_GAP_PERIOD = _c_tables.FUSION_ALTITUDE_DEFAULT_GAP_PERIOD
#: FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT, s.
DEFAULT_BARO_TIMEOUT = _c_tables.FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT
#: FUSION_ALTITUDE_STABILITY_MARGIN: a baro step is a gap unless Jury's test passes at this times its dt.
STABILITY_MARGIN = f32(_c_tables.FUSION_ALTITUDE_STABILITY_MARGIN)
#: FUSION_ALTITUDE_BIAS_HOLD: after a restart the bias is held while (time since it)·Kh < this.
BIAS_HOLD = f32(_c_tables.FUSION_ALTITUDE_BIAS_HOLD)


# -- float classification (FusionAltitudeIsFinite / FusionAltitudeIsNaN) ------

def _is_finite(x: np.float32) -> bool:
    return bool(np.isfinite(x))


def _is_nan(x: np.float32) -> bool:
    return bool(np.isnan(x))


def check_inputs(a: np.float32, z: np.float32, dt: np.float32) -> Status:
    """FusionAltitudeCheckInputs: a finite, z finite or NaN (no sample), dt finite and > 0."""
    if not _is_finite(a):
        return Status.INVALID_ACCEL
    if not _is_nan(z) and not _is_finite(z):
        return Status.INVALID_BARO_ALTITUDE
    if not _is_finite(dt) or not dt > 0:
        return Status.INVALID_DT
    return Status.OK


# -- settings ----------------------------------------------------------------

def _check_gains(kh: np.float32, kv: np.float32, kb: np.float32) -> Status:
    """FusionAltitudeSettingsCheck: finite, >= 0, <= FUSION_ALTITUDE_MAXIMUM_GAIN, Routh-Hurwitz."""
    if not (_is_finite(kh) and _is_finite(kv) and _is_finite(kb)) or kh < 0 or kv < 0 or kb < 0 \
            or kh > MAXIMUM_GAIN or kv > MAXIMUM_GAIN or kb > MAXIMUM_GAIN:
        return Status.INVALID_GAIN
    if kb > 0:
        if not kh * kv > kb:
            return Status.UNSTABLE_GAINS
    elif kv > 0 and not kh > 0:
        return Status.UNSTABLE_GAINS
    return Status.OK


def _discrete_stable(kh: np.float32, kv: np.float32, kb: np.float32, dt: np.float32) -> bool:
    """FusionAltitudeIsDiscreteStable: Jury's test on the discrete update at step dt (s).

    With p = Kh·dt, q = Kv·dt², s = Kb·dt³ the characteristic polynomial of the
    update of (h, v·dt, b·dt²) is z³ + (p+q−3)z² + (3−2p−q+s)z + (p−1).
    """
    with np.errstate(over="ignore", invalid="ignore"):
        p = kh * dt
        q = kv * dt * dt
        s = kb * dt * dt * dt
        if not (_is_finite(p) and _is_finite(q) and _is_finite(s)):
            return False
        if kb > 0:
            lhs = p * (f32(2) - p)
            rhs = p * (p + q - f32(2)) - s
            return bool(s > 0 and (f32(8) - f32(4) * p - f32(2) * q + s) > 0 and p > 0 and p < 2
                        and lhs > rhs and lhs > -rhs)
        if kv > 0:
            return bool(p > 0 and p < 2 and q > 0 and q < f32(4) - f32(2) * p)
        return bool(p < 2)


def step_stable(kh: np.float32, kv: np.float32, kb: np.float32, dt: np.float32, interval: np.float32) -> bool:
    """FusionAltitudeIsStepStable: the gap rule's stability limit for a baro step of dt s ending a baro interval of
    ``interval`` s: the conditions of Jury's test that bound the step from above, with T = STABILITY_MARGIN·dt,
    TD = STABILITY_MARGIN·interval, p = Kh·T, q = Kv·T·TD, s = Kb·T·TD²: p < 2, 8 − 4p − 2q + s > 0,
    p(p+q−2) − s <= p(2−p) (Kb > 0); p < 2 and q < 4 − 2p (Kb = 0 < Kv); p < 2 (Kv = Kb = 0)."""
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        t = STABILITY_MARGIN * dt
        t_interval = STABILITY_MARGIN * interval
        p = kh * t
        q = kv * t * t_interval
        s = kb * t * t_interval * t_interval
        if not (_is_finite(p) and _is_finite(q) and _is_finite(s)) or not p < 2:
            return False
        if kb > 0:
            return bool((f32(8) - f32(4) * p - f32(2) * q + s) > 0 and not (p * (p + q - f32(2)) - s) > p * (f32(2) - p))
        if kv > 0:
            return bool(q < f32(4) - f32(2) * p)
        return True


def stability_restart(h: np.float32, v: np.float32, kh: np.float32, kv: np.float32, z: np.float32, dt: np.float32,
                      interval: np.float32) -> Tuple[np.float32, np.float32, np.float32]:
    """FusionAltitudeStabilityRestart: (h, v, r) after a gap by the stability rule at baro sample z (m), step dt (s),
    baro interval D (s): v += (vMean − v)·D/(D + Kh/Kv), vMean = ((z − h) + v·(D − dt))/D; h = z; r = 0."""
    if kv > 0:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            mean = ((z - h) + v * (interval - dt)) / interval
            weight = interval / (interval + kh / kv)
            velocity = v + (mean - v) * weight
        v = velocity if _is_finite(velocity) else v
    return z, v, f32(0)


def _validate(kh: np.float32, kv: np.float32, kb: np.float32, dt: np.float32) -> Status:
    """FusionAltitudeSettingsValidate: the gains' checks, then Jury's test at dt (s)."""
    status = _check_gains(kh, kv, kb)
    if status != Status.OK:
        return status
    if not _is_finite(dt) or not dt > 0:
        return Status.INVALID_DT
    return Status.OK if _discrete_stable(kh, kv, kb, dt) else Status.UNSTABLE_DISCRETE


def _from_bandwidth(omega: np.float32, zeta: np.float32, omega_b: np.float32) -> Tuple[Status, Tuple[np.float32, ...]]:
    """FusionAltitudeSettingsFromBandwidth: Kh = 2ζω + ω_b, Kv = ω² + 2ζω·ω_b, Kb = ω²·ω_b."""
    if not (_is_finite(omega) and _is_finite(zeta) and _is_finite(omega_b)) or not omega > 0 or not zeta > 0 \
            or omega_b < 0:
        return Status.INVALID_BANDWIDTH, ()
    two_zeta_omega = f32(2) * zeta * omega
    omega_squared = omega * omega
    gains = (two_zeta_omega + omega_b, omega_squared + two_zeta_omega * omega_b, omega_squared * omega_b)
    status = _check_gains(*gains)
    if status == Status.INVALID_GAIN:
        status = Status.INVALID_BANDWIDTH
    return status, gains


def _settings_from_bandwidth(omega: np.float32, zeta: np.float32,
                             omega_b: np.float32) -> Tuple[Status, Tuple[np.float32, ...]]:
    """FusionAltitudeSettingsFromBandwidth itself where the binding registered it (``_observer_glue``), else
    its twin :func:`_from_bandwidth`."""
    c_function = _observer_glue.C_SETTINGS_FUNCTIONS.get("from_bandwidth")
    if c_function is None:
        return _from_bandwidth(omega, zeta, omega_b)
    status, values = c_function(float(omega), float(zeta), float(omega_b))
    if values is None:
        return Status(status), ()
    return Status(status), tuple(f32(values[name]) for name in ("position_gain", "velocity_gain", "bias_gain"))


#: FusionAltitudeSettingsFromPreset: {preset: (Kh, Kv, Kb)} as float32, and the gap period and baro timeout (s),
#: read from C by the generator (``_c_tables.OBSERVER_PRESETS``).
_PRESET_GAINS = {name: (f32(p["position_gain"]), f32(p["velocity_gain"]), f32(p["bias_gain"]))
                 for name, p in _c_tables.OBSERVER_PRESETS.items()}
_PRESET_GAP_PERIODS = {name: p["gap_period"] for name, p in _c_tables.OBSERVER_PRESETS.items()}
_PRESET_BARO_TIMEOUTS = {name: p["baro_timeout"] for name, p in _c_tables.OBSERVER_PRESETS.items()}


class AltitudeSettings(GainSettings):
    """Observer gains (float32).

    Parameters
    ----------
    position_gain : float, default 2.40
        Kh, 1/s: baro residual into altitude.
    velocity_gain : float, default 2.88
        Kv, 1/s²: baro residual into vertical velocity.
    bias_gain : float, default 0.675
        Kb, 1/s³: baro residual into the accel bias; 0 disables bias estimation.
    gap_period : float, default 0.5
        s: an update whose dt exceeds this is a gap, not integrated (see
        :meth:`AltitudeEstimator.update`); ``inf`` never detects a gap.
    baro_timeout : float, default 2.0
        s: after this long without a baro sample the observer stops
        dead-reckoning (the velocity decays to 0, the output is flagged
        :attr:`AltitudeEstimator.baro_timed_out`); ``inf`` never times out.

    Raises
    ------
    ValueError
        A gain is not finite or negative, the observer is unstable
        (Routh–Hurwitz: Kh·Kv > Kb when Kb > 0; Kh > 0 when Kv > 0), or
        gap_period or baro_timeout is NaN or <= 0.
    """

    __slots__ = ("_gains", "_gap_period", "_baro_timeout")

    def __init__(self, position_gain: float = 2.40, velocity_gain: float = 2.88, bias_gain: float = 0.675,
                 gap_period: float = DEFAULT_GAP_PERIOD, baro_timeout: float = DEFAULT_BARO_TIMEOUT) -> None:
        names = ("position_gain", "velocity_gain", "bias_gain")
        given = tuple(_common.as_float(value, name) for value, name in zip((position_gain, velocity_gain, bias_gain),
                                                                             names))
        with np.errstate(over="ignore"):
            gains = tuple(f32(value) for value in given)
            period = f32(_common.as_float(gap_period, "gap_period"))
            timeout = f32(_common.as_float(baro_timeout, "baro_timeout"))
        status = _observer_glue.C_SETTINGS_FUNCTIONS.get("check_gains", _check_gains)(*gains)  # C where built
        if status != Status.OK:  # the message names the value given (1e200, not the float32 inf it becomes)
            _observer_glue.raise_settings_error(status, given if status == Status.INVALID_GAIN
                                                else tuple(float(g) for g in gains))
        if not period > 0:
            raise ValueError(f"gap_period must be > 0 s (inf: never a gap); got {float(period)}")
        if not timeout > 0:
            raise ValueError(f"baro_timeout must be > 0 s (inf: never times out); got {float(timeout)}")
        self._gains = gains
        self._gap_period = period
        self._baro_timeout = timeout

    @classmethod
    def from_bandwidth(cls, omega: float, zeta: float = 0.7, omega_b: Optional[float] = None,
                       gap_period: float = DEFAULT_GAP_PERIOD,
                       baro_timeout: float = DEFAULT_BARO_TIMEOUT) -> "AltitudeSettings":
        """Gains from position-loop bandwidth ω (rad/s), damping ζ and bias-loop bandwidth ω_b (rad/s).

        ``Kh = 2ζω + ω_b``, ``Kv = ω² + 2ζω·ω_b``, ``Kb = ω²·ω_b`` in float32;
        ``omega_b`` defaults to ``float32(ω) / 5``; ``gap_period`` and ``baro_timeout`` in s.
        """
        omega32 = f32(_common.as_float(omega, "omega"))
        zeta32 = f32(_common.as_float(zeta, "zeta"))
        omega_b32 = omega32 / f32(5) if omega_b is None else f32(_common.as_float(omega_b, "omega_b"))
        status, gains = _settings_from_bandwidth(omega32, zeta32, omega_b32)
        if status != Status.OK:
            _observer_glue.raise_settings_error(status, (float(omega32), float(zeta32), float(omega_b32)))
        return cls(*gains, gap_period=gap_period, baro_timeout=baro_timeout)

    @classmethod
    def preset(cls, name: str) -> "AltitudeSettings":
        """Preset gains: ``balloon`` (ω 0.2), ``fixed_wing`` (0.5), ``vtol`` (1.5, the default), ``racing`` (5.0),
        ``rocket`` (1.0 with ω_b = 0: no bias learning in flight; set the bias from a pad calibration).

        The gap period is 5 s for ``balloon`` (1 Hz baro logs), 0.5 s for the others; the baro timeout
        10 s for ``balloon``, 2 s for the others.
        """
        _observer_glue.check_preset(name)
        return cls(*_PRESET_GAINS[name], gap_period=_PRESET_GAP_PERIODS[name],
                   baro_timeout=_PRESET_BARO_TIMEOUTS[name])

    @property
    def position_gain(self) -> float:
        """Kh, 1/s."""
        return float(self._gains[0])

    @property
    def velocity_gain(self) -> float:
        """Kv, 1/s²."""
        return float(self._gains[1])

    @property
    def bias_gain(self) -> float:
        """Kb, 1/s³."""
        return float(self._gains[2])

    @property
    def gap_period(self) -> float:
        """s: an update whose dt exceeds this is a gap, not integrated."""
        return float(self._gap_period)

    @property
    def baro_timeout(self) -> float:
        """s: after this long without a baro sample the observer stops dead-reckoning."""
        return float(self._baro_timeout)

    def validate(self, dt: float) -> None:
        """Check that the update is stable at sample period ``dt`` (s) (Jury's test).

        Raises ValueError if not; warns :class:`DiscretisationWarning` when the
        fastest observer pole ω has ω·dt ≥ 0.1.
        """
        dt32 = f32(_common.as_float(dt, "dt"))
        c_validate = _observer_glue.C_SETTINGS_FUNCTIONS.get("validate")  # C where built, else the twin
        status = _validate(*self._gains, dt32) if c_validate is None else Status(c_validate(self.as_dict(), dt32))
        if status != Status.OK:
            _observer_glue.raise_settings_error(status, self.as_tuple(), float(dt))
        _observer_glue.warn_if_coarse(self.as_tuple(), float(dt32))

    def as_tuple(self) -> Tuple[float, float, float]:
        """(position_gain, velocity_gain, bias_gain) as Python floats."""
        return (self.position_gain, self.velocity_gain, self.bias_gain)

    def as_dict(self) -> dict:
        """The settings as {name: value}, in the order of the C struct (gains, gap_period, baro_timeout)."""
        return {"position_gain": self.position_gain, "velocity_gain": self.velocity_gain,
                "bias_gain": self.bias_gain, "gap_period": self.gap_period, "baro_timeout": self.baro_timeout}

    def __eq__(self, other: object) -> bool:
        if not hasattr(other, "as_tuple") or not hasattr(other, "velocity_gain"):
            return NotImplemented
        return (self.as_tuple() == other.as_tuple()  # type: ignore[attr-defined]
                and self.gap_period == getattr(other, "gap_period", DEFAULT_GAP_PERIOD)
                and self.baro_timeout == getattr(other, "baro_timeout", DEFAULT_BARO_TIMEOUT))

    def __hash__(self) -> int:
        return hash((self.as_tuple(), self.gap_period, self.baro_timeout))

    def __repr__(self) -> str:
        kh, kv, kb = (str(g) for g in self._gains)
        return (f"AltitudeSettings(position_gain={kh}, velocity_gain={kv}, bias_gain={kb}, "
                f"gap_period={self._gap_period}, baro_timeout={self._baro_timeout})")

    def __reduce__(self):
        return (type(self), (*self.as_tuple(), self.gap_period, self.baro_timeout))


def _as_settings(settings: object) -> AltitudeSettings:
    if isinstance(settings, AltitudeSettings):
        return settings
    if hasattr(settings, "as_tuple"):
        return AltitudeSettings(*settings.as_tuple(),  # type: ignore[attr-defined]
                                gap_period=getattr(settings, "gap_period", DEFAULT_GAP_PERIOD),
                                baro_timeout=getattr(settings, "baro_timeout", DEFAULT_BARO_TIMEOUT))
    raise TypeError(f"settings must be AltitudeSettings, got {type(settings).__name__}")


# -- estimator ---------------------------------------------------------------

class AltitudeEstimator(BaroGapDiagnostics, Checkpointable):
    """3rd-order complementary observer: baro altitude + vertical acceleration.

    Estimates altitude (m), vertical velocity (m/s, +up) and the
    accelerometer's vertical bias (m/s², +up).

    Parameters
    ----------
    settings : AltitudeSettings, optional
        Gains; the defaults (VTOL multirotor) if omitted.

    Notes
    -----
    Inputs: vertical acceleration (m/s², earth frame, +up, gravity removed),
    baro altitude (m; NaN for "no baro this step") and dt (s). The first baro
    sample sets the reference (auto-zero). NED users negate. Copies and
    pickles carry the full state, so a run can be checkpointed and resumed.
    """

    __slots__ = ("_settings", "_h", "_v", "_b", "_r", "_gap_time", "_since_restart", "_since_baro", "_gap_count",
                 "_baro_timeouts", "_reference_set", "_baro_timed_out")

    def __init__(self, settings: Optional[AltitudeSettings] = None) -> None:
        # FusionAltitudeInitialise
        self._settings = AltitudeSettings() if settings is None else _as_settings(settings)
        self._h = self._v = self._b = self._r = self._gap_time = self._since_baro = f32(0)
        self._since_restart = f32(-1)  # no restart yet
        self._gap_count = self._baro_timeouts = 0
        self._reference_set = self._baro_timed_out = False

    # FusionAltitudeTiming: gaps (dt > gap period), stability gaps (an unstable baro step), then the baro timeout
    def _timing(self, dt: np.float32, baro_sample: bool, unstable: bool) -> None:
        if self._reference_set and dt > self._settings._gap_period:  # a gap: restart from the next baro sample
            self._gap_count = (self._gap_count + 1) & 0xFFFFFFFF
            self._reference_set = False
            self._gap_time = dt
        elif self._reference_set and unstable:  # a stability gap: restart at this step's baro sample
            self._gap_count = (self._gap_count + 1) & 0xFFFFFFFF
            self._since_restart = f32(0)
        elif not self._reference_set and self._gap_time > 0:  # still waiting for the baro after a gap
            self._gap_time += dt
        elif self._reference_set and self._since_restart >= 0:  # time since the restart (bias hold)
            self._since_restart += dt
        if baro_sample:
            self._since_baro = f32(0)
        elif self._reference_set or self._gap_time > 0:
            self._since_baro += dt
            if not self._baro_timed_out and self._since_baro > self._settings._baro_timeout:
                self._baro_timeouts = (self._baro_timeouts + 1) & 0xFFFFFFFF
                self._baro_timed_out = True

    # FusionAltitudeUpdate; ``unstable`` (the sweep's shared rule) replaces the step's own stability test
    def _update(self, a: np.float32, z: np.float32, dt: np.float32, unstable: Optional[bool] = None) -> Status:
        status = check_inputs(a, z, dt)
        if status != Status.OK:
            return status
        baro_sample = _is_finite(z)
        # D: the baro interval this step ends, s (dt alone with the timeout off: FusionAltitudeIsStepStable)
        interval = self._since_baro + dt if _is_finite(self._settings._baro_timeout) else dt
        if unstable is None:
            unstable = (baro_sample and self._reference_set and not self._baro_timed_out
                        and not step_stable(*self._settings._gains, dt, interval))
        else:
            unstable = baro_sample and self._reference_set and not self._baro_timed_out and unstable
        self._timing(dt, baro_sample, unstable)
        if not baro_sample:
            if self._reference_set:
                if self._baro_timed_out:  # no dead reckoning beyond the timeout: v decays to 0
                    timeout = self._settings._baro_timeout
                    self._v *= timeout / (timeout + dt)
                else:
                    self._v += (a - self._b) * dt
                self._h += self._v * dt
            self._r = _NAN
            return Status.OK
        if not self._reference_set:
            self._restart(z)
            return Status.OK
        if unstable:  # a stability gap: restart at this sample (the bias hold started in the timing)
            self._h, self._v, self._r = stability_restart(self._h, self._v, self._settings._gains[0],
                                                          self._settings._gains[1], z, dt, interval)
            return Status.OK
        if self._baro_timed_out:  # the first baro sample after a timeout: restart at it, v kept
            self._h = z
            self._r = f32(0)
            self._since_restart = f32(0)
            self._baro_timed_out = False
            return Status.OK
        kh, kv, kb = self._settings._gains
        r = z - self._h
        self._v += ((a - self._b) + kv * r) * dt
        self._h += (self._v + kh * r) * dt
        if not (self._since_restart >= 0 and self._since_restart * kh < BIAS_HOLD):  # no bias hold after a restart
            self._b -= (kb * r) * dt
        self._r = r
        return Status.OK

    # FusionAltitudeReset
    def _reset(self, z: np.float32) -> Status:
        if not _is_finite(z):
            return Status.INVALID_BARO_ALTITUDE
        self._h = z
        self._v = self._r = self._gap_time = self._since_baro = f32(0)
        self._since_restart = f32(-1)  # no bias hold
        self._reference_set, self._baro_timed_out = True, False
        return Status.OK

    # FusionAltitudeRestart: v = mean velocity over the gap (0 on the first sample ever)
    def _restart(self, z: np.float32) -> None:
        velocity = f32(0)
        if self._gap_time > 0:
            self._since_restart = f32(0)  # the bias hold starts
            with np.errstate(over="ignore"):
                velocity = (z - self._h) / self._gap_time
            velocity = velocity if _is_finite(velocity) else f32(0)  # overflow: a gap of a few ulps
        self._v = velocity
        self._h = z
        self._r = self._gap_time = f32(0)
        self._reference_set, self._baro_timed_out = True, False

    def update(self, accel: float, baro_altitude: float, dt: float) -> None:
        with np.errstate(over="ignore"):
            a = f32(_common.as_float(accel, "accel"))
            z = f32(_common.as_float(baro_altitude, "baro_altitude"))
            t = f32(_common.as_float(dt, "dt"))
        status = self._update(a, z, t)
        if status != Status.OK:
            _observer_glue.raise_update_error(status, float(accel), float(baro_altitude), float(dt))  # type: ignore[arg-type]

    def reset(self, baro_altitude: float, accel_bias: Optional[float] = None) -> None:
        """Set the reference: altitude = ``baro_altitude`` (m), velocity 0, residual 0.

        The bias estimate is kept unless ``accel_bias`` (m/s², +up) is given
        (warm start from a ground calibration).
        """
        with np.errstate(over="ignore"):
            z = f32(_common.as_float(baro_altitude, "baro_altitude"))
            b = None if accel_bias is None else f32(_common.as_float(accel_bias, "accel_bias"))
        if not _is_finite(z):
            _observer_glue.raise_reset_error(Status.INVALID_BARO_ALTITUDE, float(z), 0.0)
        if b is not None:
            if not _is_finite(b):
                _observer_glue.raise_reset_error(Status.INVALID_ACCEL_BIAS, float(z), float(b))
            self._b = b
        self._reset(z)

    def update_batch(self, accel, baro_altitude, dt, out: Optional[Sequence[np.ndarray]] = None) -> AltitudeBatch:
        """Process arrays of samples, continuing from the current state.

        Equal, bit for bit, to calling :meth:`update` for each sample. On a bad
        sample nothing is applied (the state is as before the call) and
        ValueError names the argument and the first bad index.
        """
        a, z, t, dt_is_array, result = _observer_glue.prepare_batch(accel, baro_altitude, dt, out)
        trial = copy.copy(self)
        for i in range(a.shape[0]):
            ti = t[i] if dt_is_array else t[0]
            status = trial._update(a[i], z[i], ti)
            if status != Status.OK:
                _observer_glue.raise_update_error(status, float(a[i]), float(z[i]), float(ti), i, dt_is_array)
            result.altitude[i] = trial._h
            result.vertical_velocity[i] = trial._v
            result.accel_bias[i] = trial._b
            result.baro_residual[i] = trial._r
        self._h, self._v, self._b, self._r = trial._h, trial._v, trial._b, trial._r
        self._gap_time, self._gap_count = trial._gap_time, trial._gap_count
        self._since_restart = trial._since_restart
        self._since_baro, self._baro_timeouts = trial._since_baro, trial._baro_timeouts
        self._reference_set = trial._reference_set
        self._baro_timed_out = trial._baro_timed_out
        return result if out is None else out  # out=: the caller's object itself

    altitude = state_property("_h", "Altitude estimate h, m (0 until the reference is set).")
    vertical_velocity = state_property("_v", "Vertical velocity estimate v, m/s, +up.")
    accel_bias = state_property("_b", "Accelerometer bias estimate b, m/s², +up (subtracted from the input).")
    baro_residual = state_property(
        "_r", "Baro residual z − h of the last update before its correction, m (0 after reset, NaN without baro).")
    reference_set = state_property(
        "_reference_set",
        "Whether the reference is set (first baro sample or reset); False again from a gap to the next baro sample.",
        bool)
    settings = settings_property(
        AltitudeSettings, "The gains; assign new :class:`AltitudeSettings` to retune without losing the state.",
        _as_settings)

    def _get_state(self) -> tuple:
        return ((*self._settings.as_tuple(), self._settings.gap_period, self._settings.baro_timeout), float(self._h),
                float(self._v), float(self._b), float(self._r), float(self._gap_time), float(self._since_restart),
                float(self._since_baro), self._gap_count, self._baro_timeouts, self._reference_set,
                self._baro_timed_out)

    def _set_state(self, state: tuple) -> None:
        # the C struct's order; a 6-tuple is a checkpoint from before the gap fields, a 9-tuple one from before the
        # baro timeout
        since_baro, baro_timeouts, baro_timed_out = 0.0, 0, False
        if len(state) == 6:
            gains, h, v, b, r, reference_set = state
            gap_time, since_restart, gap_count = 0.0, -1.0, 0
        elif len(state) == 9:
            gains, h, v, b, r, gap_time, since_restart, gap_count, reference_set = state
        else:
            (gains, h, v, b, r, gap_time, since_restart, since_baro, gap_count, baro_timeouts, reference_set,
             baro_timed_out) = state
        self._settings = AltitudeSettings(*gains)
        self._h, self._v, self._b, self._r = f32(h), f32(v), f32(b), f32(r)
        self._reference_set = bool(reference_set)
        self._gap_time, self._gap_count = f32(gap_time), int(gap_count)
        self._since_restart = f32(since_restart)
        self._since_baro, self._baro_timeouts = f32(since_baro), int(baro_timeouts)
        self._baro_timed_out = bool(baro_timed_out)

    def __repr__(self) -> str:
        return (f"AltitudeEstimator(altitude={self._h}, vertical_velocity={self._v}, accel_bias={self._b}, "
                f"baro_residual={self._r}, settings={self._settings!r})")


_common.share_docstrings(AltitudeEstimator, _observer_glue.AltitudeContract)
