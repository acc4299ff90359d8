"""Figures for scenario runs and log runs (the ``[plot]`` extra: matplotlib).

matplotlib is imported inside the functions, with the Agg backend, so
importing this module never needs it.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

__all__ = ["plot_scenario", "plot_log_run"]


def _pyplot():
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as error:
        raise ImportError("plotting needs matplotlib: pip install 'fusion-altitude[plot]'") from error
    return plt


def plot_scenario(result, path: str) -> None:
    """Write a PNG of a scenario run: altitude, error, and accelerometer bias.

    Panels: truth, raw baro and fused altitude (m); raw-baro and fused error
    (m) with the transient shaded; bias estimate vs the true vertical bias
    (m/s²).

    Parameters
    ----------
    result : fusion_altitude.scenarios.ScenarioResult
        A run from :func:`fusion_altitude.scenarios.run_scenario`.
    path : str
        Output file (the extension picks the format).
    """
    plt = _pyplot()
    t = result.time
    fig, axes = plt.subplots(3, 1, figsize=(10, 8.5), sharex=True, constrained_layout=True)
    baro = ~np.isnan(result.baro_altitude)
    axes[0].plot(t[baro], result.baro_altitude[baro], ".", ms=1.5, color="0.6", label="baro (raw)")
    axes[0].plot(t, result.trajectory.altitude, color="k", lw=1.2, label="truth")
    axes[0].plot(t, result.estimate.altitude, color="C0", lw=1.0, label="fused estimate")
    axes[0].set_ylabel("altitude (m)")
    axes[0].legend(loc="upper right", fontsize=8)
    stats = result.statistics()
    axes[0].set_title(f"scenario {result.name}, seed {result.seed}: fused RMS {stats.rms * 100:.1f} cm, "
                      f"max {stats.max * 100:.1f} cm after {result.transient:g} s")
    axes[1].plot(t[baro], result.baro_error[baro], ".", ms=1.5, color="0.6", label="baro − truth")
    axes[1].plot(t, result.altitude_error, color="C0", lw=1.0, label="estimate − truth")
    axes[1].axvspan(t[0], t[0] + result.transient, color="0.9", zorder=0, label="transient")
    limit = max(3 * stats.max, 0.05)
    axes[1].set_ylim(-limit, limit)
    axes[1].set_ylabel("error (m)")
    axes[1].legend(loc="upper right", fontsize=8)
    axes[2].plot(t, result.estimate.accel_bias, color="C1", label="bias estimate")
    axes[2].axhline(result.true_bias, color="k", ls="--", lw=1, label="true vertical bias")
    axes[2].set_ylabel("accel bias (m/s²)")
    axes[2].set_xlabel("time (s)")
    axes[2].legend(loc="lower right", fontsize=8)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_log_run(run, path: str, title: Optional[str] = None) -> None:
    """Write a PNG of a log run: baro, fused estimate and the autopilot's own estimate.

    Panels: altitude (m) with baro, fused estimate and (if present) the
    reference estimate; fused − reference and baro − reference (m), or the
    baro residual when there is no reference; vertical velocity (m/s);
    bias estimate (m/s²).

    Parameters
    ----------
    run : fusion_altitude.logs.LogRun
        Output of :func:`fusion_altitude.logs.run_log`.
    path : str
        Output file.
    title : str, optional
        Figure title; default the log's source.
    """
    plt = _pyplot()
    t = run.time
    fig, axes = plt.subplots(4, 1, figsize=(10, 10), sharex=True, constrained_layout=True)
    baro = ~np.isnan(run.baro_altitude)
    axes[0].plot(t[baro], run.baro_altitude[baro], ".", ms=1.5, color="0.6", label="baro altitude")
    if run.reference_altitude is not None:
        axes[0].plot(t, run.reference_altitude, color="k", lw=1.2, label=run.reference_name or "reference")
    axes[0].plot(t, run.estimate.altitude, color="C0", lw=1.0, label="fused estimate")
    axes[0].set_ylabel("altitude (m)")
    axes[0].legend(loc="best", fontsize=8)
    axes[0].set_title(title or run.source)
    if run.reference_altitude is not None:
        axes[1].plot(t[baro], run.baro_altitude[baro] - run.reference_altitude[baro], ".", ms=1.5,
                     color="0.6", label="baro − reference")
        axes[1].plot(t, run.estimate.altitude - run.reference_altitude, color="C0", lw=1.0,
                     label="fused − reference")
        axes[1].set_ylabel("difference (m)")
    else:
        axes[1].plot(t, run.estimate.baro_residual, ".", ms=1.5, color="C3", label="baro residual")
        axes[1].set_ylabel("residual (m)")
    axes[1].legend(loc="best", fontsize=8)
    axes[2].plot(t, run.estimate.vertical_velocity, color="C0", lw=1.0, label="fused")
    if run.reference_velocity is not None:
        axes[2].plot(t, run.reference_velocity, color="k", lw=1.0, label=run.reference_name or "reference")
    axes[2].set_ylabel("vertical velocity (m/s)")
    axes[2].legend(loc="best", fontsize=8)
    axes[3].plot(t, run.estimate.accel_bias, color="C1")
    axes[3].set_ylabel("accel bias (m/s²)")
    axes[3].set_xlabel("time (s)")
    fig.savefig(path, dpi=110)
    plt.close(fig)
