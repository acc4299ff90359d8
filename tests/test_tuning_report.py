"""tuning.report(settings, dt): the analysis behind ``fusion-altitude tune``, as a library function."""

import math

import numpy as np
import pytest

from fusion_altitude import AltitudeSettings, tuning


def test_each_continuous_pole_is_paired_with_its_own_discrete_pole():
    report = tuning.report(AltitudeSettings.from_bandwidth(1.5, 0.7, 0.3), 0.01)
    for s, tau, z in report.poles:
        assert abs(z - np.exp(s * 0.01)) < 1e-3
        assert tau == pytest.approx(1 / abs(s.real))


def test_pairing_holds_when_sorting_by_magnitude_would_mismatch():
    # slow real pole, fast complex pair: |s| order and |z| order disagree
    report = tuning.report(AltitudeSettings.from_bandwidth(8.0, 0.3, 0.05), 0.02)
    for s, _, z in report.poles:
        assert abs(z - np.exp(s * 0.02)) < 0.05


def test_a_stable_choice_passes_routh_hurwitz_and_jury():
    report = tuning.report(AltitudeSettings(), 0.01)
    assert report.stable and [ok for _, ok, _ in report.checks[:2]] == [True, True]


def test_a_rate_too_slow_for_the_gains_fails_jury():
    report = tuning.report(AltitudeSettings.from_bandwidth(50.0, 0.7), 0.05)
    assert not report.stable and not report.checks[1][1]


def test_loop_separation_is_checked_only_with_the_bandwidths():
    settings = AltitudeSettings.from_bandwidth(1.5, 0.7, 0.6)
    assert len(tuning.report(settings, 0.01).checks) == 3
    assert tuning.report(settings, 0.01, omega=1.5, omega_b=0.6).checks[3][1] is False


@pytest.mark.parametrize("dt", [0.0, -0.01, math.inf, math.nan, 1e-308])
def test_a_bad_period_names_dt(dt):
    with pytest.raises(ValueError, match="dt"):
        tuning.report(AltitudeSettings(), dt)


def test_steps_per_baro_counts_grid_steps_per_baro_sample():
    baro = np.full(12, np.nan)
    baro[::4] = 1.0
    assert tuning.steps_per_baro(baro) == 4.0
    assert tuning.steps_per_baro(np.full(3, np.nan)) == 1.0
