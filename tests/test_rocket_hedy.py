"""The rocket estimator on a real flight: "Hedy" (TU Wien Space Team, EuRoC 2025), CATS flight computer.

Our events and height (C core, default settings, long-axis accelerometer −Y
minus g, baro through the ISA) against the CATS flight computer's own
filtered estimate (hedy_flight_info.csv), with the CATS events found as
``fusion-altitude run`` and examples/rocket_hedy.py find them: the log read by
:func:`fusion_altitude.logs.read_cats`, its events by
:func:`fusion_altitude.rocket.flight_computer_events` (events_from_estimates on
its height and velocity, its acceleration the time derivative of that
velocity). The CATS estimate is a reference, not the truth.
"""

import os
from pathlib import Path

import numpy as np
import pytest

from fusion_altitude import rocket
from fusion_altitude.logs import read_cats
from fusion_altitude.sensors import pressure_to_altitude

ROOT = Path(__file__).resolve().parents[1]


def shared_data() -> Path:
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


def read(name: str) -> np.ndarray:
    path = shared_data() / name
    assert path.is_file(), f"{path} is missing"
    return np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding=None)


@pytest.fixture(scope="module")
def hedy():
    baro, imu, info = read("hedy_baro.csv"), read("hedy_imu.csv"), read("hedy_flight_info.csv")
    assert np.array_equal(baro["ts"], imu["ts"])
    time = baro["ts"].astype(np.float64)
    accel = rocket.long_axis_accel(np.column_stack([imu["Ax"], imu["Ay"], imu["Az"]]), axis=1, sign=-1)
    batch, events = rocket.run_rocket(time, accel, pressure_to_altitude(baro["P"].astype(np.float64)))
    cats, how = rocket.flight_computer_events(read_cats(str(shared_data() / "hedy_baro.csv")))
    assert how.startswith("read off its height and velocity")
    cats_height = np.interp(time, info["ts"], info["height"])
    return time, batch, events, cats, cats_height


def test_hedy_apogee_is_within_0_1_s_and_0_1_percent_of_the_cats_apogee(hedy):
    _, _, events, cats, _ = hedy
    assert abs(events["apogee"].time - cats["apogee"].time) <= 0.1
    assert abs(events["apogee"].height - cats["apogee"].height) <= 0.001 * cats["apogee"].height


def test_hedy_launch_and_burnout_are_within_0_1_s_of_the_cats_estimate(hedy):
    _, _, events, cats, _ = hedy
    assert abs(events["launch"].time - cats["launch"].time) <= 0.1
    assert abs(events["burnout"].time - cats["burnout"].time) <= 0.1


def test_hedy_height_never_goes_down_by_more_than_1_m_during_the_ascent(hedy):
    """Launch to apogee (measured: 0.229 m), through the lockout, the shock at 9.1 s and the re-admission at 24.2 s."""
    _, batch, events, _, _ = hedy
    ascent = batch.height[events["launch"].sample:events["apogee"].sample + 1].astype(np.float64)
    drop = (np.maximum.accumulate(ascent) - ascent).max()
    assert drop <= 1.0, drop


def test_hedy_main_altitude_is_crossed_within_0_1_s_of_the_cats_height(hedy):
    _, _, events, cats, _ = hedy
    assert abs(events["main"].time - cats["main"].time) <= 0.1


def test_hedy_log_ends_before_landing_so_no_landed_event(hedy):
    _, _, events, cats, _ = hedy
    assert not events["landed"].occurred and not cats["landed"].occurred


def test_hedy_descent_height_follows_the_cats_height_within_2_m_rms(hedy):
    time, batch, events, _, cats_height = hedy
    descent = np.arange(time.size) > events["apogee"].sample
    difference = batch.height[descent] - cats_height[descent]
    assert np.sqrt(np.mean(difference ** 2)) < 2.0


def test_hedy_baro_is_locked_out_through_the_transonic_part_and_fused_after(hedy):
    time, batch, events, _, _ = hedy
    fast = (time > 2.0) & (time < 20.0)
    assert not (batch.baro[fast] == rocket.BaroFate.FUSED).any()  # locked out, or a spike (the shock at 9.1 s)
    assert (batch.baro[fast] == rocket.BaroFate.LOCKED_OUT).mean() > 0.98
    assert (batch.baro[events["apogee"].sample:] == rocket.BaroFate.FUSED).all()


def test_hedy_pad_log_is_ignition_shake_so_the_pad_stays_uncalibrated(hedy):
    """0.65 s of log before lift-off, with ±10 m/s² of ignition shake: no stationary window."""
    time, batch, events, _, _ = hedy
    assert events["launch"].sample < 70
    assert batch.accel_bias[events["launch"].sample] == 0.0
