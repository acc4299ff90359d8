"""Builds the Cython extension around the header-only C core in csrc/."""

import platform
import sys
from pathlib import Path

from Cython.Build import cythonize
from setuptools import Extension, setup

# IEEE float32 without FMA contraction, so that the extension gives the same
# bits as the reference and as the header on a microcontroller.
if sys.platform == "win32":
    compile_args = ["/fp:precise"]
else:
    # -fno-math-errno: sqrtf (the INS) inlines as one instruction, without a libm call for errno (same result)
    compile_args = ["-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-math-errno"]
    if sys.platform.startswith("linux") and platform.machine() in ("x86_64", "AMD64"):
        # the gain sweep also gets an AVX2 clone, chosen at load time (same bits: no FMA)
        compile_args.append("-DFUSION_ALTITUDE_SWEEP_MULTIVERSION")

# Per module: the INS step is a chain of short fixed-count loops over its 8x8 covariance; unrolled, its
# batch runs 3 % faster on x86-64 (benchmarks/c_steps.c ins: 154 -> 150 ns/step). Unrolling does not
# reorder floating-point operations: the same bits.
EXTRA_ARGS = {} if sys.platform == "win32" else {"_ins": ["-funroll-loops"]}

# One extension per binding module fusion_altitude/_core/_NAME.pyx; each wraps
# headers from csrc/ and holds no copy of an algorithm. The _NAME_fields.pxi
# they include are generated from the headers: python tools/generate_bindings.py.
extensions = [
    Extension(
        f"fusion_altitude._core.{path.stem}",
        [str(path)],
        include_dirs=["csrc"],
        depends=[str(p) for p in sorted(Path("csrc").glob("*.h")) + sorted(Path("fusion_altitude/_core").glob("*.px[di]"))],
        extra_compile_args=compile_args + EXTRA_ARGS.get(path.stem, []),
    )
    for path in sorted(Path("fusion_altitude/_core").glob("_*.pyx"))
]
# The shared helpers are plain Python (the reference runs on them without any build); compiled as
# well, they cost less per call (the update argument shim, conversions). The .py stays the source.
extensions.append(Extension("fusion_altitude._core._common", ["fusion_altitude/_core/_common.py"], extra_compile_args=compile_args))

# The fast log decoder (not part of the MCU core): fusion_altitude/logs/_decode.pyx over the C scanners beside it.
extensions.append(Extension("fusion_altitude.logs._decode", ["fusion_altitude/logs/_decode.pyx"],
                            include_dirs=["fusion_altitude/logs"],
                            depends=["fusion_altitude/logs/_scan_common.h", "fusion_altitude/logs/_dataflash_scan.h",
                                     "fusion_altitude/logs/_ulog_scan.h"],
                            extra_compile_args=["-O2"] if sys.platform != "win32" else []))
# The C scan of small numeric CSV bodies (fusion_altitude/logs/_csv_scan.h; issue 25, item 3).
extensions.append(Extension("fusion_altitude.logs._text_decode", ["fusion_altitude/logs/_text_decode.pyx"],
                            include_dirs=["fusion_altitude/logs"], depends=["fusion_altitude/logs/_csv_scan.h"],
                            extra_compile_args=["-O2", "-ffp-contract=off"] if sys.platform != "win32" else []))

setup(ext_modules=cythonize(extensions, compiler_directives={"language_level": "3"}))
