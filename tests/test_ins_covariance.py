"""The INS covariance conditioning on the fuzzer's finding
csrc/fuzz/findings/ins_negative_attitude_variance.bin (default settings):
the reference equals the C bit for bit on it, and no variance goes negative."""

import importlib.util
from pathlib import Path

import numpy as np

from fusion_altitude import _ins
from fusion_altitude.reference import ins as reference

ROOT = Path(__file__).resolve().parents[1]
FINDING = ROOT / "csrc" / "fuzz" / "findings" / "ins_negative_attitude_variance.bin"


def finding_updates():
    """The fuzzer input's update calls, float32 as the fuzzer passes them (decode_ins.py)."""
    spec = importlib.util.spec_from_file_location("decode_ins", ROOT / "csrc" / "fuzz" / "findings" / "decode_ins.py")
    decode_ins = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(decode_ins)
    calls = decode_ins.decode(FINDING.read_bytes())
    decode_ins.header(calls, FINDING.name)  # raises if a settings call would change the run
    return [call[1:] for call in calls if call[0] == "update"]


def run(impl):
    """Every accepted update's covariance, in order (rejected updates raise and change nothing)."""
    ins = impl.InsEstimator()
    covariances = []
    for gyro, accel, mag, baro, dt in finding_updates():
        try:
            ins.update(gyro, accel, dt, baro_altitude=baro, mag=None if np.isnan(mag).all() else mag)
        except ValueError:
            continue
        covariances.append(np.asarray(ins.covariance, dtype=np.float32).copy())
    return covariances


def test_reference_equals_the_c_bit_for_bit_on_the_fuzzer_finding():
    c, python = run(_ins), run(reference)
    assert len(c) == len(python) >= 243
    for step, (a, b) in enumerate(zip(c, python)):
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32)), step


def test_no_variance_goes_negative_on_the_fuzzer_finding():
    worst = min(float(np.diagonal(P).min()) for P in run(reference))
    assert worst >= 0.0, worst
