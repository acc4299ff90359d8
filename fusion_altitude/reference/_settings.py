"""The settings classes' common behaviour. Each estimator's settings are ONE pure-Python class.

The reference estimators use them, and so does the C binding: ``fusion_altitude.KalmanSettings``
*is* ``fusion_altitude.reference.KalmanSettings``. The binding converts them to the C
struct at the estimator boundary (``_settings_to_c``, generated from the header by
``tools/generate_bindings.py``); the defaults come from the header's ``...SettingsDefault()``
through the generated ``fusion_altitude/_c_tables.py``.

Every settings class has ``as_dict``, ``replace``, equality, hashing, a repr, pickling and
``coerce`` (accept an equal settings object from elsewhere).
"""

from __future__ import annotations

from typing import Callable

from .._core._c_tables import OBSERVER_SETTINGS


class Settings:
    """Base of every settings class. A subclass defines ``as_dict`` and names ``_DISTINCT``."""

    __slots__ = ()

    #: A setting name only this estimator's settings have: how settings of the
    #: same estimator built elsewhere are recognised.
    _DISTINCT = ""

    def as_dict(self) -> dict:
        """Every setting as {name: value}, in the order of the C struct."""
        raise NotImplementedError

    def replace(self, **changes):
        """A copy with some settings changed (checked as by the constructor)."""
        return type(self)(**{**self.as_dict(), **changes})

    @classmethod
    def _is_like(cls, other: object) -> bool:
        return hasattr(other, "as_dict") and hasattr(other, cls._DISTINCT)

    def __eq__(self, other: object) -> bool:
        if not self._is_like(other):
            return NotImplemented
        return self.as_dict() == other.as_dict()  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash(tuple(self.as_dict().items()))

    def __repr__(self) -> str:
        return f"{type(self).__name__}(" + ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items()) + ")"

    def __reduce__(self):
        return (_from_dict, (type(self), self.as_dict()))

    @classmethod
    def coerce(cls, settings: object):
        """``settings`` itself, or an equal instance of ``cls`` built from another settings object."""
        if isinstance(settings, cls):
            return settings
        if cls._is_like(settings):
            return cls(**settings.as_dict())  # type: ignore[attr-defined]
        raise TypeError(f"settings must be {cls.__name__}, got {type(settings).__name__}")


class KeywordSettings(Settings):
    """Base of dict-backed settings. Subclasses set ``_values`` in ``__init__`` and name ``_DISTINCT``."""

    __slots__ = ("_values",)

    def __getattr__(self, name: str):
        values = object.__getattribute__(self, "_values")
        if name in values:
            return values[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def as_dict(self) -> dict:
        """Every setting as {name: value}, in the order of the C struct."""
        return dict(self._values)

    def __hash__(self) -> int:
        return hash(tuple(self._values.items()))

    def _keep_checked(self, values: dict, check: Callable[[dict], int],
                      raise_error: Callable[[int, dict], None]) -> None:
        """Keep ``values`` (converted by the glue) when ``check(values)``, the twin of the header's
        ``…SettingsCheck``, returns OK (0); otherwise ``raise_error(status, values)`` raises, naming the setting."""
        status = check(values)
        if status != 0:
            raise_error(status, values)
        self._values = values


#: The observer's gains, in the order of FusionAltitudeSettings.
GAIN_NAMES = tuple(name for name, *_ in OBSERVER_SETTINGS)


class GainSettings(Settings):
    """Base of the observer's settings, which hold a tuple of gains (``as_tuple``)."""

    __slots__ = ()
    _DISTINCT = "velocity_gain"

    def as_tuple(self) -> tuple:
        raise NotImplementedError

    def as_dict(self) -> dict:
        """The gains as {name: value}, in the order of the C struct."""
        return dict(zip(GAIN_NAMES, self.as_tuple()))


def _from_dict(cls: type, values: dict):
    """What unpickling calls."""
    return cls(**values)
