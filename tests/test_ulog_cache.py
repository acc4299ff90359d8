"""What the fast ULog decoder keeps between logs (fusion_altitude/logs/_ulog_fast.py) changes no result.

The definitions of one firmware (its F messages' bytes: the parsed formats, each topic's layout, each segment's
plan keyed by the bytes of its A messages) are kept in an LRU of ``FIRMWARES`` entries. A read with a warm cache
gives the same LogData, bit for bit, as one with a cold cache, on every shared ULog and fixture; a declined log is
declined for the same reason either way; the same A messages under other formats give other dtypes; the cache is
bounded; threads reading at once get what one thread gets. The end of the plain walk taken from the message
walks (when they stepped over nothing) is the one the walk of every header gives.
"""

import struct
import sys
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from decoder_harness import write_ulog_fixture  # noqa: E402
from fusion_altitude.logs import _truncation, _ulog_fast, ulog  # noqa: E402

SHARED = ["px4_sample_log_small.ulg", "px4_octorotor_2hz_baro.ulg"]
FIXTURES = ["new", "old", "sync", "appended", "appended-old"]


def _fixture(tmp_path, name):
    return write_ulog_fixture(tmp_path / f"{name}.ulg", name, duration=3.0)


def _log_paths(tmp_path, shared_logs):
    return [shared_logs / name for name in SHARED] + [_fixture(tmp_path, name) for name in FIXTURES]


def _topics(blob, cold):
    """``ULogTopics(blob).data`` as {key: {field: (dtype, bytes)}}, or the NeedsReference message; ``cold``:
    the firmware cache emptied first."""
    if cold:
        _ulog_fast.firmware_definitions.cache_clear()
    try:
        data = _ulog_fast.ULogTopics(blob, ulog._TOPICS).data
    except _ulog_fast.NeedsReference as error:
        return f"declined: {error}"
    return {key: {name: (values.dtype, values.tobytes()) for name, values in topic.items()}
            for key, topic in data.items()}


def _log_fields(path, cold):
    """Every field of ``read_ulog(path)`` (arrays as dtype, shape and bytes), or the error; ``cold``: the
    firmware cache emptied first."""
    if cold:
        _ulog_fast.firmware_definitions.cache_clear()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            data = ulog.read_ulog(str(path))
        except Exception as error:  # compared between the two reads
            return (type(error).__name__, str(error))
    return {name: (value.dtype, value.shape, list(value) if value.dtype == object else value.tobytes())
            if isinstance(value, np.ndarray) else value for name, value in vars(data).items()}


def _writer_log(field_type="float", duplicate_msg_id=False, timestamp=True, firmware=0):
    """A small ULog of one topic, ``sensor_combined`` (a uint64 timestamp and a 3-array ``v`` of
    ``field_type``), subscribed once as msg_id 0 (twice if ``duplicate_msg_id``), 5 samples; ``firmware`` > 0
    adds a format ``firmware_<n>`` (other F messages, the same A and D messages)."""
    writer = fx.ULogWriter()
    if firmware:
        writer.define(f"firmware_{firmware}", [("uint64_t", "timestamp", 1)])
    fields = ([("uint64_t", "timestamp", 1)] if timestamp else [("uint64_t", "time", 1)]) + [(field_type, "v", 3)]
    writer.define("sensor_combined", fields)
    writer.subscribe("sensor_combined")
    if duplicate_msg_id:
        writer.data += fx.ULogWriter._message(b"A", struct.pack("<BH", 1, 0) + b"sensor_combined")
    stamp = "timestamp" if timestamp else "time"
    for k in range(5):
        writer.write("sensor_combined", {stamp: 1_000_000 + 5000 * k, "v": (k, 2 * k, 3 * k)})
    return writer.bytes()


def test_a_warm_cache_gives_the_log_data_of_a_cold_one_on_every_shared_log_and_fixture(tmp_path, shared_logs):
    for path in _log_paths(tmp_path, shared_logs):
        cold = _log_fields(path, cold=True)
        assert _log_fields(path, cold=False) == cold, path.name
        assert _ulog_fast.firmware_definitions.cache_info().hits >= 1


def test_a_warm_cache_gives_the_topics_of_a_cold_one_on_every_shared_log_and_fixture(tmp_path, shared_logs):
    for path in _log_paths(tmp_path, shared_logs):
        blob = path.read_bytes()
        cold = _topics(blob, cold=True)
        assert not isinstance(cold, str), path.name
        assert _topics(blob, cold=False) == cold, path.name


def test_a_warm_cache_gives_the_topics_or_the_decline_of_a_cold_one_on_fuzz_mutations(tmp_path, shared_logs):
    """The reader fuzz's mutations of the shared sample and a fixture (seed 2, 30 each), each read warm (its
    firmware read just before) and cold: the same topics, or declined for the same reason."""
    rng = np.random.default_rng(2)
    for seed in (shared_logs / SHARED[0], _fixture(tmp_path, "new")):
        original = seed.read_bytes()
        for data in fx.mutations(original, rng, 30):
            cold = _topics(data, cold=True)
            _topics(original, cold=False)
            assert _topics(data, cold=False) == cold


@pytest.mark.parametrize("log, reason", [
    (dict(duplicate_msg_id=True), "msg_id 0 subscribed twice"),
    (dict(timestamp=False), "sensor_combined: no timestamp field"),
])
def test_a_declined_log_is_declined_for_the_same_reason_with_a_warm_cache(log, reason):
    blob = _writer_log(**log)
    assert _topics(blob, cold=True) == f"declined: {reason}"
    assert _topics(blob, cold=False) == f"declined: {reason}"
    assert _ulog_fast.firmware_definitions.cache_info().hits >= 1


def test_the_same_subscription_bytes_under_other_formats_give_other_dtypes():
    single, double = _writer_log("float"), _writer_log("double")
    _ulog_fast.firmware_definitions.cache_clear()
    tables = [_ulog_fast.ULogTopics(blob, None).data[("sensor_combined", 0)].table for blob in (single, double)]
    assert [tables[0].dtype["v[0]"], tables[1].dtype["v[0]"]] == [np.float32, np.float64]
    assert [list(table["v[2]"]) for table in tables] == [[0.0, 3.0, 6.0, 9.0, 12.0]] * 2
    assert _ulog_fast.firmware_definitions.cache_info().currsize == 2


def test_the_firmware_cache_keeps_the_most_recently_read_firmwares_up_to_its_bound():
    _ulog_fast.firmware_definitions.cache_clear()
    logs = [_writer_log(firmware=k) for k in range(_ulog_fast.FIRMWARES + 8)]
    assert len(logs) > _ulog_fast.FIRMWARES
    for blob in logs:
        _topics(blob, cold=False)
    info = _ulog_fast.firmware_definitions.cache_info()
    assert (info.maxsize, info.currsize, info.hits) == (_ulog_fast.FIRMWARES, _ulog_fast.FIRMWARES, 0)
    _topics(logs[-1], cold=False)
    assert _ulog_fast.firmware_definitions.cache_info().hits == 1


def test_threads_reading_at_once_get_what_one_thread_gets(tmp_path, shared_logs):
    blobs = [path.read_bytes() for path in _log_paths(tmp_path, shared_logs)]
    expected = [_topics(blob, cold=True) for blob in blobs]

    def read(k):
        if k % 7 == 0:
            _ulog_fast.firmware_definitions.cache_clear()
        return _topics(blobs[k % len(blobs)], cold=False)

    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(read, range(8 * len(blobs))))
    assert results == [expected[k % len(blobs)] for k in range(len(results))]


def test_two_reads_share_no_array_a_caller_could_change():
    blob = _writer_log("float")
    first, second = (_ulog_fast.ULogTopics(blob, None).data[("sensor_combined", 0)] for _ in range(2))
    assert not np.shares_memory(first.table, second.table)
    first.table["v[0]"][:] = -1.0
    assert list(_ulog_fast.ULogTopics(blob, None).data[("sensor_combined", 0)]["v[0]"]) == [0.0, 1.0, 2.0, 3.0, 4.0]


def test_the_plain_end_from_the_walks_is_the_end_of_the_walk_of_every_header(tmp_path, shared_logs):
    """On the shared logs and fixtures, whole and cut at a few places (inside headers and payloads): the
    bytes missing from the last message are those :func:`_truncation.ulog_missing_bytes` counts; the sound
    shared logs take the end from the walks (no second walk)."""
    for path in _log_paths(tmp_path, shared_logs):
        blob = path.read_bytes()
        for cut in (len(blob), len(blob) - 1, len(blob) - 2, len(blob) - 5, len(blob) * 2 // 3 + 1):
            cut_path = fx.write_bytes(tmp_path / "cut.ulg", blob[:cut])
            try:
                decoded = _ulog_fast.ULogTopics(blob[:cut], ulog._TOPICS)
            except _ulog_fast.NeedsReference:
                continue
            assert decoded.missing_bytes() == _truncation.ulog_missing_bytes(cut_path), (path.name, cut)
    for name in SHARED:
        assert _ulog_fast.ULogTopics((shared_logs / name).read_bytes(), ulog._TOPICS).plain_end is not None


def _messages(blob):
    """(array, offsets, types, sizes) of every message pyulog reads in a ULog: the definitions, then the data
    section."""
    from fusion_altitude.logs import _decode

    array = np.frombuffer(blob, dtype=np.uint8)
    offsets, types, sizes, start, found, cut = _decode.ulog_definitions(array)
    if not found or cut:
        return array, offsets, types, sizes
    walk = _decode.ulog_data_walk(array, start, [])
    return (array, np.concatenate([offsets, walk[0]]), np.concatenate([types, walk[1]]),
            np.concatenate([sizes, walk[2]]))


def _mutated_logs(tmp_path, shared_logs):
    rng = np.random.default_rng(3)
    originals = [path.read_bytes() for path in _log_paths(tmp_path, shared_logs)]
    return originals + [data for original in originals[:3] for data in fx.mutations(original, rng, 20)]


def test_each_vouched_for_format_is_parsed_in_c_as_pyulog_parses_it(tmp_path, shared_logs):
    from fusion_altitude.logs import _decode

    parsed = 0
    for blob in _mutated_logs(tmp_path, shared_logs):
        array, offsets, types, sizes = _messages(blob)
        formats = types == ord("F")
        starts, lengths = offsets[formats].tolist(), sizes[formats].tolist()
        names = _decode.ulog_format_names(array, np.ascontiguousarray(offsets[formats]),
                                          np.ascontiguousarray(sizes[formats]))
        for start, length, name in zip(starts, lengths, names):
            if name is not None:
                payload = blob[start + 3:start + 3 + length]
                assert _decode.ulog_format_fields(payload, len(name)) == _ulog_fast._parse_format(payload)[1]
                parsed += 1
    assert parsed > 1000


def test_the_message_checks_in_c_are_pyulogs_parse_errors(tmp_path, shared_logs):
    """``ulog_message_checks`` and the checks of ``ulog_checked_tables`` against a transcription: each failing
    type and each non-ASCII key."""
    from fusion_altitude.logs import _decode

    minimum = {ord("L"): 9, ord("C"): 11, ord("A"): 3, ord("D"): 2}
    for blob in _mutated_logs(tmp_path, shared_logs):
        array, offsets, types, sizes = _messages(blob)
        failing, undecided = set(), []
        for k, (offset, kind, size) in enumerate(zip(offsets.tolist(), types.tolist(), sizes.tolist())):
            payload = blob[offset + 3:offset + 3 + size]
            if kind in minimum and size < minimum[kind] or kind == ord("O") and size != 2:
                failing.add(kind)
            elif kind in b"IMPQ":
                key = payload[1:] if kind in b"MQ" else payload
                if key and any(byte >= 0x80 for byte in key[1:1 + key[0]]):
                    undecided.append(k)
                elif not _ulog_fast._info_ok(payload, multiple=kind in b"MQ"):
                    failing.add(kind)
        expected = (bytes(kind for kind in b"LCADOIMPQ" if kind in failing), undecided)
        assert _decode.ulog_message_checks(array, offsets, types, sizes) == expected
        assert _decode.ulog_checked_tables(array, offsets, types, sizes, [])[1:] == expected  # counting as it checks
