"""The columnar CSV path (pyarrow, fusion_altitude/logs/_table.py ``_arrow``) accepts nothing numpy's parser
refuses and gives the same bits; refused text goes to numpy's parser and the line-numbered slow path as before.

Every shared CSV, every CSV fixture and 20 reader-fuzz mutations of each
fixture, for every column alone and all columns together: where pyarrow
accepts the text, :func:`numpy.loadtxt` (``_numpy``) accepts it too and the
arrays are equal byte for byte; and whole reads give the same LogData with
and without the columnar path.
"""

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import logfixtures as fx  # noqa: E402
from fusion_altitude import logs  # noqa: E402
from fusion_altitude.logs import _table  # noqa: E402

CSV_OPTIONS = dict(time_column="time", accel_column="accel", baro_column="baro", reference_column="reference")


def _fixtures(directory: Path) -> list:
    fx.write_generic_csv(directory / "generic.csv", duration=5.0)
    fx.write_altos_csv(directory / "altos.csv", duration=5.0)
    (directory / "cats").mkdir()
    fx.write_cats_set(directory / "cats", duration=2.0)
    files = [directory / "generic.csv", directory / "altos.csv", *sorted((directory / "cats").glob("*.csv")),
             Path(fx.raven_csv(directory)), Path(fx.rrc3_csv(directory))]
    for make in (fx.altos_telemetry_csv, fx.altos_14_csv, fx.telemega_dead_imu_csv, fx.easymini_csv,
                 fx.csv_with_absurd_baro, fx.csv_with_millisecond_time):
        files.append(Path(make(directory)))
    return files


def _assert_arrow_agrees_with_numpy(path) -> int:
    """Compare the two parsers on every column of ``path``; return how many comparisons pyarrow accepted."""
    try:
        table = _table.split_header(str(path), _table.read_text(str(path)))
    except logs.LogError:
        return 0
    accepted = 0
    everything = list(range(len(table.header)))
    for columns in [everything] + [[k] for k in everything]:
        arrow = _table._arrow(table, columns, None)
        if arrow is None:
            continue
        numpy_result = _table._numpy(table, columns, None)
        assert numpy_result is not None, (str(path), columns, "pyarrow accepted what numpy refuses")
        assert arrow.shape == numpy_result.shape and arrow.tobytes() == numpy_result.tobytes(), (str(path), columns)
        accepted += 1
    return accepted


def test_shared_csvs_parse_the_same_with_pyarrow_and_numpy(shared_logs):
    assert sum(_assert_arrow_agrees_with_numpy(path) for path in sorted(shared_logs.glob("*.csv"))) > 0


def test_csv_fixtures_parse_the_same_with_pyarrow_and_numpy(tmp_path):
    assert sum(_assert_arrow_agrees_with_numpy(path) for path in _fixtures(tmp_path)) > 0


def test_fuzz_mutations_of_csv_fixtures_parse_the_same_with_pyarrow_and_numpy(tmp_path):
    rng = np.random.default_rng(2)
    for number, path in enumerate(_fixtures(tmp_path)):
        for data in fx.mutations(path.read_bytes(), rng, 20):
            _assert_arrow_agrees_with_numpy(fx.write_bytes(tmp_path / f"mutation{number}.csv", data))


def _read(path, **options):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = logs.load_log(str(path), **options)
        except logs.LogError as error:
            result = str(error)
    return result, [str(w.message) for w in caught if not issubclass(w.category, ResourceWarning)]


@pytest.mark.parametrize("name", ["hedy_baro.csv", "rrc3_juno3.csv", "raven_ndrt2020.csv", "generic"])
def test_reads_are_the_same_with_and_without_the_columnar_path(shared_logs, tmp_path, monkeypatch, name):
    if name == "generic":
        path, options = tmp_path / "generic.csv", CSV_OPTIONS
        fx.write_generic_csv(path, duration=20.0)
    else:
        path, options = shared_logs / name, {}
    mine, my_warnings = _read(path, **options)
    monkeypatch.setattr(_table, "_arrow", lambda *arguments: None)
    theirs, their_warnings = _read(path, **options)
    assert my_warnings == their_warnings
    if isinstance(theirs, str):
        assert mine == theirs
        return
    for field, value in vars(theirs).items():
        other = vars(mine)[field]
        if isinstance(value, np.ndarray):
            assert other.dtype == value.dtype and other.shape == value.shape, field
            assert (list(other) == list(value)) if value.dtype == object else other.tobytes() == value.tobytes(), field
        else:
            assert other == value, field
