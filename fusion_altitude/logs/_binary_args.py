"""The argument checks the binary-log readers (:mod:`.dataflash`, :mod:`.ulog`) share."""

from __future__ import annotations

import os
from typing import Optional, Sequence

from ._data import LogError


def checked_instance(path: str, instance: Optional[int], decoder: str, decoders: Sequence[str], what: str) -> int:
    """The sensor instance a binary-log reader is asked for (0 when ``instance`` is None), after checking its
    arguments.

    Raises
    ------
    ValueError
        ``decoder`` is not one of ``decoders``.
    LogError
        ``instance`` below 0, or ``path`` a directory (not ``what``, e.g. "a PX4 ULog").
    """
    if decoder not in decoders:
        raise ValueError(f"decoder must be one of {', '.join(decoders)}, got {decoder!r}")
    want = 0 if instance is None else int(instance)
    if want < 0:
        raise LogError(f"instance must be 0 or more, got {want}")
    if os.path.isdir(path):
        raise LogError(f"{path}: is a directory, not {what}")
    return want

