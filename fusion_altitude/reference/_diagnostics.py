"""The gap and baro-timeout diagnostics that the observer and the complementary filter report alike."""

from __future__ import annotations


class BaroGapDiagnostics:
    """``gap_count``, ``baro_timed_out`` and ``baro_timeouts`` of an estimator that keeps them in
    ``_gap_count``, ``_baro_timed_out`` and ``_baro_timeouts`` (its own ``__slots__``)."""

    __slots__ = ()

    @property
    def gap_count(self) -> int:
        """Number of gaps so far: updates whose dt exceeded ``settings.gap_period`` once the reference was set."""
        return self._gap_count

    @property
    def baro_timed_out(self) -> bool:
        """True from a baro timeout to the next baro sample: the output is not baro-aided."""
        return self._baro_timed_out

    @property
    def baro_timeouts(self) -> int:
        """Number of baro timeouts so far: times no baro sample came for more than ``settings.baro_timeout`` s."""
        return self._baro_timeouts
