"""One meaning per name (docs/architecture.md, "Names"): the INS's height above its start has its own name, its
altitude in the baro's datum is what ``run -o`` writes as ``altitude``, and the rocket layer answers to its stem."""

import numpy as np
import pytest

import fusion_altitude as fa
import fusion_altitude.reference as ref


def _ins_after_a_few_steps(cls):
    ins = cls()
    for k in range(200):
        ins.update([0.0, 0.0, 0.0], [0.0, 0.0, 9.80665], 0.01, baro_altitude=120.0 + 0.01 * k)
    return ins


@pytest.mark.parametrize("cls", [fa.InsEstimator, ref.InsEstimator], ids=["binding", "reference"])
def test_the_ins_height_above_start_is_its_altitude_above_the_first_baro_sample(cls):
    ins = _ins_after_a_few_steps(cls)
    assert ins.height_above_start == ins.altitude
    assert abs(ins.height_above_start) < 5.0  # ≈ 0 at the first baro reading, not 120 m


@pytest.mark.parametrize("cls", [fa.InsEstimator, ref.InsEstimator], ids=["binding", "reference"])
def test_the_ins_baro_datum_altitude_is_height_plus_baro_bias(cls):
    ins = _ins_after_a_few_steps(cls)
    assert ins.baro_datum_altitude == float(np.float32(ins.altitude) + np.float32(ins.baro_bias))
    assert abs(ins.baro_datum_altitude - 121.0) < 5.0


def test_the_ins_batch_names_match_the_estimator():
    n = 200
    batch = fa.InsEstimator().update_batch(np.zeros((n, 3)), np.tile([0.0, 0.0, 9.80665], (n, 1)), 0.01,
                                           baro_altitude=np.full(n, 50.0))
    assert batch.height_above_start is batch.altitude
    np.testing.assert_array_equal(batch.baro_datum_altitude, batch.altitude + batch.baro_bias)


def test_the_rocket_reference_answers_to_the_rocket_stem():
    import fusion_altitude.reference.flight as flight
    import fusion_altitude.reference.rocket as rocket

    assert rocket is flight and rocket.RocketEstimator is ref.RocketEstimator
