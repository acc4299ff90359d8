// FusionAltitude: the rocket estimator (fusion_altitude_rocket.h) at 100 Hz with a
// 25 Hz barometer: pad calibration, launch, burnout, apogee and landing.
// Prints height above the pad (cm), vertical velocity (cm/s) and the phase.
#include <fusion_altitude_rocket.h>

// ---- Replace these two stubs with your sensor drivers ----------------------

// Accelerometer along the rocket's long axis (nose up), m/s^2, minus g: about 0 on the pad.
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

static FusionAltitudeRocket rocket;

void setup() {
    Serial.begin(115200);
    const FusionAltitudeRocketStatus status = FusionAltitudeRocketInitialise(&rocket, NULL); // the default settings
    if (status != FusionAltitudeRocketStatusOk) {
        Serial.println(FusionAltitudeRocketStatusMessage(status));
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
    const FusionAltitudeRocketStatus status = FusionAltitudeRocketUpdate(&rocket, ReadVerticalAccel(), baro, dt);
    if (status != FusionAltitudeRocketStatusOk) {
        Serial.println(FusionAltitudeRocketStatusMessage(status));
        return;
    }
    PrintCentimetres("height ", FusionAltitudeRocketGetHeight(&rocket));
    PrintCentimetres("velocity ", FusionAltitudeRocketGetVerticalVelocity(&rocket));
    Serial.print("phase ");
    Serial.println((int) FusionAltitudeRocketGetPhase(&rocket));
}
