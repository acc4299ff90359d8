"""The fast DataFlash decoder (C, fusion_altitude/logs/_decode.pyx) reads what pymavlink reads, bit for bit.

pymavlink is the reference: on the shared log, every fixture generation and
the reader-fuzz mutations of the fixtures, ``read_dataflash(decoder="fast")``
and ``read_dataflash(decoder="pymavlink")`` give the same LogData (every array
compared by its bytes, time stamps included), the same warnings and the same
errors; and the decoded messages themselves (every field the reader uses, of
every type it asks for) equal pymavlink's ``to_dict`` values. The C scanner's
libFuzzer corpus is replayed under ASan + UBSan.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from decoder_harness import DATAFLASH_FIXTURES, assert_fuzz_corpus_replays_clean, assert_same_log  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude.logs import _dataflash_fast as fast  # noqa: E402
from fusion_altitude.logs import _decode, dataflash  # noqa: E402

FIXTURES = DATAFLASH_FIXTURES


def _assert_same_log(path, **options):
    """Both decoders give the same LogData bit for bit, the same warnings, or the same error."""
    assert_same_log(dataflash.read_dataflash, path, "pymavlink", **options)


def _pymavlink_messages(path):
    """pymavlink's ``to_dict`` of every message the reader asks for, by type name, in file order."""
    from pymavlink import DFReader

    reader = DFReader.DFReader_binary(str(path), zero_time_base=True)
    out = {}
    try:
        while True:
            message = reader.recv_match(type=dataflash.KINDS)
            if message is None:
                return out
            out.setdefault(message.get_type(), []).append(message.to_dict())
    finally:
        reader.filehandle.close()


def _fast_messages(path):
    """The fast decoder's columns (read in C) of every field the reader uses, by type name, and MSG's text."""
    index = fast.DataFlashIndex(Path(path).read_bytes(), str(path), dataflash.KINDS, dataflash.FIELDS_USED)
    parts, _ = fast.read_families(index, dataflash.KINDS, dataflash.FIELDS_USED,
                                  lambda kind, columns, count: (kind, None))
    out = {}
    for kind, ((offsets, fmt, columns),) in parts.items():
        out[kind] = {field: values for field, values in columns.items() if field in dataflash.FIELDS_USED}
        if kind == "MSG":
            fmt = fmt()
            bodies, _ = _decode.dataflash_gather(index.data, np.ascontiguousarray(offsets), fmt.length)
            out[kind]["Message"] = [fast._python_value(fmt, "Message", row[f"f{fmt.colhash['Message']}"])
                                    for row in bodies.view(fmt.dtype).reshape(-1)]
    return out


def _assert_same_messages(path):
    theirs = _pymavlink_messages(path)
    mine = _fast_messages(path)
    assert set(mine) == set(theirs)
    for kind, rows in theirs.items():
        assert set(mine[kind]) == {field for field in rows[0] if field in dataflash.FIELDS_USED or
                                   (kind == "MSG" and field == "Message")}, kind
        for field, values in mine[kind].items():
            if field == "Message":
                assert values == [r[field] for r in rows], f"{kind}.{field}"
            else:
                expected = np.array([r[field] for r in rows], dtype=float)
                assert values.tobytes() == expected.tobytes(), f"{kind}.{field}"


def _fixture(tmp_path, name):
    path = tmp_path / f"{name}.bin"
    fx.write_dataflash(path, duration=12.0, **FIXTURES[name])
    return path


def test_shared_log_decodes_field_for_field_as_pymavlink(shared_logs):
    _assert_same_messages(shared_logs / "ardupilot_test.BIN")


def test_shared_log_reads_the_same_with_both_decoders(shared_logs):
    _assert_same_log(shared_logs / "ardupilot_test.BIN")


def test_shared_log_is_decoded_in_c_not_left_to_pymavlink(shared_logs):
    data = dataflash._read_fast(str(shared_logs / "ardupilot_test.BIN"), 0, None)
    assert data.time.size > 0


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_fixture_decodes_field_for_field_as_pymavlink(tmp_path, name):
    _assert_same_messages(_fixture(tmp_path, name))


@pytest.mark.parametrize("name", sorted(FIXTURES))
@pytest.mark.parametrize("instance", [0, 1])
def test_fixture_reads_the_same_with_both_decoders(tmp_path, name, instance):
    _assert_same_log(_fixture(tmp_path, name), instance=instance)


@pytest.mark.parametrize("name", ["TimeMS", "TimeUS"])
def test_clean_fixture_is_decoded_in_c_not_left_to_pymavlink(tmp_path, name):
    data = dataflash._read_fast(str(_fixture(tmp_path, name)), 0, None)
    assert data.time.size > 0


@pytest.mark.parametrize("name", ["TimeMS", "TimeUS"])
def test_fuzz_mutations_read_the_same_with_both_decoders(tmp_path, name):
    """The reader fuzz's mutations (truncations, bit flips, random bytes, deleted runs; seed 1, 60 per
    generation) of the fuzz seeds. Mutations on which pymavlink's indexer would end the process (an FMT
    length below 3, a type without FMT) are read by the fast decoder only, which must raise LogError."""
    seed = tmp_path / "seed.bin"
    fx.write_dataflash(seed, style=name, duration=2.0, imu_rate=25.0)
    rng = np.random.default_rng(1)
    for number, data in enumerate(fx.mutations(seed.read_bytes(), rng, 60)):
        path = Path(fx.write_bytes(tmp_path / f"mutation{number}.bin", data))
        _, _, _, status, _, _ = _decode.dataflash_index(np.frombuffer(data, dtype=np.uint8)) if data else \
            (None, None, None, "ok", None, None)
        if status != "ok":
            with pytest.raises(logs.LogError, match="where pymavlink's indexer stops the program"):
                dataflash.read_dataflash(str(path))
            continue
        _assert_same_log(path)


#: Stray bytes put into a log: zeros, and bytes that look like the start of a header.
STRAY = {"zeros": b"\0" * 5, "half-header": b"\xa3\x00\x95", "one-A3": b"\xa3"}


def _with_stray_bytes(tmp_path, style, where, stray, gps=True):
    """A fixture with ``stray`` bytes before its second message ("start"), a message at a quarter or a half of
    the log, its last message ("end"), or after its end ("after-end", inside pymavlink's 528-byte allowance);
    ``gps=False`` renames the GPS format (pymavlink's clock set-up then walks the whole log)."""
    data = _fixture(tmp_path, style).read_bytes()
    if not gps:
        at = data.index(b"GPS\0")
        data = data[:at] + b"X" + data[at + 1:]
    offsets = _decode.dataflash_index(np.frombuffer(data, dtype=np.uint8))[0]
    at = {"start": int(offsets[1]), "quarter": int(offsets[offsets.size // 4]),
          "middle": int(offsets[offsets.size // 2]), "end": int(offsets[-1]), "after-end": len(data)}[where]
    return Path(fx.write_bytes(tmp_path / f"stray-{where}.bin", data[:at] + STRAY[stray] + data[at:]))


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
@pytest.mark.parametrize("where", ["start", "quarter", "middle", "end", "after-end"])
@pytest.mark.parametrize("stray", sorted(STRAY))
def test_stray_bytes_read_the_same_with_both_decoders(tmp_path, style, where, stray):
    """pymavlink steps over bytes that start no message ("bad header" for each, outside the last 528 bytes)
    and its clock set-up walk prints "Skipped N bad bytes" for each run it passes: the same warnings."""
    _assert_same_log(_with_stray_bytes(tmp_path, style, where, stray))


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
@pytest.mark.parametrize("where", ["start", "quarter", "middle", "end"])
def test_stray_bytes_where_the_clock_walk_reads_the_whole_log_read_the_same(tmp_path, style, where):
    """Without a GPS message to set its clock by, pymavlink's clock set-up walks every message, and reports
    every run of stray bytes more than 528 bytes before the end."""
    _assert_same_log(_with_stray_bytes(tmp_path, style, where, "zeros", gps=False))


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
@pytest.mark.parametrize("where", ["start", "middle", "after-end"])
def test_stray_bytes_are_decoded_in_c_not_left_to_pymavlink(tmp_path, style, where):
    data = dataflash._read_fast(str(_with_stray_bytes(tmp_path, style, where, "half-header")), 0, None)
    assert data.time.size > 0


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
def test_random_stray_byte_insertions_read_the_same_with_both_decoders(tmp_path, style):
    """The mutation sweep for resynchronisation: 40 logs (seed 3), each with one to three runs of 1 to 40 random
    bytes (A3 and 95 among them, often) put in at random places."""
    seed = tmp_path / "seed.bin"
    fx.write_dataflash(seed, style=style, duration=2.0, imu_rate=25.0)
    original = seed.read_bytes()
    rng = np.random.default_rng(3)
    for number in range(40):
        data = original
        for _ in range(int(rng.integers(1, 4))):
            run = bytes(rng.choice([0xA3, 0x95, 0x00, int(rng.integers(256))], size=int(rng.integers(1, 41))))
            at = int(rng.integers(2, len(data) + 1))
            data = data[:at] + run + data[at:]
        path = Path(fx.write_bytes(tmp_path / f"inserted{number}.bin", data))
        status = _decode.dataflash_index(np.frombuffer(data, dtype=np.uint8))[3]
        if status != "ok":
            with pytest.raises(logs.LogError, match="where pymavlink's indexer stops the program"):
                dataflash.read_dataflash(str(path))
            continue
        _assert_same_log(path)


#: A second FMT for the BARO type: (name, format characters, columns), each padded as an FMT holds them.
REDEFINITIONS = {
    "columns-swapped": (b"BARO", b"QBffc", b"TimeUS,I,Press,Alt,Temp"),
    "characters-changed": (b"BARO", b"QBffh", b"TimeUS,I,Alt,Press,Temp"),
    "renamed": (b"BARX", b"QBffc", b"TimeUS,I,Alt,Press,Temp"),
    "longer": (b"BARO", b"QBfff", b"TimeUS,I,Alt,Press,Temp"),
}


def _with_second_fmt(tmp_path, style, case, gps=True):
    """A fixture with a second FMT for its BARO type (``REDEFINITIONS[case]``) in the middle of the log;
    ``gps=False`` renames the GPS format (pymavlink's clock set-up walk then reads the second FMT too)."""
    data = _fixture(tmp_path, style).read_bytes()
    if not gps:
        at = data.index(b"GPS\0")
        data = data[:at] + b"X" + data[at + 1:]
    first = data.index(b"\xa3\x95\x80" + bytes([132]))  # logfixtures' BARO type
    name, chars, columns = REDEFINITIONS[case]
    length = 3 + sum(np.dtype(fast.FORMAT_CHARS[c][0]).itemsize for c in chars.decode())
    fmt = data[first:first + 4] + bytes([length]) + name.ljust(4, b"\0") + chars.ljust(16, b"\0") + \
        columns.ljust(64, b"\0")
    offsets = _decode.dataflash_index(np.frombuffer(data, dtype=np.uint8))[0]
    at = int(offsets[offsets.size // 2])
    return Path(fx.write_bytes(tmp_path / f"second-fmt-{case}.bin", data[:at] + fmt + data[at:]))


@pytest.mark.parametrize("style", ["TimeMS", "TimeUS"])
@pytest.mark.parametrize("case", sorted(REDEFINITIONS))
@pytest.mark.parametrize("gps", [True, False])
def test_a_type_defined_twice_reads_the_same_with_both_decoders(tmp_path, style, case, gps):
    """pymavlink reads every message of a type with one format: the FMT its clock set-up walk read last (the
    first, when the walk stops at the first GPS fix; the second, when it walks the whole log)."""
    _assert_same_log(_with_second_fmt(tmp_path, style, case, gps))


@pytest.mark.parametrize("case", ["columns-swapped", "characters-changed"])
@pytest.mark.parametrize("gps", [True, False])
def test_a_type_defined_twice_with_its_name_and_length_is_decoded_in_c(tmp_path, case, gps):
    data = dataflash._read_fast(str(_with_second_fmt(tmp_path, "TimeUS", case, gps)), 0, None)
    assert data.time.size > 0


@pytest.mark.parametrize("renamed", [b"GWk", b"GMS", b"TimeUS"])
def test_gps_without_a_clock_field_pymavlink_reads_gives_the_same_warnings(tmp_path, renamed):
    """A GPS format whose week (or week time, or boot time) column is renamed (as a bit flip does: GWk → CWk):
    pymavlink's clock fails on every GPS message ("bad msg"), and the fast decoder leaves the log to it."""
    data = _fixture(tmp_path, "TimeUS").read_bytes()
    gps = data.index(b"GPS\0")
    columns = data.index(renamed, gps)
    assert columns < gps + 86  # inside the GPS FMT message
    path = fx.write_bytes(tmp_path / "renamed.bin", data[:columns] + b"C" + data[columns + 1:])
    _assert_same_log(path)


def test_unknown_decoder_is_refused_naming_the_argument(shared_logs):
    with pytest.raises(ValueError, match="decoder"):
        logs.load_log(str(shared_logs / "ardupilot_test.BIN"), decoder="mavlink")


def test_the_other_formats_reference_decoder_is_refused(shared_logs):
    with pytest.raises(logs.LogError, match="pyulog decoder reads only PX4 ULog"):
        logs.load_log(str(shared_logs / "ardupilot_test.BIN"), decoder="pyulog")


def test_every_scanner_fuzz_corpus_file_reads_the_same_with_both_decoders():
    """csrc/fuzz/corpus_dataflash (libFuzzer's mutations of the fixtures, stray bytes and redefined types among
    them): the same LogData, warnings or error both ways; a file on which pymavlink's indexer would end the
    process is refused by the fast decoder with LogError."""
    corpus = sorted((Path(__file__).resolve().parents[1] / "csrc" / "fuzz" / "corpus_dataflash").iterdir())
    assert len(corpus) >= 5
    for path in corpus:
        data = path.read_bytes()
        status = _decode.dataflash_index(np.frombuffer(data, dtype=np.uint8))[3] if data else "ok"
        if status != "ok" and data[:2] == dataflash.DATAFLASH_MAGIC:
            with pytest.raises(logs.LogError, match="where pymavlink's indexer stops the program"):
                dataflash.read_dataflash(str(path))
            continue
        if status == "ok":
            _assert_same_log(path)


def test_scanner_fuzz_corpus_replays_clean_under_asan_and_ubsan(tmp_path):
    """csrc/fuzz/fuzz_dataflash.c over csrc/fuzz/corpus_dataflash: the C scanner equals its byte-at-a-time
    transcription of pymavlink's indexer and reads nothing outside the log."""
    assert_fuzz_corpus_replays_clean("dataflash", tmp_path, minimum_files=3)


def test_without_the_extension_the_fast_decoder_leaves_the_log_to_pymavlink(shared_logs, monkeypatch):
    path = str(shared_logs / "ardupilot_test.BIN")
    reference = dataflash.read_dataflash(path, decoder="pymavlink")

    def missing():
        raise fast.NeedsReference("the extension fusion_altitude.logs._decode is not built")

    monkeypatch.setattr(fast, "decoder_module", missing)
    with pytest.raises(fast.NeedsReference):
        dataflash._read_fast(path, 0, None)
    assert dataflash.read_dataflash(path).time.tobytes() == reference.time.tobytes()
