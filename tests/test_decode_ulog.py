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
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from decoder_harness import assert_fuzz_corpus_replays_clean, assert_same_log  # noqa: E402
from fusion_altitude.logs import _ulog_fast, ulog  # noqa: E402

SHARED = ["px4_sample_log_small.ulg", "px4_octorotor_2hz_baro.ulg"]
FIXTURES = {"new": dict(style="new"), "old": dict(style="old"), "gap": dict(style="new", gap=(3.0, 4.0))}


def _assert_same_log(path, **options):
    """Both decoders give the same LogData bit for bit, the same warnings, or the same error."""
    assert_same_log(ulog.read_ulog, path, "pyulog", **options)


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
    assert_fuzz_corpus_replays_clean("ulog", tmp_path, minimum_files=2)
