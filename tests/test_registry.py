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


def _load(name, path):
    import importlib.util
    import sys

    if name not in sys.modules:  # registered before it runs: its dataclasses look themselves up
        spec = importlib.util.spec_from_file_location(name, path)
        sys.modules[name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]


def test_the_contract_test_has_one_row_per_registered_estimator():
    contract = _load("test_contract", ROOT / "tests" / "test_contract.py")
    assert [row.estimator for row in contract.ESTIMATORS] == \
        [entry.estimator_class for name, entry in ESTIMATORS.items() if name in BUILT_IN]


def test_the_binding_generator_has_one_module_per_built_in_estimator_with_the_registrys_class():
    generator = _load("generate_bindings", ROOT / "tools" / "generate_bindings.py")
    assert generator.ESTIMATORS == {name: ESTIMATORS[name].estimator_class for name in BUILT_IN}
    assert list(generator.MODULES) == list(BUILT_IN)


def test_every_built_in_row_is_written_on_its_adapter():
    from fusion_altitude import adapters

    assert [adapter.registry_row["name"] for adapter in adapters.ADAPTERS] == list(BUILT_IN)
    assert all(ESTIMATORS[adapter.registry_row["name"]].function() is adapter for adapter in adapters.ADAPTERS)


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


#: a block that tools/generate_bindings.py writes into a hand-written file (tools/package_init.py)
_GENERATED_BLOCK = re.compile(r"^[ \t]*# generated: (.+?) -- written by tools/generate_bindings.py.*?"
                              r"^[ \t]*# end generated: \1\n", re.M | re.S)


def _hand_written_files_naming_every_estimator():
    import subprocess

    classes = [entry.estimator_class for entry in ESTIMATORS.values() if entry.name in BUILT_IN]
    if (ROOT / ".git").exists():
        files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    else:  # an unpacked sdist: its files are the tracked ones (tests/test_distribution.py)
        files = [str(path.relative_to(ROOT)) for path in ROOT.rglob("*") if path.is_file()
                 and not {".venv", "build", "__pycache__"} & set(path.relative_to(ROOT).parts)]
    found = set()
    for name in files:
        path = ROOT / name
        if path.suffix not in (".py", ".pyx", ".pxi", ".md", ".c", ".h") or not path.is_file():
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        if "do not edit; run the script instead" in text[:200]:
            continue  # generated
        text = _GENERATED_BLOCK.sub("", text)  # the generated lines of the package's __init__ files
        if all(re.search(rf"\b{cls}\b", text) for cls in classes):
            found.add(name)
    return found


def test_the_files_that_list_every_estimator_are_the_ones_architecture_md_names():
    # a new parallel list of estimators must read the registry instead, or be counted in docs/architecture.md
    text = (ROOT / "docs" / "architecture.md").read_text()
    named = text[text.index("The\nPython files that name every estimator's class are exactly"):]
    named = named[:named.index("(and the")]
    listed = {("fusion_altitude/" + n if not n.startswith(("tools/", "tests/")) else n)
              for n in re.findall(r"`([\w/]+\.py)`", named)}
    assert _hand_written_files_naming_every_estimator() - {"docs/architecture.md"} == listed


def test_the_count_of_hand_written_files_for_a_new_estimator_matches_its_table():
    text = (ROOT / "docs" / "architecture.md").read_text()
    section = text[text.index("## Adding an estimator"):]
    section = section[:section.index("\n## ", 1)]  # this section only: later sections have tables of their own
    table = [line for line in section.splitlines() if line.startswith("| ") and not line.startswith("| step")]
    # the files of the hand-written column: backticked names with an extension, or the Makefile
    count = sum(len(re.findall(r"`[^`]*(?:\.\w+|Makefile)`", line.split(" | ")[1])) for line in table)
    stated = int(re.search(r"That is (\d+) hand-written files", section).group(1))
    assert count == stated


@pytest.fixture
def registry_complementary():
    """The complementary filter registered a second time, under a label no scenario runner knows."""
    from fusion_altitude.estimators import EstimatorEntry, register_estimator

    entry = EstimatorEntry("complementary-registry", "the complementary filter through its adapter",
                           "adapters:run_complementary_log", label="complementary (registry)")
    register_estimator(entry)
    yield entry
    del ESTIMATORS[entry.name]


def test_compare_runs_a_registered_estimator_without_a_scenario_runner_through_its_adapter(registry_complementary):
    built_in, registered = comparison.compare_scenario("clean", repeat=0,
                                                       estimators=("complementary", "complementary (registry)"))
    assert registered.estimator == "complementary (registry)" and registered.problem is None
    # the same filter: the adapter adapts only the gap period and baro timeout to the log, which a clean run never meets
    assert registered.altitude_rms == pytest.approx(built_in.altitude_rms, rel=1e-6)


def test_compare_refuses_an_unknown_estimator_label():
    with pytest.raises(ValueError, match="unknown estimator 'nonesuch'"):
        comparison.compare_scenario("clean", repeat=0, estimators=("nonesuch",))


def test_the_firmware_size_tables_have_one_block_per_estimator_of_the_generator():
    import importlib.util

    spec = importlib.util.spec_from_file_location("size_table", ROOT / "csrc" / "firmware" / "size_table.py")
    table = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(table)
    modules = list(table.estimator_modules())
    assert modules[0] == "observer" and [row[0] for row in table.ESTIMATORS] == modules[1:]
    assert sorted(modules) == sorted(BUILT_IN)  # the generator's estimators are the registry's built-in ones
