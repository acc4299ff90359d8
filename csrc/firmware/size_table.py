"""Size, stack, RAM and cycle tables of docs/embedded.md, from the Makefile's outputs.

    make -C csrc/firmware sizes             # builds, then runs this
    python3 size_table.py BUILD [--json]    # BUILD as given to the Makefile

Code size: the nm symbol size of Sized<Function> (sized_observer.c: the public function
with everything it calls inlined into one out-of-line copy; the size includes
its literal pool). Stack: the -fstack-usage line of the same wrapper. RAM: the
nm size of the FusionAltitude instance in sized_observer.c. Cycles: the instructions
QEMU executed inside SizedFusionAltitudeUpdate (cycles_observer.c, -d exec with
-singlestep), each priced with the Cortex-M4 cycle counts below.

The other estimators (ESTIMATORS: every row of MODULES in tools/generate_bindings.py after the observer's) are
measured the same way: sized_<name>.c (written by tools/make_harnesses.py, with the state's instance), and
Sized...Update traced by cycles_<name>.c; their figures are under result[<name>] and each has
its own block of docs/embedded.md (between the <!-- <name>-sizes:begin/end --> markers, which --update-doc adds for
a new estimator). Nothing here is edited for a new estimator: its table rows are the
Sized<Function>s of sized_<name>.c in file order and its traced paths the numbered list of cycles_<name>.c's
opening comment, unless FUNCTION_ORDER / TRACED_PATHS name them (the estimators measured before these were read).
"""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path
from typing import Dict, List, Tuple

FIRMWARE = Path(__file__).resolve().parent
ROOT = FIRMWARE.parents[1]
TARGETS = ("cortex-m0plus", "cortex-m4f", "cortex-m7", "rv32imac", "rv32imafc")
OPTIMISATIONS = ("Os", "O2")
FUNCTIONS = (
    "FusionAltitudeUpdate", "FusionAltitudeCheckInputs", "FusionAltitudeInitialise", "FusionAltitudeReset", "FusionAltitudeResetWithBias",
    "FusionAltitudeSetSettings", "FusionAltitudeSettingsCheck", "FusionAltitudeSettingsValidate",
    "FusionAltitudeSettingsFromBandwidth", "FusionAltitudeSettingsFromPreset", "FusionAltitudeSettingsDefault",
    "FusionAltitudeStatusMessage", "FusionAltitudeGetSettings", "FusionAltitudeGetAltitude",
    "FusionAltitudeGetVerticalVelocity", "FusionAltitudeGetAccelBias", "FusionAltitudeGetBaroResidual",
    "FusionAltitudeIsReferenceSet", "FusionAltitudeGetGapCount", "FusionAltitudeIsFinite", "FusionAltitudeIsNaN", "FusionAltitudeNaN",
    "FusionAltitudeFloatBits", "FusionAltitudeGetBaroTimeouts", "FusionAltitudeIsBaroTimedOut", "FusionAltitudeIsStepStable",
    "FusionAltitudeInfinity",
)

KALMAN_FUNCTIONS = (
    "FusionAltitudeKalmanUpdate", "FusionAltitudeKalmanInitialise", "FusionAltitudeKalmanInitialiseWith",
    "FusionAltitudeKalmanSetSettings", "FusionAltitudeKalmanSettingsCheck", "FusionAltitudeKalmanSettingsDefault",
    "FusionAltitudeKalmanMeasurementsNone", "FusionAltitudeKalmanStatusMessage", "FusionAltitudeKalmanGetSettings",
    "FusionAltitudeKalmanGetSensor", "FusionAltitudeKalmanGetCovariance", "FusionAltitudeKalmanGetHeightAboveGround",
    "FusionAltitudeKalmanGetAltitude", "FusionAltitudeKalmanGetAltitudeVariance", "FusionAltitudeKalmanGetVerticalVelocity",
    "FusionAltitudeKalmanGetAccelBias", "FusionAltitudeKalmanGetBaroOffset", "FusionAltitudeKalmanGetGpsOffset",
    "FusionAltitudeKalmanGetGapCount", "FusionAltitudeKalmanIsBaroTimedOut", "FusionAltitudeKalmanIsRangeTimedOut",
    "FusionAltitudeKalmanIsGpsTimedOut", "FusionAltitudeKalmanGetNis",
)

COMPLEMENTARY_FUNCTIONS = (
    "FusionAltitudeComplementaryUpdate", "FusionAltitudeComplementaryCheckInputs", "FusionAltitudeComplementaryInitialise",
    "FusionAltitudeComplementaryReset", "FusionAltitudeComplementarySetSettings", "FusionAltitudeComplementarySettingsCheck",
    "FusionAltitudeComplementarySettingsDefault", "FusionAltitudeComplementaryStatusMessage",
    "FusionAltitudeComplementaryGetSettings", "FusionAltitudeComplementaryGetAltitude",
    "FusionAltitudeComplementaryGetVerticalVelocity", "FusionAltitudeComplementaryGetBaroFiltered",
    "FusionAltitudeComplementaryGetBaroVelocity", "FusionAltitudeComplementaryIsReferenceSet",
    "FusionAltitudeComplementaryGetGapCount", "FusionAltitudeComplementaryGetBaroTimeouts",
    "FusionAltitudeComplementaryIsBaroTimedOut",
)

ALPHABETA_FUNCTIONS = (
    "FusionAltitudeAlphaBetaUpdate", "FusionAltitudeAlphaBetaCheckInputs", "FusionAltitudeAlphaBetaInitialise",
    "FusionAltitudeAlphaBetaInitialiseWith", "FusionAltitudeAlphaBetaSetSettings", "FusionAltitudeAlphaBetaSettingsCheck",
    "FusionAltitudeAlphaBetaSensorSettingsCheck", "FusionAltitudeAlphaBetaSettingsDefault",
    "FusionAltitudeAlphaBetaMeasurementsNone", "FusionAltitudeAlphaBetaGains", "FusionAltitudeAlphaBetaStatusMessage",
    "FusionAltitudeAlphaBetaGetSettings", "FusionAltitudeAlphaBetaGetAltitude", "FusionAltitudeAlphaBetaGetVerticalVelocity",
    "FusionAltitudeAlphaBetaGetWeight", "FusionAltitudeAlphaBetaGetQuality", "FusionAltitudeAlphaBetaIsStarted",
    "FusionAltitudeAlphaBetaGetGapCount", "FusionAltitudeAlphaBetaIsTimedOut", "FusionAltitudeAlphaBetaGetTimeoutCount",
)

ROCKET_FUNCTIONS = (
    "FusionAltitudeRocketUpdate", "FusionAltitudeRocketUpdateWithVerticalAccel", "FusionAltitudeRocketCheckInputs",
    "FusionAltitudeRocketInitialise", "FusionAltitudeRocketSettingsCheck", "FusionAltitudeRocketSettingsDefault",
    "FusionAltitudeRocketObserverSettings", "FusionAltitudeRocketStatusMessage", "FusionAltitudeRocketGetHeight",
    "FusionAltitudeRocketGetVerticalVelocity", "FusionAltitudeRocketGetAccelBias", "FusionAltitudeRocketGetPadAltitude",
    "FusionAltitudeRocketGetPhase", "FusionAltitudeRocketGetBaro", "FusionAltitudeRocketIsLockedOut",
    "FusionAltitudeRocketIsCalibrated", "FusionAltitudeRocketGetEvent", "FusionAltitudeRocketGetGapCount",
    "FusionAltitudeRocketGetTime",
)

INS_FUNCTIONS = (
    "FusionAltitudeInsUpdate", "FusionAltitudeInsCheckInputs", "FusionAltitudeInsInitialise", "FusionAltitudeInsInitialiseWith",
    "FusionAltitudeInsSetSettings", "FusionAltitudeInsSettingsCheck", "FusionAltitudeInsSettingsDefault",
    "FusionAltitudeInsNoMag", "FusionAltitudeInsIsNoMag", "FusionAltitudeInsStatusMessage", "FusionAltitudeInsGetSettings",
    "FusionAltitudeInsGetAltitude", "FusionAltitudeInsGetVerticalVelocity", "FusionAltitudeInsGetQuaternion",
    "FusionAltitudeInsGetLocalToGlobal", "FusionAltitudeInsGetGlobalQuaternion", "FusionAltitudeInsGetGyroBias",
    "FusionAltitudeInsGetAccelZBias", "FusionAltitudeInsGetBaroBias", "FusionAltitudeInsIsStationary",
    "FusionAltitudeInsIsAccelRejected", "FusionAltitudeInsGetGapCount", "FusionAltitudeInsGetBaroRejections",
    "FusionAltitudeInsGetBaroResets", "FusionAltitudeInsIsBaroRejecting", "FusionAltitudeInsIsBaroTimedOut",
    "FusionAltitudeInsIsHeightHeld", "FusionAltitudeInsGetBaroTimeouts",
)

# Cortex-M4 cycle counts (Cortex-M4 TRM r0p1, tables 3-1 and 7-1). P, the
# pipeline refill after a taken branch, is 1 to 3 cycles; 2 is used here.
PIPELINE_REFILL = 2
CONDITIONS = {"eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt", "gt", "le", "al"}
CALLS = ("baro sample, reference set (full correction)", "no baro sample (integration only)",
         "rejected (accel not finite)")
#: the paths of cycles_ins.c (ins_cycles.py and tests/test_ins_c.py use these names)
INS_CALLS = ("predict + accel (no baro, no mag)", "predict + accel + baro", "predict + accel + mag",
             "stationary: + zero rate, zero velocity, baro bias", "predict only (accel rejected by its norm)",
             "rejected input (gyro NaN)")

#: the table rows (public functions) of the estimators measured before the rows were read from sized_<name>.c
FUNCTION_ORDER = {"kalman": KALMAN_FUNCTIONS, "complementary": COMPLEMENTARY_FUNCTIONS, "alphabeta": ALPHABETA_FUNCTIONS,
                  "rocket": ROCKET_FUNCTIONS, "ins": INS_FUNCTIONS}
#: the traced paths of cycles_<name>.c, as the tables name them
TRACED_PATHS = {"ins": INS_CALLS}


def estimator_modules() -> Dict[str, tuple]:
    """The generator's MODULES (tools/generate_bindings.py): name → (header, C prefix, settings struct, state struct)."""
    if "generate_bindings" not in sys.modules:  # registered before it runs: its dataclasses look themselves up
        spec = importlib.util.spec_from_file_location("generate_bindings", ROOT / "tools" / "generate_bindings.py")
        sys.modules["generate_bindings"] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules["generate_bindings"])
    return sys.modules["generate_bindings"].MODULES


def sized_functions(name: str) -> Tuple[str, ...]:
    """The public functions sized_<name>.c wraps (its SIZED Sized<Function> definitions), in file order."""
    text = (FIRMWARE / f"sized_{name}.c").read_text()
    return tuple(re.findall(r"^SIZED [^(]*?\bSized(\w+)\(", text, re.MULTILINE))


def state_instance(name: str, struct: str) -> str:
    """The instance of struct that tools/make_harnesses.py writes into sized_<name>.c (its RAM is measured)."""
    return f"sized{struct}"


def traced_paths(name: str) -> Tuple[str, ...]:
    """The numbered paths of cycles_<name>.c's opening comment (`` *   1. baro sample ...``), in order."""
    comment = (FIRMWARE / f"cycles_{name}.c").read_text().split("/**", 1)[-1].split("*/", 1)[0]  # after a generated line
    return tuple(re.findall(r"^ \*\s+\d+\. (.+)$", comment, re.MULTILINE))


def estimator_rows() -> Tuple[tuple, ...]:
    """Each estimator after the observer: name (sized_<name>.c, cycles_<name>.c, marker <name>-sizes), public
    functions, the state's instance in sized_<name>.c, struct, update function, traced paths."""
    rows = []
    for name, (_, prefix, _, struct) in list(estimator_modules().items())[1:]:
        rows.append((name, FUNCTION_ORDER.get(name) or sized_functions(name), state_instance(name, struct), struct,
                     f"{prefix}Update", TRACED_PATHS.get(name) or traced_paths(name)))
    return tuple(rows)


ESTIMATORS = estimator_rows()


def read_symbols(path: Path) -> Dict[str, Tuple[int, int]]:
    """{name: (address, size)} from `nm -S` output."""
    symbols = {}
    for line in path.read_text().splitlines():
        fields = line.split()
        if len(fields) == 4:
            symbols[fields[3]] = (int(fields[0], 16), int(fields[1], 16))
    return symbols


def read_stack(path: Path) -> Dict[str, Tuple[int, str]]:
    """{function: (bytes, qualifier)} from a gcc .su file."""
    stack = {}
    for line in path.read_text().splitlines():
        location, size, qualifier = line.split("\t")
        stack[location.rsplit(":", 1)[1]] = (int(size), qualifier)
    return stack


def measure_sized(build: Path, stem: str, functions, instance: str) -> dict:
    """Sizes and stack of the Sized<Function> wrappers in <stem>.o, RAM of <instance> in it."""
    result: dict = {"size": {}, "stack": {}, "ram": {}, "c11_differs": []}
    for target in TARGETS:
        for opt in OPTIMISATIONS:
            variant = build / "cross" / target / f"c99-{opt}"
            sizes = read_symbols(variant / f"{stem}.nm")
            stack = read_stack(variant / f"{stem}.su")
            for function in functions:
                result["size"][f"{function}/{target}/{opt}"] = sizes[f"Sized{function}"][1]
                result["stack"][f"{function}/{target}/{opt}"] = stack[f"Sized{function}"]
            result["ram"][f"{target}/{opt}"] = sizes[instance][1]
            c11 = read_symbols(build / "cross" / target / f"c11-{opt}" / f"{stem}.nm")
            if {k: v[1] for k, v in c11.items()} != {k: v[1] for k, v in sizes.items()}:
                result["c11_differs"].append(f"{target}/{opt}")
    return result


def measure(build: Path) -> dict:
    """The observer's figures at the top level (size, stack, ram, c11_differs, cycles), each other estimator's under its name."""
    result = measure_sized(build, "sized_observer", FUNCTIONS, state_instance("observer", "FusionAltitude"))
    if (build / "cycles" / "observer-trace.log").exists():
        result["cycles"] = cycles(build / "cycles", "observer", "SizedFusionAltitudeUpdate", CALLS)
    for name, functions, instance, _, update, calls in ESTIMATORS:
        figures = measure_sized(build, f"sized_{name}", functions, instance)
        if (build / "cycles" / f"{name}-trace.log").exists():
            figures["cycles"] = cycles(build / "cycles", name, f"Sized{update}", calls)
        result[name] = figures
    return result


def transfer_words(operands: str) -> int:
    """Words moved by a multiple load/store: {r4, r5, lr} is 3, {s16-s19} 4, {d8-d9} 4."""
    words = 0
    for item in operands[operands.find("{") + 1:operands.find("}")].split(","):
        item = item.strip()
        size = 2 if item.startswith("d") else 1
        if "-" in item:
            first, last = (int(part.strip()[1:]) for part in item.split("-"))
            words += size * (last - first + 1)
        elif item:
            words += size
    return words


def instruction_cycles(mnemonic: str, taken: bool, operands: str = "") -> int:
    """Cortex-M4 cycles of one executed instruction."""
    base = mnemonic.split(".")[0]
    if base in ("push", "pop", "vpush", "vpop") or base.startswith(("ldm", "stm", "vldm", "vstm")):
        pc_loaded = base in ("pop", "ldmia", "ldm") and "pc" in operands
        return 1 + transfer_words(operands) + (PIPELINE_REFILL if pc_loaded else 0)
    is_branch = base in ("b", "bl", "bx", "blx", "cbz", "cbnz") or (base[:1] == "b" and base[1:] in CONDITIONS)
    if is_branch:
        return 1 + PIPELINE_REFILL if taken else 1
    if base in ("vmla", "vmls", "vnmla", "vnmls", "vfma", "vfms", "vfnma", "vfnms"):
        return 3
    if base in ("vdiv", "vsqrt"):
        return 14
    if base in ("vldr", "vstr") or base.startswith(("ldr", "str")):
        return 2
    return 1  # ALU, vadd/vsub/vmul/vcmp/vmrs/vmov, it, nop


def cycles(directory: Path, stem: str, symbol: str, names) -> List[dict]:
    """Cycle estimate of each call of symbol traced by QEMU (stem.nm, stem.lst, stem-trace.log).

    A call is every instruction executed from an entry into the symbol until it leaves other than by a
    bl/blx; the library functions it calls that way (memset, or sqrtf without -fno-math-errno) are
    included, as executed."""
    start, size = read_symbols(directory / f"{stem}.nm")[symbol]
    instructions = {}
    for match in re.finditer(r"^\s*([0-9a-f]+):\s+([0-9a-f]{4})(?: ([0-9a-f]{4}))?\s+([a-z][\w.]*)[ \t]*([^\n]*)",
                             (directory / f"{stem}.lst").read_text(), re.MULTILINE):
        instructions[int(match.group(1), 16)] = (4 if match.group(3) else 2, match.group(4), match.group(5))
    trace = directory / f"{stem}-trace.log"
    pcs = [int(m.group(1), 16) for m in re.finditer(r"^Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/",
                                                     trace.read_text(), re.MULTILINE)]

    def inside(address: int) -> bool:
        return start <= address < start + size

    calls: List[List[Tuple[int, int]]] = []
    current = None
    in_callee = False
    for index, pc in enumerate(pcs):
        if current is None:
            if not inside(pc):
                continue
            current = []
        following = pcs[index + 1] if index + 1 < len(pcs) else None
        current.append((pc, following))
        if inside(pc) and following is not None and not inside(following):
            if instructions[pc][1] in ("bl", "blx"):
                in_callee = True  # a library call: its instructions belong to this call
            else:
                calls.append(current)  # returned to the caller
                current, in_callee = None, False
        elif in_callee and following is not None and inside(following):
            in_callee = False
    if current:
        calls.append(current)
    estimates = []
    assert len(calls) == len(names), f"{len(calls)} calls of {symbol} traced, expected {len(names)}"
    for name, call in zip(names, calls):
        total = 0
        for pc, following in call:
            length, mnemonic, operands = instructions[pc]
            total += instruction_cycles(mnemonic, following is not None and following != pc + length, operands)
        estimates.append({"path": name, "instructions": len(call), "cycles": total})
    return estimates


def tables(result: dict, functions, struct: str, update: str) -> List[str]:
    short = {"cortex-m0plus": "M0+", "cortex-m4f": "M4F", "cortex-m7": "M7", "rv32imac": "rv32imac",
             "rv32imafc": "rv32imafc"}
    columns = [(t, o) for t in TARGETS for o in OPTIMISATIONS]
    lines = ["Code bytes (.text, including literal pools) per public function, C99:", "",
             "| function | " + " | ".join(f"{short[t]} -{o}" for t, o in columns) + " |",
             "|---|" + "---:|" * len(columns)]
    for function in functions:
        cells = [str(result["size"][f"{function}/{t}/{o}"]) for t, o in columns]
        lines.append(f"| {function} | " + " | ".join(cells) + " |")
    lines += ["", "Stack bytes (-fstack-usage, the out-of-line copy) per public function:", "",
              "| function | " + " | ".join(f"{short[t]} -{o}" for t, o in columns) + " |",
              "|---|" + "---:|" * len(columns)]
    for function in functions:
        cells = []
        for t, o in columns:
            size, qualifier = result["stack"][f"{function}/{t}/{o}"]
            cells.append(str(size) if qualifier == "static" else f"{size} ({qualifier})")
        lines.append(f"| {function} | " + " | ".join(cells) + " |")
    lines += ["", f"RAM of one estimator (sizeof({struct}), nm size of a static instance):", "",
              "| " + " | ".join(short[t] for t in TARGETS) + " |", "|" + "---:|" * len(TARGETS),
              "| " + " | ".join(f"{result['ram'][f'{t}/Os']} B" for t in TARGETS) + " |"]
    differs = result["c11_differs"]
    lines += ["", "C11 builds: " + (f"sizes differ from C99 for {', '.join(differs)}" if differs
                                     else "every symbol has the same size as in C99.")]
    if "cycles" in result:
        lines += ["", f"Cycle estimate of {update} on Cortex-M4F, -Os (instructions executed on QEMU, "
                  f"priced with Cortex-M4 TRM cycle counts, pipeline refill P = {PIPELINE_REFILL}, "
                  "zero-wait-state memory, call instruction not included):", "",
                  "| path | instructions | cycles |", "|---|---:|---:|"]
        for row in result["cycles"]:
            lines.append(f"| {row['path']} | {row['instructions']} | {row['cycles']} |")
    return lines


MARKERS = ("sizes",) + tuple(f"{name}-sizes" for name, *_ in ESTIMATORS)


def markdown_parts(result: dict) -> List[str]:
    """The observer's tables and each other estimator's (the blocks of docs/embedded.md, in MARKERS order)."""
    parts = ["\n".join(tables(result, FUNCTIONS, "FusionAltitude", "FusionAltitudeUpdate"))]
    for name, functions, _, struct, update, _ in ESTIMATORS:
        parts.append("\n".join(tables(result[name], functions, struct, update)))
    return parts


def markdown(result: dict) -> str:
    observer, *others = markdown_parts(result)
    return observer + "".join(f"\n\n<!-- {name} (fusion_altitude_{name}.h): -->\n\n{part}"
                              for (name, *_), part in zip(ESTIMATORS, others))


def with_markers(text: str) -> str:
    """docs/embedded.md with a block for every estimator: one without its ``<name>-sizes`` markers (a new row of
    MODULES) gets a section of its own after the last estimator's block, headed by its header's name."""
    for name, *_ in ESTIMATORS:
        if f"<!-- {name}-sizes:begin -->" not in text:
            last = text.rindex("-sizes:end -->") + len("-sizes:end -->")
            header = estimator_modules()[name][0]
            block = f"\n\n### {header}\n\n<!-- {name}-sizes:begin -->\n<!-- {name}-sizes:end -->"
            text = text[:last] + block + text[last:]
    return text


def update_doc(doc: Path, result: dict) -> None:
    """Replace each estimator's block of docs/embedded.md (between its markers) with fresh tables; a new
    estimator's markers are added first (:func:`with_markers`)."""
    text = with_markers(doc.read_text())
    for marker, part in zip(MARKERS, markdown_parts(result)):
        begin, end = f"<!-- {marker}:begin -->\n", f"<!-- {marker}:end -->"
        start, stop = text.index(begin) + len(begin), text.index(end)
        text = text[:start] + part + "\n" + text[stop:]
    doc.write_text(text)


if __name__ == "__main__":
    measured = measure(Path(sys.argv[1]))
    if "--update-doc" in sys.argv[2:]:
        update_doc(Path(sys.argv[sys.argv.index("--update-doc") + 1]), measured)
    else:
        print(json.dumps(measured, indent=1) if "--json" in sys.argv[2:] else markdown(measured))
