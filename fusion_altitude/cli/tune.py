"""``fusion-altitude tune``: gains, poles, settling times, stability checks and noise bandwidth for a bandwidth
choice (:func:`fusion_altitude.tuning.report`)."""

from __future__ import annotations

import argparse

from .common import MAX_OMEGA, MAX_TUNE_RATE, MAX_ZETA, MIN_TUNE_RATE, CliError, format_table, number

__all__ = ["add_parser"]


def add_parser(commands) -> None:
    """The ``tune`` subcommand: gains, poles, settling and noise of ω (rad/s), ζ, ω_b (rad/s) at a rate (Hz)."""
    tune = commands.add_parser("tune", help="gains, poles, settling and noise for a bandwidth choice",
                               description="Gains from ω, ζ, ω_b and what they do at a sample rate.")
    tune.add_argument("--omega", type=float, default=1.5,
                      help=f"position-loop bandwidth ω, rad/s, > 0 and <= {MAX_OMEGA:g} (default 1.5)")
    tune.add_argument("--zeta", type=float, default=0.7,
                      help=f"damping ratio ζ, > 0 and <= {MAX_ZETA:g} (default 0.7)")
    tune.add_argument("--omega-b", type=float, default=None,
                      help=f"bias-loop bandwidth ω_b, rad/s, >= 0 and <= {MAX_OMEGA:g} (default ω/5; 0 = no bias "
                           "estimation)")
    tune.add_argument("--rate", type=float, default=100.0,
                      help=f"sample rate, Hz, >= {MIN_TUNE_RATE:g} and <= {MAX_TUNE_RATE:g} (default 100)")
    tune.set_defaults(handler=_cmd_tune)


def _cmd_tune(args: argparse.Namespace) -> int:
    from .._core._observer import AltitudeSettings
    from ..tuning import report

    number("--omega", args.omega, 0.0, maximum=MAX_OMEGA)
    number("--zeta", args.zeta, 0.0, maximum=MAX_ZETA)
    number("--omega-b", args.omega_b, 0.0, strict=False, maximum=MAX_OMEGA)
    number("--rate", args.rate, 0.0, maximum=MAX_TUNE_RATE)
    number("--rate", args.rate, MIN_TUNE_RATE, strict=False)
    dt = 1.0 / args.rate
    omega_b = args.omega / 5.0 if args.omega_b is None else args.omega_b
    try:
        settings = AltitudeSettings.from_bandwidth(args.omega, args.zeta, omega_b)
        result = report(settings, dt, omega=args.omega, omega_b=omega_b)
    except ValueError as error:
        raise CliError(f"--omega {args.omega:g}, --zeta {args.zeta:g}, --omega-b {omega_b:g}: {error}") from None
    kh, kv, kb = settings.as_tuple()
    print(f"omega {args.omega:g} rad/s, zeta {args.zeta:g}, omega_b {omega_b:g} rad/s, rate {args.rate:g} Hz "
          f"(dt {dt:g} s)")
    print()
    print(format_table(["gain", "value", "unit"], [["position_gain Kh", kh, "1/s"], ["velocity_gain Kv", kv, "1/s²"],
                                                   ["bias_gain Kb", kb, "1/s³"]]))
    print()
    rows = [[f"{s.real:+.4f}{s.imag:+.4f}j", f"{tau:.3f}", f"{z.real:+.6f}{z.imag:+.6f}j", f"{abs(z):.6f}"]
            for s, tau, z in result.poles]
    print(format_table(["continuous pole s (rad/s)", "time constant (s)", "its discrete pole z", "|z|"], rows))
    print()
    print(f"2% settling, altitude after a baro step: {result.step_settling:.2f} s")
    print(f"2% settling, bias estimate after an accel-bias step: {result.bias_settling:.2f} s")
    print()
    print(format_table(["check", "result", "value"], [[name, "ok" if ok else "FAIL", value]
                                                      for name, ok, value in result.checks]))
    print()
    if result.stable:
        print(f"baro noise gain: {result.noise_gain:.4f} (altitude noise sd per m of white baro noise per sample)")
        print(f"equivalent noise bandwidth of baro → altitude: {result.noise_bandwidth:.4f} Hz")
    else:  # the discrete filter diverges: its noise gain and bandwidth are infinite, not a number to print
        print("baro noise gain: unstable (the discrete filter diverges at this rate: no finite noise gain)")
        print("equivalent noise bandwidth of baro → altitude: unstable")
    return 0 if result.stable else 1
