"""The rocket estimator's replay vectors (csrc/tests/vectors/rocket_vectors.h) are fresh and cover every phase.

The replays themselves run in tests/test_firmware.py (host gcc/clang, QEMU
Cortex-M4F at -Os and -O2), as for every estimator of the Makefile's ESTIMATORS.
"""

import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VECTORS = ROOT / "csrc" / "tests" / "vectors"


def load_generator():
    spec = importlib.util.spec_from_file_location("generate_rocket_vectors", VECTORS / "generate_rocket.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_rocket_vectors_are_up_to_date_and_reach_every_phase():
    text = load_generator().render()
    assert text == (VECTORS / "rocket_vectors.h").read_text(), \
        "csrc/tests/vectors/rocket_vectors.h is stale: run python csrc/tests/vectors/generate_rocket.py"
    coverage = text.split("Coverage (record counts):")[1].split("*/")[0]
    for transition in ("phase 0 -> 1", "phase 1 -> 2", "phase 2 -> 3", "phase 3 -> 4", "phase 4 -> 5"):
        assert re.search(rf"{transition} \d+", coverage), transition
    for status in (1, 2, 3):  # every rejection, on both update calls
        assert re.search(rf"\bupdate status {status} \d+", coverage)
        assert re.search(rf"\bupdate_vertical status {status} \d+", coverage)
    assert "phase 2 baro 4" in coverage and "phase 1 baro 3" in coverage  # spikes and lockout
    assert re.search(r"phase 0 -> 2 \d+", coverage)  # launch from the baro (no accelerometer)
