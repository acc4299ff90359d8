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
import struct
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from decoder_harness import ULOG_FIXTURES as FIXTURES  # noqa: E402
from decoder_harness import assert_fuzz_corpus_replays_clean, assert_same_log, write_ulog_fixture  # noqa: E402
from fusion_altitude.logs import _decode, _ulog_fast, ulog  # noqa: E402

SHARED = ["px4_sample_log_small.ulg", "px4_octorotor_2hz_baro.ulg"]


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
    return write_ulog_fixture(tmp_path / f"{name}.ulg", name, duration=6.0)


def _data_walk(path):
    """``_decode.ulog_data_walk`` of the ULog at ``path`` with the appended offsets its flag bits give."""
    blob = Path(path).read_bytes()
    array = np.frombuffer(blob, dtype=np.uint8)
    offsets, types, sizes, start, found, cut = _decode.ulog_definitions(array)
    assert found and not cut
    flags = types == ord("B")
    decoded = _ulog_fast.ULogTopics(blob, ulog._TOPICS)
    return _decode.ulog_data_walk(array, start, decoded._appended_offsets(offsets[flags].tolist(),
                                                                          sizes[flags].tolist()))


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


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_fixture_is_decoded_in_c_not_left_to_pyulog(tmp_path, name):
    assert _ulog_fast.ULogTopics(_fixture(tmp_path, name).read_bytes(), ulog._TOPICS).data


@pytest.mark.parametrize("name", ["sync", "sync-old"])
def test_damaged_bytes_are_stepped_over_and_reading_resumes_after_each_sync_message(tmp_path, name):
    _, _, _, segment_ends, skipped, synced = _data_walk(_fixture(tmp_path, name))
    assert (len(segment_ends), skipped, synced) == (1, 3, 2)


@pytest.mark.parametrize("name", ["appended", "appended-old"])
def test_appended_data_is_read_as_a_second_segment(tmp_path, name):
    _, _, _, segment_ends, skipped, synced = _data_walk(_fixture(tmp_path, name))
    assert len(segment_ends) == 2 and 0 < segment_ends[0] < segment_ends[1]


def test_appended_data_wins_for_the_topics_it_subscribes_again(tmp_path):
    """pyulog forgets the subscriptions at each appended offset: topics subscribed again take the appended
    samples (from 40 % of the flight), the others keep those before the cut (to 60 %)."""
    topics = _ulog_fast.ULogTopics(_fixture(tmp_path, "appended").read_bytes(), ulog._TOPICS).data
    assert topics[("sensor_combined", 0)]["timestamp"][0] > 2_000_000
    assert topics[("vehicle_local_position", 0)]["timestamp"][0] == 1_000_000


@pytest.mark.parametrize("seed", ["fixture", "sync", "appended", "px4_sample_log_small.ulg"])
def test_fuzz_mutations_read_the_same_with_both_decoders(tmp_path, shared_logs, seed):
    """The reader fuzz's mutations (truncations, bit flips, random bytes, deleted runs; seed 1, 40 per seed
    file) of its ULog seeds: the plain fixture, the damaged ones and the shared sample."""
    if seed == "fixture":
        path = tmp_path / "seed.ulg"
        fx.write_ulog(path, duration=2.0, imu_rate=20.0, baro_rate=10.0, gps_rate=5.0)
    elif seed in ("sync", "appended"):
        path = Path(fx.write_ulog_damaged(tmp_path / "seed.ulg", seed, duration=2.0, imu_rate=20.0, baro_rate=10.0,
                                          gps_rate=5.0))
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


def test_a_subscription_of_under_three_bytes_is_left_to_pyulog_and_reads_the_same(tmp_path):
    # the reader fuzzer's finding (seed 13): the segment's plan read the A message before its check declined it
    path = _fixture(tmp_path, "new")
    blob = path.read_bytes()
    section_start = _decode.ulog_definitions(np.frombuffer(blob, dtype=np.uint8))[3]
    short = struct.pack("<HB", 2, ord("A")) + b"\x01\x00"
    cut = fx.write_bytes(tmp_path / "short_subscription.ulg", blob[:section_start] + short + blob[section_start:])
    with pytest.raises(_ulog_fast.NeedsReference, match="A message too short"):
        _ulog_fast.ULogTopics(Path(cut).read_bytes(), ulog._TOPICS)
    _assert_same_log(cut)
