"""Cortex-M4F size, stack and cycle estimate of one FusionAltitudeInsUpdate on each path.

    python csrc/firmware/ins_cycles.py [BUILD_DIR]

Builds cycles_ins.c + sized_ins.c for bare-metal Cortex-M4F (-std=c99 -Os
-fno-math-errno, as the other cycle estimates), runs it on QEMU (mps2-an386)
single-stepped with every executed PC logged, and prices every instruction
executed between each call of SizedFusionAltitudeInsUpdate and its return
(helpers that stay out of line included) with size_table.instruction_cycles.
Prints a markdown table; exit 1 if the program fails its own path checks.
The Makefile's cycle-traces target (make -C csrc/firmware sizes) traces the
same program and prices only the instructions inside the flattened wrapper,
for the table of docs/embedded.md; with -fno-math-errno everything is inlined
there, so both give the same figures.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
CSRC = HERE.parent
sys.path.insert(0, str(HERE))
from size_table import INS_CALLS, instruction_cycles  # noqa: E402

PATHS = list(INS_CALLS)
CC = ["arm-none-eabi-gcc", "-mcpu=cortex-m4", "-mthumb", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard", "-std=c99", "-Os",
      "-fno-math-errno", "-Wall", "-Wextra", "-Wpedantic", "-Wconversion", "-Wdouble-promotion", "-Wshadow", "-Werror"]
QEMU = ["qemu-system-arm", "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
        "-semihosting-config", "enable=on,target=native"]


def build_and_trace(build: Path) -> Path:
    build.mkdir(parents=True, exist_ok=True)
    elf = build / "ins.elf"
    subprocess.run([*CC, f"-I{CSRC}", "--specs=rdimon.specs", "-T", str(HERE / "mps2_an386.ld"),
                    str(HERE / "startup_m4f.s"), str(HERE / "cycles_ins.c"), str(HERE / "sized_ins.c"), "-o",
                    str(elf)], check=True)
    (build / "ins.lst").write_text(subprocess.run(["arm-none-eabi-objdump", "-d", str(elf)], check=True,
                                                  capture_output=True, text=True).stdout)
    (build / "ins.nm").write_text(subprocess.run(["arm-none-eabi-nm", "-S", str(elf)], check=True,
                                                 capture_output=True, text=True).stdout)
    trace = build / "ins-trace.log"
    run = subprocess.run(["timeout", "300", *QEMU, "-singlestep", "-d", "exec,nochain", "-D", str(trace), "-kernel",
                          str(elf)])
    if run.returncode != 0:
        raise SystemExit(f"cycles_ins.elf failed its path checks (exit {run.returncode})")
    return trace


def estimate(build: Path):
    trace = build_and_trace(build)
    instructions = {}
    for match in re.finditer(r"^\s*([0-9a-f]+):\s+([0-9a-f]{4})(?: ([0-9a-f]{4}))?\s+([a-z][\w.]*)[ \t]*([^\n]*)",
                             (build / "ins.lst").read_text(), re.MULTILINE):
        instructions[int(match.group(1), 16)] = (4 if match.group(3) else 2, match.group(4), match.group(5))
    symbols = {}
    for line in (build / "ins.nm").read_text().splitlines():
        parts = line.split()
        if len(parts) == 4:
            symbols[parts[3]] = (int(parts[0], 16), int(parts[1], 16))
    entry = symbols["SizedFusionAltitudeInsUpdate"][0] & ~1
    main_start, main_size = symbols["main"]
    pcs = [int(m.group(1), 16) for m in re.finditer(r"^Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/", trace.read_text(),
                                                     re.MULTILINE)]
    calls, current = [], None
    for index, pc in enumerate(pcs):
        if pc == entry and current is None:
            current = []
        if current is not None:
            if main_start <= pc < main_start + main_size:
                calls.append(current)
                current = None
                continue
            following = pcs[index + 1] if index + 1 < len(pcs) else None
            current.append((pc, following))
    assert len(calls) == len(PATHS), f"{len(calls)} traced calls, expected {len(PATHS)}"
    rows = []
    for name, call in zip(PATHS, calls):
        total = 0
        for pc, following in call:
            length, mnemonic, operands = instructions[pc]
            total += instruction_cycles(mnemonic, following is not None and following != pc + length, operands)
        rows.append((name, len(call), total))
    return rows


def main() -> int:
    build = Path(sys.argv[1]) if len(sys.argv) > 1 else CSRC / "tests" / "build" / "ins"
    rows = estimate(build)
    print("| FusionAltitudeInsUpdate path (Cortex-M4F, -Os) | instructions | cycles (estimate) | µs at 168 MHz |")
    print("|---|---:|---:|---:|")
    for name, count, cycles in rows:
        print(f"| {name} | {count} | {cycles} | {cycles / 168:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
