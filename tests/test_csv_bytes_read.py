"""The generic CSV read from the file's bytes (issue 25, fleet read share): the header part decoded alone, the body
scanned in place by the C scan without decoding it, its line count from the scan, and the file opened once by
``fleet.read_log``. Every outcome (values, warnings, errors) is the text path's: ``_table.read_table`` against
``split_header(read_text(…))``, and the reads against the Python engine (tests/test_csv_engines.py's comparison).
"""

import builtins
import os
import re
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
from test_csv_engines import CSV, assert_same_both_ways  # noqa: E402

from fusion_altitude import fleet, logs  # noqa: E402
from fusion_altitude.logs import LogError, _csv_fast, _table  # noqa: E402
from fusion_altitude.logs._text_decode import longest_digit_run, scan_csv  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", str(ROOT / ".." / "shared" / "data")))
MISSING = "".join(word + "\n" for word in _table.MISSING)
ROWS = "".join(f"{i * 0.01:.2f},{(i % 7) * 0.1:.9g},{100 + i * 0.5:.9g},{100 + i * 0.25:.9g}\n" for i in range(200))

#: Files whose header part is read from bytes (ASCII) or decoded whole (not ASCII), and the ones refused.
HEADS = {
    "plain": b"time,accel,baro,reference\n",
    "blank lines first": b"\n  \n\t\ntime,accel,baro,reference\n",
    "blank by str.strip": b"\x1c\x0b\n\x0ctime,accel,baro,reference\n",
    "crlf": b"time,accel,baro,reference\r\n",
    "bom": b"\xef\xbb\xbftime,accel,baro,reference\n",
    "utf-8 name": "time,accel,baro,reference,höhe\n".encode(),
    "latin-1 name": "time,accel,baro,reference,höhe\n".encode("latin-1"),
    "no-break space line": "\u00a0\ntime,accel,baro,reference\n".encode("latin-1"),
    "no newline": b"time,accel,baro,reference",
}


def _table_fields(table):
    return table.header, table.first_line, table.preamble, table.body


def _either(read):
    try:
        return "Table", _table_fields(read())
    except LogError as error:
        return "LogError", str(error)


@pytest.mark.parametrize("name", HEADS)
@pytest.mark.parametrize("body", [ROWS.encode(), b"", b"1,2,3,4", "1,2,3,4,é\n".encode(), b"\n\n1,2,3,4\n\n"])
def test_read_table_is_split_header_of_read_text(tmp_path, name, body):
    path = tmp_path / "log.csv"
    path.write_bytes(HEADS[name] + body)
    assert _either(lambda: _table.read_table(str(path))) == \
        _either(lambda: _table.split_header(str(path), _table.read_text(str(path))))


@pytest.mark.parametrize("content", [b"", b"\n \n", b"\x00time,baro\n1,2\n", "\u00a0\n".encode("latin-1")])
def test_read_table_refuses_what_read_text_and_split_header_refuse(tmp_path, content):
    path = tmp_path / "log.csv"
    path.write_bytes(content)
    expected = _either(lambda: _table.split_header(str(path), _table.read_text(str(path))))
    assert expected[0] == "LogError"
    assert _either(lambda: _table.read_table(str(path))) == expected


@pytest.mark.parametrize("content", [b"time,accel,baro,reference", b"time,accel,baro,reference\n",
                                     b"\ntime,accel,baro,reference", b"time,accel,baro,reference\n0,0,1,1"])
def test_a_header_without_rows_reads_as_the_text_path_reads_it(tmp_path, content):
    path = tmp_path / "log.csv"
    path.write_bytes(content)
    assert assert_same_both_ways(path, **CSV)[0] == "LogError"


def test_an_ascii_generic_csv_is_read_without_decoding_its_body(tmp_path, monkeypatch):
    path = tmp_path / "log.csv"
    path.write_bytes(HEADS["plain"] + ROWS.encode())
    expected = logs.load_log(str(path), **CSV)

    def refuse(*_):
        raise AssertionError("the body was decoded")

    monkeypatch.setattr(_table, "_decoded", refuse)
    got = logs.load_log(str(path), **CSV)
    assert got.baro_altitude.tobytes() == expected.baro_altitude.tobytes()
    assert got.time.tobytes() == expected.time.tobytes()


@pytest.mark.parametrize("body", [ROWS, "1,2\n\n  \n3,4", ",1,\n2,,3\n", "1, -,a\n2,Drogue ,b\n3, -,a\n", "x\n"])
def test_the_scan_of_bytes_from_start_is_the_scan_of_the_text(body):
    raw = b"head,er\n" + body.encode()
    from_bytes = scan_csv(raw, [0], [1], MISSING, 8)
    from_text = scan_csv(body, [0], [1], MISSING)
    assert from_bytes[0] == from_text[0] and from_bytes[3:] == from_text[3:]
    if from_text[0] == "ok":
        assert from_bytes[1].tobytes() == from_text[1].tobytes()
        for (cells, index), (cells_text, index_text) in zip(from_bytes[2], from_text[2]):
            assert list(cells) == list(cells_text) and index.tolist() == index_text.tolist()
            assert all(type(cell) is str for cell in cells)


def test_the_scan_refuses_a_start_outside_the_body():
    with pytest.raises(ValueError, match="start"):
        scan_csv(b"1,2\n", [0], [], MISSING, 5)


def test_a_body_of_lines_shorter_than_its_first_is_read_whole():
    body = "1.00000000000000,2.00000000000000\n" + "1,2\n" * 5000  # more rows than the first line's length suggests
    status, numbers, _, lines, _ = scan_csv(body.encode(), [0, 1], [], MISSING)
    assert status == "ok" and numbers.shape == (5001, 2) and lines == 5001
    assert numbers.tobytes() == np.tile([1.0, 2.0], (5001, 1)).tobytes()


def test_the_line_count_counts_blank_lines_and_an_unterminated_last_line():
    assert scan_csv("1\n\n2\n", [0], [], MISSING)[3] == 3
    assert scan_csv("1\n2", [0], [], MISSING)[3] == 2


def test_each_column_of_the_scan_is_contiguous():
    numbers = scan_csv(ROWS, [0, 1, 2, 3], [], MISSING)[1]
    assert all(numbers[:, j].flags.c_contiguous for j in range(4))


@pytest.mark.parametrize("seed", range(5))
def test_the_longest_digit_run_answers_as_the_regular_expression(seed):
    rng = np.random.default_rng(seed)
    for _ in range(400):
        sample = "".join(rng.choice(list("0123456789.,\n-eé"), size=int(rng.integers(0, 60)),
                                    p=[0.09] * 10 + [0.1 / 6] * 6))
        expected = re.search("[0-9]{16}", sample.replace(".", "")) is None
        assert _csv_fast._short_numbers(sample) is expected
        assert _csv_fast._short_numbers(sample.encode()) is expected
        assert (longest_digit_run(sample.encode()) <= 15) is expected


def test_blank_lines_in_the_body_keep_the_line_numbers_of_the_warnings(tmp_path):
    rows = ROWS.splitlines()
    rows[50] = rows[50].rsplit(",", 2)[0] + ",1e30," + rows[50].rsplit(",", 1)[1]
    path = tmp_path / "log.csv"
    path.write_text("time,accel,baro,reference\n\n" + "\n".join(rows[:100]) + "\n\n  \n" + "\n".join(rows[100:]) + "\n")
    outcome = assert_same_both_ways(path, **CSV)
    assert outcome[0] == "LogData" and any("line 53" in warning for warning in outcome[2])


def test_load_log_takes_column_options_for_a_generic_csv_only(tmp_path):
    path = tmp_path / "log.csv"
    path.write_bytes(HEADS["plain"] + ROWS.encode())
    assert logs.load_log(str(path), column_options=CSV).time.size == 200
    rrc3 = str(DATA / "rrc3_juno3.csv")  # an RRC3 export knows its columns: the column options are left out
    with logs.quiet_warnings():
        with_options = logs.load_log(rrc3, column_options=CSV)
        assert with_options.baro_altitude.tobytes() == logs.load_log(rrc3).baro_altitude.tobytes()


def test_a_missing_file_with_column_options_is_the_sniffers_error(tmp_path):
    missing = str(tmp_path / "missing.csv")
    with pytest.raises(LogError) as sniffed:
        logs.sniff_format(missing)
    with pytest.raises(LogError) as loaded:
        fleet.read_log(missing, CSV)
    assert str(loaded.value) == str(sniffed.value)


def test_fleet_read_log_opens_a_csv_once(tmp_path, monkeypatch):
    path = tmp_path / "log.csv"
    path.write_bytes(HEADS["plain"] + ROWS.encode() * 3)
    opened = []
    real_open = builtins.open

    def counting_open(file, *args, **kwargs):
        if str(file) == str(path):
            opened.append(file)
        return real_open(file, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", counting_open)
    with pytest.raises(LogError, match="backwards"):  # the rows repeat: read whole, then refused
        fleet.read_log(str(path), CSV)
    assert len(opened) == 1
    opened.clear()
    path.write_bytes(HEADS["plain"] + ROWS.encode())
    assert fleet.read_log(str(path), CSV).time.size == 200
    assert len(opened) == 1


RRC3_ROWS = "".join(f"{i * 0.05:.2f},{i * 0.5:.1f},{1000 - i * 0.05:.2f},10.0,25.0,{'Drogue' if i == 30 else '-'},9.1\n"
                    for i in range(60))


def test_an_ascii_rrc3_export_is_read_without_decoding_its_body(tmp_path, monkeypatch):
    path = tmp_path / "flight.csv"
    path.write_text("time,altitude,pressure,velocity,temperature,events,voltages\n" + RRC3_ROWS)
    expected = logs.load_log(str(path))

    def refuse(*_):
        raise AssertionError("the body was decoded")

    monkeypatch.setattr(_table, "_decoded", refuse)
    got = logs.load_log(str(path))
    assert got.baro_altitude.tobytes() == expected.baro_altitude.tobytes()
    assert list(got.flight_state) == list(expected.flight_state)


def test_blank_lines_in_an_rrc3_export_keep_the_line_numbers_of_the_warnings(tmp_path):
    rows = RRC3_ROWS.splitlines()
    rows[40] = rows[40].replace(",10.0,", ",5000.0,")  # a garbage row (speed): its line named in the warning
    path = tmp_path / "flight.csv"
    path.write_text("time,altitude,pressure,velocity,temperature,events,voltages\n\n" + "\n".join(rows[:20]) +
                    "\n\n  \n" + "\n".join(rows[20:]) + "\n")
    outcome = assert_same_both_ways(path)
    assert outcome[0] == "LogData" and any("line 45" in warning for warning in outcome[2])


def test_an_ascii_raven_export_is_read_without_decoding_its_body(tmp_path, monkeypatch):
    import logfixtures as fx

    path = fx.raven_csv(str(tmp_path))
    expected = logs.load_log(path)

    def refuse(*_):
        raise AssertionError("the body was decoded")

    monkeypatch.setattr(_table, "_decoded", refuse)
    got = logs.load_log(path)
    assert got.baro_altitude.tobytes() == expected.baro_altitude.tobytes()
    assert got.vertical_acceleration.tobytes() == expected.vertical_acceleration.tobytes()
