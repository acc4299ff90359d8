"""The full state survives copy and pickle, so runs can be checkpointed and resumed."""

import copy
import math
import pickle

import numpy as np
import pytest

import fusion_altitude


def warmed_up(impl):
    estimator = impl.AltitudeEstimator(impl.AltitudeSettings.preset("fixed_wing"))
    rng = np.random.default_rng(5)
    estimator.update_batch(rng.normal(0, 1, 500), 10 + rng.normal(0, 0.1, 500), 0.01)
    estimator.update(0.3, math.nan, 0.01)  # leaves a NaN residual in the state
    return estimator


@pytest.mark.parametrize("clone", [copy.copy, copy.deepcopy, lambda e: pickle.loads(pickle.dumps(e))],
                         ids=["copy", "deepcopy", "pickle"])
def test_clone_carries_the_full_state(impl, state_bits, clone):
    estimator = warmed_up(impl)
    assert state_bits(clone(estimator)) == state_bits(estimator)


def test_resumed_checkpoint_gives_identical_results(impl):
    estimator = warmed_up(impl)
    checkpoint = pickle.dumps(estimator)
    rng = np.random.default_rng(6)
    accel, baro = rng.normal(0, 1, 300), 10 + rng.normal(0, 0.1, 300)
    original = estimator.update_batch(accel, baro, 0.01)
    resumed = pickle.loads(checkpoint).update_batch(accel, baro, 0.01)
    for a, b in zip(original, resumed):
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_copies_are_independent(impl):
    estimator = warmed_up(impl)
    clone = copy.copy(estimator)
    clone.update(1.0, 20.0, 0.01)
    assert clone.altitude != estimator.altitude


def test_reference_checkpoint_resumes_in_the_c_binding(state_bits):
    estimator = warmed_up(fusion_altitude.reference)
    restored = fusion_altitude._observer._restore(estimator._get_state())
    assert state_bits(restored) == state_bits(estimator)
