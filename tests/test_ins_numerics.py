"""The INS's float32 shortcuts, as specifications: the scalar covariance update
P - c cᵀ/S, the quaternion normalisation without a square root near unit
norm, and the input bound checked on the magnitude bits. Each must give what
the textbook operation gives, to the stated bound, and C = reference."""

import pickle
import re
import struct
from pathlib import Path

import numpy as np
import pytest

import fusion_altitude as fa
from fusion_altitude import _c_tables
from fusion_altitude.reference import ins as reference

HEADER = Path(__file__).resolve().parents[1] / "csrc" / "fusion_altitude_ins.h"
f32 = np.float32


@pytest.mark.parametrize("name", ["VARIANCE_LIMIT", "ATTITUDE_VARIANCE_LIMIT", "YAW_VARIANCE_LIMIT", "NEWTON_NORM"])
def test_reference_constants_are_the_header_constants(name):
    assert getattr(reference, name) == f32(getattr(_c_tables, f"FUSION_ALTITUDE_INS_{name}"))


def test_maximum_bits_are_the_bits_of_the_maximum():
    bits = int(re.search(r"#define FUSION_ALTITUDE_INS_MAXIMUM_BITS \((0x[0-9A-Fa-f]+)u\)", HEADER.read_text()).group(1), 16)
    assert bits == struct.unpack("<I", struct.pack("<f", _c_tables.FUSION_ALTITUDE_INS_MAXIMUM))[0]


@pytest.mark.parametrize("bad", [np.nextafter(f32(1e6), f32(np.inf)), -np.nextafter(f32(1e6), f32(np.inf)), np.inf, -np.inf, np.nan])
def test_a_gyro_value_beyond_the_maximum_or_not_finite_is_refused_and_the_state_kept(bad):
    ins = fa.InsEstimator()
    ins.update((0.0, 0.0, 0.0), (0.0, 0.0, 9.80665), 0.002)
    before = pickle.dumps(ins)
    with pytest.raises(ValueError, match="gyro"):
        ins.update((0.0, float(bad), 0.0), (0.0, 0.0, 9.80665), 0.002)
    assert pickle.dumps(ins) == before


@pytest.mark.parametrize("edge", [1e6, -1e6, 0.0, -0.0])
def test_a_gyro_value_at_the_maximum_is_accepted(edge):
    ins = fa.InsEstimator()
    ins.update((0.0, 0.0, 0.0), (0.0, 0.0, 9.80665), 0.002)
    ins.update((0.0, edge, 0.0), (0.0, 0.0, 9.80665), 0.002)


@pytest.mark.parametrize("excess", [0.0, 1e-7, -3e-6, 5e-5, -9.9e-5])
def test_normalise_near_unit_norm_matches_the_square_root_to_an_ulp(excess):
    rng = np.random.default_rng(abs(hash(excess)) % 2**32)
    direction = rng.normal(size=4)
    q = (direction / np.linalg.norm(direction) * np.sqrt(1.0 + excess)).astype(f32)
    normalised = reference._normalise(q).astype(np.float64)
    exact = q.astype(np.float64) / np.linalg.norm(q.astype(np.float64))
    # one ulp of 1: the float32 rounding of the factor and of each product, as with sqrtf and a division
    assert np.max(np.abs(normalised - exact)) <= 2 ** -23
    assert abs(np.linalg.norm(normalised) - 1.0) < 2e-7


def test_normalise_far_from_unit_norm_takes_the_square_root():
    q = np.array([3.0, 4.0, 0.0, 0.0], dtype=f32)
    assert np.array_equal(reference._normalise(q), np.array([f32(3) * (f32(1) / f32(5)), f32(4) * (f32(1) / f32(5)), 0, 0], dtype=f32))


def test_the_quaternion_norm_does_not_drift_over_a_long_fast_spin():
    """10⁶ steps at 500 Hz spinning at 8 rad/s about a tilted axis (each step in the
    square-root-free range): the attitude stays a unit quaternion."""
    count = 1_000_000
    gyro = np.tile(np.array([4.0, -5.0, 4.9], dtype=f32), (count, 1))
    accel = np.tile(np.array([0.0, 0.0, 9.80665], dtype=f32), (count, 1))
    ins = fa.InsEstimator()
    result = ins.update_batch(gyro, accel, dt=0.002)
    norms = np.linalg.norm(result.quaternion.astype(np.float64), axis=1)
    assert np.max(np.abs(norms - 1.0)) < 5e-7


def test_a_scalar_update_is_p_minus_c_ct_over_s_and_keeps_p_bit_symmetric():
    rng = np.random.default_rng(7)
    A = rng.normal(size=(8, 8))
    P = (A @ A.T / 8 + np.eye(8) * 0.1).astype(f32)
    P = np.triu(P) + np.triu(P, 1).T  # bit-symmetric float32
    model = reference.InsEstimator()
    model.P = P.copy()
    dx = np.zeros(8, dtype=f32)
    model._fuse(dx, 0, f32(0.3), 2, f32(-0.8), f32(0.05), f32(0.01))
    h = np.zeros(8)
    h[0], h[2] = 0.3, -0.8
    c = P.astype(np.float64) @ h
    S = h @ c + 0.01
    expected = P.astype(np.float64) - np.outer(c, c) / S
    assert np.array_equal(model.P, model.P.T)
    assert np.max(np.abs(model.P - expected)) < 1e-6 * np.max(np.abs(P))
    assert np.allclose(dx, c / S * 0.05, rtol=1e-5, atol=1e-9)
