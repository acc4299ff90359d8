"""CSV at parse speed (issue 25, item 3): the C scan, the pyarrow reader and the C writer give what the Python
paths give.

Reading: every CSV fixture of tests/logfixtures.py, every shared CSV and
the CSV seeds of the reader fuzz (tests/fuzz_readers.py) with mutations are
read three ways — ``engine("python")`` (numpy's ``loadtxt`` and the
pure-Python pass, the old path), ``engine("pyarrow")`` (pyarrow first) and
the default (the C scan of ``_csv_scan.h`` first for small bodies) — and the
outcomes must be the same: every LogData field bit for bit and the same
warnings, or the same LogError message. The C scan's numbers are compared
with Python's ``float`` and pyarrow's on tricky cells in tests/test_csv_scan.py. Writing: ``run -o`` text is the
old writer's byte for byte and reads back to the same bits.
"""

import dataclasses
import io
import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import fuzz_readers  # noqa: E402
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude._core import _csv_write  # noqa: E402
from fusion_altitude.logs import _csv_fast  # noqa: E402
from fusion_altitude.outputs import _write_csv_stream_python, csv_columns, write_csv  # noqa: E402
from fusion_altitude.runner import run_log  # noqa: E402
from fusion_altitude._core._csv_write import write_csv_stream  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", str(ROOT / ".." / "shared" / "data")))
CSV = fuzz_readers.CSV_OPTIONS
CSV_SEEDS = ("altos", "altos-1.4", "altos-telemetry", "cats", "cats-imu", "csv", "raven", "rrc3")


def _field(value):
    """A LogData field in a form whose == is bit-for-bit equality."""
    if isinstance(value, np.ndarray) and value.dtype == object:
        return ("objects", value.shape, tuple(_field(v) for v in value.ravel().tolist()))
    if isinstance(value, np.ndarray):
        return ("array", value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, float):
        return ("float", np.float64(value).tobytes())
    if isinstance(value, (list, tuple)):
        return tuple(_field(v) for v in value)
    if isinstance(value, dict):
        return tuple(sorted((k, _field(v)) for k, v in value.items()))
    return value


def outcome(path, engine: str, **options):
    """What reading ``path`` with the CSV ``engine`` gives: every LogData field and the warnings, or the error."""
    with _csv_fast.engine(engine), warnings.catch_warnings(record=True) as issued:
        warnings.simplefilter("always")
        try:
            log = logs.load_log(str(path), **options)
        except logs.LogError as error:
            return ("LogError", str(error), [str(w.message) for w in issued])
    fields = {f.name: _field(getattr(log, f.name)) for f in dataclasses.fields(log)}
    return ("LogData", fields, [str(w.message) for w in issued])


def assert_same_both_ways(path, **options):
    """The outcome of reading ``path`` with every engine (the Python path, pyarrow, the C scan), all equal."""
    old = outcome(path, "python", **options)
    for engine in ("pyarrow", "auto"):
        new = outcome(path, engine, **options)
        assert old[0] == new[0], (path, engine, old[:2] if old[0] == "LogError" else old[0], new[0])
        if old[0] == "LogData":
            differing = [name for name in old[1] if old[1][name] != new[1][name]]
            assert differing == [], f"{path}: fields differ with {engine}: {differing}"
        else:
            assert old[1] == new[1], engine
        assert old[2] == new[2], engine
    return old


def fixture_csvs(directory: Path):
    """Every CSV fixture of tests/logfixtures.py: (path, load_log options)."""
    d = directory
    out = []
    generic = [dict(), dict(accel_units="g", altitude_units="ft"), dict(bom=True), dict(gap=(8.0, 9.0)),
               dict(repeat_every=7), dict(cut_tail=True), dict(bad_cell_row=30), dict(backwards_row=40),
               dict(gravity=fx.G), dict(time_scale=1000.0),
               dict(cells={3: {"baro": "NA"}, 4: {"baro": "nan"}, 5: {"reference": "NULL"}, 6: {"baro": " 12.5 "},
                           9: {"baro": "1e30"}, 12: {"reference": "inf"}, 20: {"baro": '"10.25"'}})]
    for i, kind in enumerate(generic):
        path = d / f"generic{i}.csv"
        fx.write_generic_csv(path, duration=6.0, rate=50.0, **kind)
        options = dict(CSV, time_units="ms") if kind.get("time_scale") else dict(CSV)
        if kind.get("accel_units"):
            options.update(accel_units="g", altitude_units="ft")
        out.append((path, options))
    fx.write_altos_csv(d / "altos.csv", duration=5.0, pad_time=1.0)
    fx.write_altos_csv(d / "altos_bom.csv", duration=5.0, pad_time=1.0, bom=True, padded=True)
    out += [(d / "altos.csv", {}), (d / "altos_bom.csv", {})]
    for style in ("current", "1.4", "v5"):
        path = d / f"altos_rocket_{style}.csv"
        fx.write_altos_rocket_csv(path, style=style, duration=5.0, pad_time=0.5)
        out.append((path, {}))
    maker_dir = d / "makers"
    maker_dir.mkdir()
    for maker in (fx.altos_telemetry_csv, fx.altos_14_csv, fx.telemega_dead_imu_csv, fx.telemega_saturating_imu_csv,
                  fx.easymini_csv, fx.raven_csv, fx.rrc3_csv):
        out.append((Path(maker(maker_dir)), {}))
    for maker in (fx.csv_with_absurd_baro, fx.csv_with_millisecond_time):
        out.append((Path(maker(maker_dir)), dict(CSV)))
    cats = d / "cats"
    cats.mkdir()
    fx.write_cats_set(cats, duration=3.0, pad_time=1.0, second_instance=True)
    out += [(cats / "flight_baro.csv", {}), (cats / "flight_imu.csv", {})]
    return out


def test_every_csv_fixture_reads_the_same_with_every_engine(tmp_path):
    cases = fixture_csvs(tmp_path)
    outcomes = [assert_same_both_ways(path, **options)[0] for path, options in cases]
    assert outcomes.count("LogData") >= len(cases) // 2  # the comparison covers real reads, not only errors


def test_every_shared_csv_reads_the_same_with_every_engine():
    assert DATA.is_dir(), f"shared data not found at {DATA}"
    shared = sorted(DATA.glob("*.csv"))
    assert len(shared) >= 5
    outcomes = [assert_same_both_ways(path)[0] for path in shared]
    assert outcomes.count("LogData") >= 4, list(zip(shared, outcomes))


def test_the_reader_fuzz_corpus_reads_the_same_with_every_engine(tmp_path):
    rng = np.random.default_rng(25)
    (tmp_path / "seeds").mkdir()
    base = fuzz_readers.seeds(str(tmp_path / "seeds"), None)
    for fmt in CSV_SEEDS:
        data, name, options, siblings = base[fmt]
        for k, mutated in enumerate([data] + fx.mutations(data, rng, 12)):
            case = tmp_path / f"{fmt}-{k}"
            case.mkdir()
            for sibling, content in siblings.items():
                fx.write_bytes(case / sibling, content)
            assert_same_both_ways(fx.write_bytes(case / name, mutated), **options)


@pytest.mark.parametrize("engine", ["pyarrow", "auto"])
def test_the_fast_engines_read_the_plain_columns_themselves(engine):
    body = "0.5,1e-3,,NA,x\n1.25,-2,nan,7,y\n"
    with _csv_fast.engine(engine):
        data = _csv_fast.read_columns(body, [0, 1, 2, 3], ("", "nan", "na"))
    assert data is not None and data.shape == (2, 4)
    assert data[:, :2].tolist() == [[0.5, 1e-3], [1.25, -2.0]]
    assert np.isnan(data[:, 2]).all() and np.isnan(data[0, 3]) and data[1, 3] == 7.0


@pytest.mark.parametrize("engine", ["pyarrow", "auto"])
def test_the_fast_engines_leave_a_row_of_another_length_to_the_python_path(engine):
    with _csv_fast.engine(engine):
        assert _csv_fast.read_columns("1,2\n3\n", [0, 1], ("",)) is None


def test_the_python_engine_turns_the_fast_reader_off():
    with _csv_fast.engine("python"):
        assert _csv_fast.read_columns("1,2\n", [0, 1], ("",)) is None


def test_an_unknown_engine_is_refused_by_name():
    with pytest.raises(ValueError, match="engine"):
        with _csv_fast.engine("fast"):
            pass
    with pytest.raises(ValueError, match="engine"):
        with _csv_write.engine("fast"):
            pass


def _awkward_columns(n: int):
    """Columns with what the writer must spell exactly: float64 extremes, float32 estimates, NaN, ±inf, ints."""
    rng = np.random.default_rng(7)
    f64 = rng.standard_normal(n) * 10.0 ** rng.integers(-320, 308, n)
    f64[:8] = [0.0, -0.0, np.nan, np.inf, -np.inf, 5e-324, 1.7976931348623157e308, 1e16]
    f32 = (rng.standard_normal(n) * 10.0 ** rng.integers(-40, 38, n)).astype(np.float32)
    f32[:4] = [np.float32(np.nan), np.float32(-np.inf), np.float32(1e-45), np.float32(3.4028235e38)]
    return [("time", np.arange(n) * 0.01), ("f64", f64), ("f32", f32), ("phase", rng.integers(-3, 9, n)),
            ("flag", rng.integers(0, 2, n).astype(bool)), ("flags", rng.integers(0, 16, n).astype(np.uint8))]


def test_the_c_writer_writes_the_python_writers_bytes():
    columns = _awkward_columns(20_000)
    old, new = io.StringIO(), io.StringIO()
    _write_csv_stream_python(columns, old, 20_000, None, 3_000)
    write_csv_stream(columns, new, 20_000, None, 3_000)
    assert new.getvalue() == old.getvalue()


def test_the_written_csv_reads_back_bit_for_bit():
    columns = _awkward_columns(5_000)
    text = io.StringIO()
    write_csv_stream(columns, text, 5_000, None, 1_000)
    rows = text.getvalue().splitlines()[1:]
    for j, (_, values) in enumerate(columns):
        read = np.array([float(row.split(",")[j]) for row in rows]).astype(values.dtype)
        assert read.tobytes() == values.tobytes()


def test_run_o_writes_the_same_file_with_both_writers(tmp_path):
    fx.write_generic_csv(tmp_path / "log.csv", duration=6.0, rate=50.0)
    run = run_log(logs.load_log(str(tmp_path / "log.csv"), **CSV))
    assert len(csv_columns(run)) >= 6
    with _csv_write.engine("python"):
        write_csv(run, str(tmp_path / "old.csv"))
    write_csv(run, str(tmp_path / "new.csv"))
    assert (tmp_path / "new.csv").read_bytes() == (tmp_path / "old.csv").read_bytes()


def test_the_shared_csvs_are_parsed_by_pyarrow_not_the_fallback(monkeypatch):
    """The comparisons above compare two paths: on the shared CSVs (RRC3 and Raven text columns included) the
    fast reader does the parsing, one pass a file."""
    taken = []

    def counting(original):
        def parse(*args, **kwargs):
            data = original(*args, **kwargs)
            taken.append(data is not None)
            return data
        return parse

    for name in ("read_numbers_and_text", "scan_bytes"):  # RRC3 scans its bytes in place (branch small6)
        monkeypatch.setattr(_csv_fast, name, counting(getattr(_csv_fast, name)))
    for name in ("hedy_imu.csv", "raven_ndrt2020.csv", "rrc3_juno3.csv"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            logs.load_log(str(DATA / name))
    assert len(taken) == 5 and all(taken)  # CATS: imu, baro, flight info (ids in the same pass); Raven; RRC3



def _rrc3_with_awkward_cells(path, extra_row=""):
    """An RRC3 export whose temperature cells are numbers, blanks, NA, padded numbers and shifted events."""
    temperatures = ["31.9", "", "NA", " 32 ", "nan", " -", " Drogue", "32.5", " Main", "-"]
    events = [" -", " Apogee", "", " -", "NULL", "", "", " main", "", ""]
    rows = ["time,altitude,pressure,velocity,temperature,events,voltages"]
    for i in range(60):
        rows.append(f"{i * 0.05:.2f},{i * 1.5:.3f},{861.7 - i * 0.1:.2f},{30.0 - i:.4f},"
                    f"{temperatures[i % 10]},{events[i % 10]},3.81")
    path.write_text("\n".join(rows) + "\n" + extra_row)
    return path


def test_rrc3_text_cells_read_by_pyarrow_as_the_python_loop_reads_them(tmp_path, monkeypatch):
    path = _rrc3_with_awkward_cells(tmp_path / "flight.csv")
    taken = []
    original = _csv_fast.read_numbers_and_text
    monkeypatch.setattr(_csv_fast, "read_numbers_and_text",
                        lambda *a, **k: taken.append(original(*a, **k)) or taken[-1])
    outcome_ = assert_same_both_ways(path)
    assert outcome_[0] == "LogData" and taken[-1] is not None  # the fast path read it


@pytest.mark.parametrize("extra_row", ["3.00,90,855.7,-30\n", "3.00,90,855.7,-30,31.9, -,3.81,9\n",
                                       "3.00,abc,855.7,-30,31.9, -,3.81\n", '3.00,90,855.7,-30,"3,1", -,3.81\n'])
def test_rrc3_rows_pyarrow_refuses_are_read_by_the_python_loop_the_same(tmp_path, extra_row):
    assert_same_both_ways(_rrc3_with_awkward_cells(tmp_path / "flight.csv", extra_row))

def test_without_pyarrow_the_numpy_path_reads_the_same(tmp_path, monkeypatch):
    fx.write_generic_csv(tmp_path / "log.csv", duration=6.0, rate=50.0, repeat_every=9)
    with_pyarrow = outcome(tmp_path / "log.csv", "auto", **CSV)
    monkeypatch.setattr(_csv_fast, "_pyarrow", lambda: None)
    with _csv_fast.engine("pyarrow"):
        assert _csv_fast.read_columns("1,2\n", [0, 1], ("",)) is None
    assert outcome(tmp_path / "log.csv", "pyarrow", **CSV) == with_pyarrow


def test_without_the_extension_run_o_falls_back_to_the_python_writer(tmp_path, monkeypatch):
    fx.write_generic_csv(tmp_path / "log.csv", duration=6.0, rate=50.0)
    run = run_log(logs.load_log(str(tmp_path / "log.csv"), **CSV))
    write_csv(run, str(tmp_path / "fast.csv"))
    monkeypatch.setattr(_csv_write, "available", lambda: False)
    monkeypatch.setattr(_csv_write, "write_csv_stream", None)  # would fail if called
    write_csv(run, str(tmp_path / "python.csv"))
    assert (tmp_path / "python.csv").read_bytes() == (tmp_path / "fast.csv").read_bytes()
