// FusionAltitude: the two-stage complementary filter (fusion_altitude_complementary.h)
// at 100 Hz with a 25 Hz barometer. Prints altitude (cm) and vertical velocity (cm/s).
#include <fusion_altitude_complementary.h>

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

static FusionAltitudeComplementary filter;

void setup() {
    Serial.begin(115200);
    FusionAltitudeComplementaryInitialise(&filter); // the default settings
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
    const FusionAltitudeComplementaryStatus status = FusionAltitudeComplementaryUpdate(&filter, ReadVerticalAccel(), baro, dt);
    if (status != FusionAltitudeComplementaryStatusOk) {
        Serial.println(FusionAltitudeComplementaryStatusMessage(status));
        return;
    }
    PrintCentimetres("altitude ", FusionAltitudeComplementaryGetAltitude(&filter));
    PrintCentimetres("velocity ", FusionAltitudeComplementaryGetVerticalVelocity(&filter));
    Serial.println();
}
