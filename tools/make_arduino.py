"""Assembles the Arduino library archive: library.properties, src/ with the headers, examples/ with a sketch per
estimator, library.json (PlatformIO), LICENSE; as a folder and as a zip for the Library Manager or "Add .ZIP
Library".

    python tools/make_arduino.py OUT_DIR   # writes OUT_DIR/FusionAltitude/ and OUT_DIR/FusionAltitude-<version>.zip

    python tools/make_arduino.py --sketches          # rewrites packaging/arduino/examples/*/*.ino from SKETCHES
    python tools/make_arduino.py --sketches --check  # exit 1 if a committed sketch differs from its template

Run by ``make -C csrc/firmware arduino``; tests/test_chips.py compiles the sketches of the folder. The sketches are
written from one template (:func:`sketch_text`): the sensor stubs, the loop timing and the printing are the same in
each; :data:`SKETCHES` holds what differs (the estimator, its inputs and outputs).
"""

import argparse
import json
import shutil
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGING = ROOT / "packaging" / "arduino"
NAME = "FusionAltitude"

ACCEL_STUB = """// Vertical acceleration, m/s^2: earth frame, +up, gravity removed (about 0 at rest).
static float ReadVerticalAccel() {
    return 0.0f;
}
"""
BARO_LOOP = ["    float baro; // m", "    if (!ReadBaroAltitude(&baro)) {", "        baro = FUSION_ALTITUDE_NO_BARO;", "    }"]
BARO_MEASUREMENTS = ["    float baro; // m", "    if (ReadBaroAltitude(&baro)) {", "        measurements.baroAltitude = baro;", "    }"]
DEFAULT_SETUP = ["    {prefix}Initialise(&{var}); // the default settings"]
PRINT_ALTITUDE = ['    PrintCentimetres("altitude ", {prefix}GetAltitude(&{var}));',
                  '    PrintCentimetres("velocity ", {prefix}GetVerticalVelocity(&{var}));', "    Serial.println();"]

#: What each example sketch (examples/<name>/<name>.ino) has of its own: the opening comment and header, the first
#: sensor stub, the estimator variable, setup's body, loop's inputs and update call, and what it prints. "{prefix}"
#: and "{var}" stand for the C prefix and the variable.
SKETCHES = {
    "Observer": dict(
        intro=["the complementary observer (fusion_altitude.h) at 100 Hz with a",
               "25 Hz barometer. Prints altitude (cm) and vertical velocity (cm/s)."],
        header="fusion_altitude.h", prefix="FusionAltitude", var="altitude", stub=ACCEL_STUB,
        setup=["    {prefix}Initialise(&{var});", "    {prefix}Settings settings;",
               "    {prefix}Status status = {prefix}SettingsFromPreset(&settings, {prefix}PresetVtol);",
               "    if (status == {prefix}StatusOk) {", "        status = {prefix}SetSettings(&{var}, &settings);", "    }",
               "    if (status != {prefix}StatusOk) {", "        Serial.println({prefix}StatusMessage(status));", "    }"],
        inputs=BARO_LOOP, update="{prefix}Update(&{var}, ReadVerticalAccel(), baro, dt)", prints=PRINT_ALTITUDE),
    "Kalman": dict(
        intro=["the Kalman filter (fusion_altitude_kalman.h) at 100 Hz with a",
               "25 Hz barometer (a rangefinder and a GPS fit the same measurements struct).",
               "Prints altitude (cm) and vertical velocity (cm/s)."],
        header="fusion_altitude_kalman.h", prefix="FusionAltitudeKalman", var="kalman", stub=ACCEL_STUB,
        setup=DEFAULT_SETUP, inputs=["    {prefix}Measurements measurements = {prefix}MeasurementsNone();"] + BARO_MEASUREMENTS,
        update="{prefix}Update(&{var}, ReadVerticalAccel(), dt, &measurements)", prints=PRINT_ALTITUDE),
    "Complementary": dict(
        intro=["the two-stage complementary filter (fusion_altitude_complementary.h)",
               "at 100 Hz with a 25 Hz barometer. Prints altitude (cm) and vertical velocity (cm/s)."],
        header="fusion_altitude_complementary.h", prefix="FusionAltitudeComplementary", var="filter", stub=ACCEL_STUB,
        setup=DEFAULT_SETUP, inputs=BARO_LOOP, update="{prefix}Update(&{var}, ReadVerticalAccel(), baro, dt)",
        prints=PRINT_ALTITUDE),
    "AlphaBeta": dict(
        intro=["the quality-weighted alpha-beta fusion (fusion_altitude_alphabeta.h)",
               "at 100 Hz with a 25 Hz barometer (lidar, sonar and GPS fit the same measurements",
               "struct). Prints altitude (cm) and vertical velocity (cm/s)."],
        header="fusion_altitude_alphabeta.h", prefix="FusionAltitudeAlphaBeta", var="fusion", stub=ACCEL_STUB,
        setup=DEFAULT_SETUP, inputs=["    {prefix}Measurements measurements = {prefix}MeasurementsNone();"] + BARO_MEASUREMENTS,
        update="{prefix}Update(&{var}, ReadVerticalAccel(), dt, &measurements)", prints=PRINT_ALTITUDE),
    "Rocket": dict(
        intro=["the rocket estimator (fusion_altitude_rocket.h) at 100 Hz with a",
               "25 Hz barometer: pad calibration, launch, burnout, apogee and landing.",
               "Prints height above the pad (cm), vertical velocity (cm/s) and the phase."],
        header="fusion_altitude_rocket.h", prefix="FusionAltitudeRocket", var="rocket",
        stub=("// Accelerometer along the rocket's long axis (nose up), m/s^2, minus g: about 0 on the pad.\n"
              + ACCEL_STUB.split("\n", 1)[1]),
        setup=["    const {prefix}Status status = {prefix}Initialise(&{var}, NULL); // the default settings",
               "    if (status != {prefix}StatusOk) {", "        Serial.println({prefix}StatusMessage(status));", "    }"],
        inputs=BARO_LOOP, update="{prefix}Update(&{var}, ReadVerticalAccel(), baro, dt)",
        prints=['    PrintCentimetres("height ", {prefix}GetHeight(&{var}));',
                '    PrintCentimetres("velocity ", {prefix}GetVerticalVelocity(&{var}));', '    Serial.print("phase ");',
                "    Serial.println((int) {prefix}GetPhase(&{var}));"]),
    "Ins": dict(
        intro=["the inertial navigation filter (fusion_altitude_ins.h) at 100 Hz",
               "with a 25 Hz barometer and no magnetometer. Prints altitude (cm) and vertical",
               "velocity (cm/s). The INS calls sqrtf: libm, linked by every Arduino core."],
        header="fusion_altitude_ins.h", prefix="FusionAltitudeIns", var="ins",
        stub="""// Gyroscope, rad/s, and accelerometer, m/s^2 (gravity included), body frame.
static void ReadImu(FusionAltitudeInsVector *const gyro, FusionAltitudeInsVector *const accel) {
    gyro->x = 0.0f;
    gyro->y = 0.0f;
    gyro->z = 0.0f;
    accel->x = 0.0f;
    accel->y = 0.0f;
    accel->z = FUSION_ALTITUDE_GRAVITY; // level and at rest
}
""",
        setup=DEFAULT_SETUP,
        inputs=["    {prefix}Vector gyro;  // rad/s", "    {prefix}Vector accel; // m/s^2", "    ReadImu(&gyro, &accel);"]
        + BARO_LOOP, update="{prefix}Update(&{var}, gyro, accel, {prefix}NoMag(), baro, dt)", prints=PRINT_ALTITUDE),
}

#: The part of every sketch between its first sensor stub and its estimator: the baro stub, the loop timing and
#: the printing helper.
SKETCH_COMMON = """
// Barometric altitude, m: true and *altitude set when a new sample is ready.
static bool ReadBaroAltitude(float *const altitude) {
    static unsigned long lastMillis = 0;
    if ((millis() - lastMillis) < 40UL) { // a 25 Hz barometer
        return false;
    }
    lastMillis = millis();
    *altitude = 100.0f;
    return true;
}

// ---- Loop timing ---------------------------------------------------------------

#define PERIOD_MICROS (10000UL) // 100 Hz
static unsigned long previousMicros;

// Seconds since the previous step once a period has passed, else 0.
static float StepDt() {
    const unsigned long now = micros();
    const unsigned long elapsed = now - previousMicros;
    if (elapsed < PERIOD_MICROS) {
        return 0.0f;
    }
    previousMicros = now;
    return (float) elapsed * 1e-6f;
}

// Prints a value in m (or m/s) as whole centimetres: no float formatting needed.
static void PrintCentimetres(const char *const label, const float value) {
    Serial.print(label);
    Serial.print((long) (value * 100.0f));
    Serial.print(" cm ");
}
"""


def sketch_text(name: str) -> str:
    """The example sketch ``name`` (a key of :data:`SKETCHES`): the template filled with its own parts."""
    part = SKETCHES[name]

    def fill(lines) -> list:
        return [line.replace("{prefix}", part["prefix"]).replace("{var}", part["var"]) for line in lines]

    out = ["// FusionAltitude: " + part["intro"][0]] + ["// " + line for line in part["intro"][1:]]
    out += [f"#include <{part['header']}>", "", "// ---- Replace these two stubs with your sensor drivers ----------------------",
            "", part["stub"].rstrip("\n")]
    out += SKETCH_COMMON.rstrip("\n").split("\n")
    out += ["", f"static {part['prefix']} {part['var']};", "", "void setup() {", "    Serial.begin(115200);"]
    out += fill(part["setup"]) + ["    previousMicros = micros();", "}", "", "void loop() {",
                                  "    const float dt = StepDt(); // s", "    if (dt == 0.0f) {", "        return;", "    }"]
    out += fill(part["inputs"]) + fill([f"    const {{prefix}}Status status = {part['update']};",
                                        "    if (status != {prefix}StatusOk) {",
                                        "        Serial.println({prefix}StatusMessage(status));", "        return;", "    }"])
    out += fill(part["prints"]) + ["}"]
    return "\n".join(out) + "\n"


def stale_sketches() -> list:
    """The committed sketches that differ from their template (paths relative to the root)."""
    return [f"packaging/arduino/examples/{name}/{name}.ino" for name in SKETCHES
            if (PACKAGING / "examples" / name / f"{name}.ino").read_text() != sketch_text(name)]


def library_version() -> str:
    """The version stated by library.properties (tools/sync_version.py keeps it equal to the package's)."""
    for line in (PACKAGING / "library.properties").read_text().splitlines():
        if line.startswith("version="):
            return line.split("=", 1)[1]
    raise ValueError("packaging/arduino/library.properties has no version= line")


def library_json() -> dict:
    """PlatformIO's manifest for the archive's layout (src/, examples/), from the repository's library.json."""
    manifest = json.loads((ROOT / "library.json").read_text())
    manifest.pop("build", None)
    manifest.pop("export", None)
    manifest["build"] = {"flags": ["-ffp-contract=off"]}
    manifest["examples"] = [{"name": entry["name"], "base": f"examples/{entry['name']}", "files": entry["files"]}
                            for entry in manifest["examples"]]
    return manifest


def assemble(out_dir: Path) -> Path:
    """Writes the library folder OUT_DIR/FusionAltitude (replacing it) and its zip; returns the zip's path."""
    library = out_dir / NAME
    if library.exists():
        shutil.rmtree(library)
    (library / "src").mkdir(parents=True)
    shutil.copy2(PACKAGING / "library.properties", library / "library.properties")
    shutil.copy2(ROOT / "LICENSE", library / "LICENSE")
    (library / "library.json").write_text(json.dumps(library_json(), indent=2) + "\n")
    for header in sorted((ROOT / "csrc").glob("fusion_altitude*.h")):
        shutil.copy2(header, library / "src" / header.name)
    shutil.copytree(PACKAGING / "examples", library / "examples")
    archive = out_dir / f"{NAME}-{library_version()}.zip"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as zipped:
        for path in sorted(library.rglob("*")):
            if path.is_file():
                zipped.write(path, path.relative_to(out_dir).as_posix())
    return archive


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", type=Path, nargs="?")
    parser.add_argument("--sketches", action="store_true", help="write the example sketches from their template")
    parser.add_argument("--check", action="store_true", help="with --sketches: exit 1 if a sketch is stale")
    args = parser.parse_args(argv)
    if args.sketches:
        if args.check:
            stale = stale_sketches()
            print("\n".join(f"stale: {path}; run python tools/make_arduino.py --sketches" for path in stale) or "fresh")
            return 1 if stale else 0
        for name in SKETCHES:
            (PACKAGING / "examples" / name / f"{name}.ino").write_text(sketch_text(name))
        return 0
    if args.out_dir is None:
        parser.error("OUT_DIR is required (or --sketches)")
    args.out_dir.mkdir(parents=True, exist_ok=True)
    print(assemble(args.out_dir))
    return 0


if __name__ == "__main__":
    sys.exit(main())
