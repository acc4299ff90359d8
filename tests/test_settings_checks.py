"""Settings checks: C where the extension is built, the reference's twin without it, and the two equal.

Each binding registers its C settings functions in its glue's ``C_SETTINGS_FUNCTIONS`` at import; the settings
classes (written once, in the references) call them from then on, and fall back to the reference's arithmetic
twin when the registry is empty (no compiled extension). These tests hold every twin equal to C over random and
edge settings (NaN, ±inf, 0, negative, huge), status for status, and the error the settings class raises — which
field it names and what it says — the same with C as with the twin.
"""

from __future__ import annotations

import contextlib
import math
import warnings
from unittest import mock

import numpy as np
from hypothesis import given, settings as hypothesis_settings
from hypothesis import strategies as st

from fusion_altitude._core import (_alphabeta, _alphabeta_glue, _c_tables, _complementary, _complementary_glue,
                                   _rocket, _rocket_glue, _ins, _ins_glue, _kalman, _kalman_glue, _observer,
                                   _observer_glue)
from fusion_altitude.reference import alphabeta as reference_alphabeta
from fusion_altitude.reference import complementary as reference_complementary
from fusion_altitude.reference import rocket as reference_flight
from fusion_altitude.reference import ins as reference_ins
from fusion_altitude.reference import kalman as reference_kalman
from fusion_altitude.reference import observer as reference_observer

f32 = np.float32

#: NaN, ±inf, 0, negative, huge (beyond the settings' maxima, beyond float32), and ordinary values.
EDGES = st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -0.0, -1.0, 0.5, 1.0, 2.0, 1e6, 1.0000001e6, 3e38,
                         1e200, -1e200])
VALUES = EDGES | st.floats(-10.0, 100.0, width=32) | st.floats(width=32)

REGISTRIES = (_observer_glue.C_SETTINGS_FUNCTIONS, _kalman_glue.C_SETTINGS_FUNCTIONS,
              _complementary_glue.C_SETTINGS_FUNCTIONS, _alphabeta_glue.C_SETTINGS_FUNCTIONS,
              _ins_glue.C_SETTINGS_FUNCTIONS, _rocket_glue.C_SETTINGS_FUNCTIONS)


def _outcome(make):
    """What building the settings gives: their values, or the error's type and message."""
    try:
        return "ok", repr(make().as_dict())
    except (ValueError, TypeError) as error:
        return type(error).__name__, str(error)


def assert_c_and_twin_agree(make):
    """``make()`` gives the same settings, or raises the same error naming the same field, with the C functions
    registered and with every registry emptied (the reference's twins)."""
    with_c = _outcome(make)
    with contextlib.ExitStack() as stack:
        for registry in REGISTRIES:
            stack.enter_context(mock.patch.dict(registry, clear=True))
        with_twin = _outcome(make)
    assert with_c == with_twin


def _names(table, skip=()):
    return [row[0] for row in table if row[0] not in skip]


# -- the registries ---------------------------------------------------------------------------------------------

def test_every_binding_registers_its_c_settings_checks_at_import():
    assert _observer_glue.C_SETTINGS_FUNCTIONS["check_gains"] is _observer.c_gains_check
    assert _observer_glue.C_SETTINGS_FUNCTIONS["validate"] is _observer.c_settings_validate
    assert _kalman_glue.C_SETTINGS_FUNCTIONS["check"] is _kalman.c_settings_check
    assert _complementary_glue.C_SETTINGS_FUNCTIONS["check"] is _complementary.c_settings_check
    assert _alphabeta_glue.C_SETTINGS_FUNCTIONS["check_sensor"] is _alphabeta.c_sensor_settings_check
    assert _alphabeta_glue.C_SETTINGS_FUNCTIONS["check_gap_period"] is _alphabeta.c_gap_period_check
    assert _ins_glue.C_SETTINGS_FUNCTIONS["check"] is _ins.c_settings_check
    assert _rocket_glue.C_SETTINGS_FUNCTIONS["check"] is _rocket.c_settings_check


def test_the_settings_classes_call_the_registered_c_check():
    calls = []

    def spy(values):
        calls.append(values)
        return 0

    with mock.patch.dict(_complementary_glue.C_SETTINGS_FUNCTIONS, check=spy):
        reference_complementary.ComplementarySettings(accel_time_constant=-1.0)  # the twin would reject it
    assert len(calls) == 1


# -- observer gains ---------------------------------------------------------------------------------------------

@hypothesis_settings(max_examples=300, deadline=None)
@given(gains=st.tuples(VALUES, VALUES, VALUES))
def test_the_twin_of_the_observer_gains_check_equals_c(gains):
    with np.errstate(over="ignore"):
        kh, kv, kb = (f32(g) for g in gains)
    assert int(reference_observer._check_gains(kh, kv, kb)) == _observer.c_gains_check(kh, kv, kb)


@hypothesis_settings(max_examples=200, deadline=None)
@given(gains=st.tuples(VALUES, VALUES, VALUES), gap_period=VALUES, baro_timeout=VALUES)
def test_observer_settings_raise_the_same_error_with_c_as_with_the_twin(gains, gap_period, baro_timeout):
    assert_c_and_twin_agree(lambda: reference_observer.AltitudeSettings(*gains, gap_period=gap_period,
                                                                        baro_timeout=baro_timeout))


@hypothesis_settings(max_examples=300, deadline=None)
@given(gains=st.tuples(VALUES, VALUES, VALUES), dt=VALUES | st.floats(1e-4, 1.0))
def test_the_twin_of_the_observer_validate_equals_c(gains, dt):
    with np.errstate(over="ignore"):
        kh, kv, kb, dt32 = (f32(value) for value in (*gains, dt))
    values = {**_observer.c_default_settings(), "position_gain": kh, "velocity_gain": kv, "bias_gain": kb}
    assert int(reference_observer._validate(kh, kv, kb, dt32)) == _observer.c_settings_validate(values, dt32)


@hypothesis_settings(max_examples=200, deadline=None)
@given(gains=st.tuples(st.floats(0.0, 200.0), st.floats(0.0, 2000.0), st.floats(0.0, 2000.0)),
       dt=VALUES | st.floats(1e-4, 1.0))
def test_observer_validate_raises_the_same_error_with_c_as_with_the_twin(gains, dt):
    def validate():
        settings = reference_observer.AltitudeSettings(*gains)
        with warnings.catch_warnings(), np.errstate(over="ignore"):  # dt beyond float32: inf, as C's float
            warnings.simplefilter("ignore", _observer_glue.DiscretisationWarning)
            settings.validate(dt)
        return settings

    assert_c_and_twin_agree(validate)


# -- Kalman -----------------------------------------------------------------------------------------------------

@hypothesis_settings(max_examples=200, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(_names(_c_tables.KALMAN_SETTINGS, ("estimate_accel_bias",
                                                                                    "gps_min_satellites"))),
                               VALUES, max_size=3),
       satellites=st.integers(-3, 40))
def test_kalman_settings_raise_the_same_error_with_c_as_with_the_twin(changes, satellites):
    assert_c_and_twin_agree(lambda: reference_kalman.KalmanSettings(gps_min_satellites=satellites, **changes))


# -- complementary ----------------------------------------------------------------------------------------------

COMPLEMENTARY_FLOATS = _names(_c_tables.COMPLEMENTARY_SETTINGS, ("per_sample_coefficients",))


@hypothesis_settings(max_examples=300, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(COMPLEMENTARY_FLOATS), VALUES, max_size=4), per_sample=st.booleans())
def test_the_twin_of_the_complementary_check_equals_c(changes, per_sample):
    values = {**_complementary.c_default_settings(), "per_sample_coefficients": per_sample}
    with np.errstate(over="ignore"):
        values.update((name, float(f32(value))) for name, value in changes.items())
    assert int(reference_complementary._check(values)) == _complementary.c_settings_check(values)


@hypothesis_settings(max_examples=200, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(COMPLEMENTARY_FLOATS), VALUES, max_size=4))
def test_complementary_settings_raise_the_same_error_with_c_as_with_the_twin(changes):
    assert_c_and_twin_agree(lambda: reference_complementary.ComplementarySettings(**changes))


# -- alpha-beta -------------------------------------------------------------------------------------------------

SENSOR_FIELDS = st.fixed_dictionaries({}, optional={
    "threshold": VALUES, "quality_min": st.integers(-3, 12), "quality_max": st.integers(-3, 10010),
    "confidence": VALUES, "altitude_min": VALUES, "altitude_max": VALUES, "gap_max": VALUES, "timeout": VALUES})


@hypothesis_settings(max_examples=300, deadline=None)
@given(fields=SENSOR_FIELDS, sensor=st.sampled_from(_alphabeta_glue.ALPHABETA_SENSORS))
def test_the_twin_of_the_alphabeta_sensor_check_equals_c(fields, sensor):
    with np.errstate(over="ignore"):
        fields = {name: value if isinstance(value, int) else float(f32(value)) for name, value in fields.items()}
    values = _alphabeta_glue.ALPHABETA_DEFAULTS[sensor]._replace(**fields)
    assert int(reference_alphabeta._sensor_status(values)) == _alphabeta.c_sensor_settings_check(values)


@hypothesis_settings(max_examples=100, deadline=None)
@given(gap_period=VALUES)
def test_the_twin_of_the_alphabeta_gap_period_check_equals_c(gap_period):
    with np.errstate(over="ignore"):
        gap_period = float(f32(gap_period))
    assert int(reference_alphabeta._gap_period_status(gap_period)) == _alphabeta.c_gap_period_check(gap_period)


@hypothesis_settings(max_examples=200, deadline=None)
@given(sensors=st.dictionaries(st.sampled_from(_alphabeta_glue.ALPHABETA_SENSORS), SENSOR_FIELDS, max_size=2),
       gap_period=st.none() | VALUES)
def test_alphabeta_settings_raise_the_same_error_with_c_as_with_the_twin(sensors, gap_period):
    extra = {} if gap_period is None else {"gap_period": gap_period}
    assert_c_and_twin_agree(lambda: reference_alphabeta.AlphaBetaSettings(**sensors, **extra))


# -- INS --------------------------------------------------------------------------------------------------------

INS_NAMES = _names(_c_tables.INS_SETTINGS)


@hypothesis_settings(max_examples=300, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(INS_NAMES), VALUES, max_size=4))
def test_the_twin_of_the_ins_check_equals_c(changes):
    with np.errstate(over="ignore"):
        values = {name: f32(changes.get(name, default)) for name, _, default, _ in _ins_glue.INS_SETTINGS}
    assert int(_ins_glue.check_ins_settings(values)) == _ins.c_settings_check(values)


@hypothesis_settings(max_examples=200, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(INS_NAMES), VALUES, max_size=4))
def test_ins_settings_raise_the_same_error_with_c_as_with_the_twin(changes):
    with np.errstate(over="ignore"):
        assert_c_and_twin_agree(lambda: reference_ins.InsSettings(**changes))


# -- rocket -----------------------------------------------------------------------------------------------------

ROCKET_NAMES = list(_rocket_glue.FIELD_NAMES)


@hypothesis_settings(max_examples=300, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(ROCKET_NAMES), VALUES, max_size=4))
def test_the_twin_of_the_rocket_check_equals_c(changes):
    with np.errstate(over="ignore"):
        values = {name: float(f32(changes.get(name, default))) for name, default in _rocket_glue.DEFAULTS.items()}
    with mock.patch.dict(_rocket_glue.C_SETTINGS_FUNCTIONS, clear=True):
        twin = _rocket_glue.check_settings_values(values)
    assert int(twin) == _rocket.c_settings_check({**values, "observer": _rocket_glue.ROCKET_OBSERVER})


@hypothesis_settings(max_examples=200, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(ROCKET_NAMES), VALUES, max_size=3),
       observer=st.none() | st.tuples(VALUES, VALUES, VALUES))
def test_rocket_settings_raise_the_same_error_with_c_as_with_the_twin(changes, observer):
    assert_c_and_twin_agree(lambda: reference_flight.RocketSettings(observer=observer, **changes))


# -- the rules, written once in the headers ---------------------------------------------------------------------

def _generator():
    import importlib
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
    return importlib.import_module("generate_bindings")


def test_every_field_of_every_settings_struct_has_a_rule_in_its_header():
    generator = _generator()
    base = generator.parse_header(generator.CSRC / "fusion_altitude.h")
    for header_name, _, settings, _ in generator.MODULES.values():
        header = generator.parse_header(generator.CSRC / header_name, base)
        structs = [settings] + [f.ctype for f in header.structs[settings] if f.ctype in header.structs]
        missing = [f"{struct}.{f.name}" for struct in structs for f in header.structs[struct] if not f.rule]
        assert not missing, f"{header_name}: no [rule: ...] in the comment of {', '.join(missing)}"


def test_a_settings_field_without_a_rule_stops_the_generator():
    generator = _generator()
    header = generator.parse_header(generator.CSRC / "fusion_altitude_complementary.h",
                                    generator.parse_header(generator.CSRC / "fusion_altitude.h"))
    header.structs["FusionAltitudeComplementarySettings"][0].rule = ""
    try:
        generator.rules_table("complementary", header, "FusionAltitudeComplementary",
                              "FusionAltitudeComplementarySettings", "COMPLEMENTARY_RULES")
    except SystemExit as stop:
        assert "accelTimeConstant has no [rule: ...]" in str(stop)
    else:
        raise AssertionError("the generator wrote a rules table with a field that has no rule")


def _breaking(terms, value):
    """Values that break one of ``terms`` each (the comparisons with a number, and "finite")."""
    is_int = isinstance(value, int) and not isinstance(value, bool)
    for term in terms:
        if term == "finite" and not is_int:
            yield math.nan
            yield math.inf
        elif isinstance(term, tuple) and not isinstance(term[1], str):
            operator, bound = term
            if is_int:
                yield {">": bound, ">=": bound - 1, "<": bound, "<=": bound + 1}[operator]
            else:
                down, up = (float(np.nextafter(f32(bound), f32(direction))) for direction in (-math.inf, math.inf))
                yield {">": float(f32(bound)), ">=": down, "<": float(f32(bound)), "<=": up}[operator]


_COMPARE = {">": lambda a, b: a > b, ">=": lambda a, b: a >= b, "<": lambda a, b: a < b, "<=": lambda a, b: a <= b}

#: Fields whose value at a bound of their own rule breaks a rule across fields that C checks with them (the
#: Kalman filter's baro_noise · ground_effect_noise_scale <= 1e6; the observer's Routh-Hurwitz test on its gains).
_CROSS_FIELD = {"baro_noise", "ground_effect_noise_scale", "position_gain", "velocity_gain", "bias_gain"}


def _at_bounds(terms, value):
    """The values at the edge of what ``terms`` accept (a bound itself, or the next float32 inside it)."""
    is_int = isinstance(value, int) and not isinstance(value, bool)
    numeric = [term for term in terms if isinstance(term, tuple) and not isinstance(term[1], str)]
    for operator, bound in numeric:
        inward = math.inf if operator == ">" else -math.inf
        edge = bound + (1 if operator == ">" else -1) if is_int and operator in "><" else \
            bound if operator in (">=", "<=") or is_int else float(np.nextafter(f32(bound), f32(inward)))
        if all(_COMPARE[op](edge, b) for op, b in numeric):
            yield edge


def _assert_c_checks_each_rule(rules, defaults, check):
    """C rejects a value that breaks one term of a field's rule with the status the rule names, and accepts the
    values at the edge of the rule."""
    assert check(defaults) == 0
    referenced = {term[1] for _, terms in rules.values() for term in terms if isinstance(term, tuple)}
    for name, (status, terms) in rules.items():
        for value in _breaking(terms, defaults[name]):
            assert check({**defaults, name: value}) == status, (name, value)
        if name in referenced or name in _CROSS_FIELD or any(isinstance(term, tuple) and isinstance(term[1], str)
                                                             for term in terms):
            continue
        for value in _at_bounds(terms, defaults[name]):
            assert check({**defaults, name: value}) == 0, (name, value)


def test_c_checks_each_header_rule_rejecting_with_the_status_it_names_and_accepting_its_edges():
    flat = ((_c_tables.OBSERVER_RULES, _observer.c_default_settings(), _observer.c_settings_check),
            (_c_tables.KALMAN_RULES, _kalman.c_default_settings(), _kalman.c_settings_check),
            (_c_tables.COMPLEMENTARY_RULES, _complementary.c_default_settings(), _complementary.c_settings_check),
            (_c_tables.INS_RULES, _ins.c_default_settings(), _ins.c_settings_check),
            ({name: rule for name, rule in _c_tables.ROCKET_RULES.items() if name != "observer"},
             _rocket.c_default_settings(), _rocket.c_settings_check))
    for rules, defaults, check in flat:
        _assert_c_checks_each_rule(rules, defaults, check)
    for sensor in _alphabeta_glue.ALPHABETA_SENSORS:
        defaults = _alphabeta_glue.ALPHABETA_DEFAULTS[sensor]._asdict()
        _assert_c_checks_each_rule(
            _c_tables.ALPHABETA_SENSOR_RULES, defaults,
            lambda values: _alphabeta.c_sensor_settings_check(_alphabeta_glue.AlphaBetaSensorSettings(**values)))
