"""Stage times and progress bars on stderr, shared by the subcommands that read, estimate, write and plot."""

from __future__ import annotations

import contextlib
import sys
import time as _time
from typing import Callable, Iterator

from .common import PROGRESS_MINIMUM

__all__ = ["STAGE_REPORT_SECONDS", "Progress"]

#: A stage that takes at least this long prints its time on stderr, s. :func:`fusion_altitude.cli.main` sets it
#: from ``fusion_altitude.cli.STAGE_REPORT_SECONDS`` (the one knob) before each command.
STAGE_REPORT_SECONDS = 0.5


class Progress:
    """Stage times and progress bars on stderr.

    Each stage (reading, estimating, writing, plotting, fitting) prints its
    duration when it takes ≥ :data:`STAGE_REPORT_SECONDS`; on a terminal,
    stages over logs of ≥ :data:`PROGRESS_MINIMUM` samples (and every fit)
    also draw a bar while they run.
    """

    def __init__(self, stream=None, width: int = 30, minimum: int = PROGRESS_MINIMUM):
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.minimum = minimum

    def bar(self, name: str) -> Callable[[int, int], None]:
        interactive = bool(getattr(self.stream, "isatty", lambda: False)())

        def draw(done: int, total: int) -> None:
            if not interactive or (total < self.minimum and name not in ("fitting", "comparing")):
                return
            filled = int(self.width * done / max(total, 1))
            self.stream.write(f"\r{name:<10} [{'#' * filled}{'.' * (self.width - filled)}] "
                              f"{100 * done / max(total, 1):5.1f}%")
            if done >= total:
                self.stream.write("\r" + " " * (self.width + 22) + "\r")
            self.stream.flush()
        return draw

    @contextlib.contextmanager
    def stage(self, name: str) -> Iterator[Callable[[int, int], None]]:
        start = _time.perf_counter()
        yield self.bar(name)
        elapsed = _time.perf_counter() - start
        if elapsed >= STAGE_REPORT_SECONDS:
            self.stream.write(f"{name}: {elapsed:.2f} s\n")
            self.stream.flush()
