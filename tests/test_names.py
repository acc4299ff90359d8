"""One meaning per name (docs/architecture.md, "Names"): the INS's height above its start has its own name, its
altitude in the baro's datum is what ``run -o`` writes as ``altitude``."""

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
def test_the_ins_height_above_start_is_near_zero_at_the_first_baro_sample(cls):
    ins = _ins_after_a_few_steps(cls)
    assert abs(ins.height_above_start) < 5.0  # ≈ 0 at the first baro reading, not 120 m


@pytest.mark.parametrize("cls", [fa.InsEstimator, ref.InsEstimator], ids=["binding", "reference"])
def test_the_ins_altitude_is_in_the_baros_datum_as_every_estimators(cls):
    ins = _ins_after_a_few_steps(cls)
    assert abs(ins.altitude - 121.0) < 5.0  # the baro reads 120-122 m
    assert ins.altitude == float(np.float32(ins.height_above_start) + np.float32(ins.baro_bias))


@pytest.mark.parametrize("cls", [fa.InsEstimator, ref.InsEstimator], ids=["binding", "reference"])
def test_the_ins_baro_datum_altitude_is_its_altitude(cls):
    ins = _ins_after_a_few_steps(cls)
    assert ins.baro_datum_altitude == ins.altitude


def test_the_ins_and_the_observer_report_altitude_in_the_same_datum():
    ins, observer = _ins_after_a_few_steps(fa.InsEstimator), fa.AltitudeEstimator()
    for k in range(200):
        observer.update(0.0, 120.0 + 0.01 * k, 0.01)
    assert abs(ins.altitude - observer.altitude) < 5.0


@pytest.mark.parametrize("cls", [fa.InsEstimator, ref.InsEstimator], ids=["binding", "reference"])
def test_the_ins_batch_altitude_is_height_above_start_plus_baro_bias(cls):
    n = 200
    batch = cls().update_batch(np.zeros((n, 3)), np.tile([0.0, 0.0, 9.80665], (n, 1)), 0.01,
                               baro_altitude=np.full(n, 50.0))
    assert batch.altitude.dtype == np.float32
    np.testing.assert_array_equal(batch.altitude, batch.height_above_start + batch.baro_bias)
    np.testing.assert_array_equal(batch.baro_datum_altitude, batch.altitude)
    assert abs(batch.altitude[-1] - 50.0) < 1.0 and abs(batch.height_above_start[-1]) < 1.0
