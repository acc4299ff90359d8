"""Copy, pickle and status messages for the reference estimators, from their ``_get_state``/``_set_state``.

Every estimator carries its full state in one tuple, so a run can be
checkpointed (``copy.copy``, ``copy.deepcopy``, ``pickle``) and resumed with
identical results. The C binding's base class (``fusion_altitude/_estimator.pyx``)
does the same, so the two implementations restore each other's checkpoints.
"""

from __future__ import annotations

from .._core import _c_tables, _common


class Checkpointable:
    """Mixin: ``__copy__``, ``__deepcopy__``, ``__reduce__`` and ``status_message`` through ``_get_state``/``_set_state``."""

    __slots__ = ()

    def _get_state(self) -> tuple:
        raise NotImplementedError

    def _set_state(self, state: tuple) -> None:
        raise NotImplementedError

    def __copy__(self):
        return restore(type(self), self._get_state())

    def __deepcopy__(self, memo: dict):
        return self.__copy__()

    def __reduce__(self):
        return (restore, (type(self), self._get_state()))

    def reset(self) -> None:
        """Back to the start state, keeping the settings (estimators with a reference altitude override this)."""
        self.__init__(self.settings)

    @classmethod
    def status_message(cls, status: int) -> str:
        """The C header's message for a status code of this estimator (``...StatusMessage``)."""
        return _common.status_message(_c_tables.STATUS_MESSAGES[cls.__name__], status)


def restore(cls: type, state: tuple):
    """A new ``cls`` instance holding ``state`` (what unpickling calls)."""
    instance = cls.__new__(cls)
    instance._set_state(state)
    return instance
