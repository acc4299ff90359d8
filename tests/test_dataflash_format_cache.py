"""The DataFlash fast reader's format cache (``_dataflash_fast.format_table``): what a log's FMT messages say is
kept per firmware, keyed by the FMT messages' bytes, and a log read with a warm cache reads exactly as with a
cold one.

Warm and cold are compared on ``dataflash._read_fast`` (the C decoder alone: a log it leaves to pymavlink
raises ``NeedsReference``, and must do so the same way warm and cold) with the harness of
``tests/test_decode_dataflash.py``: every LogData array by its bytes, the warnings, the errors. The warm read of
each file comes first, with the cache as the file before it left it (files of one firmware share an entry), then
the cold read (cache cleared).
"""

import sys
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from decoder_harness import DATAFLASH_FIXTURES, assert_same_log  # noqa: E402
from fusion_altitude.logs import _dataflash_fast as fast  # noqa: E402
from fusion_altitude.logs import _decode, dataflash  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FIXTURES = DATAFLASH_FIXTURES


#: Whether each warm read found its format table in the cache.
WARM_HITS = []


def _read(path, decoder, instance=0):
    """``_read_fast`` with the cache as it is (``decoder="fast"``) or cleared first (``"cold"``)."""
    assert decoder in ("fast", "cold")  # (the harness's first read, "fast", is the warm one)
    if decoder == "cold":
        fast.format_table.cache_clear()
    hits = fast.format_table.cache_info().hits
    try:
        return dataflash._read_fast(str(path), instance, None)
    finally:
        if decoder == "fast":
            WARM_HITS.append(fast.format_table.cache_info().hits > hits)


def _assert_warm_reads_as_cold(paths, instance=0):
    """Each file, in turn: the warm read (the cache as the files before left it) equals the cold read."""
    fast.format_table.cache_clear()
    WARM_HITS.clear()
    for path in paths:
        assert_same_log(_read, path, "cold", instance=instance)
    return sum(WARM_HITS)


def _fixture(tmp_path, name, **options):
    path = tmp_path / f"{name}.bin"
    fx.write_dataflash(path, duration=12.0, **{**FIXTURES[name], **options})
    return path


def _with_extra_fmt(data: bytes, name: bytes) -> bytes:
    """``data`` with one more FMT message at its end, for a type no message uses (type 200), named ``name``."""
    return data + b"\xa3\x95\x80" + bytes([200, 7]) + name.ljust(4, b"\0") + b"I".ljust(16, b"\0") + \
        b"TimeMS".ljust(64, b"\0")


def test_warm_cache_reads_the_shared_log_as_a_cold_one(shared_logs):
    path = shared_logs / "ardupilot_test.BIN"
    assert _assert_warm_reads_as_cold([path, path]) == 1  # (the second file's warm read found the first's table)


@pytest.mark.parametrize("instance", [0, 1])
def test_warm_cache_reads_every_fixture_as_a_cold_one(tmp_path, instance):
    assert _assert_warm_reads_as_cold([_fixture(tmp_path, name) for name in sorted(FIXTURES)], instance) >= 3


def _fmt_bytes(path) -> bytes:
    """The bytes of a log's FMT messages (the files of one firmware share them)."""
    data = np.frombuffer(Path(path).read_bytes(), dtype=np.uint8)
    offsets, types = _decode.dataflash_index(data)[:2]
    return b"".join(data[o:o + 89].tobytes() for o in offsets[types == 0x80].tolist())


def test_warm_cache_reads_every_scanner_fuzz_corpus_file_as_a_cold_one():
    """csrc/fuzz/corpus_dataflash: damaged logs (55 with the DataFlash magic, of 38 sets of FMT bytes), read in
    turn, those of one firmware one after another (each warm from the one before)."""
    corpus = [path for path in sorted((ROOT / "csrc" / "fuzz" / "corpus_dataflash").iterdir())
              if path.read_bytes()[:2] == dataflash.DATAFLASH_MAGIC]
    assert len(corpus) >= 5
    assert _assert_warm_reads_as_cold(sorted(corpus, key=_fmt_bytes)) >= 10


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
def test_warm_cache_reads_every_reader_fuzz_mutation_as_a_cold_one(tmp_path, style):
    """The reader fuzz's mutations (seed 1, 60 per generation) share their seed's FMT bytes unless a mutation
    hits them: read in turn, those of one set of FMT bytes one after another (each warm from the one before)."""
    seed = tmp_path / "seed.bin"
    fx.write_dataflash(seed, style=style, duration=2.0, imu_rate=25.0)
    rng = np.random.default_rng(1)
    paths = [Path(fx.write_bytes(tmp_path / f"mutation{number}.bin", data))
             for number, data in enumerate(fx.mutations(seed.read_bytes(), rng, 60))]
    assert _assert_warm_reads_as_cold(sorted([seed, *paths], key=_fmt_bytes)) >= 20


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
@pytest.mark.parametrize("damage", ["time-text", "renamed-GWk", "second-fmt-renamed"])
def test_a_log_left_to_pymavlink_is_left_so_with_a_warm_cache(tmp_path, style, damage):
    """A log the C decoder declines (``NeedsReference``) is declined with the same reason when its format table
    (and its clock verdict) comes from the cache, and a clean log of the same firmware is still read in C."""
    clean = _fixture(tmp_path, style).read_bytes()
    if damage == "time-text":  # IMU's time field made text ('n'; in a TimeUS log its FMT's length is then wrong)
        at = clean.index(b"\xa3\x95\x80" + bytes([129]))
        data = clean[:at + 9] + b"n" + clean[at + 10:]  # (an FMT's format characters start at its byte 9)
    elif damage == "renamed-GWk":
        gps = clean.index(b"GPS\0")
        at = clean.index(b"GWk" if style == "TimeUS" else b"Week", gps)
        data = clean[:at] + b"C" + clean[at + 1:]
    else:
        at = clean.index(b"\xa3\x95\x80" + bytes([132]))
        fmt = bytearray(clean[at:at + 89])
        fmt[5:9] = b"BARX"
        offsets = _decode.dataflash_index(np.frombuffer(clean, dtype=np.uint8))[0]
        middle = int(offsets[offsets.size // 2])
        data = clean[:middle] + bytes(fmt) + clean[middle:]
    path = Path(fx.write_bytes(tmp_path / "declined.bin", data))
    fast.format_table.cache_clear()
    reasons = []
    for _ in range(2):  # cold, then warm
        with pytest.raises(fast.NeedsReference) as caught:
            _read(path, "fast")
        reasons.append(str(caught.value))
    assert reasons[0] == reasons[1]
    assert fast.format_table.cache_info().hits >= 1
    clean_path = Path(fx.write_bytes(tmp_path / "clean.bin", clean))
    assert _read(clean_path, "fast").time.size > 0


def test_the_same_message_bytes_under_another_fmt_are_read_by_that_fmt(tmp_path):
    """Two logs with the same data messages, one with BARO's Alt and Press columns swapped in its FMT: the one's
    Alt is the other's Press (the cache keys on the FMT bytes, not on the types or names)."""
    data = _fixture(tmp_path, "TimeUS").read_bytes()
    at = data.index(b"TimeUS,I,Alt,Press,Temp")
    swapped = data[:at] + b"TimeUS,I,Press,Alt,Temp" + data[at + len(b"TimeUS,I,Alt,Press,Temp"):]
    fast.format_table.cache_clear()
    columns = []
    for blob in (data, swapped, data, swapped):  # cold, cold, warm, warm
        index = fast.DataFlashIndex(blob, "log.bin", dataflash.KINDS, dataflash.FIELDS_USED)
        parts, _ = fast.read_families(index, dataflash.KINDS, dataflash.FIELDS_USED,
                                      lambda kind, values, count: (kind, None))
        (_, _, baro), = parts["BARO"]
        columns.append((baro["Alt"], baro["Press"]))
    assert fast.format_table.cache_info().hits == 2
    assert columns[0][0].tobytes() != columns[1][0].tobytes()
    assert columns[1][0].tobytes() == columns[0][1].tobytes()
    assert columns[1][1].tobytes() == columns[0][0].tobytes()
    for cold, warm in zip(columns[:2], columns[2:]):
        assert [c.tobytes() for c in cold] == [c.tobytes() for c in warm]


def test_the_cache_keeps_at_most_its_bound_of_firmwares(tmp_path):
    """40 logs of 40 firmwares (FMT bytes that differ in one type's name): 32 entries, the oldest evicted."""
    data = _fixture(tmp_path, "TimeMS").read_bytes()
    paths = [Path(fx.write_bytes(tmp_path / f"firmware{k}.bin", _with_extra_fmt(data, b"X%03d" % k)))
             for k in range(40)]
    fast.format_table.cache_clear()
    for path in paths:
        _read(path, "fast")
    info = fast.format_table.cache_info()
    assert (info.maxsize, info.currsize, info.misses, info.hits) == (fast.FORMAT_CACHE_SIZE, 32, 40, 0)
    _read(paths[-1], "fast")
    _read(paths[0], "fast")
    assert fast.format_table.cache_info()[:2] == (1, 41)  # the newest kept, the oldest read anew


def test_what_the_cache_hands_out_cannot_be_changed(shared_logs):
    index = fast.DataFlashIndex((shared_logs / "ardupilot_test.BIN").read_bytes(), "log.bin", dataflash.KINDS,
                                dataflash.FIELDS_USED)
    for array in (index.lengths, index.column_counts, index.field_chars, index.field_offsets):
        assert not array.flags.writeable
        with pytest.raises(ValueError):
            array[0] = 1
    with pytest.raises(TypeError):
        index.name_to_id["IMU"] = 1


def test_threads_sharing_the_cache_read_as_one_thread_does(tmp_path, shared_logs):
    """Eight threads reading logs of three firmwares at once (as Dask's threads in one worker): every result is
    the sequential cold read's, bit for bit."""
    paths = [_fixture(tmp_path, "TimeMS"), _fixture(tmp_path, "TimeUS"), shared_logs / "ardupilot_test.BIN"]
    expected = {}
    for path in paths:
        data = _read(path, "cold")
        expected[path] = {k: v.tobytes() if isinstance(v, np.ndarray) and v.dtype != object else
                          (list(v) if isinstance(v, np.ndarray) else v) for k, v in vars(data).items()}
    fast.format_table.cache_clear()
    start = threading.Barrier(8)

    def work(number):
        start.wait()
        path = paths[number % len(paths)]
        results = []
        for _ in range(10):
            data = _read(path, "fast")
            results.append({k: v.tobytes() if isinstance(v, np.ndarray) and v.dtype != object else
                            (list(v) if isinstance(v, np.ndarray) else v) for k, v in vars(data).items()})
        return path, results

    with ThreadPoolExecutor(8) as pool:
        for path, results in pool.map(work, range(8)):
            assert all(result == expected[path] for result in results)
