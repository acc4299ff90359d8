"""``run -o`` and ``--plot`` lose nothing: full precision, atomic writes, outputs checked before any work."""

import os

import numpy as np
import pytest

from fusion_altitude import logs, runner
from fusion_altitude.cli import main
from fusion_altitude.plotting import decimate


def write_log(path, time, accel, baro, reference=None, time_format="{!r}"):
    header = "t,az,alt" + (",ref" if reference is not None else "")
    lines = [header]
    for i in range(time.size):
        cells = [time_format.format(float(time[i])), repr(float(accel[i])),
                 "" if np.isnan(baro[i]) else repr(float(baro[i]))]
        if reference is not None:
            cells.append(repr(float(reference[i])))
        lines.append(",".join(cells))
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def run_to_csv(tmp_path, log, *extra):
    out = tmp_path / "out.csv"
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "-o", str(out), *extra]) == 0
    return np.genfromtxt(out, delimiter=",", names=True)


def test_epoch_times_come_back_exactly(tmp_path, capsys):
    time = 1700000000.010 + 0.01 * np.arange(2000)
    log = write_log(tmp_path / "log.csv", time, np.zeros(2000), np.full(2000, 12.5), time_format="{:.3f}")
    table = run_to_csv(tmp_path, log)
    expected = np.array([float(f"{t:.3f}") for t in time])
    assert np.unique(table["time"]).size == 2000
    assert np.array_equal(table["time"], expected)


def test_eight_hour_log_keeps_every_timestamp_and_value(tmp_path, capsys):
    time = np.arange(0, 8 * 3600, 0.1)[:288_000]
    rng = np.random.default_rng(0)
    baro = 500 + rng.normal(0, 0.3, time.size)
    log = write_log(tmp_path / "log.csv", time, rng.normal(0, 0.05, time.size), baro)
    table = run_to_csv(tmp_path, log)
    assert np.array_equal(table["time"], time)
    assert np.array_equal(table["baro_altitude"], baro)


def test_estimates_at_30_km_round_trip_bit_for_bit(tmp_path, capsys):
    n = 3000
    rng = np.random.default_rng(1)
    time = 0.05 * np.arange(n)
    baro = 30_000 + 5 * np.sin(time / 10) + rng.normal(0, 0.5, n)
    log = write_log(tmp_path / "log.csv", time, rng.normal(0, 0.05, n), baro)
    table = run_to_csv(tmp_path, log)
    run = runner.run_log(logs.load_log(log, time_column="t", accel_column="az", baro_column="alt"))
    for name in ("altitude", "vertical_velocity", "accel_bias", "baro_residual"):
        written = table[name].astype(np.float32)
        assert np.array_equal(written, getattr(run.estimate, name), equal_nan=True), name
    assert np.unique(table["altitude"]).size > n // 2  # not quantised to 0.1 m steps


def test_output_columns_start_with_time_altitude_velocity_and_end_with_the_reference_and_the_flags(tmp_path, capsys):
    n = 200
    log = write_log(tmp_path / "log.csv", 0.01 * np.arange(n), np.zeros(n), np.full(n, 3.0), np.full(n, 3.1))
    table = run_to_csv(tmp_path, log, "--reference", "ref")
    names = table.dtype.names
    assert names[:3] == ("time", "altitude", "vertical_velocity") and names[-2:] == ("reference_altitude", "flags")


@pytest.mark.parametrize("flag", ["-o", "--plot"])
def test_output_equal_to_the_input_is_refused_and_the_input_kept(tmp_path, capsys, flag):
    n = 100
    log = write_log(tmp_path / "log.csv", 0.01 * np.arange(n), np.zeros(n), np.full(n, 3.0))
    before = (tmp_path / "log.csv").read_bytes()
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", flag, log]) == 2
    assert "is the input file" in capsys.readouterr().err
    assert (tmp_path / "log.csv").read_bytes() == before


@pytest.mark.parametrize("flag,name", [("-o", "out.csv"), ("--plot", "p.png")])
def test_an_output_in_a_missing_folder_is_reported_before_any_work(tmp_path, capsys, flag, name):
    n = 100
    log = write_log(tmp_path / "log.csv", 0.01 * np.arange(n), np.zeros(n), np.full(n, 3.0))
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", flag,
                 str(tmp_path / "nonexistent" / name)]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "does not exist" in captured.err and "Traceback" not in captured.err


def test_a_plot_format_matplotlib_cannot_write_is_reported_before_any_work(tmp_path, capsys):
    n = 100
    log = write_log(tmp_path / "log.csv", 0.01 * np.arange(n), np.zeros(n), np.full(n, 3.0))
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "--plot", str(tmp_path / "p.xyz")]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "'.xyz'" in captured.err and ".png" in captured.err


def test_atomic_output_keeps_the_old_file_and_leaves_nothing_behind_on_failure(tmp_path):
    target = tmp_path / "out.csv"
    target.write_text("old\n")
    with pytest.raises(RuntimeError):
        with runner.atomic_output(str(target)) as temporary:
            with open(temporary, "w") as stream:
                stream.write("half a res")
            raise RuntimeError("crash while writing")
    assert target.read_text() == "old\n" and os.listdir(tmp_path) == ["out.csv"]


def test_a_failing_plot_leaves_no_file(tmp_path, monkeypatch, capsys):
    import matplotlib.figure

    def broken(self, path, **options):
        with open(path, "wb") as stream:
            stream.write(b"\x89PNG half")
        raise OSError("disk full")

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", broken)
    assert main(["demo", "--scenario", "clean", "--plot", str(tmp_path / "demo.png")]) == 2
    assert os.listdir(tmp_path) == [] and "disk full" in capsys.readouterr().err


def test_decimation_keeps_each_column_minimum_and_maximum():
    x = np.arange(1_000_000, dtype=float)
    y = np.zeros_like(x)
    y[123_457] = 50.0   # a one-sample spike
    y[800_001] = -7.0
    dx, dy = decimate(x, y, columns=1000)
    assert dy.size <= 2000 and dy.max() == 50.0 and dy.min() == -7.0
    assert np.all(np.diff(dx) >= 0)


def test_short_series_are_not_decimated():
    x = np.arange(100.0)
    dx, dy = decimate(x, x * 2, columns=1000)
    assert np.array_equal(dx, x) and np.array_equal(dy, x * 2)


def test_progress_covers_reading_estimating_writing_and_plotting_on_a_long_log(tmp_path, capsys, monkeypatch):
    from fusion_altitude import cli

    monkeypatch.setattr(cli, "STAGE_REPORT_SECONDS", 0.0)
    n = 1000
    log = write_log(tmp_path / "log.csv", 0.01 * np.arange(n), np.zeros(n), np.full(n, 3.0))
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "-o", str(tmp_path / "o.csv"),
                 "--plot", str(tmp_path / "p.png")]) == 0
    err = capsys.readouterr().err
    for stage in ("reading", "estimating", "writing", "plotting"):
        assert f"{stage}: " in err, stage
