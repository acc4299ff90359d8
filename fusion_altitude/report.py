"""Interactive HTML reports of a log run and of a fleet (the ``[report]`` extra: Bokeh).

:func:`log_report` lays out one log: a header (file, format, vehicle,
duration, the sensor health report of ``run``, the settings used, the error
table against the log's own estimate) over linked plots on one zoomable time
axis — altitude, vertical velocity, accelerometer bias and the baro residual
(innovation) with its gate — with shaded spans for logging gaps, baro
timeouts, baro rejections and rocket lockouts, rocket phases as coloured
bands and flight events as labelled marks (ours and the flight computer's).
:func:`fleet_report` lays out a ``fleet run`` output directory: a sortable,
filterable table with a link per log to its report, and distributions.
:func:`save` writes either as one self-contained HTML file (every script and
style inline: it opens offline).

Long series are decimated per pixel column (min and max,
:func:`fusion_altitude.plotting.decimate`), so a page stays small whatever
the log's length. Bokeh is imported inside the functions: importing this
module never needs it.

Units: time s, altitude m, velocity m/s, acceleration m/s².
"""

from __future__ import annotations

import html
import math
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .plotting import COLUMNS, decimate, relative_time

__all__ = ["log_report", "fleet_report", "save", "report_title", "PLOT_HEIGHT", "COLUMNS"]

#: ``name`` of a log report's header ``Div``: :func:`save` writes it as plain HTML above the plots, so the page
#: needs no widget scripts (0.38 MB less to load).
HEADER_NAME = "fusion-altitude-header"
#: Height of each time plot, px.
PLOT_HEIGHT = 260
#: Line colours of the estimates, in run order (Bokeh's Category10 without the greys).
ESTIMATE_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22")
#: Colours of the rocket phases (Phase code → colour).
PHASE_COLOURS = ("#dddddd", "#ff9896", "#ffbb78", "#aec7e8", "#98df8a", "#c5b0d5")
#: Shaded spans: (key, legend label, colour).
SPAN_KINDS = (("gap", "logging gap", "#7f7f7f"), ("timeout", "baro timeout (not baro-aided)", "#d62728"),
              ("sensor", "GPS / rangefinder / axial accelerometer timeout", "#bcbd22"),
              ("rejected", "baro rejected", "#9467bd"), ("lockout", "rocket baro lockout", "#e377c2"))


def _bokeh():
    try:
        import bokeh  # noqa: F401
    except ImportError as error:
        raise ImportError("the HTML report needs bokeh: pip install 'fusion-altitude[report]'") from error
    import bokeh.models  # noqa: F401
    import bokeh.plotting  # noqa: F401
    return bokeh


def report_title(run) -> str:
    """The page title of a log's report: ``"<source> — fusion-altitude report"``."""
    return f"{run.source} — fusion-altitude report"


# ----------------------------------------------------------------------------
# series and spans


def _intervals(x: np.ndarray, mask: np.ndarray, merge: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
    """(starts, ends) s of the runs of True in ``mask`` on times ``x``; runs closer than ``merge`` s joined.

    A run ends at the next sample's time (or its own last sample at the log's end), so a
    one-sample run has a width.
    """
    mask = np.asarray(mask, bool)
    if not mask.any():
        return np.empty(0), np.empty(0)
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    first = np.flatnonzero(edges == 1)
    last = np.flatnonzero(edges == -1) - 1
    starts = x[first]
    ends = x[np.minimum(last + 1, x.size - 1)]
    if merge > 0 and starts.size > 1:
        keep = np.concatenate([[True], starts[1:] - ends[:-1] > merge])
        ends = np.maximum.reduceat(ends, np.flatnonzero(keep))
        starts = starts[keep]
    return starts, ends


def _series(x: np.ndarray, values, columns: int, mask: Optional[np.ndarray] = None) -> Dict[str, np.ndarray]:
    """The data of one line: x (s, float64) and y (float32), only the samples present (``mask``, default the
    finite ones), min/max-decimated per pixel column."""
    values = np.asarray(values, dtype=float)
    present = np.isfinite(values) if mask is None else (np.asarray(mask, bool) & np.isfinite(values))
    xs, ys = decimate(x[present], values[present], columns)
    return {"x": np.asarray(xs, np.float64), "y": np.asarray(ys, np.float32)}


def _estimate_label(run) -> str:
    return f"{run.estimator} estimate"


def _residual(run) -> Tuple[Optional[np.ndarray], Optional[np.ndarray], str]:
    """(residual m per step, gate half-width m per step or None, description) of an estimator's baro update.

    The observer's own ``baro_residual``; the Kalman filter's baro innovation with its gate
    (``gate``·√S, S the innovation variance, from its NIS); else baro − estimate on baro steps.
    """
    estimate = run.estimate
    if hasattr(estimate, "baro_residual"):
        return np.asarray(estimate.baro_residual, float), None, "baro residual z − h before each correction"
    innovation = getattr(estimate, "innovation", None)
    nis = getattr(estimate, "nis", None)
    if innovation is not None and nis is not None and np.ndim(innovation) == 2:
        baro_innovation = np.asarray(innovation[:, 0], float)
        baro_nis = np.asarray(nis[:, 0], float)
        with np.errstate(divide="ignore", invalid="ignore"):
            sigma = np.where(baro_nis > 0, np.abs(baro_innovation) / np.sqrt(baro_nis), np.nan)
        gate = _kalman_gate(run)
        return baro_innovation, (gate * sigma if gate is not None else None), (
            f"Kalman baro innovation; gate ±{gate:g} σ" if gate is not None else "Kalman baro innovation")
    baro = np.asarray(run.baro_altitude, float)
    return baro - np.asarray(estimate.altitude, float), None, "baro − estimate on baro samples"


def _kalman_gate(run) -> Optional[float]:
    """The innovation gate (σ) the runner's Kalman filter used: its rocket settings on a rocket log, else the
    defaults (``fusion_altitude.runner``'s rule)."""
    try:
        if getattr(run, "vehicle", "") == "rocket":
            from .rocket import rocket_kalman_settings
            return float(rocket_kalman_settings().gate)
        from ._core._kalman import KalmanSettings
        return float(KalmanSettings().gate)
    except (ImportError, AttributeError):
        return None


def _spans(run, x: np.ndarray, merge: float) -> Dict[str, Tuple[np.ndarray, np.ndarray]]:
    """Shaded spans (starts, ends) s per :data:`SPAN_KINDS` key, on the x axis ``x``."""
    from .health import not_baro_aided

    time = np.asarray(run.time, float)
    shift = x[0] - time[0]
    spans: Dict[str, Tuple[np.ndarray, np.ndarray]] = {}
    gaps = list(getattr(run, "gaps", []) or [])
    spans["gap"] = (np.array([g[0] + shift for g in gaps], float), np.array([g[0] + g[1] + shift for g in gaps], float))
    timeout = not_baro_aided(time, run.baro_altitude)
    timed_out = getattr(run.estimate, "baro_timed_out", None)
    if timed_out is not None:
        timeout = timeout | np.asarray(timed_out, bool)
    spans["timeout"] = _intervals(x, timeout, merge)
    silent = np.zeros(time.size, bool)
    for name in ("gps_altitude", "rangefinder", "axial_acceleration"):  # silent longer than each stream's timeout
        values = getattr(run, name, None)
        if values is not None and np.isfinite(np.asarray(values, float)).any():
            silent |= not_baro_aided(time, values)  # the same rule for any stream: baro_timeout_for(its rate)
    spans["sensor"] = _intervals(x, silent, merge)
    rejected = np.zeros(time.size, bool)
    lockout = np.zeros(time.size, bool)
    fate = getattr(run.estimate, "baro_fate", None)
    if fate is not None:
        from ._core._rocket_glue import BaroFate

        fate = np.asarray(fate)
        rejected |= fate == BaroFate.SPIKE
        lockout |= fate == BaroFate.LOCKED_OUT
    result = getattr(run.estimate, "result", None)
    if result is not None and np.ndim(result) == 2:
        from ._core._c_tables import KalmanResult

        rejected |= np.asarray(result[:, 0]) == KalmanResult.REJECTED
    spans["rejected"] = _intervals(x, rejected, merge)
    spans["lockout"] = _intervals(x, lockout, merge)
    return spans


def _phase_bands(run, x: np.ndarray) -> List[Tuple[str, float, float, str]]:
    """(phase name, start s, end s, colour) of the rocket estimator's phases; [] for another estimator."""
    phase = getattr(run.estimate, "phase", None)
    if phase is None:
        return []
    from ._core._rocket_glue import Phase

    phase = np.asarray(phase, int)
    change = np.flatnonzero(np.diff(phase)) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [phase.size - 1]])
    return [(Phase(int(phase[s])).name.lower(), float(x[s]), float(x[e]), PHASE_COLOURS[int(phase[s]) % 6])
            for s, e in zip(starts, ends)]


# ----------------------------------------------------------------------------
# the header


def _table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    def cell(value: Any) -> str:
        if isinstance(value, float):
            return "–" if not math.isfinite(value) else f"{value:.3f}"
        return html.escape(str(value))

    def td(value: Any) -> str:  # numbers right-aligned (the style sheet's default), text left
        numeric = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
        return f"<td>{cell(value)}</td>" if numeric else f"<td class='fa-text'>{cell(value)}</td>"

    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(td(v) for v in row) + "</tr>" for row in rows)
    return f"<table class='fa-table'><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


_STYLE = ("<style>.fa-table{border-collapse:collapse;font:12px sans-serif;margin:4px 0 10px}"
          ".fa-table td,.fa-table th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
          ".fa-table td:first-child,.fa-table th:first-child,.fa-table td.fa-text{text-align:left}"
          ".fa-head{font:13px sans-serif}.fa-head h2{margin:4px 0}.fa-head h3{margin:8px 0 2px;font-size:14px}"
          ".fa-note{color:#555;font-size:12px}</style>")


def _header_html(runs, settings: Dict[str, Any], health) -> str:
    """The report's header: the log, its sensor health, the settings used and the error table."""
    first = runs[0]
    time = np.asarray(first.time, float)
    parts = [_STYLE, "<div class='fa-head'>", f"<h2>{html.escape(str(first.source))}</h2>", _facts_html(first, time),
             _health_html(first, health, time), _settings_html(runs, settings), _comparison_html(runs),
             _events_html(runs), _notes_html(first)]
    parts.append("<div class='fa-note'>Drag to pan, scroll to zoom: every plot shares the time axis. Lines are "
                 "decimated per pixel column (min and max) on long logs.</div></div>")
    return "".join(parts)


def _facts_html(first, time: np.ndarray) -> str:
    """One line of facts about the log: format, vehicle, duration (s), samples, datum, its own estimate."""
    duration = float(time[-1] - time[0])
    source = str(first.source)
    fmt = source[source.find("(") + 1:source.rfind(")")] if "(" in source and source.endswith(")") else ""
    facts = [("format", fmt or "–"), ("vehicle", getattr(first, "vehicle", "") or "unknown"),
             ("duration", f"{duration:.2f} s ({time[0]:.3f} … {time[-1]:.3f} s)"), ("samples", f"{time.size}"),
             ("datum", f"above the start ({first.datum:.2f} m)" if first.datum else
              (getattr(first, "altitude_reference", "") or "the log's")),
             ("log's own estimate", first.reference_name if first.reference_altitude is not None else "none")]
    return " · ".join(f"<b>{html.escape(k)}</b>: {html.escape(v)}" for k, v in facts)


def _health_notes(s, time: np.ndarray) -> str:
    """What is wrong with one sensor stream (:class:`fusion_altitude.health.SensorHealth`), "; "-joined."""
    from .health import stream_notes

    return "; ".join(stream_notes(s, time[0], time[-1]))


def _health_html(first, health, time: np.ndarray) -> str:
    """The sensor health table of ``run`` (:func:`fusion_altitude.health.format_health`) as HTML, and the gaps."""
    parts = ["<h3>Sensor health</h3>"]
    rows = [[s.name, s.samples, s.rate, s.first, s.last, s.longest_outage, _health_notes(s, time)] for s in health]
    parts.append(_table(["sensor", "samples", "rate (Hz)", "first (s)", "last (s)", "longest outage (s)", "notes"],
                        rows))
    gaps = list(getattr(first, "gaps", []) or [])
    if gaps:
        parts.append(f"<div class='fa-note'>logging gaps: {len(gaps)}, longest {max(g[1] for g in gaps):.3f} s at "
                     f"{max(gaps, key=lambda g: g[1])[0]:.3f} s</div>")
    return "".join(parts)


def _settings_html(runs, settings: Dict[str, Any]) -> str:
    """The estimators, the settings each ran with, their gaps and rejections, and what their residual is."""
    rows = []
    for run in runs:
        extra = []
        if run.gap_count is not None:
            period = f" (gap period {run.gap_period:.3g} s)" if run.gap_period is not None else ""
            extra.append(f"{run.gap_count} gaps{period}")
        if run.baro_rejections is not None:
            extra.append(f"{run.baro_rejections} baro rejections, {run.baro_resets} resets")
        described = settings.get(run.estimator)
        rows.append([run.estimator, "defaults" if described is None else str(described), "; ".join(extra),
                     _residual(run)[2]])
    return "<h3>Estimators and settings</h3>" + _table(
        ["estimator", "settings", "during the run", "baro residual plotted"], rows)


def _comparison_html(runs) -> str:
    """The error table (m, m/s) of each estimate and the raw baro against the log's own estimate; "" without one."""
    first = runs[0]
    if first.reference_altitude is None or not np.isfinite(first.reference_altitude).any():
        return ""
    from .metrics import error_statistics

    rows = []
    for run in runs:
        stats = run.comparison()
        velocity = math.nan
        if run.reference_velocity is not None and np.isfinite(run.reference_velocity).any():
            velocity = error_statistics(run.time, np.asarray(run.estimate.vertical_velocity, float)
                                        - run.reference_velocity, 0.0).rms
        rows.append([f"{run.estimator} − ref", stats.mean, stats.rms, stats.max, stats.p95, velocity])
    raw = first.baro_comparison()
    rows.append(["baro − ref", raw.mean, raw.rms, raw.max, raw.p95, math.nan])
    return (f"<h3>Against the log's own estimate ({html.escape(first.reference_name)})</h3>"
            + _table(["", "mean (m)", "RMS (m)", "max |·| (m)", "p95 |·| (m)", "velocity RMS (m/s)"], rows))


def _events_html(runs) -> str:
    """The rocket estimator's flight events (s, m) beside the flight computer's; "" when no run has events."""
    events = [run for run in runs if run.events is not None]
    if not events:
        return ""
    from .rocket import flight_computer_events

    theirs, how = flight_computer_events(runs[0], pad_altitude=None)
    rows = []
    for event in events[0].events:
        row = [event.name, event.time if event.occurred else math.nan, event.height if event.occurred else math.nan]
        if theirs is not None:
            other = theirs[event.name]
            row += [other.time if other.occurred else math.nan, other.height if other.occurred else math.nan]
        rows.append(row)
    header = ["event", "time (s)", "height (m)"] + (["FC time (s)", "FC height (m)"] if theirs is not None else [])
    return ("<h3>Flight events</h3>" + _table(header, rows)
            + f"<div class='fa-note'>flight computer's events: {html.escape(how)}</div>")


def _notes_html(first) -> str:
    """The reader's notes and warnings; "" without any."""
    notes = list(getattr(first, "notes", []) or []) + [f"warning: {w}" for w in getattr(first, "warnings", []) or []]
    if not notes:
        return ""
    return "<h3>Reader notes</h3><div class='fa-note'>" + "<br>".join(html.escape(n) for n in notes) + "</div>"


# ----------------------------------------------------------------------------
# log report


def _figure(title: str, y_label: str, x_range, x_label: str):
    from bokeh.plotting import figure

    options = {"x_range": x_range} if x_range is not None else {}
    plot = figure(title=title, height=PLOT_HEIGHT, sizing_mode="stretch_width", x_axis_label=x_label,
                  y_axis_label=y_label, tools="xpan,xwheel_zoom,box_zoom,reset,save", active_scroll="xwheel_zoom",
                  active_drag="xpan", output_backend="canvas", **options)
    plot.toolbar.logo = None
    return plot


def _line(plot, data: Dict[str, np.ndarray], name: str, colour: str, width: float = 1.2, dash: str = "solid",
          dots: bool = False, legend: Optional[str] = None):
    """A line (or dots, for a sparse sensor) of ``data`` on ``plot``, named ``name`` (the hover's label) and in
    the legend as ``legend`` (default ``name``; one label for several lines is one legend entry); None if there is
    nothing to draw."""
    from bokeh.models import ColumnDataSource

    if data["x"].size == 0:
        return None
    source = ColumnDataSource(data)
    legend = legend or name
    if dots and data["x"].size <= 4 * COLUMNS:  # not decimated: each sample is one dot
        return plot.scatter("x", "y", source=source, size=3, color=colour, legend_label=legend, name=name)
    return plot.line("x", "y", source=source, line_width=width, color=colour, line_dash=dash, legend_label=legend,
                     name=name)


def _shade(plot, spans: Dict[str, Tuple[np.ndarray, np.ndarray]], phases) -> None:
    """Phase bands and shaded spans on ``plot`` (``vstrip`` glyphs: they span any y range)."""
    from bokeh.models import ColumnDataSource

    for name, start, end, colour in phases:
        plot.vstrip(x0=[start], x1=[end], fill_color=colour, fill_alpha=0.25, line_alpha=0.0,
                    legend_label=f"phase {name}", level="underlay")
    for key, label, colour in SPAN_KINDS:
        starts, ends = spans.get(key, (np.empty(0), np.empty(0)))
        if starts.size:
            plot.vstrip(x0="x0", x1="x1", source=ColumnDataSource({"x0": starts, "x1": ends}), fill_color=colour,
                        fill_alpha=0.2, line_alpha=0.0, legend_label=label, level="underlay")


def _mark_events(plot, events, shift: float, colour: str, dash: str, who: str, top: bool) -> None:
    """Vertical marks at each declared event (``vspan``), named in a row of labels on the top plot."""
    from bokeh.models import ColumnDataSource, LabelSet

    occurred = list(events.occurred())
    if not occurred:
        return
    xs = [float(e.time) + shift for e in occurred]
    plot.vspan(x=xs, line_color=colour, line_dash=dash, line_width=1.2, legend_label=f"{who} events")
    if top:  # ours in the top rows, the flight computer's below; events close in time on successive rows
        first_row = 0 if who == "our" else 3
        offsets = [-12 * (first_row + k % 3) for k in range(len(occurred))]
        names = [e.name if who == "our" else f"{e.name} (FC)" for e in occurred]
        source = ColumnDataSource({"x": xs, "name": names, "dy": offsets})
        plot.add_layout(LabelSet(x="x", y=PLOT_HEIGHT - 100, y_units="screen", text="name", y_offset="dy",
                                 x_offset=3, source=source, text_font_size="10px", text_color=colour,
                                 background_fill_color="white", background_fill_alpha=0.7))


def log_report(runs, title: Optional[str] = None, settings: Optional[Dict[str, Any]] = None,
               columns: int = COLUMNS):
    """The interactive report of one log as a Bokeh layout (show it in Jupyter, or :func:`save` it).

    Parameters
    ----------
    runs : fusion_altitude.runner.LogRun or sequence of LogRun
        One or more estimators' runs on the same log
        (:func:`fusion_altitude.runner.run_log`); the first one's log gives the
        header, the raw sensors and the shaded spans.
    title : str, optional
        Shown above the header; default the log's source.
    settings : dict, optional
        Estimator name → the settings it ran with (any object; shown with
        ``str``) for the header; missing: "defaults".
    columns : int, default :data:`COLUMNS`
        Pixel columns each series is decimated to (min and max per column).

    Returns
    -------
    bokeh.models.Column
        The header (a ``Div``) over the altitude, vertical velocity,
        accelerometer bias and baro residual plots, sharing one x range.

    Raises
    ------
    TypeError
        ``runs`` is not a LogRun or a sequence of them.
    ValueError
        ``runs`` is empty or the runs are not of one log (different times), or
        ``columns`` < 1.
    ImportError
        Bokeh is missing (the ``[report]`` extra).
    """
    runs = _checked_runs(runs, columns)
    _bokeh()
    from bokeh.layouts import column

    first = runs[0]
    x, x_label = relative_time(first.time)
    shift = float(x[0] - np.asarray(first.time, float)[0])
    merge = float(x[-1] - x[0]) / columns if x.size > 1 else 0.0
    spans = _spans(first, x, merge)
    phases = next((_phase_bands(r, x) for r in runs if getattr(r.estimate, "phase", None) is not None), [])
    header = _header_div(runs, title, settings)
    lines: list = []  # every data line drawn: the hover tool and the y range follow them
    altitude = _altitude_plot(runs, x, x_label, columns, lines)
    plots = [altitude, _velocity_plot(runs, x, x_label, columns, lines, altitude.x_range),
             _bias_plot(runs, x, x_label, columns, lines, altitude.x_range),
             _residual_plot(runs, x, x_label, columns, lines, altitude.x_range)]
    theirs = None
    if any(r.events is not None for r in runs):
        from .rocket import flight_computer_events

        theirs, _ = flight_computer_events(first, pad_altitude=None)
    for plot in plots:
        _finish_plot(plot, runs, lines, spans, phases, theirs, shift, plot is altitude)
    return column([header] + plots, sizing_mode="stretch_width")


def _header_div(runs, title: Optional[str], settings: Optional[Dict[str, Any]]):
    """The header ``Div`` of a log report (:func:`_header_html`), under ``title`` when one is given."""
    from bokeh.models import Div

    from .health import sensor_health

    header = Div(text=_header_html(runs, dict(settings or {}), sensor_health(runs[0])), sizing_mode="stretch_width",
                 name=HEADER_NAME)
    if title:
        header.text = f"<h1 style='font:bold 18px sans-serif'>{html.escape(title)}</h1>" + header.text
    return header


def _checked_runs(runs, columns: int) -> list:
    """``runs`` of :func:`log_report` as a list of LogRun of one log; TypeError or ValueError naming the argument."""
    from .runner import LogRun

    runs = [runs] if isinstance(runs, LogRun) else list(runs) if isinstance(runs, (list, tuple)) else runs
    if not isinstance(runs, list) or not all(isinstance(r, LogRun) for r in runs):
        raise TypeError("runs must be a LogRun or a list of LogRun (fusion_altitude.runner.run_log)")
    if not runs:
        raise ValueError("runs is empty: give at least one LogRun")
    if any(r.time.size != runs[0].time.size or not np.array_equal(r.time, runs[0].time) for r in runs[1:]):
        raise ValueError("runs must all be of one log (the same time stamps)")
    if not isinstance(columns, (int, np.integer)) or columns < 1:
        raise ValueError(f"columns must be an integer >= 1, got {columns!r}")
    return runs


def _colour(k: int) -> str:
    """The line colour of the ``k``-th estimate."""
    return ESTIMATE_COLOURS[k % len(ESTIMATE_COLOURS)]


def _altitude_plot(runs, x: np.ndarray, x_label: str, columns: int, lines: list):
    """Altitude (m): the baro, the log's own estimate, GPS, rangefinder and each estimate; lines drawn → ``lines``."""
    first = runs[0]
    altitude = _figure("Altitude", "altitude above the start (m)" if first.datum else "altitude (m)", None, x_label)
    lines.append(_line(altitude, _series(x, first.baro_altitude, columns), "baro altitude", "#999999", dots=True))
    if first.reference_altitude is not None:
        lines.append(_line(altitude, _series(x, first.reference_altitude, columns),
                           first.reference_name or "log's own estimate", "black", 1.5))
    if first.gps_altitude is not None:
        lines.append(_line(altitude, _series(x, first.gps_altitude, columns), "GPS altitude", "#bcbd22", dots=True))
    if first.rangefinder is not None:
        lines.append(_line(altitude, _series(x, first.rangefinder, columns), "rangefinder (distance to ground)",
                           "#17becf", dots=True))
    for k, run in enumerate(runs):
        lines.append(_line(altitude, _series(x, run.estimate.altitude, columns), _estimate_label(run), _colour(k)))
    return altitude


def _velocity_plot(runs, x: np.ndarray, x_label: str, columns: int, lines: list, x_range):
    """Vertical velocity (m/s): the log's own and each estimate's; lines drawn → ``lines``."""
    first = runs[0]
    velocity = _figure("Vertical velocity", "vertical velocity (m/s)", x_range, x_label)
    if first.reference_velocity is not None:
        lines.append(_line(velocity, _series(x, first.reference_velocity, columns),
                           first.reference_name or "log's own estimate", "black", 1.5))
    for k, run in enumerate(runs):
        lines.append(_line(velocity, _series(x, run.estimate.vertical_velocity, columns), _estimate_label(run),
                           _colour(k)))
    return velocity


def _bias_plot(runs, x: np.ndarray, x_label: str, columns: int, lines: list, x_range):
    """Each estimate's accelerometer bias (m/s²), or the vertical acceleration input when none estimates one."""
    bias = _figure("Accelerometer bias", "accel bias (m/s²)", x_range, x_label)
    drawn_bias = False
    for k, run in enumerate(runs):
        values = getattr(run.estimate, "accel_bias", getattr(run.estimate, "accel_z_bias", None))
        if values is not None:
            drawn = _line(bias, _series(x, values, columns), f"{run.estimator} accel bias", _colour(k))
            lines.append(drawn)
            drawn_bias = drawn_bias or drawn is not None
    if not drawn_bias:  # no estimator with a bias: the input it would learn it from
        bias.title.text = "Vertical acceleration input (no estimator here estimates an accelerometer bias)"
        bias.yaxis.axis_label = "vertical acceleration (m/s²)"
        lines.append(_line(bias, _series(x, runs[0].vertical_acceleration, columns), "vertical acceleration",
                           "#ff7f0e", 0.8))
    return bias


def _residual_plot(runs, x: np.ndarray, x_label: str, columns: int, lines: list, x_range):
    """Each estimator's baro residual (m) and its gate (±, where it has one); lines drawn → ``lines``."""
    residual_plot = _figure("Baro residual (innovation)", "residual (m)", x_range, x_label)
    for k, run in enumerate(runs):
        residual, gate, _ = _residual(run)
        colour = _colour(k)
        lines.append(_line(residual_plot, _series(x, residual, columns), f"{run.estimator} residual", colour,
                           dots=True))
        if gate is not None and np.isfinite(gate).any():
            for sign, name in ((1.0, "+"), (-1.0, "−")):
                lines.append(_line(residual_plot, _series(x, sign * gate, columns), f"{run.estimator} gate ({name})",
                                   colour, 1.0, dash="dashed", legend=f"{run.estimator} gate (±)"))
    residual_plot.title.text += " (what each estimator's is: the header's estimator table)"
    return residual_plot


def _finish_plot(plot, runs, lines: list, spans, phases, theirs, shift: float, top: bool) -> None:
    """Shade the spans and phases, mark our and the flight computer's events (labelled on the ``top`` plot), add
    the hover tool over the data ``lines``, put the legend beside the plot and fit the y range to the data."""
    from bokeh.models import HoverTool

    _shade(plot, spans, phases)
    for run in runs:
        if run.events is not None:
            _mark_events(plot, run.events, shift, "#d62728", "solid", "our", top)
            break
    if theirs is not None:
        _mark_events(plot, theirs, shift, "black", "dashed", "flight computer", top)
    data_lines = [r for r in plot.renderers if r in lines]
    plot.add_tools(HoverTool(renderers=data_lines, tooltips=[("", "$name"), ("time (s)", "@x{0.000}"),
                                                             ("value", "@y{0.000}")]))
    legend = plot.legend[0]
    legend.click_policy = "hide"
    legend.label_text_font_size = "10px"
    legend.label_height = 12
    legend.glyph_height = 12
    legend.spacing = 0
    legend.padding = 4
    plot.add_layout(legend, "right")  # beside the plot: it never hides the data
    plot.y_range.renderers = data_lines or "auto"


# ----------------------------------------------------------------------------
# fleet report


#: Columns of the fleet table: (summary column, heading).
FLEET_COLUMNS = (("log_id", "log"), ("status", "status"), ("error", "error"), ("estimator", "estimator"),
                 ("duration_s", "duration (s)"), ("imu_rate_hz", "IMU rate (Hz)"), ("baro_rate_hz", "baro rate (Hz)"),
                 ("imu_gaps", "IMU gaps"), ("baro_gaps", "baro gaps"), ("estimator_gaps", "estimator gaps"),
                 ("rms_error_m", "RMS vs log (m)"), ("baro_rms_error_m", "baro RMS (m)"),
                 ("final_accel_bias_m_s2", "final bias (m/s²)"), ("stopped_streams", "stopped"))

_TEXT_COLUMNS = ("log_id", "status", "error", "estimator", "stopped_streams")
_COUNT_COLUMNS = ("imu_gaps", "baro_gaps", "estimator_gaps")


def _histogram(title: str, x_label: str, values: Sequence[float], bins: int = 20):
    """A histogram figure of the finite ``values``."""
    from bokeh.plotting import figure

    values = np.asarray([v for v in values if v is not None and math.isfinite(v)], float)
    plot = figure(title=title, height=220, width=360, x_axis_label=x_label, y_axis_label="logs",
                  tools="pan,wheel_zoom,reset,save", output_backend="canvas")
    plot.toolbar.logo = None
    if values.size:
        low, high = float(values.min()), float(values.max())
        if high == low:
            low, high = low - 0.5, high + 0.5
        counts, edges = np.histogram(values, bins=bins, range=(low, high))
        plot.quad(left=edges[:-1], right=edges[1:], bottom=0, top=counts, fill_color="#1f77b4", line_color="white")
    else:
        plot.title.text += " (no value)"
        plot.scatter([0], [0], alpha=0.0)  # an empty plot still renders its axes
    return plot


def fleet_report(summary, links: Optional[Dict[str, str]] = None, title: str = "Fleet"):
    """The fleet's report as a Bokeh layout: a sortable, filterable table and distributions.

    Parameters
    ----------
    summary : pyarrow.Table, list of dict or str
        The summary of ``fleet run`` (:func:`fusion_altitude.fleet.summary`),
        its rows, or its output directory.
    links : dict, optional
        log_id → URL (relative to the page) of that log's report; the log's
        cell links there.
    title : str, default "Fleet"

    Returns
    -------
    bokeh.models.Column
        Header, a text filter and a status filter, the table (click a heading
        to sort), histograms of the RMS against the logs' own estimates (m),
        the final accelerometer bias (m/s²) and the gap counts.
    """
    if isinstance(summary, str):
        from .fleet import summary as read_summary
        summary = read_summary(summary)
    rows = summary.to_pylist() if hasattr(summary, "to_pylist") else list(summary)
    if not all(isinstance(row, dict) for row in rows):
        raise TypeError("summary must be a pyarrow.Table, a list of dict rows or an output directory")
    _bokeh()
    from bokeh.layouts import column, row as layout_row
    from bokeh.models import Div

    source, view, table = _fleet_table(rows, dict(links or {}))
    text, status = _fleet_filters(source, view)
    ok = [row for row in rows if row.get("status") == "ok"]
    failed = len(rows) - len(ok)
    header = Div(text=_STYLE + f"<div class='fa-head'><h2>{html.escape(title)}</h2><b>logs</b>: {len(rows)} · "
                 f"<b>ok</b>: {len(ok)} · <b>failed</b>: {failed}. Click a heading to sort; a log's name opens its "
                 "report.</div>", sizing_mode="stretch_width")
    gaps = [float(row.get("imu_gaps") or 0) + float(row.get("baro_gaps") or 0) for row in ok]
    histograms = layout_row(
        _histogram("RMS against the log's own estimate", "RMS (m)", [row.get("rms_error_m") for row in ok]),
        _histogram("Final accelerometer bias", "bias (m/s²)", [row.get("final_accel_bias_m_s2") for row in ok]),
        _histogram("Gaps (IMU + baro)", "gaps per log", gaps))
    return column(header, layout_row(text, status), table, histograms, sizing_mode="stretch_width")


def _fleet_table(rows: List[Dict[str, Any]], links: Dict[str, str]):
    """The fleet's sortable table of :data:`FLEET_COLUMNS` (a log's name links to its report in ``links``):
    (its ColumnDataSource, its CDSView, the DataTable)."""
    from bokeh.models import (BooleanFilter, CDSView, ColumnDataSource, DataTable, HTMLTemplateFormatter,
                              NumberFormatter, TableColumn)

    data: Dict[str, list] = {}
    for name, _ in FLEET_COLUMNS:
        values = [row.get(name) for row in rows]
        if name in _TEXT_COLUMNS:
            data[name] = ["" if v is None else str(v) for v in values]
        else:
            data[name] = [math.nan if v is None else float(v) for v in values]
    data["report"] = [links.get(row.get("log_id"), "") for row in rows]
    data["path"] = ["" if row.get("path") is None else str(row.get("path")) for row in rows]
    source = ColumnDataSource(data)
    view = CDSView(filter=BooleanFilter([True] * len(rows)))
    link = HTMLTemplateFormatter(template="<% if (report) { %><a href=\"<%= report %>\" target=\"_blank\">"
                                          "<%= value %></a><% } else { %><%= value %><% } %>")
    table_columns = []
    for name, heading in FLEET_COLUMNS:
        options: Dict[str, Any] = {}
        if name == "log_id":
            options.update(formatter=link, width=260)
        elif name in _COUNT_COLUMNS:
            options.update(formatter=NumberFormatter(format="0"), width=70)
        elif name not in _TEXT_COLUMNS:
            options.update(formatter=NumberFormatter(format="0.000"), width=90)
        table_columns.append(TableColumn(field=name, title=heading, **options))
    table = DataTable(source=source, view=view, columns=table_columns, sortable=True, sizing_mode="stretch_width",
                      height=min(600, 60 + 26 * max(len(rows), 1)), index_position=None)
    return source, view, table


def _fleet_filters(source, view):
    """The text filter (log, path, error) and the status filter over the table's ``source`` and ``view``."""
    from bokeh.models import CustomJS, Select, TextInput

    text = TextInput(title="filter (log, path, error)", value="", width=320)
    status = Select(title="status", value="all", options=["all", "ok", "failed"], width=140)
    refilter = CustomJS(args={"source": source, "view": view, "text": text, "status": status}, code="""
        const needle = text.value.trim().toLowerCase();
        const d = source.data;
        const keep = [];
        for (let i = 0; i < d.log_id.length; i++) {
            const hay = (d.log_id[i] + ' ' + d.path[i] + ' ' + d.error[i]).toLowerCase();
            const shown = needle === '' || hay.includes(needle);
            keep.push(shown && (status.value === 'all' || d.status[i] === status.value));
        }
        view.filter.booleans = keep;
        source.change.emit();
    """)
    text.js_on_change("value", refilter)
    status.js_on_change("value", refilter)
    return text, status


# ----------------------------------------------------------------------------
# writing


def save(layout, path: str, title: str = "fusion-altitude report") -> int:
    """Write ``layout`` (:func:`log_report`, :func:`fleet_report`) as one self-contained HTML file.

    Every script and style is inline (``bokeh.resources.INLINE``): the page
    opens offline. A log report's header is written as plain HTML above the
    plots (the page then needs no widget scripts). Written through a
    temporary file renamed onto ``path``.

    Parameters
    ----------
    layout : bokeh.models.LayoutDOM
    path : str
        Output file (``.html``).
    title : str
        The page's title.

    Returns
    -------
    int
        Bytes written.
    """
    _bokeh()
    from bokeh.embed import file_html
    from bokeh.resources import INLINE

    from .runner import atomic_output

    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file name, got {type(path).__name__}")
    children = list(getattr(layout, "children", None) or [])
    header = ""
    if children and getattr(children[0], "name", None) == HEADER_NAME:  # a log report's header: plain HTML
        from bokeh.layouts import column

        header = f"<div style='padding:4px 8px'>{children[0].text}</div>\n"
        layout = column(children[1:], sizing_mode=layout.sizing_mode)
    if header:  # before the Bokeh root, in the body of Bokeh's own page template
        page = file_html(layout, INLINE, title=title, template_variables={"fa_header": header},
                         template="{% block contents %}{{ fa_header | safe }}{{ super() }}{% endblock %}")
    else:
        page = file_html(layout, INLINE, title=title)
    payload = page.encode("utf-8")
    with atomic_output(str(path)) as temporary:
        with open(temporary, "wb") as handle:
            handle.write(payload)
    return len(payload)
