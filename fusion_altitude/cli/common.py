"""What every subcommand of the CLI shares: the limits of its numeric options, its errors (one line on stderr, exit
status 2; 3 for a refused estimate), number, output-path and extra checks, and the plain-text table. Every other
module of ``cli/`` imports it; it imports none of them."""

from __future__ import annotations

import contextlib
import math
import os
from typing import List, Optional, Sequence

__all__ = ["PROGRESS_MINIMUM", "MAX_TUNE_RATE", "MIN_TUNE_RATE", "MAX_OMEGA", "MAX_ZETA", "CliError", "EstimateError",
           "format_table", "number", "same_file", "input_files", "is_sibling_name", "RUN_OUTPUT_EXTENSIONS",
           "check_output", "try_create", "check_plot", "same_file_name", "check_attitude"]

#: Logs with at least this many samples get progress bars on stderr.
PROGRESS_MINIMUM = 100_000
#: Highest ``tune --rate``, Hz: the settling times come from a float64 simulation of 600 s at the rate.
MAX_TUNE_RATE = 10_000.0
#: Lowest ``tune --rate``, Hz (one sample in 1000 s): below it dt³ · the gains overflow float64.
MIN_TUNE_RATE = 0.001
#: Highest ``--omega``/``--omega-b`` (tune) and ``--omega-max`` (fit), rad/s: at the highest ``tune --rate``
#: ω·dt = 1, far past the observer's stability limit; beyond it the gains overflow float32.
MAX_OMEGA = 10_000.0
#: Highest ``tune --zeta``: far past any useful damping; beyond it the gains overflow.
MAX_ZETA = 100.0


class CliError(Exception):
    """An input problem to report to the user in one line (exit status 2)."""

    status = 2


class EstimateError(CliError):
    """An estimate that cannot be printed (non-finite, or a runaway from every height source of the log): one
    line, exit status 3. Never an exit 0 with an answer the program cannot stand behind."""

    status = 3


def format_table(header: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """Plain-text table: the first column left-aligned, the others right-aligned.

    Floats are printed with 4 decimals (NaN as "—"); other values with ``str``.
    """
    def cell(value: object) -> str:
        if isinstance(value, float):
            return "—" if math.isnan(value) else f"{value:.4f}"
        return str(value)

    text = [[cell(v) for v in row] for row in [list(header)] + [list(r) for r in rows]]
    widths = [max(len(row[i]) for row in text) for i in range(len(header))]
    lines = []
    for k, row in enumerate(text):
        parts = [row[0].ljust(widths[0])] + [row[i].rjust(widths[i]) for i in range(1, len(row))]
        lines.append("  ".join(parts).rstrip())
        if k == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


# ----------------------------------------------------------------------------
# validation of flags (by their names) and of output paths


def number(flag: str, value: Optional[float], minimum: Optional[float] = None, strict: bool = True,
            maximum: Optional[float] = None) -> None:
    """CliError naming ``flag`` unless ``value`` is finite and above ``minimum`` (≥ when not strict)."""
    if value is None:
        return
    if not math.isfinite(value):
        raise CliError(f"{flag} must be a finite number, got {value:g}")
    if minimum is not None and (value <= minimum if strict else value < minimum):
        raise CliError(f"{flag} must be {'>' if strict else '>='} {minimum:g}, got {value:g}")
    if maximum is not None and value > maximum:
        raise CliError(f"{flag} must be <= {maximum:g}, got {value:g}")


def check_search_flags(args) -> None:
    """CliError for the search flags ``fit`` and ``fleet fit`` share: ``--skip`` (s, >= 0) and the omega range
    (rad/s, ``--omega-min`` below ``--omega-max``, both in (0, MAX_OMEGA])."""
    number("--skip", args.skip, 0.0, strict=False)
    number("--omega-min", args.omega_min, 0.0, maximum=MAX_OMEGA)
    number("--omega-max", args.omega_max, 0.0, maximum=MAX_OMEGA)
    if args.omega_min >= args.omega_max:
        raise CliError(f"--omega-min ({args.omega_min:g}) must be below --omega-max ({args.omega_max:g})")


def same_file_name(a: str, b: str) -> bool:
    """``a`` and ``b`` name the same path (after making them absolute; neither need exist)."""
    return os.path.abspath(a) == os.path.abspath(b)


def same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def input_files(path: str) -> List[str]:
    """Every file the reader of ``path`` opens: the file itself and, for a multi-file log (a CATS set: baro, IMU,
    flight info), its siblings."""
    from .. import logs

    files = [path]
    with contextlib.suppress(OSError, ValueError):
        if logs.sniff_format(path) == "cats":
            files += list(logs.find_cats_files(path).values())
    return files


def is_sibling_name(path: str, inputs: Sequence[str]) -> bool:
    """``path`` (existing or not) is named as a member of the multi-file log in ``inputs`` (a CATS
    ``<prefix>baro.csv``/``imu.csv``/``flight_info.csv`` beside them): the next read would take it for one."""
    from ..logs import cats

    mine = cats._split_name(os.path.abspath(path))
    if mine is None:
        return False
    for source in inputs:
        theirs = cats._split_name(os.path.abspath(source)) if source and not os.path.isdir(source) else None
        if theirs is not None and os.path.realpath(mine[0]) == os.path.realpath(theirs[0]) \
                and mine[1].lower() == theirs[1].lower():
            return True
    return False


#: File name endings of ``run -o`` (a device, a FIFO or ``-`` get CSV).
RUN_OUTPUT_EXTENSIONS = (".csv", ".parquet")


def check_output(path: Optional[str], flag: str, inputs: Sequence[str] = (), stdout: bool = False,
                  extensions: Optional[Sequence[str]] = None) -> None:
    """Before any work: ``path`` can be written and touches no input.

    Refused, each in one line: an empty name or a folder; any file the
    reader opens (``inputs`` and, for a multi-file log, its siblings, after
    symlinks and hard links: same device and inode) or a name the next read
    would take for one; a folder that does not exist or where no file can be
    created (tried: ``/proc``); an extension not in ``extensions`` (None:
    any; ``.parquet`` needs pyarrow); ``-`` unless ``stdout``. An existing device or FIFO is accepted when writable: it is
    written in place, never replaced.
    """
    if path is None:
        return
    if not path or path.endswith(os.sep):
        raise CliError(f"{flag} needs a file name, got {path!r}")
    if path == "-":
        if stdout:
            return
        raise CliError(f"{flag} - (standard output) is not supported here: give a file name")
    every = [f for source in inputs if source for f in input_files(source)]
    for source in every:
        if os.path.exists(path) and same_file(path, source):
            what = "the input file" if any(same_file(source, given) for given in inputs if given) else \
                f"a file the reader opens with {inputs[0]}"
            raise CliError(f"{flag} {path} is {what}: refusing to overwrite it")
    if is_sibling_name(path, every):
        raise CliError(f"{flag} {path} is named as a file of the multi-file log {inputs[0]}: the next read would "
                       "take it for one; choose another name")
    from ..outputs import is_special_output

    if is_special_output(path):
        if not os.access(path, os.W_OK):
            raise CliError(f"{flag} {path}: permission denied")
        return
    extension = os.path.splitext(path)[1].lower()
    if extensions is not None and extension not in extensions:
        raise CliError(f"{flag} {path}: writes {' or '.join(extensions)} files, not {extension or 'a name without an extension'}")
    if extension == ".parquet":
        try:
            import pyarrow.parquet  # noqa: F401
        except ImportError:
            raise CliError(f"{flag} {path}: Parquet output needs pyarrow: pip install 'fusion-altitude[fleet]'") from None
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise CliError(f"{flag} {path}: folder {folder} does not exist")
    if os.path.isdir(path):
        raise CliError(f"{flag} {path} is a folder, not a file")
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        raise CliError(f"{flag} {path}: permission denied")
    try_create(path, flag, folder)


def try_create(path: str, flag: str, folder: str) -> None:
    """CliError naming ``path`` when no file can be created in its folder (a read-only or virtual file system
    such as /proc, where the access check says yes): a temporary file is created there and removed."""
    import tempfile

    try:
        handle, probe = tempfile.mkstemp(prefix=".fusion-altitude-probe.", dir=folder)
    except OSError as error:
        raise CliError(f"{flag} {path}: cannot create a file in {folder}: {error.strerror}") from None
    os.close(handle)
    with contextlib.suppress(OSError):
        os.unlink(probe)


def check_plot(path: Optional[str], inputs: Sequence[str] = ()) -> None:
    """Before any work: matplotlib is installed, it can write ``path``'s format, and the path is writable."""
    if path is None:
        return
    check_output(path, "--plot", inputs)
    from ..plotting import check_plot_path

    try:
        check_plot_path(path)
    except ImportError:
        raise CliError("--plot needs matplotlib: pip install 'fusion-altitude[plot]'") from None
    except ValueError as error:
        raise CliError(f"--plot {path}: {error}") from None


def check_attitude(attitude: str) -> None:
    """Before any work: ``--attitude ahrs`` has imufusion (the ``[ahrs]`` extra)."""
    if attitude == "ahrs":
        try:
            import imufusion  # noqa: F401
        except ImportError:
            raise CliError("--attitude ahrs needs imufusion: pip install 'fusion-altitude[ahrs]'") from None
