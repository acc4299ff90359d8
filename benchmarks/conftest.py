"""Fixtures for the pytest-benchmark suite (run only when named: ``pytest benchmarks/``)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _signals import make_signals  # noqa: E402

#: Samples for the batch benchmarks.
BATCH_SAMPLES = 1_000_000
#: Samples for the pure-Python reference (about 2.5 µs each).
REFERENCE_SAMPLES = 20_000
#: Samples per round of the per-sample update() benchmark.
PER_SAMPLE_CHUNK = 10_000


@pytest.fixture(scope="session")
def signals():
    return make_signals(BATCH_SAMPLES)


@pytest.fixture(scope="session")
def out_arrays():
    import fusion_altitude

    return fusion_altitude.AltitudeBatch(*(np.empty(BATCH_SAMPLES, dtype=np.float32) for _ in range(4)))
