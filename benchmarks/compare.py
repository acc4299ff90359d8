"""Compare the speed of the binding with a plain C loop, in one run.

    python benchmarks/compare.py [--samples N] [--repeat K]

Compiles a plain C loop over the header (csrc/fusion_altitude.h) with the
system C compiler and the flags setup.py uses, loads it with ctypes and times
it on the same arrays as ``AltitudeEstimator.update_batch``. Checks first that
both give the same bits. Every case is timed ``--repeat`` times with
``time.perf_counter_ns`` and the minimum is reported (the least disturbed run),
in ns per sample; the ratio column is that time over the C loop's.

Inputs: 100 Hz IMU with a baro sample every 4th step (NaN between;
``--baro-every``), seeded noise, scalar dt = 0.01 s unless the case says
otherwise. Exit status 1 if a target check fails.

The last table (benchmarks/targets.py) is issue 16's and issue 13's (INS): each target with its
measured wall and CPU time and PASS/FAIL (``--no-targets`` skips it).
"""

from __future__ import annotations

import argparse
import ctypes
import os
import platform
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _signals import make_signals  # noqa: E402
from _timing import best_ns  # noqa: E402

import fusion_altitude  # noqa: E402
from fusion_altitude import reference  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
HEADER_DIR = REPO / "csrc"
# The flags setup.py compiles the extension with.
CFLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math"]

C_SOURCE = r"""
#include <stddef.h>
#include "fusion_altitude.h"

/* What a C user writes: one estimator, one dt, four output arrays.
 * Returns the index of the first rejected sample, or -1. */
ptrdiff_t fa_loop(const float *accel, const float *baro, float dt, ptrdiff_t n,
                  float *altitude, float *velocity, float *bias, float *residual) {
    FusionAltitude state;
    FusionAltitudeInitialise(&state);
    for (ptrdiff_t i = 0; i < n; i++) {
        if (FusionAltitudeUpdate(&state, accel[i], baro[i], dt) != FusionAltitudeStatusOk) {
            return i;
        }
        altitude[i] = FusionAltitudeGetAltitude(&state);
        velocity[i] = FusionAltitudeGetVerticalVelocity(&state);
        bias[i] = FusionAltitudeGetAccelBias(&state);
        residual[i] = FusionAltitudeGetBaroResidual(&state);
    }
    return -1;
}

/* The same with one dt per sample. */
ptrdiff_t fa_loop_dt_array(const float *accel, const float *baro, const float *dt, ptrdiff_t n,
                           float *altitude, float *velocity, float *bias, float *residual) {
    FusionAltitude state;
    FusionAltitudeInitialise(&state);
    for (ptrdiff_t i = 0; i < n; i++) {
        if (FusionAltitudeUpdate(&state, accel[i], baro[i], dt[i]) != FusionAltitudeStatusOk) {
            return i;
        }
        altitude[i] = FusionAltitudeGetAltitude(&state);
        velocity[i] = FusionAltitudeGetVerticalVelocity(&state);
        bias[i] = FusionAltitudeGetAccelBias(&state);
        residual[i] = FusionAltitudeGetBaroResidual(&state);
    }
    return -1;
}
"""

F32P = np.ctypeslib.ndpointer(dtype=np.float32, ndim=1, flags="C_CONTIGUOUS")
F32P_W = np.ctypeslib.ndpointer(dtype=np.float32, ndim=1, flags=("C_CONTIGUOUS", "WRITEABLE"))


def compiler() -> str:
    for name in (os.environ.get("CC"), sysconfig.get_config_var("CC"), "cc", "gcc", "clang"):
        if name:
            exe = shutil.which(name.split()[0])
            if exe:
                return exe
    sys.exit("compare.py: no C compiler found (set CC)")


def build_c_loop(workdir: Path):
    """Compile the C loop into a shared library in workdir and load it."""
    source = workdir / "fa_loop.c"
    library = workdir / "fa_loop.so"
    source.write_text(C_SOURCE)
    cc = compiler()
    command = [cc, *CFLAGS, "-fPIC", "-shared", f"-I{HEADER_DIR}", str(source), "-o", str(library)]
    subprocess.run(command, check=True)
    lib = ctypes.CDLL(str(library))
    lib.fa_loop.restype = ctypes.c_ssize_t
    lib.fa_loop.argtypes = [F32P, F32P, ctypes.c_float, ctypes.c_ssize_t, F32P_W, F32P_W, F32P_W, F32P_W]
    lib.fa_loop_dt_array.restype = ctypes.c_ssize_t
    lib.fa_loop_dt_array.argtypes = [F32P, F32P, F32P, ctypes.c_ssize_t, F32P_W, F32P_W, F32P_W, F32P_W]
    version = subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    return lib, f"{version}, {' '.join(CFLAGS)}"



def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.dtype == b.dtype == np.float32 and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=1_000_000, help="samples for the C loop and batch cases (default 1e6)")
    parser.add_argument("--repeat", type=int, default=7, help="timed runs per case, minimum reported (default 7)")
    parser.add_argument("--reference-samples", type=int, default=20_000,
                        help="samples for the pure-Python reference (default 2e4)")
    parser.add_argument("--baro-every", type=int, default=4,
                        help="one baro sample every this many IMU samples, NaN between (default 4: 25 Hz baro, "
                             "100 Hz IMU; 1 puts the full correction on every sample's dependency chain)")
    parser.add_argument("--no-sweep", dest="sweep", action="store_false", help="skip the gain-sweep table")
    parser.add_argument("--no-kalman", dest="kalman", action="store_false", help="skip the Kalman filter table")
    parser.add_argument("--no-hobby", dest="hobby", action="store_false",
                        help="skip the complementary filter and alpha-beta fusion table")
    parser.add_argument("--sweep-samples", type=int, default=100_000, help="samples for the sweep cases (default 1e5)")
    parser.add_argument("--no-targets", dest="targets", action="store_false",
                        help="skip the table of issue 16's and issue 13's targets (benchmarks/targets.py)")
    args = parser.parse_args(argv)
    n = args.samples
    repeat = max(1, args.repeat)

    signals = make_signals(n, baro_every=args.baro_every)
    accel, baro, dt = signals.accel, signals.baro_altitude, signals.dt
    dt_array = signals.dt_array
    accel64, baro64 = accel.astype(np.float64), baro.astype(np.float64)
    out_c = [np.empty(n, dtype=np.float32) for _ in range(4)]
    out_py = fusion_altitude.AltitudeBatch(*(np.empty(n, dtype=np.float32) for _ in range(4)))

    with tempfile.TemporaryDirectory(prefix="fusion_altitude_bench_") as tmp:
        lib, compiler_info = build_c_loop(Path(tmp))

        # Honesty check: the floor computes exactly what update_batch computes.
        for c_run, py_dt in ((lambda: lib.fa_loop(accel, baro, dt, n, *out_c), dt),
                             (lambda: lib.fa_loop_dt_array(accel, baro, dt_array, n, *out_c), dt_array)):
            assert c_run() == -1, "C loop rejected a sample"
            batch = fusion_altitude.AltitudeEstimator().update_batch(accel, baro, py_dt)
            for field, c_out, py_out in zip(batch._fields, out_c, batch):
                assert same_bits(c_out, py_out), f"C loop and update_batch differ in {field}"
        del batch  # so that the "malloc recycles pages" case below really can
        # ... and update() per sample ends in the same state as the C loop.
        m = min(n, 2000)
        est = fusion_altitude.AltitudeEstimator()
        for i in range(m):
            est.update(float(accel[i]), float(baro[i]), dt)
        assert lib.fa_loop(accel, baro, dt, m, *[o[:m] for o in out_c]) == -1
        state = np.float32([est.altitude, est.vertical_velocity, est.accel_bias, est.baro_residual])
        assert same_bits(state, np.float32([o[m - 1] for o in out_c])), "update() differs from the C loop"

        def c_loop():
            lib.fa_loop(accel, baro, dt, n, *out_c)

        def c_loop_dt_array():
            lib.fa_loop_dt_array(accel, baro, dt_array, n, *out_c)

        def batch_out():
            fusion_altitude.AltitudeEstimator().update_batch(accel, baro, dt, out=out_py)

        def batch_out_dt_array():
            fusion_altitude.AltitudeEstimator().update_batch(accel, baro, dt_array, out=out_py)

        def batch_alloc_recycled():
            # The result is dropped at once, so malloc hands the same (already
            # mapped) pages to the next call.
            fusion_altitude.AltitudeEstimator().update_batch(accel, baro, dt)

        kept = []

        def batch_alloc_fresh():
            # Every result is kept, as a caller collecting results does: each call
            # writes 16 bytes/sample of never-touched pages (page faults).
            kept.append(fusion_altitude.AltitudeEstimator().update_batch(accel, baro, dt))

        def batch_f64():
            fusion_altitude.AltitudeEstimator().update_batch(accel64, baro64, dt, out=out_py)

        accel_list, baro_list = accel.tolist(), baro.tolist()

        def per_sample():
            update = fusion_altitude.AltitudeEstimator().update
            for a, z in zip(accel_list, baro_list):
                update(a, z, dt)

        def per_sample_numpy():
            update = fusion_altitude.AltitudeEstimator().update
            for a, z in zip(accel, baro):  # numpy float32 scalars
                update(a, z, dt)

        def empty_loop():
            for a, z in zip(accel_list, baro_list):
                pass

        n_ref = min(n, args.reference_samples)
        accel_ref, baro_ref = accel[:n_ref], baro[:n_ref]

        def reference_batch():
            reference.AltitudeEstimator().update_batch(accel_ref, baro_ref, dt)

        rows = []  # (case, ns/sample)
        t_c = best_ns(c_loop, repeat) / n
        rows.append(("C loop (floor, same header and flags)", t_c))
        t_out = best_ns(batch_out, repeat) / n
        rows.append(("update_batch, out=", t_out))
        rows.append(("update_batch, no out, malloc recycles pages", best_ns(batch_alloc_recycled, repeat) / n))
        rows.append(("update_batch, no out, fresh pages (results kept)", best_ns(batch_alloc_fresh, repeat) / n))
        kept.clear()
        rows.append(("update_batch, out=, float64 inputs", best_ns(batch_f64, repeat) / n))
        t_c_dt = best_ns(c_loop_dt_array, repeat) / n
        rows.append(("C loop, per-sample dt array", t_c_dt))
        rows.append(("update_batch, out=, per-sample dt array", best_ns(batch_out_dt_array, repeat) / n))
        t_update = best_ns(per_sample, repeat) / n
        rows.append(("update() per sample from Python (incl. for loop)", t_update))
        t_empty = best_ns(empty_loop, repeat) / n
        rows.append(("  of which: empty `for a, z in zip(...)` loop", t_empty))
        rows.append(("update() per sample, iterating the numpy arrays", best_ns(per_sample_numpy, repeat) / n))
        t_ref = best_ns(reference_batch, max(1, min(repeat, 3))) / n_ref
        rows.append((f"pure-Python reference update_batch ({n_ref} samples)", t_ref))

    print(f"fusion-altitude {fusion_altitude.__version__}, Python {platform.python_version()}, "
          f"numpy {np.__version__}, {platform.machine()}, {os.cpu_count()} CPUs")
    print(f"C loop: {compiler_info}")
    print(f"{n} samples (100 Hz IMU, baro every {args.baro_every} samples), minimum of {repeat} runs, time.perf_counter_ns")
    print()
    print("| case | ns/sample | × C loop |")
    print("|---|---:|---:|")
    for case, ns in rows:
        print(f"| {case} | {ns:.1f} | {ns / t_c:.2f} |")
    print()
    checks = [
        (f"update_batch with out= <= 1.3x C loop: {t_out / t_c:.2f}x", t_out <= 1.3 * t_c),
        (f"update_batch >= 40x faster than pure-Python reference: {t_ref / t_out:.0f}x", t_ref >= 40 * t_out),
        (f"update() from Python <= 150 ns/sample: {t_update:.0f} ns", t_update <= 150),
    ]
    for text, ok in checks:
        print(f"- [{'PASS' if ok else 'FAIL'}] {text}")
    if args.sweep:
        import sweep_bench
        print()
        print(f"Gain sweep ({args.sweep_samples} samples, baro every sample; K=1024 on an eighth of them):")
        print()
        sweep_rows, sweep_checks = sweep_bench.run(args.sweep_samples, max(1, min(repeat, 5)), baro_every=1)
        sweep_bench.print_table(sweep_rows, sweep_checks)
        checks += sweep_checks
    if args.kalman:
        import kalman_bench
        print()
        print(f"Multi-sensor Kalman filter ({args.samples} steps, baro, rangefinder and GPS on every step):")
        print()
        kalman_rows = kalman_bench.run(args.samples, max(1, min(repeat, 5)))
        kalman_bench.print_table(kalman_rows)
        checks += kalman_bench.checks(kalman_rows)
    if args.hobby:
        import hobby_bench
        print()
        print(f"Two-stage complementary filter and alpha-beta fusion ({args.samples} steps):")
        print()
        hobby_bench.print_table(hobby_bench.run(args.samples, max(1, min(repeat, 5))))
    if args.targets:
        import targets
        print()
        target_rows = targets.run(args.samples, repeat, args.sweep_samples)
        targets.print_table(target_rows)
        checks += targets.checks(target_rows)
    return 0 if all(ok for _, ok in checks) else 1


if __name__ == "__main__":
    sys.exit(main())
