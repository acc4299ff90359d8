"""Read one log with two decoders and compare: the harness of tests/test_decode_dataflash.py and
tests/test_decode_ulog.py (the fast C decoders against pymavlink and pyulog)."""

import subprocess
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: The DataFlash fixtures the decoder tests write (``logfixtures.write_dataflash`` options by name).
DATAFLASH_FIXTURES = {
    "TimeMS": dict(style="TimeMS"),
    "TimeUS": dict(style="TimeUS"),
    "TimeUS-gap-repeats": dict(style="TimeUS", gap=(5.0, 6.0), repeat_every=7),
    "TimeMS-corrupt-tail": dict(style="TimeMS", corrupt_tail=True),
    "TimeUS-corrupt-tail": dict(style="TimeUS", corrupt_tail=True),
}
#: The ULog fixtures (``logfixtures.write_ulog`` options by name; ``damage``: ``write_ulog_damaged``'s kind).
ULOG_FIXTURES = {"new": dict(style="new"), "old": dict(style="old"), "gap": dict(style="new", gap=(3.0, 4.0)),
                 "sync": dict(style="new", damage="sync"), "sync-old": dict(style="old", damage="sync"),
                 "appended": dict(style="new", damage="appended"), "appended-old": dict(style="old", damage="appended")}


def write_ulog_fixture(path, name, duration):
    """Write the ULog fixture ``name`` of :data:`ULOG_FIXTURES`, ``duration`` s long, to ``path``."""
    import logfixtures as fx

    options = dict(ULOG_FIXTURES[name])
    damage = options.pop("damage", None)
    if damage is None:
        fx.write_ulog(path, duration=duration, **options)
    else:
        fx.write_ulog_damaged(path, damage, duration=duration, **options)
    return path


def read_with(reader, path, decoder, **options):
    """(LogData or the error as (type name, message), warning texts) of ``reader(path, decoder=decoder)``.

    Warnings of the reference libraries' unclosed files (ResourceWarning, collected at random moments) are not
    the reader's and are left out."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = reader(str(path), decoder=decoder, **options)
        except Exception as error:  # compared between the decoders
            result = (type(error).__name__, str(error))
    return result, [str(w.message) for w in caught if not issubclass(w.category, ResourceWarning)]


def assert_same_log(reader, path, reference, **options):
    """``reader`` with ``decoder="fast"`` and ``decoder=reference`` gives the same LogData bit for bit (every
    array by its bytes, dtype and shape), the same warnings, or the same error."""
    mine, my_warnings = read_with(reader, path, "fast", **options)
    theirs, their_warnings = read_with(reader, path, reference, **options)
    assert my_warnings == their_warnings
    if isinstance(theirs, tuple) or isinstance(mine, tuple):
        assert mine == theirs
        return
    mine_fields, their_fields = vars(mine), vars(theirs)
    assert set(mine_fields) == set(their_fields)
    for name, value in their_fields.items():
        other = mine_fields[name]
        if isinstance(value, np.ndarray):
            assert isinstance(other, np.ndarray) and other.dtype == value.dtype and other.shape == value.shape, name
            if value.dtype == object:
                assert list(other) == list(value), name
            else:
                assert other.tobytes() == value.tobytes(), name
        else:
            assert other == value, name


def assert_fuzz_corpus_replays_clean(name, directory, minimum_files):
    """Build ``csrc/fuzz/fuzz_<name>.c`` with clang under libFuzzer, ASan and UBSan (warnings are errors) in
    ``directory`` and replay ``csrc/fuzz/corpus_<name>`` (at least ``minimum_files`` inputs): every input runs,
    none fails a CHECK or a sanitizer."""
    binary = directory / f"fuzz_{name}"
    build = subprocess.run(["clang", "-std=c99", "-g", "-O1", "-fsanitize=fuzzer,address,undefined",
                            "-fno-sanitize-recover=all", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
                            f"-I{ROOT / 'fusion_altitude' / 'logs'}", f"-I{ROOT / 'csrc'}",
                            str(ROOT / "csrc" / "fuzz" / f"fuzz_{name}.c"), "-o", str(binary)],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    files = sorted((ROOT / "csrc" / "fuzz" / f"corpus_{name}").iterdir())
    assert len(files) >= minimum_files
    run = subprocess.run([str(binary), "-runs=0", *map(str, files)], capture_output=True, text=True, timeout=600,
                         cwd=directory)
    assert run.returncode == 0, run.stderr[-3000:]
    assert run.stderr.count("Executed ") == len(files)
    assert "ERROR" not in run.stderr
