"""Regenerate the README's estimator comparison table and plot.

Run::

    python examples/compare_estimators.py [--seed 0] [--fit-seed 1] [--plot compare.png]

Same as ``fusion-altitude compare --markdown --plot compare.png --plot-scenario baro-glitches``:
every estimator on every comparison scenario, from seeds, so the numbers are reproducible
(timings are this machine's).
"""

import argparse

from fusion_altitude import comparison as compare


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--fit-seed", type=int, default=1)
    parser.add_argument("--plot", default=None, help="write the overlay plot of --plot-scenario here")
    parser.add_argument("--plot-scenario", default="baro-glitches")
    args = parser.parse_args(argv)
    rows = compare.compare(seed=args.seed, fit_seed=args.fit_seed)
    print(compare.format_markdown(rows))
    if args.plot:
        compare.plot_comparison(args.plot_scenario, args.plot, seed=args.seed, fit_seed=args.fit_seed)
        print(f"\nplot written to {args.plot}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
