"""The estimator contract, estimator × implementation: what every estimator promises, in C and in the reference.

The rows are derived from the estimator registry (fusion_altitude.estimators) and the binding generator's tables
(tools/generate_bindings.py): a new estimator joins without a line here (see docs/architecture.md).
"""

import copy
import importlib
import importlib.util
import inspect
import math
import pickle
import re
import subprocess
import sys
import threading
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, Tuple

import numpy as np
import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

import fusion_altitude
import fusion_altitude.reference
from fusion_altitude import _c_tables
from fusion_altitude.estimators import ESTIMATORS as REGISTRY

ROOT = Path(__file__).resolve().parents[1]


def _load_generator():
    """tools/generate_bindings.py, for its tables (MODULES, SETTINGS_CLASSES, ENUM_NAMES)."""
    if "generate_bindings" not in sys.modules:  # registered before it runs: its dataclasses look themselves up
        spec = importlib.util.spec_from_file_location("generate_bindings", ROOT / "tools" / "generate_bindings.py")
        sys.modules["generate_bindings"] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules["generate_bindings"])
    return sys.modules["generate_bindings"]


GENERATOR = _load_generator()


def _altitude_inputs(rng, n):
    baro = 50 + np.cumsum(rng.normal(0.0, 0.05, n))
    baro[rng.random(n) < 0.5] = np.nan
    return {"accel": rng.normal(0.0, 0.5, n), "baro_altitude": baro, "dt": rng.uniform(0.005, 0.02, n)}


def _kalman_inputs(rng, n):
    inputs = _altitude_inputs(rng, n)
    gps = 80 + np.cumsum(rng.normal(0.0, 0.3, n))
    gps[rng.random(n) < 0.8] = np.nan
    rangefinder = rng.uniform(0.0, 9.0, n)
    rangefinder[rng.random(n) < 0.3] = np.nan
    return {**inputs, "range_distance": rangefinder, "gps_altitude": gps}


def _alphabeta_inputs(rng, n):
    inputs = _kalman_inputs(rng, n)
    lidar = inputs.pop("range_distance")
    return {**inputs, "lidar_altitude": lidar, "sonar_altitude": lidar * 0.98}


def _rocket_inputs(rng, n):
    inputs = _altitude_inputs(rng, n)
    inputs["accel"][n // 3:n // 3 + n // 10] += 40.0  # a boost after the pad, so the phases move on
    return inputs


def _ins_inputs(rng, n):
    baro = 50 + np.cumsum(rng.normal(0.0, 0.05, n))
    baro[rng.random(n) < 0.5] = np.nan
    mag = np.tile([0.2, 0.0, -0.4], (n, 1)) + rng.normal(0.0, 0.01, (n, 3))
    mag[rng.random(n) < 0.7] = np.nan
    return {"gyro": rng.normal(0.0, 0.02, (n, 3)), "accel": np.tile([0.0, 0.0, 9.81], (n, 1)) + rng.normal(0.0, 0.3, (n, 3)),
            "dt": rng.uniform(0.005, 0.02, n), "baro_altitude": baro, "mag": mag}


#: The update argument order of the contract: (accel, baro_altitude, dt, *, other sensors).
CONTRACT_ORDER = ("accel", "baro_altitude", "dt")
#: Exception: an estimator that needs the raw IMU (``"gyro"`` in its registry row's ``needs``: the INS) takes
#: (gyro, accel, dt, baro_altitude=NaN, mag=None) with 3-vectors, as imufusion users call an AHRS; baro and mag are
#: optional and positional.
IMU_ORDER = ("gyro", "accel", "dt", "baro_altitude", "mag")
#: The input builders; each estimator gets the one that fills the most of its update's parameters (all of them
#: parameters of its update), and an estimator made for a vehicle that vehicle's motion (VEHICLE_INPUTS).
INPUT_BUILDERS = (_altitude_inputs, _kalman_inputs, _alphabeta_inputs, _ins_inputs)
VEHICLE_INPUTS = {"rocket": _rocket_inputs}


@dataclass
class Row:
    """One estimator: its class name, settings class name, binding module, inputs and a settings change."""

    estimator: str
    settings: str
    module: object
    inputs: Callable
    change: Dict[str, object]  # keyword arguments of settings.replace that change something
    status: str  # the status enum in fusion_altitude._c_tables
    enums: Tuple[Tuple[str, str], ...] = ()  # other enums: (name in _c_tables, C_<name>_VALUES of the binding)
    #: The positional parameters of update/update_batch (the rest keyword-only, or ``out``).
    positional: Tuple[str, ...] = CONTRACT_ORDER
    retune: bool = True  # ``estimator.settings = ...`` mid-run (the rocket estimator's settings are fixed at start)
    gil_samples: int = 400_000  # a batch long enough to see the GIL released
    legacy: bool = False  # the old positional order still accepted for one release (_common.argument_order)


def _input_builder(entry, reference_class) -> Callable:
    """The inputs of ``entry``: its vehicle's, else the builder filling the most of its update's parameters."""
    if entry.vehicle in VEHICLE_INPUTS:
        return VEHICLE_INPUTS[entry.vehicle]
    parameters = set(inspect.signature(reference_class.update_batch).parameters)
    names = {builder: set(builder(np.random.default_rng(0), 1)) for builder in INPUT_BUILDERS}
    fitting = sorted((builder for builder in INPUT_BUILDERS if names[builder] <= parameters),
                     key=lambda builder: len(names[builder]))
    assert fitting and (len(fitting) == 1 or len(names[fitting[-1]]) > len(names[fitting[-2]])), entry.name
    return fitting[-1]


def _settings_change(settings_class) -> Dict[str, object]:
    """A change of the first float setting (doubled, or 1 from 0) that the settings class accepts."""
    defaults = settings_class().as_dict()
    for name, value in defaults.items():
        if isinstance(value, float) and math.isfinite(value):
            change = {name: value * 2.0 if value else 1.0}
            try:
                settings_class(**{**defaults, **change})
            except ValueError:
                continue
            return change
    raise AssertionError(f"{settings_class.__name__}: no float setting to change")


def _other_enums(module, prefix: str) -> Tuple[Tuple[str, str], ...]:
    """(the generated enum's name, ``C_<SUFFIX>_VALUES``) of each enum the binding exports besides its status."""
    enums = []
    for cname, name in GENERATOR.ENUM_NAMES.items():
        suffix = cname[len(prefix):] if cname.startswith(prefix) else ""
        if suffix and suffix != "Status" and hasattr(module, f"C_{suffix.upper()}_VALUES"):
            enums.append((name, f"C_{suffix.upper()}_VALUES"))
    exported = {name for name in dir(module) if re.fullmatch(r"C_\w+_VALUES", name)} - {"C_STATUS_VALUES"}
    assert exported == {values for _, values in enums}, (prefix, exported)
    return tuple(enums)


def _row(entry) -> Row:
    """The contract row of a registry entry, from the registry and the generator's tables."""
    prefix = GENERATOR.MODULES[entry.name][1]
    module = importlib.import_module(f"fusion_altitude._core._{entry.name}")
    reference_class = getattr(fusion_altitude.reference, entry.estimator_class)
    settings = GENERATOR.SETTINGS_CLASSES[entry.name]
    inputs = _input_builder(entry, reference_class)
    vectors = any(np.ndim(values) > 1 for values in inputs(np.random.default_rng(0), 1).values())
    return Row(entry.estimator_class, settings, module, inputs, _settings_change(getattr(fusion_altitude, settings)),
               GENERATOR.ENUM_NAMES[prefix + "Status"], _other_enums(module, prefix),
               positional=IMU_ORDER if "gyro" in entry.needs else CONTRACT_ORDER,
               retune=inspect.getattr_static(reference_class, "settings").fset is not None,
               gil_samples=200_000 if vectors else 400_000,
               legacy=hasattr(reference_class.update, "__wrapped__"))


#: One row per registered estimator of the generator (all built-in ones), in registry order.
ESTIMATORS = [_row(entry) for name, entry in REGISTRY.items() if name in GENERATOR.MODULES]
IMPLEMENTATIONS = {"c": fusion_altitude, "reference": fusion_altitude.reference}

by_row = pytest.mark.parametrize("row", ESTIMATORS, ids=[row.estimator for row in ESTIMATORS])
by_impl = pytest.mark.parametrize("impl", list(IMPLEMENTATIONS.values()), ids=list(IMPLEMENTATIONS))


def bits(value):
    """A state or output with every float as its float32 bit pattern (NaNs and signed zeros compare exactly)."""
    if isinstance(value, dict):
        return {key: bits(item) for key, item in value.items()}
    if isinstance(value, (tuple, list)):
        return tuple(bits(item) for item in value)
    if isinstance(value, np.ndarray):
        return value.view(np.uint32).tobytes() if value.dtype == np.float32 else value.tobytes()
    if isinstance(value, (float, np.floating)):
        return int(np.float32(value).view(np.uint32))
    return value


def state(estimator):
    return bits(estimator._get_state())


def sample(values, i):
    """Sample i of a batch input: a float, or a list for a vector input (the INS's gyro, accel, mag)."""
    return values[i].tolist() if np.ndim(values) > 1 else float(values[i])


def run_per_sample(estimator, inputs):
    n = len(inputs["accel"])
    for i in range(n):
        estimator.update(**{name: sample(values, i) for name, values in inputs.items()})


def warmed_up(impl, row, n=300, seed=1):
    estimator = getattr(impl, row.estimator)()
    estimator.update_batch(**row.inputs(np.random.default_rng(seed), n))
    return estimator


# -- one source of truth ------------------------------------------------------------------------------------------

def test_generated_files_match_the_headers():
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "generate_bindings.py"), "--check"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


@by_row
def test_binding_and_reference_share_one_settings_class(row):
    assert getattr(fusion_altitude, row.settings) is getattr(fusion_altitude.reference, row.settings)


@by_row
def test_default_settings_equal_the_header(row):
    c_defaults = row.module.c_default_settings()
    assert getattr(fusion_altitude, row.settings)().as_dict() == c_defaults


@by_row
def test_status_enum_equals_the_header(row):
    status = getattr(_c_tables, row.status)
    assert {member.name: int(member) for member in status} == row.module.C_STATUS_VALUES


ENUM_ROWS = [(row, name, values) for row in ESTIMATORS for name, values in row.enums]


@pytest.mark.parametrize("row, name, values", ENUM_ROWS, ids=[name for _, name, _ in ENUM_ROWS])
def test_other_enums_equal_the_header(row, name, values):
    assert {member.name: int(member) for member in getattr(_c_tables, name)} == getattr(row.module, values)


@by_row
@by_impl
def test_status_messages_are_the_headers(impl, row):
    estimator = getattr(impl, row.estimator)
    for status in row.module.C_STATUS_VALUES.values():
        assert estimator.status_message(status) == row.module.c_status_message(status)


# -- one contract -------------------------------------------------------------------------------------------------

@by_row
@by_impl
def test_every_estimator_has_the_contract_methods(impl, row):
    estimator = getattr(impl, row.estimator)()
    settings = estimator.settings
    assert callable(estimator.reset) and callable(estimator.update) and callable(estimator.status_message)
    assert "out" in inspect.signature(estimator.update_batch).parameters
    assert isinstance(settings.as_dict(), dict)
    assert settings.replace(**row.change) != settings


@by_row
def test_binding_and_reference_classes_have_one_docstring(row):
    c_class, reference_class = getattr(fusion_altitude, row.estimator), getattr(fusion_altitude.reference, row.estimator)
    assert reference_class.__doc__ and c_class.__doc__ == reference_class.__doc__


@by_row
def test_binding_has_the_references_public_methods_with_the_same_parameters(row):
    c_class, reference_class = getattr(fusion_altitude, row.estimator), getattr(fusion_altitude.reference, row.estimator)
    public = {name for name in dir(reference_class) if not name.startswith("_")}
    assert public <= set(dir(c_class))
    for name in sorted(public):
        reference_member = getattr(reference_class, name)
        if callable(reference_member) and not isinstance(reference_member, property):
            assert list(inspect.signature(getattr(c_class, name)).parameters) == \
                list(inspect.signature(reference_member).parameters), name


@by_row
@by_impl
@pytest.mark.parametrize("method", ["update", "update_batch"])
def test_updates_take_accel_baro_altitude_dt_then_keywords(impl, row, method):
    parameters = list(inspect.signature(getattr(getattr(impl, row.estimator), method)).parameters.values())
    count = len(row.positional)
    assert tuple(p.name for p in parameters[1:1 + count]) == row.positional
    assert all(p.kind is p.KEYWORD_ONLY or p.name == "out" for p in parameters[1 + count:])


LEGACY = [row for row in ESTIMATORS if row.legacy]


@pytest.mark.parametrize("row", LEGACY, ids=[row.estimator for row in LEGACY])
@by_impl
def test_the_old_positional_order_still_works_for_one_release_with_a_deprecation_warning(impl, row):
    inputs = row.inputs(np.random.default_rng(8), 30)
    new, old = getattr(impl, row.estimator)(), getattr(impl, row.estimator)()
    new.update_batch(accel=inputs["accel"], baro_altitude=inputs["baro_altitude"], dt=0.01)
    with pytest.warns(DeprecationWarning, match="from the next release the order is"):
        old.update_batch(inputs["accel"], 0.01, inputs["baro_altitude"])
    assert state(old) == state(new)
    with pytest.warns(DeprecationWarning):
        old.update(0.1, 0.01, 12.0)
    new.update(0.1, 12.0, dt=0.01)
    assert state(old) == state(new)


# Call patterns of update(accel, ...): (positional arguments after accel, keyword arguments).
CALLS = [
    ((), {"baro_altitude": 12.0, "dt": 0.01}),  # the contract, by keyword: no warning
    ((12.0,), {"dt": 0.01}),  # the contract with baro_altitude positional: no warning
    ((), {"dt": 0.01}),  # baro_altitude left out: no sample
    ((), {}),  # dt left out: TypeError naming dt
    ((12.0,), {"dt": None}),
    ((12.0,), {"dt": 0.01, "baro_altitude": 3.0}),  # given twice
    ((0.01,), {}),  # the old order (accel, dt): warns
    ((0.01, 12.0), {}),  # (accel, dt, baro_altitude): warns
    ((0.01, 12.0, 3.0), {}),
    ((0.01, 12.0), {"baro_altitude": 3.0}),  # old order, a name given twice: warns, then TypeError
    ((0.01, 12.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0), {}),  # too many
    ((0.01,), {"dt": 0.02, "baro_altitude": 3.0}),
    ((), {"baro_altitude": 12.0, "dt": -1.0}),  # rejected by the C check: ValueError naming dt
    ((), {"baro_altitude": "x", "dt": 0.01}),  # not a number: TypeError naming it
]


def _outcome(call):
    """(result or exception type and message, [(category, message, file name)] of the warnings)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = ("ok", call())
        except (TypeError, ValueError) as error:
            # CPython and Cython word their own argument errors apart ("C.f() got multiple values for argument
            # 'x'" / "f() got multiple values for keyword argument 'x'"): compare them without the difference
            message = re.sub(r"^\w+\.(?=\w+\(\))", "", str(error)).replace("keyword argument", "argument")
            result = (type(error).__name__, message)
    return result, [(w.category.__name__, str(w.message), Path(w.filename).name) for w in caught]


@pytest.mark.parametrize("row", LEGACY, ids=[row.estimator for row in LEGACY])
@pytest.mark.parametrize("method", ["update", "update_batch"])
def test_binding_and_reference_parse_update_arguments_alike(row, method):
    """The bindings parse (accel, *args, **keywords) in Cython, the reference through _common.argument_order:
    the same results, errors, warnings (pointing at the caller's line) and states for every call pattern."""
    estimators = {name: getattr(impl, row.estimator)() for name, impl in IMPLEMENTATIONS.items()}
    for args, kwargs in CALLS:
        if method == "update_batch":  # the same pattern, one step long
            args = tuple(np.array([value]) if isinstance(value, float) else value for value in args)
            kwargs = {key: np.array([value]) if isinstance(value, float) and key != "dt" else value
                      for key, value in kwargs.items()}
        outcomes = {}
        for name, estimator in estimators.items():
            (kind, value), caught = _outcome(lambda: getattr(estimator, method)(0.1, *args, **kwargs))
            outcomes[name] = ((kind, bits(tuple(value)) if kind == "ok" and value is not None else value), caught,
                              state(estimator))
        assert outcomes["c"] == outcomes["reference"], (args, kwargs)
        (kind, _), caught, _ = outcomes["c"]
        assert all(file == Path(__file__).name for _, _, file in caught), (args, kwargs)
        assert bool(caught) == (len(args) > 1 or (len(args) == 1 and "dt" not in kwargs)), (args, kwargs)


@by_row
@by_impl
@pytest.mark.parametrize("clone", [copy.copy, copy.deepcopy, lambda e: pickle.loads(pickle.dumps(e))],
                         ids=["copy", "deepcopy", "pickle"])
def test_a_clone_resumes_with_identical_results(impl, row, clone):
    estimator = warmed_up(impl, row)
    twin = clone(estimator)
    assert state(twin) == state(estimator)
    more = row.inputs(np.random.default_rng(2), 100)
    assert bits(tuple(twin.update_batch(**more))) == bits(tuple(estimator.update_batch(**more)))
    assert state(twin) == state(estimator)


@by_row
def test_a_reference_checkpoint_restores_in_the_binding_and_back(row):
    reference = warmed_up(fusion_altitude.reference, row)
    binding = fusion_altitude.reference._checkpoint.restore(getattr(fusion_altitude, row.estimator),
                                                            reference._get_state())
    assert state(binding) == state(reference)
    back = fusion_altitude.reference._checkpoint.restore(type(reference), binding._get_state())
    assert state(back) == state(reference)


@by_row
@by_impl
@pytest.mark.parametrize("name, value", [("accel", math.inf), ("dt", -1.0)])
def test_a_bad_update_names_the_argument_and_leaves_the_state(impl, row, name, value):
    estimator = warmed_up(impl, row)
    before = state(estimator)
    arguments = {key: sample(values, 0) for key, values in row.inputs(np.random.default_rng(3), 1).items()}
    bad = [value, *arguments[name][1:]] if isinstance(arguments[name], list) else value  # a vector: one component
    with pytest.raises(ValueError, match=rf"^{name} "):
        estimator.update(**{**arguments, name: bad})
    assert state(estimator) == before


@by_row
@by_impl
@pytest.mark.parametrize("name, value", [("accel", math.inf), ("dt", -1.0)])
def test_a_bad_batch_names_the_argument_and_index_and_leaves_the_state(impl, row, name, value):
    estimator = warmed_up(impl, row)
    before = state(estimator)
    inputs = row.inputs(np.random.default_rng(4), 20)
    inputs[name][7] = value
    with pytest.raises(ValueError, match=rf"^{name}\[7\] "):
        estimator.update_batch(**inputs)
    assert state(estimator) == before


@by_row
@by_impl
def test_a_batch_equals_per_sample_updates(impl, row):
    inputs = {name: values.astype(np.float32).astype(float) for name, values in
              row.inputs(np.random.default_rng(5), 200).items()}
    batched, stepped = getattr(impl, row.estimator)(), getattr(impl, row.estimator)()
    batched.update_batch(**inputs)
    run_per_sample(stepped, inputs)
    assert state(batched) == state(stepped)


@by_row
@by_impl
def test_a_batch_writes_into_out_and_returns_it(impl, row):
    inputs = row.inputs(np.random.default_rng(6), 50)
    expected = getattr(impl, row.estimator)().update_batch(**inputs)
    out = type(expected)(*(np.full_like(array, 7) for array in expected))
    result = getattr(impl, row.estimator)().update_batch(**inputs, out=out)
    assert result is out
    assert bits(tuple(result)) == bits(tuple(expected))
    listed = [np.full_like(array, 7) for array in expected]  # any sequence of the arrays: that object comes back
    assert getattr(impl, row.estimator)().update_batch(**inputs, out=listed) is listed
    assert bits(tuple(listed)) == bits(tuple(expected))


@by_row
@by_impl
def test_reset_keeps_the_settings(impl, row):
    settings = getattr(impl, row.settings)().replace(**row.change)
    if row.retune:
        estimator = warmed_up(impl, row)
        estimator.settings = settings
    else:
        estimator = getattr(impl, row.estimator)(settings)
        estimator.update_batch(**row.inputs(np.random.default_rng(1), 300))
    estimator.reset(*([12.5] if "baro_altitude" in inspect.signature(estimator.reset).parameters else []))
    assert estimator.settings == settings


@by_row
def test_reset_agrees_between_implementations(row):
    c, reference = warmed_up(fusion_altitude, row), warmed_up(fusion_altitude.reference, row)
    arguments = [12.5] if "baro_altitude" in inspect.signature(c.reset).parameters else []
    c.reset(*arguments)
    reference.reset(*arguments)
    assert state(c) == state(reference)


@by_row
def test_a_c_batch_releases_the_gil(row):
    n = row.gil_samples
    inputs = {name: np.zeros((n, *np.shape(values)[1:]), np.float32)
              for name, values in row.inputs(np.random.default_rng(0), 1).items()}
    inputs["dt"] = 0.01
    estimator = getattr(fusion_altitude, row.estimator)()
    out = estimator.update_batch(**inputs)  # allocates the outputs once (and warms up)
    finished = threading.Event()

    def run_batches():
        for _ in range(5):
            estimator.update_batch(**inputs, out=out)
        finished.set()

    worker = threading.Thread(target=run_batches)
    worker.start()
    ticks = 0
    while not finished.is_set():
        ticks += 1
        time.sleep(0)  # yields the GIL; a batch holding it would leave this loop one turn per batch
    worker.join()
    assert ticks > 50


# -- C = reference, bit for bit -----------------------------------------------------------------------------------

@by_row
@hypothesis_settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 120))
def test_c_equals_the_reference_bit_for_bit(row, seed, n):
    inputs = row.inputs(np.random.default_rng(seed), n)
    c, reference = getattr(fusion_altitude, row.estimator)(), getattr(fusion_altitude.reference, row.estimator)()
    assert bits(tuple(c.update_batch(**inputs))) == bits(tuple(reference.update_batch(**inputs)))
    assert state(c) == state(reference)


@by_row
@hypothesis_settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_settings_accepted_by_python_are_exactly_those_c_accepts(row, data):
    settings_class = getattr(fusion_altitude, row.settings)
    defaults = settings_class().as_dict()
    special = st.sampled_from([0.0, -1.0, 1.0, 1e7, math.inf, math.nan, 0.5])
    sensors = [name for name, value in defaults.items() if hasattr(value, "_fields")]  # per-sensor settings
    if sensors:
        sensor = data.draw(st.sampled_from(sensors + ["gap_period"]))
        if sensor == "gap_period":
            values = {**defaults, "gap_period": data.draw(special)}
        else:
            field = data.draw(st.sampled_from([f for f in defaults[sensor]._fields if not f.startswith("quality")]))
            values = {**defaults, sensor: defaults[sensor]._replace(**{field: data.draw(special)})}
        c_values = {name: value for name, value in values.items() if name not in sensors}
        c_values["sensors"] = [values[name]._asdict() for name in sensors]
    else:
        field = data.draw(st.sampled_from([name for name, value in defaults.items() if isinstance(value, float)]))
        values = {**defaults, field: data.draw(special)}
        c_values = values
    try:
        settings_class(**values)
        accepted = True
    except ValueError:
        accepted = False
    assert accepted == (row.module.c_settings_check(c_values) == 0)
