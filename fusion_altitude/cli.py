"""Command line ``fusion-altitude``: a thin layer over the library.

Subcommands
-----------
demo
    Simulate a scenario (:mod:`fusion_altitude.scenarios`), print an error
    table and optionally plot it.
tune
    Gains, poles, settling times, stability checks and noise bandwidth for a
    bandwidth choice (:mod:`fusion_altitude.tuning`-style report built from
    :mod:`fusion_altitude.metrics`).
run
    Run the observer on a recorded log: CSV, PX4 ULog or ArduPilot DataFlash
    (:mod:`fusion_altitude.logs`).
compare
    Every estimator (observer, fitted observer, Kalman filter, two-stage
    complementary filter, α-β fusion, raw baro) on the simulator's scenarios:
    one table (:mod:`fusion_altitude.compare`).

Errors in user input are printed as one line on stderr with exit status 2,
never as a traceback.
"""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional, Sequence

from ._version import __version__

__all__ = ["main", "build_parser", "format_table"]


class CliError(Exception):
    """An input problem to report to the user in one line (exit status 2)."""


def format_table(header: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """Plain-text table: the first column left-aligned, the others right-aligned.

    Floats are printed with 4 significant decimals; other values with ``str``.
    """
    def cell(value: object) -> str:
        if isinstance(value, float):
            return f"{value:.4f}"
        return str(value)

    text = [[cell(v) for v in row] for row in [list(header)] + [list(r) for r in rows]]
    widths = [max(len(row[i]) for row in text) for i in range(len(header))]
    lines = []
    for k, row in enumerate(text):
        parts = [row[0].ljust(widths[0])] + [row[i].rjust(widths[i]) for i in range(1, len(row))]
        lines.append("  ".join(parts).rstrip())
        if k == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


# ----------------------------------------------------------------------------
# demo


def _cmd_demo(args: argparse.Namespace) -> int:
    from ._common import GRAVITY
    from .scenarios import PUBLISHED, describe, run_scenario

    result = run_scenario(args.scenario, seed=args.seed, attitude=args.attitude)
    fused = result.statistics()
    baro = result.baro_statistics()
    print(f"scenario {result.name}, seed {result.seed}: {describe(result.name)}")
    print(f"attitude: {'imufusion AHRS' if result.attitude == 'ahrs' else 'truth (imufusion not installed)'}; "
          f"errors after the first {result.transient:g} s")
    print()
    rows = [
        ["mean error (m)", baro.mean, fused.mean],
        ["RMS error (m)", baro.rms, fused.rms],
        ["max |error| (m)", baro.max, fused.max],
        ["95th pct |error| (m)", baro.p95, fused.p95],
    ]
    published = PUBLISHED.get(result.name, {})
    header = ["", "raw baro", "fused"]
    if published:
        header.append("published")
        for row, key in zip(rows, ("mean", "rms", "max", None)):
            row.append(published.get(key, "") if key else "")
    print(format_table(header, rows))
    print()
    print(f"final accel bias estimate: {result.final_bias:+.4f} m/s² ({result.final_bias / GRAVITY:+.4f} g); "
          f"true vertical bias {result.true_bias:+.4f} m/s² ({result.true_bias / GRAVITY:+.4f} g)")
    if args.plot:
        from .plotting import plot_scenario

        plot_scenario(result, args.plot)
        print(f"plot written to {args.plot}")
    return 0


# ----------------------------------------------------------------------------
# tune


def _cmd_tune(args: argparse.Namespace) -> int:
    import numpy as np

    from . import metrics
    from ._observer import AltitudeSettings

    dt = 1.0 / args.rate
    omega_b = args.omega / 5.0 if args.omega_b is None else args.omega_b
    try:
        settings = AltitudeSettings.from_bandwidth(args.omega, args.zeta, omega_b)
    except ValueError as error:
        raise CliError(str(error)) from None
    kh, kv, kb = settings.as_tuple()
    print(f"omega {args.omega:g} rad/s, zeta {args.zeta:g}, omega_b {omega_b:g} rad/s, rate {args.rate:g} Hz "
          f"(dt {dt:g} s)")
    print()
    print(format_table(["gain", "value", "unit"], [["position_gain Kh", kh, "1/s"], ["velocity_gain Kv", kv, "1/s²"],
                                                   ["bias_gain Kb", kb, "1/s³"]]))
    print()
    poles = np.roots([1.0, kh, kv, kb])
    zpoles = metrics.discrete_poles(kh, kv, kb, dt)
    rows = []
    for s_pole, z_pole in zip(sorted(poles, key=lambda p: (abs(p), p.imag)), sorted(zpoles, key=lambda z: -abs(z))):
        tau = 1.0 / abs(s_pole.real) if s_pole.real != 0 else float("inf")
        rows.append([f"{s_pole.real:+.4f}{s_pole.imag:+.4f}j", f"{tau:.3f}",
                     f"{z_pole.real:+.6f}{z_pole.imag:+.6f}j", f"{abs(z_pole):.6f}"])
    print(format_table(["continuous pole s (rad/s)", "time constant (s)", "discrete pole z", "|z|"], rows))
    print()
    step = metrics.step_settling_time(kh, kv, kb, dt)
    bias = metrics.bias_settling_time(kh, kv, kb, dt)
    print(f"2% settling, altitude after a baro step: {step:.2f} s")
    print(f"2% settling, bias estimate after an accel-bias step: {bias:.2f} s")
    print()
    fastest = float(np.max(np.abs(poles)))
    checks = [
        ("Routh-Hurwitz: Kh·Kv > Kb", kh * kv > kb, f"{kh * kv:.4g} > {kb:.4g}"),
    ]
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            settings.validate(dt)
        jury = (True, f"max |z| = {np.max(np.abs(zpoles)):.6f} < 1")
    except ValueError:
        jury = (False, f"max |z| = {np.max(np.abs(zpoles)):.6f} >= 1: diverges at this rate")
    checks.append(("Jury: discrete update stable at this dt", jury[0], jury[1]))
    checks.append(("discretisation: ω·dt < 0.1 (fastest pole)", fastest * dt < 0.1, f"{fastest * dt:.4g}"))
    checks.append(("loop separation: ω_b ≤ ω/5", omega_b <= args.omega / 5 * (1 + 1e-9),
                   f"{omega_b:g} vs {args.omega / 5:g}"))
    print(format_table(["check", "result", "value"], [[name, "ok" if ok else "FAIL", value]
                                                      for name, ok, value in checks]))
    print()
    gain = metrics.noise_gain(kh, kv, kb, dt)
    print(f"baro noise gain: {gain:.4f} (altitude noise sd per m of white baro noise per sample)")
    print(f"equivalent noise bandwidth of baro → altitude: {metrics.noise_bandwidth(kh, kv, kb, dt):.4f} Hz")
    return 0 if all(ok for _, ok, _ in checks[:2]) else 1


# ----------------------------------------------------------------------------
# run


class _ProgressBar:
    """A text progress bar on stderr, drawn only for long logs."""

    def __init__(self, minimum: int = 100_000, width: int = 40):
        self.minimum = minimum
        self.width = width

    def __call__(self, done: int, total: int) -> None:
        if total < self.minimum:
            return
        filled = int(self.width * done / total)
        sys.stderr.write(f"\r[{'#' * filled}{'.' * (self.width - filled)}] {100 * done / total:5.1f}% "
                         f"{done}/{total} samples")
        if done >= total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def _csv_options(args: argparse.Namespace, reference: bool = False) -> dict:
    """load_log keyword arguments for a CSV log (none for .ulg/.bin); CliError names missing flags."""
    suffix = args.file.lower().rsplit(".", 1)[-1] if "." in args.file else ""
    if suffix in ("ulg", "bin"):
        return {}
    missing = [flag for flag, value in (("--time", args.time), ("--accel", args.accel)) if value is None]
    if args.baro is None and args.pressure is None:
        missing.append("--baro or --pressure")
    if missing:
        raise CliError(f"a CSV log needs {', '.join(missing)}")
    if args.baro is not None and args.pressure is not None:
        raise CliError("give --baro or --pressure, not both")
    options = dict(time_column=args.time, accel_column=args.accel, baro_column=args.baro,
                   pressure_column=args.pressure, accel_units=args.accel_units, sea_level_pa=args.sea_level_pa)
    if reference:
        options["reference_column"] = args.reference
    return options


def _cmd_run(args: argparse.Namespace) -> int:
    import numpy as np

    from . import logs, runner
    from ._observer import AltitudeSettings

    try:
        data = logs.load_log(args.file, **_csv_options(args))
        settings = AltitudeSettings.preset(args.preset)
        run = runner.run_log(data, settings, progress=_ProgressBar())
    except (logs.LogError, ValueError) as error:
        raise CliError(str(error)) from None
    n_baro = int(np.sum(np.isfinite(data.baro_altitude)))
    duration = float(data.time[-1] - data.time[0])
    print(f"{data.source}: {data.time.size} samples over {duration:.2f} s "
          f"({data.time.size / max(duration, 1e-9):.1f} Hz), {n_baro} baro samples; preset {args.preset}")
    for note in data.notes:
        print(f"  {note}")
    if data.clipped is not None and data.clipped.any():
        print(f"  accelerometer clipped on {int(data.clipped.sum())} samples (baro-trusting gains, bias frozen there)")
    print()
    h = run.estimate.altitude
    baro = data.baro_altitude
    rows = [["final altitude (m)", float(h[-1]), float(baro[np.isfinite(baro)][-1])],
            ["max altitude (m)", float(np.max(h)), float(np.nanmax(baro))],
            ["min altitude (m)", float(np.min(h)), float(np.nanmin(baro))]]
    header = ["", "fused", "baro"]
    if data.reference_altitude is not None:
        header.append("reference")
        ref = data.reference_altitude
        rows[0].append(float(ref[np.isfinite(ref)][-1]))
        rows[1].append(float(np.nanmax(ref)))
        rows[2].append(float(np.nanmin(ref)))
    print(format_table(header, rows))
    print(f"final accel bias estimate: {float(run.estimate.accel_bias[-1]):+.4f} m/s²")
    if data.reference_altitude is not None:
        fused = run.comparison()
        raw = run.baro_comparison()
        print()
        print(f"against {data.reference_name} (shifted to the baro datum):")
        print(format_table(["", "fused − ref", "baro − ref"],
                           [["mean (m)", fused.mean, raw.mean], ["RMS (m)", fused.rms, raw.rms],
                            ["max |·| (m)", fused.max, raw.max]]))
    if args.output:
        runner.write_csv(run, args.output)
        print(f"estimates written to {args.output}")
    if args.plot:
        from .plotting import plot_log_run

        plot_log_run(run, args.plot)
        print(f"plot written to {args.plot}")
    return 0


def _fit_inputs(args: argparse.Namespace):
    """(source, time s, accel m/s², baro m, reference m, default RMS row or None, skip s) for ``fit``."""
    import numpy as np

    from . import logs

    if args.scenario is not None:
        from .scenarios import run_scenario
        if args.file is not None:
            raise CliError("give a log FILE or --scenario, not both")
        result = run_scenario(args.scenario, args.seed)
        skip = result.transient if args.skip is None else args.skip
        mask = result.time >= result.time[0] + skip
        preset_rms = float(np.sqrt(np.mean(result.altitude_error[mask] ** 2)))
        return (f"scenario {args.scenario}, seed {args.seed} (reference: simulator truth)", result.time,
                result.vertical_acceleration, result.baro_altitude, result.trajectory.altitude,
                ("scenario preset, as `demo` runs it", preset_rms), skip)
    if args.file is None:
        raise CliError("give a log FILE (with a reference) or --scenario NAME")
    data = logs.load_log(args.file, **_csv_options(args, reference=True))
    if data.reference_altitude is None:
        raise CliError(f"{data.source} has no reference altitude: give --reference COLUMN (CSV), or a .ulg/.bin "
                       "with the autopilot's own height estimate")
    skip = 5.0 if args.skip is None else args.skip
    return (f"{data.source} (reference: {data.reference_name})", data.time, data.vertical_acceleration,
            data.baro_altitude, data.reference_altitude, None, skip)


def _cmd_fit(args: argparse.Namespace) -> int:
    import numpy as np

    from . import logs, runner, tuning

    try:
        source, time, accel, baro, reference, preset_row, skip = _fit_inputs(args)
        mask = np.asarray(time) >= time[0] + skip
        if not mask.any():
            raise CliError(f"--skip {skip} s leaves no sample of a {time[-1] - time[0]:.1f} s log")
        result = tuning.fit(accel, baro, runner.sample_periods(time), reference, mask=mask,
                            omega_range=(args.omega_min, args.omega_max))
    except (logs.LogError, ValueError) as error:
        raise CliError(str(error)) from None
    counted = mask & np.isfinite(baro) & np.isfinite(reference)
    baro_rms = float(np.sqrt(np.mean((baro[counted] - reference[counted]) ** 2))) if counted.any() else float("nan")
    gains = result.settings
    print(f"{source}: {len(time)} samples, metrics after {skip:g} s")
    print(f"best of {len(result.landscape)} stable candidates: omega {result.omega:.4g} rad/s, zeta {result.zeta:.3g}, "
          f"omega_b {result.omega_b:.4g} rad/s")
    print(f"  position_gain {gains.position_gain:.6g} 1/s, velocity_gain {gains.velocity_gain:.6g} 1/s², "
          f"bias_gain {gains.bias_gain:.6g} 1/s³")
    print()
    rows = [["fitted gains", result.rms_error, ""],
            ["VTOL default gains", result.default_rms_error,
             f"{100 * (1 - result.rms_error / result.default_rms_error):+.0f}%"]]
    if preset_row is not None:
        rows.append([preset_row[0], preset_row[1], f"{100 * (1 - result.rms_error / preset_row[1]):+.0f}%"])
    rows.append(["raw baro", baro_rms, ""])
    print(format_table(["altitude − reference", "RMS (m)", "fit improves by"], rows))
    print()
    print("runners-up:")
    print(format_table(["omega (rad/s)", "zeta", "omega_b (rad/s)", "RMS (m)"],
                       [[row["omega"], row["zeta"], row["omega_b"], row["rms_error"]] for row in result.landscape[1:6]]))
    if args.plot:
        from .plotting import plot_fit_landscape

        plot_fit_landscape(result, args.plot, title=source)
        print(f"plot written to {args.plot}")
    return 0


# ----------------------------------------------------------------------------
# compare


def _cmd_compare(args: argparse.Namespace) -> int:
    from . import compare

    scenarios = args.scenario or list(compare.SCENARIOS)
    rows = compare.compare(scenarios, seed=args.seed, fit_seed=args.fit_seed, attitude=args.attitude,
                           repeat=args.repeat)
    print(f"seed {args.seed} (observer (fit): gains fitted on seed {args.fit_seed}), attitude {args.attitude}; "
          "errors after each scenario's transient; recovery: s after the fault ends until |error| <= 0.5 m")
    print()
    if args.markdown:
        print(compare.format_markdown(rows))
    else:
        print(format_table(compare.HEADER, compare.table_cells(rows)))
    if args.plot:
        compare.plot_comparison(args.plot_scenario or scenarios[0], args.plot, seed=args.seed,
                                fit_seed=args.fit_seed, attitude=args.attitude)
        print(f"plot written to {args.plot}")
    return 0


# ----------------------------------------------------------------------------
# parser


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``fusion-altitude``."""
    from .scenarios import scenario_names

    parser = argparse.ArgumentParser(
        prog="fusion-altitude",
        description="Altitude and vertical-velocity estimation: barometer + accelerometer fusion.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    demo = commands.add_parser("demo", help="simulate a flight and print the error table",
                               description="Simulate a scenario, run the observer, print raw-baro vs fused errors.")
    demo.add_argument("--scenario", default="realistic", choices=scenario_names(),
                      help="scenario to simulate (default: realistic)")
    demo.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    demo.add_argument("--attitude", default="auto", choices=("auto", "ahrs", "truth"),
                      help="attitude source: the imufusion AHRS, the truth, or auto (AHRS if installed)")
    demo.add_argument("--plot", metavar="OUT.png", help="write a plot (needs the [plot] extra)")
    demo.set_defaults(handler=_cmd_demo)

    tune = commands.add_parser("tune", help="gains, poles, settling and noise for a bandwidth choice",
                               description="Gains from ω, ζ, ω_b and what they do at a sample rate.")
    tune.add_argument("--omega", type=float, default=1.5, help="position-loop bandwidth ω, rad/s (default 1.5)")
    tune.add_argument("--zeta", type=float, default=0.7, help="damping ratio ζ (default 0.7)")
    tune.add_argument("--omega-b", type=float, default=None, help="bias-loop bandwidth ω_b, rad/s (default ω/5)")
    tune.add_argument("--rate", type=float, default=100.0, help="sample rate, Hz (default 100)")
    tune.set_defaults(handler=_cmd_tune)

    run = commands.add_parser("run", help="run the observer on a recorded log (CSV, .ulg, .bin)",
                              description="Run the observer on a log. CSV needs --time, --accel and --baro or "
                                          "--pressure; PX4 .ulg and ArduPilot .bin are read by message name.")
    run.add_argument("file", help="CSV, PX4 ULog (.ulg) or ArduPilot DataFlash (.bin) log")
    _add_csv_arguments(run)
    run.add_argument("--preset", default="vtol", choices=("balloon", "fixed_wing", "vtol", "racing"),
                     help="observer gains (default vtol)")
    run.add_argument("-o", "--output", metavar="OUT.csv", help="write the estimates per sample")
    run.add_argument("--plot", metavar="OUT.png", help="write a plot (needs the [plot] extra)")
    run.set_defaults(handler=_cmd_run)

    fit = commands.add_parser("fit", help="fit the gains to a reference altitude (a log or a scenario)",
                              description="Search omega, zeta, omega_b for the gains whose altitude best matches a "
                                          "reference: a log's reference column or autopilot estimate, or a "
                                          "simulated scenario's truth.")
    fit.add_argument("file", nargs="?", help="CSV (with --reference), PX4 ULog (.ulg) or ArduPilot DataFlash (.bin)")
    _add_csv_arguments(fit)
    fit.add_argument("--reference", help="CSV: reference altitude column, m (empty = unknown that row)")
    fit.add_argument("--scenario", choices=scenario_names(), help="fit on a simulated scenario instead of a log")
    fit.add_argument("--seed", type=int, default=0, help="scenario seed (default: 0)")
    fit.add_argument("--skip", type=float, default=None,
                     help="seconds at the start left out of the metric (default: the scenario's transient, 5 s for logs)")
    fit.add_argument("--omega-min", type=float, default=0.05, help="lowest omega searched, rad/s (default 0.05)")
    fit.add_argument("--omega-max", type=float, default=20.0, help="highest omega searched, rad/s (default 20)")
    fit.add_argument("--plot", metavar="OUT.png", help="contour plot of RMS over (omega, omega_b) ([plot] extra)")
    fit.set_defaults(handler=_cmd_fit)

    from .compare import SCENARIOS
    comparison = commands.add_parser(
        "compare", help="every estimator on the simulator's scenarios: one table",
        description="Observer (preset and fitted gains), Kalman filter, two-stage complementary filter, "
                    "quality-weighted alpha-beta fusion and raw baro on the same simulated data: altitude RMS and "
                    "max error, velocity RMS, recovery time after a sensor fault, C batch ns/sample.")
    comparison.add_argument("--scenario", action="append", choices=scenario_names(), metavar="NAME",
                            help=f"scenario (repeatable; default: {', '.join(SCENARIOS)})")
    comparison.add_argument("--seed", type=int, default=0, help="simulation seed (default: 0)")
    comparison.add_argument("--fit-seed", type=int, default=1,
                            help="seed the fitted observer's gains are fitted on (default: 1, held out)")
    comparison.add_argument("--attitude", default="truth", choices=("truth", "ahrs"),
                            help="attitude source (default truth: the same numbers with or without imufusion)")
    comparison.add_argument("--repeat", type=int, default=5, help="timing repeats, best taken (default 5)")
    comparison.add_argument("--markdown", action="store_true", help="print a Markdown table")
    comparison.add_argument("--plot", metavar="OUT.png", help="overlay the estimators for one scenario ([plot] extra)")
    comparison.add_argument("--plot-scenario", choices=scenario_names(), metavar="NAME",
                            help="scenario of the plot (default: the first one compared)")
    comparison.set_defaults(handler=_cmd_compare)
    return parser


def _add_csv_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--time", help="CSV: time column, s")
    parser.add_argument("--accel", help="CSV: vertical acceleration column (earth frame, +up, gravity removed)")
    parser.add_argument("--accel-units", default="m/s^2", choices=("m/s^2", "g"), help="CSV: units of --accel")
    parser.add_argument("--baro", help="CSV: baro altitude column, m (empty = no sample that row)")
    parser.add_argument("--pressure", help="CSV: static pressure column, Pa (instead of --baro)")
    parser.add_argument("--sea-level-pa", type=float, default=101325.0,
                        help="CSV: reference pressure for --pressure, Pa (default 101325)")


def main(argv: Optional[List[str]] = None) -> int:
    """Entry point of ``fusion-altitude`` and ``python -m fusion_altitude``; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "handler", None) is None:
        parser.print_help()
        return 2
    try:
        return int(args.handler(args) or 0)
    except CliError as error:
        print(f"fusion-altitude {args.command}: error: {error}", file=sys.stderr)
        return 2
    except ImportError as error:
        print(f"fusion-altitude {args.command}: error: {error}", file=sys.stderr)
        return 2
