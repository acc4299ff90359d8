"""Every input problem is one line on stderr and exit status 2, never a traceback; messages name the flag."""

import subprocess
import sys
import warnings

import pytest

from fusion_altitude.cli import main


def csv_log(path, n=300, baro=True, reference=False):
    """A still log with live sensors (a little noise: a constant channel is a dead sensor, and warned about)."""
    rows = ["t,az,alt,ref"]
    for i in range(n):
        noise = 0.01 * ((i * 7) % 5 - 2)
        rows.append(f"{0.02 * i:.2f},{noise:.2f},{f'{5.0 + noise:.2f}' if baro else ''},{'5.1' if reference else ''}")
    path.write_text("\n".join(rows) + "\n")
    return str(path)


def one_line_error(capsys, *fragments):
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert "Traceback" not in captured.err and "np.float" not in captured.err
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    return lines[0]


@pytest.mark.parametrize("argv,flag", [
    (["tune", "--rate", "0"], "--rate"),
    (["tune", "--rate", "-100"], "--rate"),
    (["tune", "--rate", "nan"], "--rate"),
    (["tune", "--rate", "1e308"], "--rate"),
    (["tune", "--omega", "0"], "--omega"),
    (["tune", "--zeta", "-1"], "--zeta"),
    (["tune", "--omega-b", "-0.1"], "--omega-b"),
    (["demo", "--seed", "-1"], "--seed"),
    (["fit", "--scenario", "clean", "--omega-min", "0"], "--omega-min"),
    (["fit", "--scenario", "clean", "--omega-min", "5", "--omega-max", "1"], "--omega-min"),
    (["fit", "--scenario", "clean", "--skip", "-1"], "--skip"),
    (["compare", "--repeat", "-1"], "--repeat"),
])
def test_a_bad_flag_value_is_named_in_one_line(argv, flag, capsys):
    assert main(argv) == 2
    one_line_error(capsys, flag)


def test_tune_prints_nothing_before_refusing_a_negative_rate(capsys):
    assert main(["tune", "--rate", "-100"]) == 2
    assert capsys.readouterr().out == ""


def test_a_csv_whose_baro_column_is_empty_is_a_one_line_error(tmp_path, capsys):
    log = csv_log(tmp_path / "log.csv", baro=False)
    assert main(["run", log, "--time", "t", "--accel", "az", "--baro", "alt"]) == 2
    one_line_error(capsys, "baro")


@pytest.mark.parametrize("value", ["-5", "0", "inf"])
def test_a_bad_sea_level_pressure_blames_the_flag_not_the_data(tmp_path, capsys, value):
    log = csv_log(tmp_path / "log.csv")
    assert main(["run", log, "--time", "t", "--accel", "az", "--pressure", "alt", "--sea-level-pa", value]) == 2
    one_line_error(capsys, "--sea-level-pa")


def test_csv_column_flags_on_a_ulog_are_refused_by_name(capsys):
    import os
    path = os.path.join(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", "../shared/data"), "px4_sample_log_small.ulg")
    assert main(["run", path, "--time", "t"]) == 2
    one_line_error(capsys, "--time")


def test_fit_skip_beyond_the_log_is_an_error_without_a_numpy_warning(tmp_path, capsys):
    log = csv_log(tmp_path / "log.csv", reference=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["fit", log, "--time", "t", "--accel", "az", "--baro", "alt", "--reference", "ref",
                     "--skip", "1000"]) == 2
    one_line_error(capsys, "--skip 1000")


def test_fit_on_a_short_log_warns_that_the_score_covers_little_data(tmp_path, capsys):
    log = csv_log(tmp_path / "log.csv", n=500, reference=True)  # 10 s
    assert main(["fit", log, "--time", "t", "--accel", "az", "--baro", "alt", "--reference", "ref"]) == 0
    assert "warning: the fit is scored over only 5.0 s" in capsys.readouterr().err


def test_compare_with_repeat_0_prints_no_timing(capsys):
    assert main(["compare", "--scenario", "terrain-step", "--repeat", "0"]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith("terrain-step")]
    assert rows and all(line.split()[-1] == "—" for line in rows) and ">15" not in "".join(
        line.split()[-1] for line in rows)


def test_attitude_ahrs_without_imufusion_is_reported_before_work(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "imufusion", None)  # import fails
    assert main(["demo", "--attitude", "ahrs"]) == 2
    one_line_error(capsys, "imufusion")


def test_plot_without_matplotlib_is_reported_before_work(capsys, monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert main(["demo", "--plot", str(tmp_path / "p.png")]) == 2
    line = one_line_error(capsys, "[plot]")
    assert capsys.readouterr().out == "" and "matplotlib" in line


def test_output_piped_into_head_ends_quietly():
    process = subprocess.Popen([sys.executable, "-m", "fusion_altitude", "tune"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, cwd="/")
    process.stdout.close()  # the reader is gone before the first byte, as with `| head -0`
    stderr = process.stderr.read().decode()
    process.wait(timeout=120)
    assert stderr == "" and process.returncode == 141


def test_no_command_prints_help_and_exits_2(capsys):
    assert main([]) == 2
    assert "usage" in capsys.readouterr().out


def test_unknown_estimator_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["run", "x.csv", "--estimator", "magic"])
    assert exit_.value.code == 2 and "magic" in capsys.readouterr().err


def test_messages_give_plain_numbers_not_numpy_reprs(tmp_path, capsys):
    log = tmp_path / "log.csv"
    log.write_text("t,az,alt\n0,0,1\n2.99,0,1\n1.5,0,1\n")
    assert main(["run", str(log), "--time", "t", "--accel", "az", "--baro", "alt"]) == 2
    line = one_line_error(capsys)
    assert "2.99" in line and "np." not in line


def test_body_accelerometer_columns_must_be_three(tmp_path, capsys):
    log = csv_log(tmp_path / "log.csv")
    assert main(["run", log, "--time", "t", "--accel-body", "az,alt", "--attitude-columns", "a,b,c,d",
                 "--baro", "alt"]) == 2
    one_line_error(capsys, "--accel-body")


def test_a_ground_temperature_that_is_neither_a_number_nor_log_is_named(tmp_path, capsys):
    log = csv_log(tmp_path / "log.csv")
    assert main(["run", log, "--time", "t", "--accel", "az", "--pressure", "alt", "--ground-temperature", "warm"]) == 2
    one_line_error(capsys, "--ground-temperature")


def test_run_warns_when_the_preset_is_unstable_at_the_logs_baro_rate(tmp_path, capsys):
    rows = ["t,az,alt"] + [f"{0.1 * i:.1f},0,{'5' if i % 10 == 0 else ''}" for i in range(600)]  # 1 Hz baro, 10 Hz
    (tmp_path / "log.csv").write_text("\n".join(rows) + "\n")
    assert main(["run", str(tmp_path / "log.csv"), "--time", "t", "--accel", "az", "--baro", "alt"]) == 0
    captured = capsys.readouterr()
    assert "the default preset vtol is unstable at this log's rate" in captured.err  # so run picks a stable one
    assert "baro on 1 of 10.00 steps" in captured.err and "preset fixed_wing" in captured.out
    assert main(["run", str(tmp_path / "log.csv"), "--time", "t", "--accel", "az", "--baro", "alt",
                 "--preset", "vtol"]) == 0
    assert "warning: --preset vtol is unstable at this log's rate" in capsys.readouterr().err
    assert main(["run", str(tmp_path / "log.csv"), "--time", "t", "--accel", "az", "--baro", "alt",
                 "--preset", "balloon"]) == 0
    assert "unstable" not in capsys.readouterr().err
