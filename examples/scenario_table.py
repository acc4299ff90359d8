"""Agreement with the published figures: mean ± sd over seeds of the ``realistic`` scenario, and ``clean``.

Run::

    python examples/scenario_table.py [--seeds 20]

Prints a Markdown table: errors after 5 s (cm) and the final bias estimate (g).
"""

import argparse

import numpy as np

from fusion_altitude import GRAVITY
from fusion_altitude.scenarios import PUBLISHED, run_scenario


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20, help="number of seeds, 0 … N−1 (default 20)")
    args = parser.parse_args(argv)
    runs = [run_scenario("realistic", seed, attitude="ahrs") for seed in range(args.seeds)]
    stats = np.array([[r.statistics().mean, r.statistics().rms, r.statistics().max, r.final_bias / GRAVITY]
                      for r in runs])
    published = PUBLISHED["realistic"]
    print(f"| realistic, after 5 s | ours: mean ± sd over {args.seeds} seeds | published |")
    print("|---|---|---|")
    for label, column, scale, unit, key in [("mean error", 0, 100, "cm", "mean"), ("RMS error", 1, 100, "cm", "rms"),
                                            ("max abs error", 2, 100, "cm", "max")]:
        values = stats[:, column] * scale
        sign = "+" if key == "mean" else ""
        print(f"| {label} | {values.mean():{sign}.2f} ± {values.std(ddof=1):.2f} {unit} | "
              f"{published[key] * scale:{sign}.1f} {unit} |")
    bias = stats[:, 3]
    print(f"| final bias estimate | {bias.mean():.4f} ± {bias.std(ddof=1):.4f} g | ≈ 0.012 g (true 0.012 g) |")
    clean = run_scenario("clean", attitude="ahrs").statistics()
    print(f"| clean: max abs error after 5 s (deterministic) | {clean.max * 100:.2f} cm | "
          f"{PUBLISHED['clean']['max'] * 100:.1f} cm |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
