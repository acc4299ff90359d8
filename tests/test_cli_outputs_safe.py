"""Your files are safe: no output replaces an input, a sibling of a multi-file log, a device or a pipe; the
output format follows the extension; errors name the user's path; a fleet sees flights, not files."""

import os
import re
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fusion_altitude.cli import main



@pytest.fixture
def shared_data(shared_logs):
    return shared_logs


@pytest.fixture
def cats(tmp_path, shared_data):
    """A copy of the CATS flight (baro, IMU, flight info) whose first 3000 rows make a short flight."""
    for role in ("baro", "imu", "flight_info"):
        lines = (shared_data / f"hedy_{role}.csv").read_text().splitlines(keepends=True)[:3000]
        (tmp_path / f"hedy_{role}.csv").write_text("".join(lines))
    return tmp_path


def run(cats, *argv):
    return main(["run", str(cats / "hedy_baro.csv"), *argv])


def contents(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


@pytest.mark.parametrize("role", ["imu", "flight_info", "baro"])
@pytest.mark.parametrize("flag", ["-o", "--events-csv"])
def test_an_output_on_any_file_of_a_multi_file_log_is_refused_and_nothing_changes(cats, capsys, flag, role):
    before = contents(cats)
    assert run(cats, flag, str(cats / f"hedy_{role}.csv")) == 2
    err = capsys.readouterr().err
    assert "refusing to overwrite it" in err and len(err.strip().splitlines()) == 1
    assert contents(cats) == before


@pytest.mark.parametrize("link", ["symlink", "hardlink"])
def test_an_output_through_a_link_to_a_sibling_is_refused(cats, capsys, link):
    target = cats / "other" / "imu_link.csv"
    target.parent.mkdir()
    (os.symlink if link == "symlink" else os.link)(cats / "hedy_imu.csv", target)
    before = contents(cats)
    assert run(cats, "-o", str(target)) == 2
    assert "refusing to overwrite it" in capsys.readouterr().err and contents(cats) == before


def test_an_output_named_as_a_missing_member_of_the_set_is_refused(cats, capsys):
    (cats / "hedy_flight_info.csv").unlink()
    assert run(cats, "-o", str(cats / "hedy_flight_info.csv")) == 2
    assert "the next read would take it for one" in capsys.readouterr().err
    assert not (cats / "hedy_flight_info.csv").exists()


def test_dash_writes_the_csv_to_stdout_and_the_report_to_stderr(cats, capsys):
    assert run(cats, "-o", "-") == 0
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert lines[0].startswith("time,altitude,vertical_velocity") and len(lines) == 1 + 2999  # header + rows
    assert "flight events" in captured.err and not (Path.cwd() / "-").exists()


def test_a_fifo_is_written_in_place_and_stays_a_fifo(cats, tmp_path):
    fifo = tmp_path / "out.fifo"
    os.mkfifo(fifo)
    with open(tmp_path / "received.csv", "wb") as sink:
        reader = subprocess.Popen(["cat", str(fifo)], stdout=sink)
        status = subprocess.run([sys.executable, "-m", "fusion_altitude", "run", str(cats / "hedy_baro.csv"), "-o",
                                 str(fifo)], capture_output=True, text=True, timeout=120).returncode
        reader.wait(timeout=60)
    received = (tmp_path / "received.csv").read_text()
    assert status == 0 and stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert received.startswith("time,altitude") and len(received.splitlines()) > 2000


def test_dev_null_stays_a_device(cats, capsys):
    assert run(cats, "-o", os.devnull) == 0
    assert stat.S_ISCHR(os.stat(os.devnull).st_mode)


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="Linux only: /dev/full")
def test_a_full_device_is_an_error_naming_it_and_stays_a_device(cats, capsys):
    assert run(cats, "-o", "/dev/full") == 2
    err = capsys.readouterr().err
    assert "/dev/full: No space left on device" in err and stat.S_ISCHR(os.stat("/dev/full").st_mode)


def test_an_unknown_extension_is_refused_before_any_work(cats, capsys):
    assert run(cats, "-o", str(cats / "out.txt")) == 2
    captured = capsys.readouterr()
    assert "writes .csv or .parquet files, not .txt" in captured.err and captured.out == ""


def test_parquet_output_holds_the_same_columns_as_the_csv(cats, capsys):
    import pyarrow.parquet as pq

    assert run(cats, "-o", str(cats / "out.csv")) == 0
    assert run(cats, "-o", str(cats / "out.parquet")) == 0
    table = pq.read_table(cats / "out.parquet")
    csv = np.genfromtxt(cats / "out.csv", delimiter=",", names=True)
    assert tuple(table.column_names) == csv.dtype.names
    np.testing.assert_array_equal(table.column("altitude").to_numpy(), csv["altitude"].astype(np.float32))


def test_a_folder_where_no_file_can_be_created_is_refused_before_any_work_naming_the_users_path(cats, capsys):
    assert run(cats, "-o", "/proc/x.csv") == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "-o /proc/x.csv: cannot create a file in /proc" in captured.err
    assert ".part" not in captured.err


def test_a_fleet_of_one_cats_flight_is_one_row(cats, tmp_path):
    from fusion_altitude import fleet

    assert fleet.expand_paths(str(cats)) == [str(cats / "hedy_baro.csv")]


def test_a_cats_imu_file_given_alone_is_still_its_flight(cats):
    from fusion_altitude import fleet

    assert fleet.expand_paths([str(cats / "hedy_imu.csv")]) == [str(cats / "hedy_imu.csv")]


def test_reader_warnings_in_the_fleet_are_one_line_warnings_never_python_warning_text(tmp_path, shared_data):
    logs = tmp_path / "logs"
    logs.mkdir()
    shutil.copyfile(shared_data / "px4_sample_log_small.ulg", logs / "a.ulg")
    result = subprocess.run([sys.executable, "-m", "fusion_altitude", "fleet", "run", str(logs), "-o",
                             str(tmp_path / "out"), "--workers", "1"], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "LogWarning" not in result.stderr and ".py:" not in result.stderr
    assert any(line.startswith("warning: a.ulg-") and "logging gap" in line for line in result.stderr.splitlines())


def test_a_truncated_ulog_is_read_flagged_and_warned(tmp_path, shared_data):
    from fusion_altitude import logs

    blob = (shared_data / "px4_sample_log_small.ulg").read_bytes()
    (tmp_path / "cut.ulg").write_bytes(blob[:300000])
    with pytest.warns(logs.LogWarning, match="ends inside a message"):
        data = logs.load_log(str(tmp_path / "cut.ulg"))
    assert data.truncated
    assert not logs.load_log(str(shared_data / "px4_sample_log_small.ulg")).truncated


def test_a_dataflash_log_cut_inside_a_message_is_flagged(tmp_path, shared_data):
    from fusion_altitude.logs import _truncation

    blob = (shared_data / "ardupilot_test.BIN").read_bytes()
    (tmp_path / "cut.bin").write_bytes(blob[:40000])
    assert _truncation.dataflash_missing_bytes(str(tmp_path / "cut.bin")) == 48
    # the shared fixture is pymavlink's test.BIN, itself cut at 64 KiB inside a message
    assert len(blob) == 65536 and _truncation.dataflash_missing_bytes(str(shared_data / "ardupilot_test.BIN")) == 21
    ends = [i for i in range(len(blob) - 200, len(blob)) if blob[i:i + 2] == b"\xa3\x95"]
    (tmp_path / "boundary.bin").write_bytes(blob[:ends[-1]])  # cut just before the last message start
    assert _truncation.dataflash_missing_bytes(str(tmp_path / "boundary.bin")) is None


def test_the_fleet_summary_flags_a_truncated_log(tmp_path, shared_data):
    from fusion_altitude import fleet

    folder = tmp_path / "logs"
    folder.mkdir()
    blob = (shared_data / "px4_sample_log_small.ulg").read_bytes()
    (folder / "whole.ulg").write_bytes(blob)
    (folder / "cut.ulg").write_bytes(blob[:300000])
    result = fleet.run_many(str(folder), output_dir=str(tmp_path / "out"), workers=1)
    rows = {row["path"].rsplit("/", 1)[-1]: row for row in result.summary.to_pylist()}
    assert rows["cut.ulg"]["truncated"] and not rows["whole.ulg"]["truncated"]
    assert "ends inside a message" in rows["cut.ulg"]["warnings"]


def test_a_fleet_of_the_shared_data_is_one_row_per_flight_without_python_warning_text(tmp_path, shared_data):
    logs = tmp_path / "logs"
    logs.mkdir()
    for path in shared_data.iterdir():
        if path.suffix.lower() in (".ulg", ".bin", ".csv"):
            shutil.copyfile(path, logs / path.name)
    (logs / "cut.ulg").write_bytes((shared_data / "px4_sample_log_small.ulg").read_bytes()[:300000])
    flights = {path.name for path in logs.iterdir()} - {"hedy_imu.csv", "hedy_flight_info.csv"}
    result = subprocess.run([sys.executable, "-m", "fusion_altitude", "fleet", "run", str(logs), "-o",
                             str(tmp_path / "out"), "--workers", "1"], capture_output=True, text=True, timeout=900)
    assert "Traceback" not in result.stderr and not re.search(r"\w+Warning\b|\.py:\d+", result.stderr), result.stderr
    from fusion_altitude import fleet

    rows = fleet.summary(str(tmp_path / "out")).to_pylist()
    assert sorted(row["path"].rsplit("/", 1)[-1] for row in rows) == sorted(flights)
    truncated = [row["path"].rsplit("/", 1)[-1] for row in rows if row["truncated"]]
    assert "cut.ulg" in truncated and "px4_sample_log_small.ulg" not in truncated


@pytest.mark.parametrize("where", ["the log directory", "a folder inside it", "its parent",
                                   "a link to the log directory"])
def test_a_fleet_output_directory_among_the_logs_is_refused_before_any_work(cats, tmp_path, capsys, where):
    output = {"the log directory": cats, "a folder inside it": cats / "out", "its parent": cats.parent,
              "a link to the log directory": tmp_path.parent / f"{tmp_path.name}-link"}[where]
    if where == "a link to the log directory":
        output.symlink_to(cats, target_is_directory=True)
    before = contents(cats)
    assert main(["fleet", "run", str(cats), "-o", str(output), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and f"-o {output}" in err
    assert contents(cats) == before and not (cats / "out").exists() and not (cats / "summary.csv").exists()


def test_the_library_refuses_a_fleet_output_directory_that_holds_a_log(cats):
    from fusion_altitude import fleet

    with pytest.raises(ValueError, match="output_dir .* holds the log"):
        fleet.run_many([str(cats / "hedy_baro.csv")], output_dir=str(cats), workers=1)
