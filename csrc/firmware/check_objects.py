"""Checks the cross-compiled objects for double precision and libm.

    python3 check_objects.py BUILD/cross

Scans every <target>/<std>-<opt>/*.lst (objdump -d) and *.undefined (nm -u)
written by the Makefile. Fails on a double-precision instruction (ARM: any
.f64 operation such as vcvt.f64.f32; RISC-V: any .d operation, fld, fsd), on
a soft-double helper (__aeabi_d*, __aeabi_f2d, __adddf3, __muldf3, any *df*
libgcc routine) and on a libm symbol (sqrt, pow, ...), except sqrtf in the
INS objects (ALLOWED: fusion_altitude_ins.h may call sqrtf, libm's one
allowed function; nothing else may). Prints one line per object checked and
exits 1 on any finding.
"""

import re
import sys
from pathlib import Path

DOUBLE_INSTRUCTION = re.compile(
    r"^\s*[0-9a-f]+:\s+(?:[0-9a-f]{2,8} ?)+\s+("
    r"v\w*\.f64\S*"                   # ARM VFP double: vcvt.f64.f32, vadd.f64, vmov.f64 ...
    r"|f\w*\.d(?:\.\w+)?|fcvt\.\w+\.d"  # RISC-V D extension: fadd.d, fcvt.d.s, fcvt.s.d ...
    r"|fld|fsd"
    r")\s", re.MULTILINE)
FORBIDDEN_SYMBOL = re.compile(
    r"^(__aeabi_d\w*|__aeabi_[fil]2d|__aeabi_d2\w+|__\w*df\d?|"
    r"sqrtf?|powf?|expf?|logf?|sinf?|cosf?|tanf?|atan2?f?|fabsf?|floorf?|ceilf?|fmodf?|roundf?|truncf?|hypotf?)$")

#: Symbols an object may need although FORBIDDEN_SYMBOL matches them, by object stem.
ALLOWED = {"sized_ins": {"sqrtf"}}


def check(cross: Path) -> int:
    listings = sorted(cross.glob("*/*/*.lst"))
    if not listings:
        print(f"no listings under {cross}", file=sys.stderr)
        return 1
    failures = 0
    for listing in listings:
        variant = listing.relative_to(cross).with_suffix("")
        findings = [m.group(1) for m in DOUBLE_INSTRUCTION.finditer(listing.read_text())]
        undefined = listing.with_suffix(".undefined").read_text().split()
        symbols = [s for s in undefined if s != "U"]
        allowed = ALLOWED.get(listing.stem, set())
        findings += [s for s in symbols if FORBIDDEN_SYMBOL.match(s) and s not in allowed]
        status = "FAIL " + ", ".join(sorted(set(findings))) if findings else "ok"
        print(f"{variant}: {status} (needs: {', '.join(symbols) or 'nothing'})")
        failures += bool(findings)
    print(f"{len(listings)} objects checked, {failures} with double or libm")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(check(Path(sys.argv[1])))
