"""Two study tables over simulated rocket flights (:func:`fusion_altitude.sim.rocket_sim.simulate_rocket_flight`):
the rocket estimator's event and height figures (:func:`summary`) and the Kalman filter against it
(:func:`kalman_comparison`). An application: it runs the rocket helpers on the simulator, so it sits above both
(``python -m fusion_altitude.rocket_study [--kalman]``).
"""

import numpy as np

from ._core._kalman import KalmanEstimator, KalmanSettings
from .metrics import error_statistics
from .rocket import rocket_kalman_settings, run_rocket
from .sim.rocket_sim import simulate_rocket_flight

__all__ = ["summary", "kalman_comparison"]


def summary(seeds: int = 20) -> str:
    """The event and height figures of :func:`fusion_altitude.rocket.run_rocket` (default settings)
    over ``seeds`` simulated flights, as a Markdown table (``python -m fusion_altitude.rocket_study``)."""
    rows = {"apogee delay after the true apogee (s)": [], "apogee height error (%)": [],
            "true height at main (m; set 250)": [], "largest height drop during the ascent (m)": [],
            "launch delay (s)": [], "burnout delay (s)": [], "max ascent height error (m)": [],
            "max descent height error after main (m)": [], "peak speed (m/s)": [], "peak static-port error (m)": []}
    for seed in range(seeds):
        flight = simulate_rocket_flight(seed)
        batch, events = run_rocket(flight.time, flight.accel, flight.baro_altitude)
        truth = flight.trajectory.altitude
        up = slice(events["launch"].sample, events["apogee"].sample + 1)
        ascent = batch.height[up].astype(np.float64)
        after_main = slice(events["main"].sample, None)
        rows["apogee delay after the true apogee (s)"].append(events["apogee"].time - flight.apogee_time)
        rows["apogee height error (%)"].append(100 * (events["apogee"].height - flight.apogee_height) / flight.apogee_height)
        rows["true height at main (m; set 250)"].append(float(np.interp(events["main"].time, flight.time, truth)))
        rows["largest height drop during the ascent (m)"].append(float((np.maximum.accumulate(ascent) - ascent).max()))
        rows["launch delay (s)"].append(events["launch"].time - flight.launch_time)
        rows["burnout delay (s)"].append(events["burnout"].time - flight.burnout_time)
        rows["max ascent height error (m)"].append(float(np.abs(ascent - truth[up]).max()))
        rows["max descent height error after main (m)"].append(float(np.abs(batch.height[after_main] - truth[after_main]).max()))
        rows["peak speed (m/s)"].append(float(flight.trajectory.vertical_velocity.max()))
        rows["peak static-port error (m)"].append(float(-flight.static_port_error.min()))
    lines = [f"| over {seeds} seeds | min | mean | max |", "|---|---|---|---|"]
    for name, values in rows.items():
        lines.append(f"| {name} | {min(values):+.3f} | {np.mean(values):+.3f} | {max(values):+.3f} |")
    return "\n".join(lines)


def kalman_comparison(seeds: int = 5) -> str:
    """RMS height error over whole simulated flights (m): the Kalman filter with its default and its rocket
    settings (accel as given, baro above the pad) and the rocket estimator
    (``python -m fusion_altitude.rocket_study --kalman``)."""
    lines = ["| seed | Kalman, default settings | Kalman, rocket settings | RocketEstimator |", "|---|---|---|---|"]
    for seed in range(seeds):
        flight = simulate_rocket_flight(seed)
        truth = flight.trajectory.altitude
        baro = flight.baro_altitude - flight.model.pad_altitude
        rms = []
        for settings in (KalmanSettings(), rocket_kalman_settings()):
            result = KalmanEstimator(settings).update_batch(flight.accel, baro_altitude=baro, dt=flight.dt)
            rms.append(error_statistics(flight.time, result.altitude - truth, transient=-np.inf).rms)  # whole flight
        batch, _ = run_rocket(flight.time, flight.accel, flight.baro_altitude)
        rms.append(error_statistics(flight.time, batch.height - truth, transient=-np.inf).rms)
        lines.append(f"| {seed} | " + " | ".join(f"{value:.1f}" for value in rms) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    import sys

    print(kalman_comparison() if "--kalman" in sys.argv[1:] else summary())
