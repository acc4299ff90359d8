"""Gains: defaults, presets, the bandwidth formulas and the stability checks."""

import pickle
import warnings

import numpy as np
import pytest

import fusion_altitude
from fusion_altitude import DiscretisationWarning

PRESET_OMEGA = {"balloon": 0.2, "fixed_wing": 0.5, "vtol": 1.5, "racing": 5.0}


def test_defaults_are_the_vtol_gains(impl):
    settings = impl.AltitudeSettings()
    assert settings.as_tuple() == tuple(float(np.float32(g)) for g in (2.40, 2.88, 0.675))
    assert settings == impl.AltitudeSettings.preset("vtol")


@pytest.mark.parametrize("name, omega", sorted(PRESET_OMEGA.items()))
def test_presets_are_the_exact_formulas_rounded_to_float32(impl, name, omega):
    zeta, omega_b = 0.7, omega / 5
    exact = (2 * zeta * omega + omega_b, omega**2 + 2 * zeta * omega * omega_b, omega**2 * omega_b)
    assert impl.AltitudeSettings.preset(name).as_tuple() == tuple(float(np.float32(g)) for g in exact)


def test_balloon_and_fixed_wing_presets_follow_the_formulas_not_the_quoted_table(impl):
    # A widely copied table gives Kv 0.06 / Kb 0.008 for the balloon and Kv 0.35 for the fixed-wing.
    assert impl.AltitudeSettings.preset("balloon").velocity_gain == pytest.approx(0.0512)
    assert impl.AltitudeSettings.preset("balloon").bias_gain == pytest.approx(0.0016)
    assert impl.AltitudeSettings.preset("fixed_wing").velocity_gain == pytest.approx(0.32)


def test_unknown_preset_lists_the_known_ones(impl):
    with pytest.raises(ValueError, match="balloon, fixed_wing, vtol, racing"):
        impl.AltitudeSettings.preset("helicopter")


def test_from_bandwidth_defaults_to_zeta_0_7_and_omega_b_a_fifth_of_omega(impl):
    settings = impl.AltitudeSettings.from_bandwidth(1.5)
    assert settings.as_tuple() == pytest.approx((2.40, 2.88, 0.675), rel=1e-6)
    explicit = impl.AltitudeSettings.from_bandwidth(1.5, zeta=0.7, omega_b=0.3)
    assert explicit.as_tuple() == pytest.approx(settings.as_tuple(), rel=1e-6)


def test_from_bandwidth_with_zero_omega_b_disables_the_bias_loop(impl):
    assert impl.AltitudeSettings.from_bandwidth(2.0, 1.0, 0.0).bias_gain == 0.0


@pytest.mark.parametrize("arguments", [(0.0,), (-1.0,), (float("nan"),), (1.0, 0.0), (1.0, 0.7, -0.1)])
def test_from_bandwidth_rejects_out_of_range_arguments(impl, arguments):
    with pytest.raises(ValueError, match="omega"):
        impl.AltitudeSettings.from_bandwidth(*arguments)


def test_validate_accepts_the_defaults_at_100_hz_without_warning(impl):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        impl.AltitudeSettings().validate(0.01)


def test_validate_warns_when_omega_dt_reaches_0_1_but_stays_stable(impl):
    with pytest.warns(DiscretisationWarning, match="omega \\* dt"):
        impl.AltitudeSettings.preset("racing").validate(0.05)


def test_validate_rejects_a_step_that_makes_the_update_diverge(impl):
    with pytest.raises(ValueError, match="unstable at dt"):
        impl.AltitudeSettings.preset("racing").validate(0.3)


def test_validate_rejects_bad_dt(impl):
    with pytest.raises(ValueError, match="^dt"):
        impl.AltitudeSettings().validate(0.0)


def update_matrix(kh, kv, kb, dt):
    """The homogeneous semi-implicit update of (h, v, b), derived from the update equations."""
    return np.array([[1 - kh * dt - kv * dt**2, dt, -dt**2],
                     [-kv * dt, 1, -dt],
                     [kb * dt, 0, 1]])


def test_jury_test_agrees_with_the_eigenvalues_of_the_update():
    rng = np.random.default_rng(1)
    checked = 0
    for _ in range(4000):
        kh, kv, kb = rng.uniform(0, 30, 3) * rng.integers(0, 2, 3)
        dt = 10 ** rng.uniform(-3, 0)
        try:
            settings = fusion_altitude.AltitudeSettings(kh, kv, kb)
        except ValueError:
            continue
        gains = [float(g) for g in settings.as_tuple()]
        radius = np.max(np.abs(np.linalg.eigvals(update_matrix(*gains, dt))))
        if gains[2] == 0:
            # the bias mode is the eigenvalue 1 by construction; so is v's when Kv = 0
            keep = 1 if gains[1] == 0 else 2
            radius = np.max(np.abs(np.linalg.eigvals(update_matrix(*gains, dt)[:keep, :keep])))
        if abs(radius - 1) < 1e-3:
            continue  # too close to the boundary for float32 to decide
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                settings.validate(dt)
                stable = True
            except ValueError:
                stable = False
        assert stable == (radius < 1), (gains, dt, radius)
        checked += 1
    assert checked > 1000


def test_settings_compare_equal_across_implementations():
    assert fusion_altitude.AltitudeSettings() == fusion_altitude.reference.AltitudeSettings()


def test_settings_have_a_readable_repr(impl):
    assert repr(impl.AltitudeSettings()) == \
        "AltitudeSettings(position_gain=2.4, velocity_gain=2.88, bias_gain=0.675, gap_period=0.5)"


def test_settings_pickle_and_hash(impl):
    settings = impl.AltitudeSettings.preset("fixed_wing")
    assert pickle.loads(pickle.dumps(settings)) == settings
    assert len({settings, impl.AltitudeSettings.preset("fixed_wing")}) == 1


def test_settings_are_read_only(impl):
    with pytest.raises(AttributeError):
        impl.AltitudeSettings().position_gain = 1.0
