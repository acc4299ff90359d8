"""The read-only properties of the references, declared as one line each.

Most getters of a reference estimator return one field of its state, converted to a Python type:
``altitude = state_property("_h", "Altitude estimate h, m.")`` is the property

.. code-block:: python

    @property
    def altitude(self) -> float:
        \"\"\"Altitude estimate h, m.\"\"\"
        return float(self._h)

and ``channels_property`` the same over each sensor channel (``KalmanSensors``, ``AlphaBetaSensors``).
``BaroGapDiagnostics`` holds the gap and baro-timeout counters that the observer and the complementary
filter report alike.
"""

from __future__ import annotations

from operator import attrgetter
from typing import Callable, Optional


def state_property(attribute: str, doc: Optional[str], kind: Callable = float, index: Optional[int] = None) -> property:
    """A read-only property returning ``kind(self.<attribute>)``, or ``kind(self.<attribute>[index])``.

    Parameters
    ----------
    attribute : str
        The state field, a dotted path allowed (``"_obs._v"``).
    doc : str or None
        The property's docstring.
    kind : callable, default float
        The Python type of the value (float, int, bool, an enum); its name is the getter's return annotation.
    index : int, optional
        An entry of the field (a state vector's).
    """
    field = attrgetter(attribute)

    def get(self):
        return kind(field(self) if index is None else field(self)[index])

    get.__annotations__ = {"return": kind.__name__}
    get.__doc__ = doc
    return property(get, doc=doc)


def channels_property(channels: str, attribute: str, result: type, doc: str, kind: Callable = float) -> property:
    """A read-only property returning ``result(*(kind(c.<attribute>) for c in self.<channels>))``: one value
    per sensor channel, e.g. each Kalman sensor's innovation as a ``KalmanSensors``."""
    field = attrgetter(attribute)

    def get(self):
        return result(*(kind(field(channel)) for channel in getattr(self, channels)))

    get.__annotations__ = {"return": result.__name__}
    get.__doc__ = doc
    return property(get, doc=doc)


def settings_property(settings_class: type, doc: Optional[str], coerce: Optional[Callable] = None,
                      attribute: str = "_settings") -> property:
    """The ``settings`` property of an estimator that can be retuned: the settings in use (a ``settings_class``),
    and an assignment that keeps the state and stores ``coerce(settings)`` (default
    ``settings_class.coerce``, which raises TypeError on anything else)."""
    convert = settings_class.coerce if coerce is None else coerce

    def get(self):
        return getattr(self, attribute)

    def assign(self, settings) -> None:
        setattr(self, attribute, convert(settings))

    get.__annotations__ = {"return": settings_class.__name__}
    assign.__annotations__ = {"settings": settings_class.__name__, "return": "None"}
    get.__doc__ = doc
    return property(get, assign, doc=doc)


class BaroGapDiagnostics:
    """``gap_count``, ``baro_timed_out`` and ``baro_timeouts`` of an estimator that keeps them in
    ``_gap_count``, ``_baro_timed_out`` and ``_baro_timeouts`` (its own ``__slots__``)."""

    __slots__ = ()

    gap_count = state_property(
        "_gap_count",
        "Number of gaps so far: updates whose dt exceeded ``settings.gap_period`` once the reference was set.", int)
    baro_timed_out = state_property(
        "_baro_timed_out", "True from a baro timeout to the next baro sample: the output is not baro-aided.", bool)
    baro_timeouts = state_property(
        "_baro_timeouts",
        "Number of baro timeouts so far: times no baro sample came for more than ``settings.baro_timeout`` s.", int)
