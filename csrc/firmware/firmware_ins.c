/**
 * @file firmware_ins.c
 * @brief A firmware-style translation unit that calls every public function
 * of fusion_altitude_ins.h: set-up with checked settings and a 500 Hz IMU
 * task (the seed's rate) with a baro at about 71 Hz (every 7th tick) and a
 * magnetometer at 50 Hz (every 10th tick). Cross-compiled for each target
 * with warnings as errors; its object code is checked for double
 * instructions and for libm calls other than sqrtf (with sized_ins.c, one
 * out-of-line copy of each public function).
 */

#include "fusion_altitude_ins.h"

volatile float firmwareInsGyro[3];  /* rad/s, body */
volatile float firmwareInsAccel[3]; /* m/s^2, body, specific force */
volatile float firmwareInsMag[3];   /* any unit, body */
volatile float firmwareInsBaro;     /* m, pressure altitude */
volatile float firmwareInsAltitude; /* m above the reference, +up */
volatile float firmwareInsVelocity; /* m/s, +up */
volatile float firmwareInsQuaternion[4];
volatile float firmwareInsGlobal[4];
volatile float firmwareInsYaw[4];
volatile float firmwareInsGyroBias[3];  /* rad/s */
volatile float firmwareInsAccelZBias;   /* m/s^2 */
volatile float firmwareInsBaroBias;     /* m */
volatile float firmwareInsBaroNoise;    /* m */
volatile bool firmwareInsStationary;
volatile bool firmwareInsAccelRejected;
volatile uint32_t firmwareInsGaps;
volatile uint32_t firmwareInsBaroRejections; /* baro readings the innovation gate rejected */
volatile uint32_t firmwareInsBaroResets;     /* height resets after a rejection streak */
volatile bool firmwareInsBaroRejecting;
volatile bool firmwareInsBaroAided;     /* false while the baro is timed out */
volatile bool firmwareInsHeightHeld;    /* dead reckoning stopped beyond the horizon */
volatile uint32_t firmwareInsBaroTimeouts;
volatile uint32_t firmwareInsTick;
const char *volatile firmwareInsError;

static FusionAltitudeIns firmwareIns;

bool FirmwareInsSetup(void);
void FirmwareInsTask(void);

/* Defaults with a noisier baro and a shorter stationary window, checked before use. */
bool FirmwareInsSetup(void) {
    FusionAltitudeInsSettings settings = FusionAltitudeInsSettingsDefault();
    settings.baroNoise = 0.5f;
    settings.stationaryWindow = 0.5f;
    FusionAltitudeInsStatus status = FusionAltitudeInsSettingsCheck(&settings);
    if (status == FusionAltitudeInsStatusOk) {
        status = FusionAltitudeInsInitialiseWith(&firmwareIns, &settings);
    }
    if (status != FusionAltitudeInsStatusOk) {
        firmwareInsError = FusionAltitudeInsStatusMessage(status);
        FusionAltitudeInsInitialise(&firmwareIns); /* fall back to the defaults */
        return false;
    }
    return true;
}

/* One 500 Hz IMU step. */
void FirmwareInsTask(void) {
    const uint32_t tick = firmwareInsTick++;
    FusionAltitudeInsVector gyro, accel, mag;
    gyro.x = firmwareInsGyro[0];
    gyro.y = firmwareInsGyro[1];
    gyro.z = firmwareInsGyro[2];
    accel.x = firmwareInsAccel[0];
    accel.y = firmwareInsAccel[1];
    accel.z = firmwareInsAccel[2];
    if ((tick % 10u) == 0u) {
        mag.x = firmwareInsMag[0];
        mag.y = firmwareInsMag[1];
        mag.z = firmwareInsMag[2];
    } else {
        mag = FusionAltitudeInsNoMag();
    }
    if (FusionAltitudeInsIsNoMag(mag) && ((tick % 10u) == 0u)) {
        firmwareInsError = "mag read NaN";
    }
    const float baro = ((tick % 7u) == 0u) ? firmwareInsBaro : FUSION_ALTITUDE_NO_BARO;
    const float dt = 0.002f;
    if (FusionAltitudeInsCheckInputs(gyro, accel, mag, baro, dt) != FusionAltitudeInsStatusOk) {
        firmwareInsError = "bad sample";
        return;
    }
    const FusionAltitudeInsStatus status = FusionAltitudeInsUpdate(&firmwareIns, gyro, accel, mag, baro, dt);
    if (status != FusionAltitudeInsStatusOk) {
        firmwareInsError = FusionAltitudeInsStatusMessage(status);
        return;
    }
    firmwareInsAltitude = FusionAltitudeInsGetAltitude(&firmwareIns);
    firmwareInsVelocity = FusionAltitudeInsGetVerticalVelocity(&firmwareIns);
    const FusionAltitudeInsQuaternion q = FusionAltitudeInsGetQuaternion(&firmwareIns);
    firmwareInsQuaternion[0] = q.w;
    firmwareInsQuaternion[1] = q.x;
    firmwareInsQuaternion[2] = q.y;
    firmwareInsQuaternion[3] = q.z;
    const FusionAltitudeInsQuaternion global = FusionAltitudeInsGetGlobalQuaternion(&firmwareIns);
    firmwareInsGlobal[0] = global.w;
    firmwareInsGlobal[1] = global.x;
    firmwareInsGlobal[2] = global.y;
    firmwareInsGlobal[3] = global.z;
    const FusionAltitudeInsQuaternion yaw = FusionAltitudeInsGetLocalToGlobal(&firmwareIns);
    firmwareInsYaw[0] = yaw.w;
    firmwareInsYaw[1] = yaw.x;
    firmwareInsYaw[2] = yaw.y;
    firmwareInsYaw[3] = yaw.z;
    const FusionAltitudeInsVector bias = FusionAltitudeInsGetGyroBias(&firmwareIns);
    firmwareInsGyroBias[0] = bias.x;
    firmwareInsGyroBias[1] = bias.y;
    firmwareInsGyroBias[2] = bias.z;
    firmwareInsAccelZBias = FusionAltitudeInsGetAccelZBias(&firmwareIns);
    firmwareInsBaroBias = FusionAltitudeInsGetBaroBias(&firmwareIns);
    firmwareInsStationary = FusionAltitudeInsIsStationary(&firmwareIns);
    firmwareInsAccelRejected = FusionAltitudeInsIsAccelRejected(&firmwareIns);
    firmwareInsGaps = FusionAltitudeInsGetGapCount(&firmwareIns);
    firmwareInsBaroRejections = FusionAltitudeInsGetBaroRejections(&firmwareIns);
    firmwareInsBaroResets = FusionAltitudeInsGetBaroResets(&firmwareIns);
    firmwareInsBaroRejecting = FusionAltitudeInsIsBaroRejecting(&firmwareIns);
    firmwareInsBaroAided = !FusionAltitudeInsIsBaroTimedOut(&firmwareIns);
    firmwareInsHeightHeld = FusionAltitudeInsIsHeightHeld(&firmwareIns);
    firmwareInsBaroTimeouts = FusionAltitudeInsGetBaroTimeouts(&firmwareIns);
    /* retune the baro noise in flight: a stationary vehicle trusts its baro less (ground effect) */
    FusionAltitudeInsSettings settings = FusionAltitudeInsGetSettings(&firmwareIns);
    const float baroNoise = firmwareInsStationary ? 1.0f : 0.5f;
    if (settings.baroNoise != baroNoise) {
        settings.baroNoise = baroNoise;
        if (FusionAltitudeInsSetSettings(&firmwareIns, &settings) != FusionAltitudeInsStatusOk) {
            firmwareInsError = "settings";
        }
    }
    firmwareInsBaroNoise = settings.baroNoise;
}
