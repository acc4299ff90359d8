"""The C scan of numeric CSV bodies (``fusion_altitude/logs/_csv_scan.h`` through ``_text_decode.scan_csv``; issue 25,
item 3): every cell it reads is Python's ``float`` of the stripped cell, bit for bit (and pyarrow's, where pyarrow
reads it), missing words are NaN, and what it does not read it hands on, naming the body line where it stopped —
the line the readers' errors name. The readers' outcomes with and without it are compared in
tests/test_csv_engines.py.
"""

import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude.logs import _csv_fast, _table  # noqa: E402
from fusion_altitude.logs._text_decode import scan_csv  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", str(ROOT / ".." / "shared" / "data")))
MISSING = "".join(word + "\n" for word in _table.MISSING)

#: Cells the scan reads: plain decimals, exponents, signs, padding, 15 and more digits, extremes, infinities.
READ = ["0", "-0", "+0.0", "1e5", "1E-5", "-5.391191E-05", ".5", "5.", "-.5e+3", "  12.5 ", "\t7\t", "861.70",
        "123456789012345", "1234567890123456789", "0.1", "0.30000000000000004", "1.2605042016806722",
        "1.7976931348623157e308", "1e309", "-1e309", "4.9e-324", "2.4703282292062328e-324", "1e-400",
        "9007199254740993", "9007199254740993.0000000001", "3." + "1" * 300, "0." + "0" * 30 + "1", "1" + "0" * 25,
        "1e22", "1e23", "123456789012345e-22", "0.000000000000000000000000000001e30", "inf", "-Infinity", "+INF"]
#: Cells meaning "no value" (the readers' MISSING, any case): NaN.
MISSING_CELLS = ["", "  ", "nan", "NaN", "NA", "n/a", "N/A", "-", "null", "None"]
#: Cells the scan hands on (the Python path decides them: values or errors).
HANDED_ON = ["1_000", "0x10", "-nan", "+NaN", "1e", "e5", "1.2.3", "--1", "abc", "+", ".", "1 2", "1e+", "nan(1)",
             "3." + "1" * 400]


def scan_one(cell: str):
    return scan_csv(f"{cell},1\n", [0, 1], [], MISSING)


@pytest.mark.parametrize("cell", READ)
def test_a_plain_number_is_pythons_float_bit_for_bit(cell):
    status, numbers, _, _, _ = scan_one(cell)
    assert status == "ok"
    assert numbers[0, 0].tobytes() == np.float64(float(cell)).tobytes()


@pytest.mark.parametrize("cell", [c for c in READ if c == c.strip()])
def test_a_plain_number_is_pyarrows_bit_for_bit(cell):
    with _csv_fast.engine("pyarrow"):
        pyarrow = _csv_fast.read_columns(f"{cell},1\n", [0], _table.MISSING)
    assert pyarrow is not None
    assert scan_one(cell)[1][0, 0].tobytes() == pyarrow[0, 0].tobytes()


@pytest.mark.parametrize("cell", MISSING_CELLS)
def test_a_missing_word_is_nan(cell):
    status, numbers, _, _, _ = scan_one(cell)
    assert status == "ok" and numbers[0, 0].tobytes() == np.float64(np.nan).tobytes()


@pytest.mark.parametrize("cell", HANDED_ON)
def test_anything_else_is_handed_on_naming_the_cell(cell):
    status, numbers, _, line, position = scan_csv(f"1,2\n{cell},1\n", [0, 1], [], MISSING)
    assert (status, numbers, line, position) == ("not a number", None, 1, 0)


def test_random_decimals_are_pythons_float_bit_for_bit():
    rng = np.random.default_rng(25)
    cells = []
    for _ in range(20_000):
        digits = "".join(rng.choice(list("0123456789"), rng.integers(1, 22)))
        point = int(rng.integers(0, len(digits) + 1))
        cell = ("-" if rng.random() < 0.5 else "") + digits[:point] + "." + digits[point:]
        if rng.random() < 0.5:
            cell += f"e{int(rng.integers(-330, 310))}"
        cells.append(cell)
    status, numbers, _, _, _ = scan_csv("\n".join(cells) + "\n", [0], [], MISSING)
    assert status == "ok"
    assert numbers[:, 0].tobytes() == np.array([float(c) for c in cells]).tobytes()


def test_a_missing_final_newline_and_blank_lines_are_read_as_the_readers_read_them():
    status, numbers, _, _, _ = scan_csv("1,2\n\n  \n3,4", [1, 0], [], MISSING)
    assert status == "ok" and numbers.tolist() == [[2.0, 1.0], [4.0, 3.0]]


def test_empty_cells_are_nan():
    status, numbers, _, _, _ = scan_csv(",1,\n2,,3\n", [0, 1, 2], [], MISSING)
    assert status == "ok"
    assert np.isnan(numbers[0, 0]) and np.isnan(numbers[0, 2]) and np.isnan(numbers[1, 1])


def test_text_columns_are_their_distinct_stripped_cells_and_an_index_per_row():
    status, numbers, text, _, _ = scan_csv("1, -,a\n2,Drogue ,b\n3, -,a\n", [0], [1, 2], MISSING)
    assert status == "ok" and numbers[:, 0].tolist() == [1.0, 2.0, 3.0]
    (events, event_rows), (letters, letter_rows) = text
    assert events[event_rows].tolist() == ["-", "Drogue", "-"] and len(events) == 2
    assert letters[letter_rows].tolist() == ["a", "b", "a"]


@pytest.mark.parametrize("body, status, line, cell", [
    ("1,2\n3\n", "ragged", 1, 1),
    ("1,2\n3,4,5\n", "ragged", 1, 3),
    ('1,2\n"3",4\n', "not plain text", 1, 0),
    ("1,2\n3,4\r\n", "not plain text", 1, 1),
    ("1,2\n3,\u00b04\n", "not plain text", -1, -1),
])
def test_a_body_that_is_not_plain_is_handed_on_naming_where(body, status, line, cell):
    result = scan_csv(body, [0, 1], [], MISSING)
    assert (result[0], result[3], result[4]) == (status, line, cell)


def test_a_bad_number_stops_the_scan_on_the_line_the_reader_names(tmp_path):
    path = tmp_path / "bad.csv"
    fx.write_generic_csv(path, duration=6.0, rate=50.0, bad_cell_row=30)
    with pytest.raises(logs.LogError) as error:
        logs.load_log(str(path), time_column="time", accel_column="accel", baro_column="baro")
    table = _table.split_header(str(path), _table.read_text(str(path)))
    columns = [table.index("time"), table.index("accel"), table.index("baro")]
    status, _, _, line, _ = scan_csv(table.body, columns, [], MISSING)
    assert status == "not a number"
    assert f"line {table.first_line + line}," in str(error.value)


def test_the_small_shared_exports_are_read_by_the_scan_and_the_large_by_pyarrow(monkeypatch):
    """Small bodies, and large ones of short numbers (the CATS baro file), go to the scan; large bodies of
    17-digit numbers (the CATS IMU and flight-info files) to pyarrow."""
    scanned, parsed = [], []
    scan, parse = _csv_fast._scan, _csv_fast._parse
    monkeypatch.setattr(_csv_fast, "_scan", lambda *a: scanned.append(scan(*a) is not None) or scan(*a))
    monkeypatch.setattr(_csv_fast, "_parse", lambda *a: parsed.append(a[1]) or parse(*a))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in ("rrc3_juno3.csv", "raven_ndrt2020.csv"):
            logs.load_log(str(DATA / name))
        assert scanned == [True, True] and parsed == []
        logs.load_log(str(DATA / "hedy_imu.csv"))
    assert scanned == [True, True, True] and len(parsed) == 2


def test_a_large_body_goes_to_the_scan_only_when_its_numbers_are_short():
    assert _csv_fast._short_numbers("0.010,-0.13210,,100.016\n" * 1000)
    assert _csv_fast._short_numbers("1e-05,123456789012345\n")
    assert not _csv_fast._short_numbers("0.1,0.12088581174612045\n")
    assert not _csv_fast._short_numbers("1,2\n" + "3.1234567890123456\n")


@pytest.mark.parametrize("raw", [b"a\r\nb\rc\n\r\r\n", b"", b"\r", b"x\r\n", "\u00e9\r\n\r".encode(), b"abc", b"\r\r",
                                 b"\n\r", b"1,2\r\n3,4"])
def test_newlines_are_normalised_in_c_as_str_replace_does(raw):
    from fusion_altitude.logs._text_decode import newlines

    assert newlines(raw).decode() == raw.decode().replace("\r\n", "\n").replace("\r", "\n")


def test_read_text_normalises_newlines_in_c(tmp_path):
    path = tmp_path / "crlf.csv"
    path.write_bytes(b"time,baro\r\n0,1\r\n1,2\r3,4")
    assert _table.read_text(str(path)) == "time,baro\n0,1\n1,2\n3,4"
    from fusion_altitude.logs import _text_decode

    assert hasattr(_text_decode, "newlines")  # the fast path read_text takes (it falls back silently without it)


@pytest.mark.parametrize("newline, final", [("\r\n", True), ("\r\n", False), ("\n", False), ("\r", True)])
def test_a_csv_with_tricky_cells_reads_the_same_with_every_engine_and_the_scan_reads_it(tmp_path, monkeypatch,
                                                                                     newline, final):
    from test_csv_engines import CSV, assert_same_both_ways

    rows = ["time,accel,baro,reference"]
    numbers = ["1e2", " -5.391191E-05 ", "+0.5", ".25", "7.", "1.2605042016806722", "1e-400", "-0", "2.5e+1",
               "123456789012345678901234567890e-29", "\t9.81"]
    cells = numbers + ["", "NA", "nan", "N/A", " null "]
    for i in range(60):
        rows.append(f"{i * 0.02:.2f},{numbers[i % len(numbers)]},{cells[(i * 7) % len(cells)]},"
                    f"{cells[(i * 3) % len(cells)]}")
    path = tmp_path / "tricky.csv"
    path.write_bytes((newline.join(rows) + (newline if final else "")).encode())
    scanned = []
    scan = _csv_fast._scan
    monkeypatch.setattr(_csv_fast, "_scan", lambda *a: scanned.append(scan(*a) is not None) or scan(*a))
    outcome = assert_same_both_ways(path, **CSV)
    assert outcome[0] == "LogData" and True in scanned


def test_the_scan_fuzz_corpus_replays_clean_under_asan_and_ubsan(tmp_path):
    """csrc/fuzz/fuzz_csv.c over csrc/fuzz/corpus_csv: every number the scan reads is strtod's, every row and
    text cell a plain split's, and it reads nothing outside the body."""
    from decoder_harness import assert_fuzz_corpus_replays_clean

    assert_fuzz_corpus_replays_clean("csv", tmp_path, minimum_files=8)
