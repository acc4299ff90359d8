"""Copy and pickle for the reference estimators, from their ``_get_state``/``_set_state``.

Every estimator carries its full state in one tuple, so a run can be
checkpointed (``copy.copy``, ``copy.deepcopy``, ``pickle``) and resumed with
identical results.
"""

from __future__ import annotations


class Checkpointable:
    """Mixin: ``__copy__``, ``__deepcopy__`` and ``__reduce__`` through ``_get_state``/``_set_state``."""

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


def restore(cls: type, state: tuple):
    """A new ``cls`` instance holding ``state`` (what unpickling calls)."""
    instance = cls.__new__(cls)
    instance._set_state(state)
    return instance
