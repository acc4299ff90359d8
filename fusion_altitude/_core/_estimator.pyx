# cython: language_level=3
"""The base of every binding estimator: checkpointing and status messages, once.

It mirrors :class:`fusion_altitude.reference._checkpoint.Checkpointable`: a
subclass defines ``_get_state``/``_set_state`` (generated from the header's
state struct, see ``tools/generate_bindings.py``) and gets ``copy.copy``,
``copy.deepcopy`` and ``pickle`` that carry the full state, so a run can be
checkpointed and resumed with identical results.
"""

from fusion_altitude import _c_tables, _common
from fusion_altitude.reference._checkpoint import restore


cdef class Estimator:
    """Copy, deepcopy, pickle and ``status_message`` through the subclass's ``_get_state``/``_set_state``."""

    def __copy__(self):
        return restore(type(self), self._get_state())

    def __deepcopy__(self, memo):
        return self.__copy__()

    def __reduce__(self):
        return (restore, (type(self), self._get_state()))

    def reset(self):
        """Back to the start state, keeping the settings (estimators with a reference altitude override this)."""
        self.__init__(self.settings)

    @classmethod
    def status_message(cls, status):
        """The C header's message for a status code of this estimator (``...StatusMessage``)."""
        return _common.status_message(_c_tables.STATUS_MESSAGES[cls.__name__], status)
