"""``fusion-altitude report`` and ``fleet report`` without a browser: arguments, refusals, what the page holds.

The pages in a real browser: tests/test_report_browser.py.
"""

import sys

import pytest

from fusion_altitude import report, runner
from fusion_altitude.cli import main
from fusion_altitude.logs import LogWarning, load_log


def _log(path):
    with pytest.warns(LogWarning):  # the shared PX4 log's logging gap, said by the reader
        return load_log(str(path))


def _run(argv, capsys):
    status = main(argv)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_report_writes_the_logs_name_with_html_in_the_current_folder_by_default(shared_logs, tmp_path, monkeypatch,
                                                                                   capsys):
    monkeypatch.chdir(tmp_path)
    status, out, _ = _run(["report", str(shared_logs / "rrc3_juno3.csv")], capsys)
    assert status == 0 and "report written to rrc3_juno3.html" in out
    assert (tmp_path / "rrc3_juno3.html").stat().st_size > 0


def test_report_refuses_an_output_that_is_not_html(shared_logs, tmp_path, capsys):
    status, _, err = _run(["report", str(shared_logs / "rrc3_juno3.csv"), "-o", str(tmp_path / "r.png")], capsys)
    assert status == 2 and "-o" in err and ".html" in err and not (tmp_path / "r.png").exists()


def test_report_refuses_to_overwrite_its_input(shared_logs, tmp_path, capsys):
    log = tmp_path / "log.html"
    log.write_bytes((shared_logs / "rrc3_juno3.csv").read_bytes())
    before = log.read_bytes()
    status, _, err = _run(["report", str(log), "-o", str(log)], capsys)
    assert status == 2 and "refusing to overwrite" in err and log.read_bytes() == before


def test_report_refuses_an_estimator_the_log_cannot_feed(shared_logs, tmp_path, capsys):
    status, _, err = _run(["report", str(shared_logs / "rrc3_juno3.csv"), "--estimator", "ins", "-o",
                           str(tmp_path / "r.html")], capsys)
    assert status == 2 and "--estimator ins needs raw" in err and not (tmp_path / "r.html").exists()


def test_report_refuses_a_preset_without_the_observer(shared_logs, tmp_path, capsys):
    status, _, err = _run(["report", str(shared_logs / "px4_sample_log_small.ulg"), "--estimator", "kalman",
                           "--preset", "vtol", "-o", str(tmp_path / "r.html")], capsys)
    assert status == 2 and "--preset" in err


def test_report_runs_the_observer_with_the_preset_run_picks_on_a_slow_baro(shared_logs, tmp_path, capsys):
    # the 2 Hz baro is too slow for vtol: `run` picks fixed_wing and says so; the report does the same
    log = str(shared_logs / "px4_octorotor_2hz_baro.ulg")
    status, _, err = _run(["report", log, "--estimator", "observer", "-o", str(tmp_path / "r.html")], capsys)
    assert status == 0 and "running preset fixed_wing" in err
    assert "preset fixed_wing" in (tmp_path / "r.html").read_text()


def test_report_without_bokeh_says_which_extra_to_install(shared_logs, tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "bokeh", None)
    status, _, err = _run(["report", str(shared_logs / "rrc3_juno3.csv"), "-o", str(tmp_path / "r.html")], capsys)
    assert status == 2 and "fusion-altitude[report]" in err and not (tmp_path / "r.html").exists()
    with pytest.raises(ImportError, match=r"fusion-altitude\[report\]"):
        report.save(None, str(tmp_path / "r.html"))


def test_fleet_report_refuses_a_folder_that_does_not_exist(tmp_path, capsys):
    status, _, err = _run(["fleet", "report", str(tmp_path / "nothing")], capsys)
    assert status == 2 and "no such directory" in err


def test_fleet_report_refuses_a_folder_without_a_fleet_run(tmp_path, capsys):
    status, _, err = _run(["fleet", "report", str(tmp_path)], capsys)
    assert status == 2 and "summary.parquet" in err and not (tmp_path / "fleet.html").exists()


def test_the_header_has_the_health_of_every_sensor_and_the_error_table(shared_logs):
    data = _log(shared_logs / "px4_sample_log_small.ulg")
    run = runner.run_log(data, estimator="kalman")
    header = report.log_report(run).children[0].text
    for stream in ("accelerometer", "baro", "gps"):
        assert f"<td class='fa-text'>{stream}</td>" in header, stream
    assert "Against the log's own estimate" in header and "<td class='fa-text'>kalman − ref</td>" in header
    assert "<td class='fa-text'>baro − ref</td>" in header


def test_a_logging_gap_of_the_log_is_a_shaded_span(shared_logs):
    data = _log(shared_logs / "px4_sample_log_small.ulg")
    assert data.gaps
    layout = report.log_report(runner.run_log(data, estimator="observer"))
    labels = [item.label.value for plot in layout.children[1:] for item in plot.legend[0].items]
    assert "logging gap" in labels


def test_the_kalman_residual_is_drawn_with_its_gate(shared_logs):
    data = _log(shared_logs / "px4_sample_log_small.ulg")
    layout = report.log_report(runner.run_log(data, estimator="kalman"))
    residual = layout.children[-1]
    names = [r.name for r in residual.renderers if r.name]
    assert "kalman residual" in names and "kalman gate (+)" in names and "kalman gate (−)" in names
    assert "Kalman baro innovation; gate ±" in layout.children[0].text


def test_report_agl_puts_every_altitude_above_the_start(shared_logs, tmp_path, capsys):
    page = tmp_path / "agl.html"
    status, _, err = _run(["report", str(shared_logs / "px4_sample_log_small.ulg"), "--agl", "-o", str(page)],
                          capsys)
    assert status == 0, err
    text = page.read_text()
    assert "altitude above the start (m)" in text and "above the start (" in text


def test_a_stream_that_stops_is_a_shaded_sensor_timeout(shared_logs):
    """The Raven's axial accelerometer is logged for the first 4.5 s only (shared data README)."""
    data = _log(shared_logs / "raven_ndrt2020.csv")
    layout = report.log_report(runner.run_log(data, estimator="rocket"))
    labels = [item.label.value for item in layout.children[1].legend[0].items]
    assert "GPS / rangefinder / axial accelerometer timeout" in labels
