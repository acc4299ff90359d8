"""Specification of the ``fusion-altitude`` command line."""

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import fusion_altitude
from fusion_altitude.cli import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def shared_data():
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


def _number(text, label, column):
    """The float in ``column`` (0 = raw baro, 1 = fused) of the table row starting with ``label``."""
    for line in text.splitlines():
        if line.startswith(label):
            return float(line[len(label):].split()[column])
    raise AssertionError(f"no row {label!r} in:\n{text}")


def test_version_flag_prints_package_version(tmp_path):
    completed = subprocess.run([sys.executable, "-m", "fusion_altitude", "--version"],
                               capture_output=True, text=True, check=True, cwd=tmp_path)
    assert completed.stdout.strip() == f"fusion-altitude {fusion_altitude.__version__}"


def test_demo_fused_rms_error_is_below_raw_baro_rms_error(capsys):
    assert main(["demo", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert _number(out, "RMS error (m)", 1) < _number(out, "RMS error (m)", 0) / 3


def test_demo_reports_final_bias_estimate_near_true_bias(capsys):
    assert main(["demo", "--seed", "2"]) == 0
    out = capsys.readouterr().out
    match = re.search(r"bias estimate: ([+-][\d.]+) m/s².*true vertical bias ([+-][\d.]+) m/s²", out)
    estimate, true = float(match.group(1)), float(match.group(2))
    assert abs(estimate - true) < 0.3 * abs(true)


def test_demo_is_deterministic_for_a_seed(capsys):
    main(["demo", "--seed", "7"])
    first = capsys.readouterr().out
    main(["demo", "--seed", "7"])
    assert capsys.readouterr().out == first


def test_demo_output_differs_between_seeds(capsys):
    main(["demo", "--seed", "7"])
    first = capsys.readouterr().out
    main(["demo", "--seed", "8"])
    assert capsys.readouterr().out != first


def test_demo_rejects_unknown_scenario_with_usage_error(capsys):
    try:
        main(["demo", "--scenario", "submarine"])
    except SystemExit as exit_:
        assert exit_.code == 2
    else:
        raise AssertionError("expected a usage error")
    assert "submarine" in capsys.readouterr().err


def test_tune_prints_the_vtol_gains_for_omega_1_5(capsys):
    assert main(["tune", "--omega", "1.5", "--zeta", "0.7", "--rate", "100"]) == 0
    out = capsys.readouterr().out
    assert "position_gain Kh  2.4000" in out and "bias_gain Kb      0.6750" in out


def test_tune_flags_a_coarse_discretisation(capsys):
    main(["tune", "--omega", "50", "--rate", "100"])
    assert "discretisation" in [line.split("  ")[0] for line in capsys.readouterr().out.splitlines()
                                if "FAIL" in line][0]


def test_tune_rejects_negative_omega_in_one_line(capsys):
    assert main(["tune", "--omega", "-1"]) == 2
    assert "omega" in capsys.readouterr().err


def _write_csv(path, text):
    path.write_text(text)
    return str(path)


def test_run_csv_with_irregular_time_and_missing_baro_writes_estimates(tmp_path, capsys):
    rows = ["t,az,alt"] + [f"{0.01 * i + 0.003 * (i % 3):.4f},0.0,{'' if i % 4 else 10.0}" for i in range(500)]
    log = _write_csv(tmp_path / "log.csv", "\n".join(rows) + "\n")
    out_csv = tmp_path / "out.csv"
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt", "-o", str(out_csv)]) == 0
    table = np.genfromtxt(out_csv, delimiter=",", names=True)
    assert table.shape == (500,) and abs(table["altitude"][-1] - 10.0) < 1e-3


def test_run_csv_missing_column_names_the_column(tmp_path, capsys):
    log = _write_csv(tmp_path / "log.csv", "t,az,alt\n0,0,1\n0.01,0,1\n")
    assert main(["run", log, "--time", "t", "--accel", "accel_z", "--baro", "alt"]) == 2
    err = capsys.readouterr().err
    assert "'accel_z'" in err and "Traceback" not in err


def test_run_csv_bad_cell_names_line_and_column(tmp_path, capsys):
    log = _write_csv(tmp_path / "log.csv", "t,az,alt\n0,0,1\n0.01,oops,1\n")
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt"]) == 2
    err = capsys.readouterr().err
    assert "line 3" in err and "'az'" in err


def test_run_csv_time_going_backwards_names_the_line(tmp_path, capsys):
    log = _write_csv(tmp_path / "log.csv", "t,az,alt\n0,0,1\n0.02,0,1\n0.01,0,1\n")
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt"]) == 2
    assert "line 4" in capsys.readouterr().err


def test_run_csv_pressure_column_is_converted_to_altitude(tmp_path, capsys):
    rows = ["t,az,p"] + [f"{0.01 * i:.2f},0,89874.6" for i in range(200)]
    log = _write_csv(tmp_path / "log.csv", "\n".join(rows) + "\n")
    out_csv = tmp_path / "out.csv"
    assert main(["run", log, "--time", "t", "--accel", "az", "--pressure", "p", "-o", str(out_csv)]) == 0
    assert abs(np.genfromtxt(out_csv, delimiter=",", names=True)["altitude"][-1] - 1000.0) < 0.5


def test_run_missing_file_is_a_one_line_error(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.csv"), "--time", "t", "--accel", "a", "--baro", "b"]) == 2
    assert "no such file" in capsys.readouterr().err


def test_run_ulog_prints_ekf_comparison(shared_data, capsys):
    assert main(["run", str(shared_data / "px4_sample_log_small.ulg")]) == 0
    assert "PX4 EKF (vehicle_local_position)" in capsys.readouterr().out


def test_run_dataflash_prints_ekf_comparison(shared_data, capsys):
    assert main(["run", str(shared_data / "ardupilot_test.BIN")]) == 0
    assert "ArduPilot EKF" in capsys.readouterr().out


def test_demo_plot_writes_a_png(tmp_path, capsys):
    path = tmp_path / "demo.png"
    assert main(["demo", "--plot", str(path)]) == 0
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_run_plot_writes_a_png(shared_data, tmp_path, capsys):
    path = tmp_path / "run.png"
    assert main(["run", str(shared_data / "px4_sample_log_small.ulg"), "--plot", str(path)]) == 0
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_python_m_runs_from_the_checkout_root_with_an_editable_install():
    completed = subprocess.run([sys.executable, "-m", "fusion_altitude", "--version"],
                               capture_output=True, text=True, cwd=ROOT)
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout.strip() == f"fusion-altitude {fusion_altitude.__version__}"
