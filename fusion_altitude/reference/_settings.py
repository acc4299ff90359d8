"""Settings held as ``{name: value}`` in the C struct's order, for the reference estimators.

The Kalman filter, the complementary filter and the alpha-beta fusion take
their settings as keyword arguments; this base gives them attribute access,
``as_dict``, equality with the C binding's settings, hashing, a repr, pickling
and the conversion of foreign settings objects.
"""

from __future__ import annotations


class KeywordSettings:
    """Base of dict-backed settings. Subclasses set ``_values`` in ``__init__`` and name ``_DISTINCT``."""

    __slots__ = ("_values",)

    #: A setting name only this estimator's settings have: how settings of the
    #: same estimator from the other implementation (the C binding) are recognised.
    _DISTINCT = ""

    def __getattr__(self, name: str):
        values = object.__getattribute__(self, "_values")
        if name in values:
            return values[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def as_dict(self) -> dict:
        """Every setting as {name: value}, in the order of the C struct."""
        return dict(self._values)

    @classmethod
    def _is_like(cls, other: object) -> bool:
        return hasattr(other, "as_dict") and hasattr(other, cls._DISTINCT)

    def __eq__(self, other: object) -> bool:
        if not self._is_like(other):
            return NotImplemented
        return self.as_dict() == other.as_dict()  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash(tuple(self._values.items()))

    def __repr__(self) -> str:
        return f"{type(self).__name__}(" + ", ".join(f"{k}={v!r}" for k, v in self._values.items()) + ")"

    def __reduce__(self):
        return (_from_dict, (type(self), self.as_dict()))

    @classmethod
    def coerce(cls, settings: object):
        """``settings`` itself, or an equal instance of ``cls`` built from the other implementation's settings."""
        if isinstance(settings, cls):
            return settings
        if cls._is_like(settings):
            return cls(**settings.as_dict())  # type: ignore[attr-defined]
        raise TypeError(f"settings must be {cls.__name__}, got {type(settings).__name__}")


def _from_dict(cls: type, values: dict):
    """What unpickling calls."""
    return cls(**values)
