"""The estimator comparison: one short scenario through the library and the CLI."""

import math

import numpy as np
import pytest

from fusion_altitude import comparison as compare
from fusion_altitude.cli import main


@pytest.fixture(scope="module")
def terrain_rows():
    return compare.compare_scenario("terrain-step", repeat=1)


def test_every_estimator_gets_a_row_with_finite_metrics(terrain_rows):
    assert [r.estimator for r in terrain_rows] == compare.estimators_for("terrain-step")
    for row in terrain_rows:
        assert math.isfinite(row.altitude_rms) and row.altitude_max >= row.altitude_rms
        if row.estimator == "raw baro":
            assert row.ns_per_sample is None and row.recovery is None and math.isnan(row.velocity_rms)
        else:
            assert row.ns_per_sample > 0 and math.isfinite(row.velocity_rms) and row.recovery is not None


def test_same_seed_same_numbers(terrain_rows):
    again = compare.compare_scenario("terrain-step", repeat=1)
    for a, b in zip(terrain_rows, again):
        assert a.altitude_rms == b.altitude_rms and np.array_equal(a.altitude, b.altitude, equal_nan=True)


def test_the_bias_free_complementary_filter_carries_the_12_mg_offset(terrain_rows):
    rows = {r.estimator: r for r in terrain_rows}
    # 12 mg on body z: b·T_v·T_h = 0.118 · 9.99 · 4.99 = 5.9 m at steady state
    assert 3.0 < rows["complementary"].altitude_rms < 7.0
    assert rows["observer"].altitude_rms < 0.1 and rows["Kalman"].altitude_rms < 0.1


def test_cli_compare_prints_the_table(capsys):
    assert main(["compare", "--scenario", "terrain-step", "--repeat", "1", "--markdown"]) == 0
    text = capsys.readouterr().out
    assert "| terrain-step | alpha-beta |" in text and "ns/sample" in text
