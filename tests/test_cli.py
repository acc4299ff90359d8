"""Specification of the ``fusion-altitude`` command line."""

import re
import subprocess
import sys

import fusion_altitude
from fusion_altitude.cli import main


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
