"""The INS covariance conditioning on the fuzzer's findings (csrc/fuzz/findings/,
decoded by decode_ins.py): the reference equals the C bit for bit on each, no
variance goes negative, and the attitude variance stays finite and at most
FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT (rad^2).

They were found before the baro innovation gate existed and replay without it (AS_FOUND).

- ins_negative_attitude_variance.bin (default settings): 1e5 m baro jumps made
  P[0][0] negative (-9.1e-6 at the 243rd accepted update) before the
  conditioning.
- ins_attitude_variance_growth.bin (default settings) and
  ins_attitude_variance_growth_zero_rate_noise.bin (accel_rejection 0.1 rad,
  recovery_trigger_period 0.2 s): once round-off made the attitude block
  indefinite, P grew about 100-fold per step to infinity (167th and 208th
  accepted update) before the attitude variance limit.
"""

import functools
import importlib.util
from pathlib import Path

import numpy as np
import pytest

from fusion_altitude import _c_tables, _ins
from fusion_altitude.reference import ins as reference

ROOT = Path(__file__).resolve().parents[1]
FINDINGS = ROOT / "csrc" / "fuzz" / "findings"
FINDING_NAMES = ("ins_negative_attitude_variance.bin", "ins_attitude_variance_growth.bin",
                 "ins_attitude_variance_growth_zero_rate_noise.bin")
GROWTH = FINDING_NAMES[1:]


@functools.lru_cache(maxsize=None)
def _decode_ins():
    spec = importlib.util.spec_from_file_location("decode_ins", FINDINGS / "decode_ins.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: The findings were found before the INS had a baro innovation gate; they replay without one (a gate of 1e6
#: sigma), so that their baro jumps drive the covariance as they did.
AS_FOUND = {"baro_gate": 1e6}


def finding_run(name):
    """The settings keywords in effect (``AS_FOUND`` applied) and the update calls of one finding, float32 as the
    fuzzer passes them."""
    decode_ins = _decode_ins()
    settings, updates = decode_ins.run_in_effect(decode_ins.decode((FINDINGS / name).read_bytes()))
    keywords = {field[0]: float(value) for field, value in zip(_c_tables.INS_SETTINGS, settings)}
    return {**keywords, **AS_FOUND}, [call[1:] for call in updates]


def run(impl, name):
    """Every accepted update's covariance, in order (rejected updates raise and change nothing)."""
    keywords, updates = finding_run(name)
    ins = impl.InsEstimator(impl.InsSettings(**keywords))
    covariances = []
    for gyro, accel, mag, baro, dt in updates:
        try:
            ins.update(gyro, accel, dt, baro_altitude=baro, mag=None if np.isnan(mag).all() else mag)
        except ValueError:
            continue
        covariances.append(np.asarray(ins.covariance, dtype=np.float32).copy())
    return covariances


def test_the_growth_findings_run_with_the_settings_the_fuzzer_used():
    defaults = {field[0]: field[3] for field in _c_tables.INS_SETTINGS}
    assert finding_run(GROWTH[0])[0] == pytest.approx({**defaults, **AS_FOUND})
    changed = {key: value for key, value in finding_run(GROWTH[1])[0].items()
               if value != pytest.approx({**defaults, **AS_FOUND}[key])}
    assert changed == {"accel_rejection": pytest.approx(0.1), "recovery_trigger_period": pytest.approx(0.2)}


@pytest.mark.parametrize("name", FINDING_NAMES)
def test_with_the_default_baro_gate_the_finding_keeps_p_finite_and_the_attitude_bounded(name):
    keywords, updates = finding_run(name)
    ins = _ins.InsEstimator(_ins.InsSettings(**{**keywords, "baro_gate": 5.0}))
    for gyro, accel, mag, baro, dt in updates:
        try:
            ins.update(gyro, accel, dt, baro_altitude=baro, mag=None if np.isnan(mag).all() else mag)
        except ValueError:
            continue
        P = np.asarray(ins.covariance)
        assert np.isfinite(P).all() and (np.diagonal(P) >= 0).all()
        assert np.diagonal(P)[:3].max() <= _c_tables.FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT
    assert ins.baro_rejections > 0  # its 1e5 m baro jumps fail the gate


@pytest.mark.parametrize("name", FINDING_NAMES)
def test_reference_equals_the_c_bit_for_bit_on_the_fuzzer_finding(name):
    c, python = run(_ins, name), run(reference, name)
    assert len(c) == len(python) >= 160
    for step, (a, b) in enumerate(zip(c, python)):
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32)), step


@pytest.mark.parametrize("name", FINDING_NAMES)
def test_no_variance_goes_negative_on_the_fuzzer_finding(name):
    worst = min(float(np.diagonal(P).min()) for P in run(_ins, name))
    assert worst >= 0.0, worst


@pytest.mark.parametrize("name", GROWTH)
def test_the_covariance_stays_finite_and_the_attitude_variance_bounded_on_the_growth_finding(name):
    covariances = run(_ins, name)
    assert all(np.isfinite(P).all() for P in covariances)
    largest = max(float(np.diagonal(P)[:3].max()) for P in covariances)
    assert largest <= _c_tables.FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT, largest


def test_the_attitude_variance_limit_is_reached_on_the_default_settings_growth_finding():
    # the limit is what that run needs: it is reached (without it, P went to infinity). The other finding
    # (zero-rate noise) was found on the Joseph-form update; with P - c cᵀ/S its attitude variance peaks at
    # 84 rad², under the limit, and it stays a finite/bounded regression input above.
    largest = max(float(np.diagonal(P)[:3].max()) for P in run(_ins, GROWTH[0]))
    assert largest == _c_tables.FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT


def test_the_attitude_variance_limit_is_the_same_in_c_and_the_reference():
    assert reference.ATTITUDE_VARIANCE_LIMIT == np.float32(_c_tables.FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT)
