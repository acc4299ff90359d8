"""The estimator registry (fusion_altitude.estimators) is the one list of estimators: the CLI, compare, the fleet,
the package's public classes and the contract test agree with it, so a list that drifts from it fails here."""

import argparse
import re
from pathlib import Path

import pytest

import fusion_altitude
from fusion_altitude import comparison, fleet
from fusion_altitude._core._estimator import Estimator
from fusion_altitude.cli import build_parser
from fusion_altitude.estimators import ESTIMATORS, observer_rate

ROOT = Path(__file__).resolve().parents[1]
BUILT_IN = ("observer", "kalman", "complementary", "alphabeta", "ins", "rocket")


def _run_choices():
    commands = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    run = commands.choices["run"]
    return next(a for a in run._actions if a.dest == "estimator").choices


def test_the_registry_holds_the_built_in_estimators_in_table_order():
    assert tuple(ESTIMATORS)[:len(BUILT_IN)] == BUILT_IN


def test_run_offers_exactly_the_registered_estimators():
    assert list(_run_choices()) == list(ESTIMATORS)


def test_compare_has_one_row_per_registered_estimator_in_registry_order():
    labels = [entry.table_label for entry in ESTIMATORS.values()]
    rows = [label for label in comparison.ESTIMATORS if label not in ("observer (fit)", "raw baro")]
    assert rows == labels


def test_the_fleet_accepts_every_registered_estimator():
    for name in ESTIMATORS:
        assert fleet.resolve_settings(name, None) is None or name == "observer"


def test_every_registered_class_is_public_and_every_public_estimator_class_is_registered():
    registered = {entry.estimator_class for entry in ESTIMATORS.values()}
    public = {name for name in fusion_altitude.__all__
              if isinstance(getattr(fusion_altitude, name, None), type) and issubclass(getattr(fusion_altitude, name), Estimator)}
    assert registered == public


def test_the_contract_test_has_one_row_per_registered_estimator():
    rows = re.findall(r'^    Row\("(\w+)"', (ROOT / "tests" / "test_contract.py").read_text(), re.M)
    assert sorted(rows) == sorted(entry.estimator_class for entry in ESTIMATORS.values())


def test_only_the_observer_takes_presets_and_only_rocket_logs_default_to_the_rocket_layer():
    assert [e.name for e in ESTIMATORS.values() if e.takes_preset] == ["observer"]
    assert [e.name for e in ESTIMATORS.values() if e.vehicle] == ["rocket"]


def test_every_adapter_of_the_registry_imports():
    for entry in ESTIMATORS.values():
        assert callable(entry.function()), entry.name


@pytest.mark.parametrize("baro_every, preset", [(1, "vtol"), (50, "fixed_wing")])
def test_the_observer_rate_computes_the_default_preset_and_its_advice_once(baro_every, preset):
    import numpy as np

    from fusion_altitude.logs import LogData

    time = np.arange(0, 60, 0.01)
    baro = np.full(time.size, np.nan)
    baro[::baro_every] = 0.0
    rate = observer_rate(LogData("simulated", time, np.zeros(time.size), baro))
    assert rate.default_preset == preset
    assert rate.steps_per_baro == pytest.approx(baro_every)
    assert rate.stability_period == pytest.approx(0.01 * baro_every)
    assert rate.is_stable(rate.default_preset) == (rate.default_preset in rate.stable_presets)
