// FusionAltitude: the complementary observer (fusion_altitude.h) at 100 Hz with a
// 25 Hz barometer. Prints altitude (cm) and vertical velocity (cm/s).
#include <fusion_altitude.h>

// ---- Replace these two stubs with your sensor drivers ----------------------

// Vertical acceleration, m/s^2: earth frame, +up, gravity removed (about 0 at rest).
static float ReadVerticalAccel() {
    return 0.0f;
}

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

static FusionAltitude altitude;

void setup() {
    Serial.begin(115200);
    FusionAltitudeInitialise(&altitude);
    FusionAltitudeSettings settings;
    FusionAltitudeStatus status = FusionAltitudeSettingsFromPreset(&settings, FusionAltitudePresetVtol);
    if (status == FusionAltitudeStatusOk) {
        status = FusionAltitudeSetSettings(&altitude, &settings);
    }
    if (status != FusionAltitudeStatusOk) {
        Serial.println(FusionAltitudeStatusMessage(status));
    }
    previousMicros = micros();
}

void loop() {
    const float dt = StepDt(); // s
    if (dt == 0.0f) {
        return;
    }
    float baro; // m
    if (!ReadBaroAltitude(&baro)) {
        baro = FUSION_ALTITUDE_NO_BARO;
    }
    const FusionAltitudeStatus status = FusionAltitudeUpdate(&altitude, ReadVerticalAccel(), baro, dt);
    if (status != FusionAltitudeStatusOk) {
        Serial.println(FusionAltitudeStatusMessage(status));
        return;
    }
    PrintCentimetres("altitude ", FusionAltitudeGetAltitude(&altitude));
    PrintCentimetres("velocity ", FusionAltitudeGetVerticalVelocity(&altitude));
    Serial.println();
}
