"""Figures for scenario runs and log runs (the ``[plot]`` extra: matplotlib).

matplotlib is imported inside the functions, with the Agg backend, so
importing this module never needs it. Every figure is written atomically
(:func:`save_figure`) and long series are decimated for display
(:func:`decimate`: min and max per pixel column, so spikes stay visible).
"""

from __future__ import annotations

from typing import Optional

import numpy as np

__all__ = ["plot_scenario", "plot_log_run", "plot_fit_landscape", "decimate", "save_figure", "check_plot_path",
           "relative_time", "COLUMNS"]

#: Pixel columns a long series is decimated to (a 10-inch figure at 110 dpi is 1100 px wide; 2000 leaves margin).
COLUMNS = 2000


def _pyplot():
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as error:
        raise ImportError("plotting needs matplotlib: pip install 'fusion-altitude[plot]'") from error
    return plt


def check_plot_path(path: str) -> None:
    """Raise ImportError without matplotlib, ValueError naming the extension if matplotlib cannot write it.

    Called before any work so that a missing extra or a typo in ``--plot``
    costs nothing.
    """
    _pyplot()
    from matplotlib.backend_bases import FigureCanvasBase

    import os

    extension = os.path.splitext(path)[1].lower().lstrip(".")
    formats = FigureCanvasBase.get_supported_filetypes()
    if extension not in formats:
        raise ValueError(f"cannot write a plot as {'.' + extension if extension else 'a file without extension'!r}"
                         f": use one of {', '.join('.' + f for f in sorted(formats))}")


def save_figure(figure, path: str, **options) -> None:
    """``figure.savefig(path)`` through a temporary file renamed onto ``path`` (no half-written plot)."""
    from .outputs import atomic_output

    with atomic_output(path) as temporary:
        figure.savefig(temporary, **options)


def decimate(x, y, columns: int = COLUMNS):
    """Min/max decimation of a line for display: at most 2·``columns`` points that draw like the full series.

    The samples are split into ``columns`` runs of equal count; each run
    contributes its minimum and maximum (in time order), so every spike
    and every envelope survives. Series of ≤ 4·``columns`` samples are
    returned unchanged. NaNs are ignored within a run (a run of only NaN
    gives NaN: a gap in the line).

    Parameters
    ----------
    x, y : array_like
        Same length; x increasing (time, s).
    columns : int
        Pixel columns of the target axis.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    n = y.size
    if n <= 4 * columns:
        return x, y
    per = int(np.ceil(n / columns))
    pad = per * int(np.ceil(n / per)) - n
    xs = np.concatenate([x, np.full(pad, x[-1])]).reshape(-1, per)
    ys = np.concatenate([y, np.full(pad, np.nan)]).reshape(-1, per)
    filled = np.isfinite(ys)
    any_finite = filled.any(axis=1)
    low_index = np.argmin(np.where(filled, ys, np.inf), axis=1)
    high_index = np.argmax(np.where(filled, ys, -np.inf), axis=1)
    rows = np.arange(ys.shape[0])
    first = np.minimum(low_index, high_index)
    second = np.maximum(low_index, high_index)
    out_x = np.column_stack([xs[rows, first], xs[rows, second]]).ravel()
    out_y = np.column_stack([ys[rows, first], ys[rows, second]]).ravel()
    out_y[np.repeat(~any_finite, 2)] = np.nan
    return out_x, out_y


def _decimated_style(args, kwargs, decimated: bool):
    """A dotted series drawn as a thin line once decimated: min/max pairs joined by a line fill each pixel
    column from its minimum to its maximum, where dots would show only the two extremes."""
    if not decimated or not args or args[0] != ".":
        return args, kwargs
    kwargs = {k: v for k, v in kwargs.items() if k not in ("ms", "markersize")}
    kwargs.setdefault("lw", 0.6)
    return ("-",) + tuple(args[1:]), kwargs


def relative_time(time):
    """Times for a plot's x axis and their axis label.

    Parameters
    ----------
    time : array_like
        Sample times, s.

    Returns
    -------
    x : numpy.ndarray
        ``time`` as float, s; epoch-like times (|first| > 10^6 s) as seconds since the first sample.
    label : str
        The x axis label: "time (s)", or "time (s) since t = <first> s".
    """
    time = np.asarray(time, dtype=float)
    if time.size and abs(time[0]) > 1e6:
        return time - time[0], f"time (s) since t = {time[0]:.3f} s"
    return time, "time (s)"


#: The old private name of :func:`relative_time`, kept for one release.
_relative_time = relative_time


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
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def plot_log_run(run, path: str, title: Optional[str] = None) -> None:
    """Write a PNG of a log run: baro, fused estimate and the autopilot's own estimate.

    Panels: altitude (m) with baro, fused estimate and (if present) the
    reference estimate; fused − reference and baro − reference (m), or the
    baro residual when there is no reference; vertical velocity (m/s);
    bias estimate (m/s²).

    Parameters
    ----------
    run : fusion_altitude.runner.LogRun
        Output of :func:`fusion_altitude.runner.run_log`.
    path : str
        Output file.
    title : str, optional
        Figure title; default the log's source.
    """
    plt = _pyplot()
    t, time_label = relative_time(run.time)
    label = f"{getattr(run, 'estimator', 'observer')} estimate"
    fig, axes = plt.subplots(4, 1, figsize=(10, 10), sharex=True, constrained_layout=True)
    line = _line_plotter(t)
    baro = ~np.isnan(run.baro_altitude)
    line(axes[0], run.baro_altitude, ".", mask=baro, ms=1.5, color="0.6", label="baro altitude", zorder=1)
    if run.reference_altitude is not None:
        line(axes[0], run.reference_altitude, color="k", lw=1.2, label=run.reference_name or "reference", zorder=2)
    line(axes[0], run.estimate.altitude, color="C0", lw=1.0, label=label, zorder=3)
    axes[0].set_ylabel("altitude above start (m)" if getattr(run, "datum", 0.0) else "altitude (m)")
    axes[0].legend(loc="best", fontsize=8)
    axes[0].set_title(title or run.source)
    _difference_panel(line, axes[1], run, baro)
    _velocity_and_bias_panels(line, axes[2], axes[3], run, label)
    axes[3].set_xlabel(time_label)
    events = getattr(run, "events", None)
    if events is not None:
        offset = float(np.asarray(run.time, float)[0]) if time_label != "time (s)" else 0.0
        for axis in axes:
            mark_events(axis, events, offset, labels=axis is axes[0])
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def _line_plotter(t: np.ndarray):
    """``line(axis, values, *args, mask=None, **kwargs)``: plot ``values`` (at ``mask``) against the times
    ``t``, thinned by :func:`decimate`, in the thinned style when thinned."""

    def line(axis, values, *args, mask=None, **kwargs):
        values = np.asarray(values, dtype=float)
        x, y = decimate(t if mask is None else t[mask], values if mask is None else values[mask])
        decimated = x.size < (t.size if mask is None else int(mask.sum()))
        args, kwargs = _decimated_style(args, kwargs, decimated)
        axis.plot(x, y, *args, **kwargs)

    return line


def _difference_panel(line, axis, run, baro: np.ndarray) -> None:
    """Fused − reference and baro − reference (m); without a reference the baro residual, else baro − estimate."""
    estimate = run.estimate
    if run.reference_altitude is not None:
        line(axis, run.baro_altitude - run.reference_altitude, ".", mask=baro, ms=1.5, color="0.6",
             label="baro − reference", zorder=1)
        line(axis, np.asarray(estimate.altitude, float) - run.reference_altitude, color="C0", lw=1.0,
             label="estimate − reference", zorder=3)
        axis.set_ylabel("difference (m)")
    elif hasattr(estimate, "baro_residual"):
        line(axis, estimate.baro_residual, ".", ms=1.5, color="C3", label="baro residual")
        axis.set_ylabel("residual (m)")
    else:
        line(axis, run.baro_altitude - np.asarray(estimate.altitude, float), ".", mask=baro, ms=1.5,
             color="C3", label="baro − estimate")
        axis.set_ylabel("baro − estimate (m)")
    axis.legend(loc="best", fontsize=8)


def _velocity_and_bias_panels(line, velocity_axis, bias_axis, run, label: str) -> None:
    """Vertical velocity (m/s), ours and the reference's; the accelerometer bias (m/s²), else the vertical
    acceleration (m/s²)."""
    estimate = run.estimate
    line(velocity_axis, estimate.vertical_velocity, color="C0", lw=1.0, label=label)
    if run.reference_velocity is not None:
        line(velocity_axis, run.reference_velocity, color="k", lw=1.0, label=run.reference_name or "reference")
    velocity_axis.set_ylabel("vertical velocity (m/s)")
    velocity_axis.legend(loc="best", fontsize=8)
    if hasattr(estimate, "accel_bias"):
        line(bias_axis, estimate.accel_bias, color="C1")
        bias_axis.set_ylabel("accel bias (m/s²)")
    else:
        line(bias_axis, run.vertical_acceleration, color="C1", lw=0.5)
        bias_axis.set_ylabel("vertical accel (m/s²)")


def mark_events(axis, events, offset: float = 0.0, labels: bool = True) -> list:
    """Mark flight events on a time axis: a dashed vertical line at each declared event, named on top.

    Parameters
    ----------
    axis : matplotlib.axes.Axes
    events : fusion_altitude.rocket.FlightEvents
        Times in the log's seconds.
    offset : float, default 0
        Subtracted from each event time (s), as the x axis of :func:`relative_time`.
    labels : bool, default True
        Write each event's name next to its line, each on the highest row where it does not
        overlap a name to its left (events close in time, e.g. launch, max_speed and burnout on a
        long flight, are stacked instead of written over each other). Call after the data are
        plotted, so that the x limits are final.

    Returns
    -------
    list of (str, float)
        The (event name, x position s) drawn.
    """
    drawn = []
    occurred = list(events.occurred())
    rows = event_label_rows(axis, [float(event.time) - offset for event in occurred],
                            [event.name for event in occurred]) if labels else []
    for k, event in enumerate(occurred):
        x = float(event.time) - offset
        axis.axvline(x, color="C3", linestyle="--", linewidth=0.8, alpha=0.7, zorder=0)
        if labels:
            axis.annotate(event.name, xy=(x, 1.0), xycoords=("data", "axes fraction"), xytext=(2, -10 - 9 * rows[k]),
                          textcoords="offset points", fontsize=7, color="C3")
        drawn.append((event.name, x))
    return drawn


def event_label_rows(axis, positions, names, fontsize: float = 7.0) -> list:
    """Row (0 = top) of each event label so that no two labels in one row overlap.

    Greedy from left to right: a label takes the first row whose last label ends (estimated
    width 0.6·fontsize per character plus 4 points) left of its own start. ``positions`` are
    in data units (s) on ``axis``'s current x limits.
    """
    left, right = axis.get_xlim()
    width_points = axis.get_window_extent().width * 72.0 / axis.figure.dpi
    scale = width_points / (right - left) if right != left else 0.0
    ends = []  # per row: x (points) where its last label ends
    rows = [0] * len(positions)
    for k in sorted(range(len(positions)), key=lambda i: positions[i]):
        start = (positions[k] - left) * scale + 2.0
        row = next((r for r, end in enumerate(ends) if end <= start), len(ends))
        if row == len(ends):
            ends.append(0.0)
        ends[row] = start + 0.6 * fontsize * len(names[k]) + 4.0
        rows[k] = row
    return rows


def plot_fit_landscape(result, path: str, title: Optional[str] = None) -> None:
    """Write a contour plot of a fit's RMS error (m) over ω (rad/s, log axis) and ω_b.

    The vertical axis is ω_b/ω (the grid the search walks, so the contours
    interpolate between neighbours only); each point shows the best ζ found
    there. The fitted gains are
    marked with a star, the VTOL default (ω 1.5, ω_b 0.3) with a cross.

    Parameters
    ----------
    result : fusion_altitude.FitResult
        What :func:`fusion_altitude.fit` returned.
    path : str
        Output file (the extension picks the format).
    """
    plt = _pyplot()
    import matplotlib.tri as mtri

    landscape = result.landscape
    best = {}
    for row in landscape[np.isfinite(landscape["rms_error"])]:
        key = (round(float(row["omega"]), 9), round(float(row["omega_b"]), 9))
        best[key] = min(best.get(key, np.inf), float(row["rms_error"]))
    keys = np.array(list(best))
    rms = np.array(list(best.values()))
    x, y = np.log10(keys[:, 0]), keys[:, 1] / keys[:, 0]
    figure, axes = plt.subplots(figsize=(8, 5.5))
    if len(rms) >= 3:
        triangles = mtri.Triangulation(x, y)
        levels = np.geomspace(rms.min(), np.percentile(rms, 95), 15)
        filled = axes.tricontourf(triangles, np.minimum(rms, levels[-1]), levels=levels, cmap="viridis_r",
                                  extend="max")
        figure.colorbar(filled, ax=axes, label="RMS altitude error (m), best ζ")
    axes.scatter(x, y, s=3, color="k", alpha=0.3, label="candidates")
    axes.scatter([np.log10(result.omega)], [result.omega_b / result.omega], marker="*", s=220, color="red",
                 label=f"fit: ω {result.omega:.3g}, ζ {result.zeta:.2g}, ω_b {result.omega_b:.3g} "
                       f"({result.rms_error:.3g} m)")
    axes.scatter([np.log10(1.5)], [0.2], marker="x", s=100, color="white", linewidths=2,
                 label=f"VTOL default ({result.default_rms_error:.3g} m)")
    ticks = [t for t in (0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20) if x.min() - 0.1 <= np.log10(t) <= x.max() + 0.1]
    axes.set_xticks(np.log10(ticks))
    axes.set_xticklabels([f"{t:g}" for t in ticks])
    axes.set_xlabel("position-loop bandwidth ω (rad/s)")
    axes.set_ylabel("bias-loop bandwidth / position-loop bandwidth, ω_b / ω")
    axes.set_title(title or "fit landscape")
    axes.legend(loc="upper left", fontsize=8)
    figure.tight_layout()
    save_figure(figure, path, dpi=110)
    plt.close(figure)
