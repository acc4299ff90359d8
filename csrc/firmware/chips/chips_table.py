"""Markdown tables of the RISC-V 32, AVR and Arduino-sketch measurements of docs/embedded.md, from the
Makefile's outputs (make chips-table runs the builds, then this).

    python3 chips_table.py BUILD                 # print the tables
    python3 chips_table.py BUILD --update-doc DOC  # write them between <!-- chips:begin/end --> of DOC

RISC-V: the replay result of each estimator's vectors (rv32imac and rv32imafc, -Os and -O2: "bit-exact" when
every record's status and state bits equal the reference's), the code size of its Update (the nm size of
Sized...Update, -Os, flattened as in sized_<name>.c) and the instructions QEMU retired in each Update path
(minstret under -icount: instructions, not cycles; QEMU models no pipeline). AVR (atmega1284p under simavr):
the replay of each estimator's vectors (streamed, -Os and -O2), the code size of Sized...Update and the CPU cycles of each path, counted by Timer1 (simavr is cycle
accurate per instruction); the replay verdict as for RISC-V. Sketches: avr-size / arm-none-eabi-size of each example sketch (flash = text + data,
RAM = data + bss).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

ESTIMATORS = {"observer": ("Observer", "SizedFusionAltitudeUpdate"),
              "kalman": ("Kalman filter", "SizedFusionAltitudeKalmanUpdate"),
              "complementary": ("Complementary filter", "SizedFusionAltitudeComplementaryUpdate"),
              "alphabeta": ("Alpha-beta fusion", "SizedFusionAltitudeAlphaBetaUpdate"),
              "rocket": ("Rocket estimator", "SizedFusionAltitudeRocketUpdate"),
              "ins": ("INS", "SizedFusionAltitudeInsUpdate")}
SKETCHES = ("Observer", "Kalman", "Complementary", "AlphaBeta", "Rocket", "Ins")
RISCV_TARGETS = ("rv32imac", "rv32imafc")


def symbol_size(nm: Path, symbol: str) -> int:
    """Bytes of one symbol in an `nm -S` listing (the wrapped name when linked with --wrap)."""
    for line in nm.read_text().splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[3] in (symbol, f"__real_{symbol}"):
            return int(parts[1], 16)
    raise ValueError(f"{nm}: no {symbol}")


def step_counts(log: Path, unit: str) -> list:
    return [int(count) for count in re.findall(rf"^step \d+: (\d+) {unit}$", log.read_text(), re.M)]


def replay_result(log: Path) -> str:
    match = re.search(r"^replay: (\d+) records, (\d+) mismatches$", log.read_text(), re.M)
    if match is None:
        return "did not finish"
    return "bit-exact" if match.group(2) == "0" else f"{match.group(2)} of {match.group(1)} differ"


def tables(build: Path) -> str:
    out = ["RISC-V 32 under QEMU (`make -C csrc/firmware replay-riscv steps-riscv`): replays of the shared vectors "
           "at -Os and -O2, Update code size (-Os) and instructions retired per Update path, in the order of "
           "`cycles_<name>.c` (its comment names the paths; the last is a rejected input):", "",
           "| Header | Records | rv32imac replay | rv32imafc replay | rv32imac Update (B) | rv32imafc Update (B) "
           "| rv32imac instructions per path | rv32imafc instructions per path |",
           "|---|---:|---|---|---:|---:|---|---|"]
    for name, (title, symbol) in ESTIMATORS.items():
        results, sizes, counts = [], [], []
        records = ""
        for target in RISCV_TARGETS:
            logs = [build / "riscv" / target / f"replay_{name}-{opt}.log" for opt in ("Os", "O2")]
            verdicts = {replay_result(log) for log in logs}
            results.append(verdicts.pop() if len(verdicts) == 1 else " / ".join(replay_result(log) for log in logs))
            records = re.search(r"^replay: (\d+) records", logs[0].read_text(), re.M).group(1)
            sizes.append(str(symbol_size(build / "riscv" / target / f"steps_{name}.nm", symbol)))
            counts.append(", ".join(str(count) for count in step_counts(build / "riscv" / target / f"steps_{name}.log",
                                                                        "instructions")))
        out.append(f"| {title} | {records} | {results[0]} | {results[1]} | {sizes[0]} | {sizes[1]} | {counts[0]} "
                   f"| {counts[1]} |")
    out += ["", "AVR (atmega1284p, 16 MHz) under simavr (`make -C csrc/firmware replay-avr steps-avr`): the replays "
            "(records streamed from the host) at -Os and -O2, Update code size (-Os) and CPU cycles per Update path "
            "(same order), every path returning its expected status:", "",
            "| Header | Records | AVR replay | AVR Update (B) | AVR cycles per path | slowest accepted path at 16 MHz (µs) |",
            "|---|---:|---|---:|---|---:|"]
    for name, (title, symbol) in ESTIMATORS.items():
        # the INS at -O2 does not fit the atmega1284p's stack beside its settings table (Makefile: AVR_NOT_REPLAYED)
        logs = [build / "avr" / f"replay_{name}-{opt}.log" for opt in (("Os",) if name == "ins" else ("Os", "O2"))]
        verdicts = {replay_result(log) for log in logs}
        verdict = verdicts.pop() if len(verdicts) == 1 else " / ".join(replay_result(log) for log in logs)
        if name == "ins":
            verdict += " (-Os; -O2 needs more stack than the replay leaves)"
        records = re.search(r"^replay: (\d+) records", logs[0].read_text(), re.M).group(1)
        cycles = step_counts(build / "avr" / f"steps_{name}.log", "cycles")
        size = symbol_size(build / "avr" / f"steps_{name}.nm", symbol)
        out.append(f"| {title} | {records} | {verdict} | {size} | {', '.join(map(str, cycles))} "
                   f"| {max(cycles[:-1]) / 16:.0f} |")
    out += ["", "Arduino example sketches (`make -C csrc/firmware arduino-sketches`, -Os, warning-free), "
            "flash and RAM in bytes:", "", "| Sketch | ATmega328P flash | ATmega328P RAM | Cortex-M4F flash | Cortex-M4F RAM |",
            "|---|---:|---:|---:|---:|"]
    for sketch in SKETCHES:
        row = []
        for board in ("avr", "m4f"):
            text, data, bss = (int(value) for value in
                               (build / "arduino" / board / f"{sketch}.size").read_text().splitlines()[-1].split()[:3])
            row += [str(text + data), str(data + bss)]
        out.append(f"| {sketch} | " + " | ".join(row) + " |")
    return "\n".join(out) + "\n"


def main(argv: list) -> int:
    build = Path(argv[1])
    text = tables(build)
    if len(argv) == 4 and argv[2] == "--update-doc":
        doc = Path(argv[3])
        content = doc.read_text()
        pattern = re.compile(r"(<!-- chips:begin -->\n).*?(<!-- chips:end -->)", re.S)
        if not pattern.search(content):
            raise ValueError(f"{doc}: no <!-- chips:begin/end --> markers")
        doc.write_text(pattern.sub(lambda match: match.group(1) + text + match.group(2), content))
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
