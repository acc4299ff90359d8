"""Timing helper shared by the benchmark scripts."""

import time


def best_ns(run, repeat: int) -> int:
    """Minimum wall time of run() over repeat calls, ns (after one warm-up call).

    The minimum is the least disturbed run: on a shared, noisy machine it is
    the most repeatable statistic of a short benchmark.
    """
    run()
    best = None
    for _ in range(repeat):
        start = time.perf_counter_ns()
        run()
        elapsed = time.perf_counter_ns() - start
        best = elapsed if best is None else min(best, elapsed)
    return best
