"""Fit the observer gains to the simulator's truth on three scenarios.

    python examples/fit_scenarios.py [--seed N]

For each scenario (a VTOL in the ``realistic`` one, a weather balloon, a
fixed-wing-like climb–cruise–descent) it runs :func:`fusion_altitude.fit`
against the truth after the scenario's transient and prints the RMS altitude
error of the fitted gains, of the VTOL default gains, and of the scenario's
own preset as ``fusion-altitude demo`` runs it — on the seed it was fitted
to, and on the next seed (a different noise draw: the held-out check that the
fit did not just learn the noise).
"""

import argparse

import fusion_altitude
from fusion_altitude.metrics import error_statistics
from fusion_altitude.scenarios import run_scenario
from fusion_altitude.tuning import settings_for_baro_rate, steps_per_baro

SCENARIOS = ("realistic", "balloon", "climb-cruise-descend")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    print("| scenario | fitted ω, ζ, ω_b | fitted RMS (m) | VTOL default RMS (m) | preset RMS (m) | improvement vs default "
          "| held-out seed: fitted / default RMS (m) |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for name in SCENARIOS:
        result = run_scenario(name, args.seed)
        mask = result.time > result.time[0] + result.transient
        fit = fusion_altitude.fit(result.vertical_acceleration, result.baro_altitude, result.trajectory.dt,
                                  result.trajectory.altitude, mask=mask,
                                  steps_per_baro=steps_per_baro(result.baro_altitude))
        preset_rms = result.statistics().rms
        held_out = run_scenario(name, args.seed + 1)
        fitted_rms, default_rms = (held_out_rms(held_out, settings) for settings in (fit.settings, None))
        print(f"| {name} | {fit.omega:.3g} rad/s, {fit.zeta:.2g}, {fit.omega_b:.3g} rad/s | {fit.rms_error:.4f} | "
              f"{fit.default_rms_error:.4f} | {preset_rms:.4f} | {100 * (1 - fit.rms_error / fit.default_rms_error):.0f}% "
              f"| {fitted_rms:.4f} / {default_rms:.4f} |")


def held_out_rms(result, settings) -> float:
    """RMS altitude error (m) after the transient of gains on a scenario run, compensated for the baro rate
    as ``demo``, ``run``, ``fit`` and ``compare`` run them."""
    gains = settings_for_baro_rate(settings or fusion_altitude.AltitudeSettings(), steps_per_baro(result.baro_altitude))
    estimate = fusion_altitude.AltitudeEstimator(gains).update_batch(
        result.vertical_acceleration, result.baro_altitude, result.trajectory.dt)
    try:
        return error_statistics(result.time, estimate.altitude - result.trajectory.altitude, result.transient).rms
    except ValueError:  # the estimate overflowed: these gains are unstable at this baro rate
        return float("nan")


if __name__ == "__main__":
    main()
