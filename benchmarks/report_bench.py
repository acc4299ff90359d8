"""Size and load time of the HTML reports in headless Chromium (docs/report.md).

For every shared log (``fusion-altitude report LOG``, the estimator ``run``
picks), one ``--all-estimators`` report, a generated 1-million-row CSV
log (the simulator, :func:`report_browser.write_long_csv`) and a fleet page
(``fleet report`` of a ``fleet run`` of three shared logs, their own
reports included in its time): the page's size
and the time from navigation start to every plot drawn (the page's own
``performance.now()``): the first load in a fresh browser (cold: Bokeh's
script compiled for the first time), then the best and median of
``--repeat`` more loads (warm). Prints a Markdown table.

    python benchmarks/report_bench.py [--repeat 5] [--rows 1000000] [--screenshot docs/images/report.png]

Needs Debian's chromium and chromium-driver and the ``[test]`` extra;
FUSION_ALTITUDE_SHARED_DATA as the tests use it (default ../shared/data).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import report_browser  # noqa: E402

from fusion_altitude import fleet  # noqa: E402
from fusion_altitude.cli import main  # noqa: E402


#: The logs of the measured fleet page (as tests/test_report_browser.py's fleet).
FLEET_LOGS = ("px4_sample_log_small.ulg", "px4_octorotor_2hz_baro.ulg", "rrc3_juno3.csv")


def _report(arguments, page: Path) -> float:
    """Write a report with the CLI; s it took (read, estimate, write)."""
    start = time.perf_counter()
    status = main(["report", *arguments, "-o", str(page)])
    if status != 0:
        raise SystemExit(f"report {' '.join(arguments)} failed with status {status}")
    return time.perf_counter() - start


def main_bench() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="loads per page (default 5)")
    parser.add_argument("--rows", type=int, default=1_000_000, help="rows of the generated CSV log")
    parser.add_argument("--screenshot", help="save a screenshot of the Hedy report here (PNG)")
    args = parser.parse_args()
    shared = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        cases = [(Path(p).name, [p]) for p in fleet.expand_paths(str(shared))]
        cases.append(("px4_sample_log_small.ulg --all-estimators",
                      [str(shared / "px4_sample_log_small.ulg"), "--all-estimators"]))
        log = report_browser.write_long_csv(folder / "long.csv", rows=args.rows)
        cases.append((f"generated CSV, {args.rows} rows", [str(log), *report_browser.LONG_CSV_FLAGS]))
        pages = []
        for k, (name, arguments) in enumerate(cases):
            page = folder / f"page{k}.html"
            pages.append((name, page, _report(arguments, page)))
        fleet_logs = [str(shared / name) for name in FLEET_LOGS]  # a fleet page and its links
        fleet.run_many(fleet_logs, output_dir=str(folder / "fleet"), workers=1)
        start = time.perf_counter()
        if main(["fleet", "report", str(folder / "fleet")]) != 0:
            raise SystemExit("fleet report failed")
        cases.append((f"fleet report of {', '.join(FLEET_LOGS)}", None))
        pages.append((cases[-1][0], folder / "fleet" / "fleet.html", time.perf_counter() - start))
        print("| log | rows | page (MB) | report written in (s) | cold load (s) | warm load best (s) | "
              "warm load median (s) |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for (name, page, written), (_, arguments) in zip(pages, cases):
            driver = report_browser.open_chromium()  # a fresh browser per page: the first load is a cold one
            try:
                cold = report_browser.load(driver, page)
                loads = [report_browser.load(driver, page) for _ in range(args.repeat)]
                errors = report_browser.console_errors(driver)
                if errors:
                    raise SystemExit(f"{name}: console errors {errors}")
                if args.screenshot and name == "hedy_baro.csv":
                    driver.save_screenshot(args.screenshot)
            finally:
                driver.quit()
            print(f"| {name} | {_rows(arguments)} | {page.stat().st_size / 1e6:.2f} | {written:.2f} | {cold:.2f} | "
                  f"{min(loads):.2f} | {statistics.median(loads):.2f} |", flush=True)


def _rows(arguments) -> str:
    """Rows of the log on the estimator's grid ("3 logs" for the fleet page)."""
    if arguments is None:
        return f"{len(FLEET_LOGS)} logs"
    from fusion_altitude import logs

    import warnings

    options = {}
    flags = list(arguments[1:])
    if "--time" in flags:
        options = {"time_column": "time", "accel_column": "vertical_acceleration", "baro_column": "baro_altitude"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return str(logs.load_log(arguments[0], **options).time.size)


if __name__ == "__main__":
    main_bench()
