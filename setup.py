"""Builds the Cython extension around the header-only C core in csrc/."""

import sys

from Cython.Build import cythonize
from setuptools import Extension, setup

# IEEE float32 without FMA contraction, so that the extension gives the same
# bits as the reference and as the header on a microcontroller.
if sys.platform == "win32":
    compile_args = ["/fp:precise"]
else:
    compile_args = ["-O2", "-ffp-contract=off", "-fno-fast-math"]

extensions = [
    Extension(
        "fusion_altitude._observer",
        ["fusion_altitude/_observer.pyx"],
        include_dirs=["csrc"],
        depends=["csrc/fusion_altitude.h", "fusion_altitude/cfusion_altitude.pxd"],
        extra_compile_args=compile_args,
    ),
]

setup(ext_modules=cythonize(extensions, compiler_directives={"language_level": "3"}))
