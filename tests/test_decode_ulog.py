"""The fast ULog decoder (C index, fusion_altitude/logs/_ulog_fast.py) reads what pyulog reads, bit for bit.

pyulog is the reference: on the shared logs, every fixture style and the
reader-fuzz mutations of the fuzz seeds, ``read_ulog(decoder="fast")`` and
``read_ulog(decoder="pyulog")`` give the same LogData (every array compared by
its bytes, time stamps included), the same warnings and the same errors; and
the decoded topics themselves (every field of every topic the reader asks for,
nested types flattened) equal pyulog's ``data_list``.
"""

import contextlib
import io
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from fusion_altitude.logs import _ulog_fast, ulog  # noqa: E402

SHARED = ["px4_sample_log_small.ulg", "px4_octorotor_2hz_baro.ulg"]
FIXTURES = {"new": dict(style="new"), "old": dict(style="old"), "gap": dict(style="new", gap=(3.0, 4.0))}


def _read(path, decoder, **options):
    """(LogData or the error as (type name, message), warning texts) of one read."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = ulog.read_ulog(str(path), decoder=decoder, **options)
        except Exception as error:  # compared between the decoders
            result = (type(error).__name__, str(error))
    return result, [str(w.message) for w in caught if not issubclass(w.category, ResourceWarning)]


def _assert_same_log(path, **options):
    """Both decoders give the same LogData bit for bit, the same warnings, or the same error."""
    mine, my_warnings = _read(path, "fast", **options)
    theirs, their_warnings = _read(path, "pyulog", **options)
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


def _assert_same_topics(path):
    from pyulog import ULog

    with contextlib.redirect_stdout(io.StringIO()):
        reference = ULog(str(path), ulog._TOPICS)
    theirs = {(d.name, d.multi_id): d.data for d in reference.data_list}
    mine = _ulog_fast.ULogTopics(Path(path).read_bytes(), ulog._TOPICS).data
    assert set(mine) == set(theirs)
    for key, fields in theirs.items():
        assert list(mine[key]) == list(fields), key
        for name, values in fields.items():
            assert mine[key][name].dtype == values.dtype, (key, name)
            assert mine[key][name].tobytes() == values.tobytes(), (key, name)


def _fixture(tmp_path, name):
    path = tmp_path / f"{name}.ulg"
    fx.write_ulog(path, duration=6.0, **FIXTURES[name])
    return path


@pytest.mark.parametrize("name", SHARED)
def test_shared_log_decodes_topic_for_topic_as_pyulog(shared_logs, name):
    _assert_same_topics(shared_logs / name)


@pytest.mark.parametrize("name", SHARED)
@pytest.mark.parametrize("instance", [0, 1])
def test_shared_log_reads_the_same_with_both_decoders(shared_logs, name, instance):
    _assert_same_log(shared_logs / name, instance=instance)


@pytest.mark.parametrize("name", SHARED)
def test_shared_log_is_decoded_in_c_not_left_to_pyulog(shared_logs, name):
    assert _ulog_fast.ULogTopics((shared_logs / name).read_bytes(), ulog._TOPICS).data


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_fixture_decodes_topic_for_topic_as_pyulog(tmp_path, name):
    _assert_same_topics(_fixture(tmp_path, name))


@pytest.mark.parametrize("name", sorted(FIXTURES))
@pytest.mark.parametrize("instance", [0, 1])
def test_fixture_reads_the_same_with_both_decoders(tmp_path, name, instance):
    _assert_same_log(_fixture(tmp_path, name), instance=instance)


@pytest.mark.parametrize("seed", ["fixture", "px4_sample_log_small.ulg"])
def test_fuzz_mutations_read_the_same_with_both_decoders(tmp_path, shared_logs, seed):
    """The reader fuzz's mutations (truncations, bit flips, random bytes, deleted runs; seed 1, 40 per seed
    file) of its two ULog seeds."""
    if seed == "fixture":
        path = tmp_path / "seed.ulg"
        fx.write_ulog(path, duration=2.0, imu_rate=20.0, baro_rate=10.0, gps_rate=5.0)
    else:
        path = shared_logs / seed
    rng = np.random.default_rng(1)
    for number, data in enumerate(fx.mutations(path.read_bytes(), rng, 40)):
        _assert_same_log(fx.write_bytes(tmp_path / f"mutation{number}.ulg", data))


def test_unknown_decoder_is_refused_naming_the_argument(shared_logs):
    with pytest.raises(ValueError, match="decoder"):
        ulog.read_ulog(str(shared_logs / SHARED[0]), decoder="pymavlink")


def test_scanner_fuzz_corpus_replays_clean_under_asan_and_ubsan(tmp_path):
    """csrc/fuzz/fuzz_ulog.c over csrc/fuzz/corpus_ulog: the C scanner walks the messages as pyulog does and
    reads nothing outside the log."""
    import subprocess

    root = Path(__file__).resolve().parents[1]
    binary = tmp_path / "fuzz_ulog"
    build = subprocess.run(["clang", "-std=c99", "-g", "-O1", "-fsanitize=fuzzer,address,undefined",
                            "-fno-sanitize-recover=all", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
                            f"-I{root / 'fusion_altitude' / 'logs'}", str(root / "csrc" / "fuzz" / "fuzz_ulog.c"),
                            "-o", str(binary)], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    files = sorted((root / "csrc" / "fuzz" / "corpus_ulog").iterdir())
    assert len(files) >= 2
    run = subprocess.run([str(binary), "-runs=0", *map(str, files)], capture_output=True, text=True, timeout=600,
                         cwd=tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    assert run.stderr.count("Executed ") == len(files)
    assert "ERROR" not in run.stderr
