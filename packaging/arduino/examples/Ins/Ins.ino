// FusionAltitude: the inertial navigation filter (fusion_altitude_ins.h) at 100 Hz
// with a 25 Hz barometer and no magnetometer. Prints altitude (cm) and vertical
// velocity (cm/s). The INS calls sqrtf: libm, linked by every Arduino core.
#include <fusion_altitude_ins.h>

// ---- Replace these two stubs with your sensor drivers ----------------------

// Gyroscope, rad/s, and accelerometer, m/s^2 (gravity included), body frame.
static void ReadImu(FusionAltitudeInsVector *const gyro, FusionAltitudeInsVector *const accel) {
    gyro->x = 0.0f;
    gyro->y = 0.0f;
    gyro->z = 0.0f;
    accel->x = 0.0f;
    accel->y = 0.0f;
    accel->z = FUSION_ALTITUDE_GRAVITY; // level and at rest
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

static FusionAltitudeIns ins;

void setup() {
    Serial.begin(115200);
    FusionAltitudeInsInitialise(&ins); // the default settings
    previousMicros = micros();
}

void loop() {
    const float dt = StepDt(); // s
    if (dt == 0.0f) {
        return;
    }
    FusionAltitudeInsVector gyro;  // rad/s
    FusionAltitudeInsVector accel; // m/s^2
    ReadImu(&gyro, &accel);
    float baro; // m
    if (!ReadBaroAltitude(&baro)) {
        baro = FUSION_ALTITUDE_NO_BARO;
    }
    const FusionAltitudeInsStatus status = FusionAltitudeInsUpdate(&ins, gyro, accel, FusionAltitudeInsNoMag(), baro, dt);
    if (status != FusionAltitudeInsStatusOk) {
        Serial.println(FusionAltitudeInsStatusMessage(status));
        return;
    }
    PrintCentimetres("altitude ", FusionAltitudeInsGetAltitude(&ins));
    PrintCentimetres("velocity ", FusionAltitudeInsGetVerticalVelocity(&ins));
    Serial.println();
}
