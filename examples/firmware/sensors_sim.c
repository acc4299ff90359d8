/**
 * @file sensors_sim.c
 * @brief A simulated board so that the example runs on QEMU: 10 s on the
 * ground, a climb of 24 m (8 s), a hover, and at 40 s a barometer that fails
 * (its reading jumps by +40 m, e.g. a blocked static port or prop-wash). The
 * accelerometer has a 0.25 m/s^2 bias and both sensors a little noise.
 */

#include "sensors.h"

#define DURATION_TICKS (60 * SENSORS_RATE)
#define BARO_FAULT_TICK (40 * SENSORS_RATE)
#define GROUND_ALTITUDE (312.0f) /* m above sea level */
#define ACCEL_BIAS (0.25f)       /* m/s^2 */

static uint32_t tick;
static float altitude;       /* m, truth */
static float velocity;       /* m/s, truth */
static float acceleration;   /* m/s^2, truth */
static uint32_t noiseState = 1u;

/* Uniform noise in [-amplitude, amplitude] from a 32-bit LCG (no libm, no double). */
static float Noise(const float amplitude) {
    noiseState = noiseState * 1664525u + 1013904223u;
    const float unit = (float) (noiseState >> 8) * (1.0f / 16777216.0f); /* [0, 1) */
    return amplitude * (2.0f * unit - 1.0f);
}

bool SensorsWaitForTick(void) {
    tick++;
    const float t = (float) tick / (float) SENSORS_RATE; /* s */
    if ((t > 10.0f) && (t <= 14.0f)) {
        acceleration = 1.5f; /* climb */
    } else if ((t > 14.0f) && (t <= 18.0f)) {
        acceleration = -1.5f; /* level off */
    } else {
        acceleration = 0.0f;
    }
    velocity += acceleration / (float) SENSORS_RATE;
    altitude += velocity / (float) SENSORS_RATE;
    return tick <= DURATION_TICKS;
}

float SensorsReadAccel(void) {
    return acceleration + ACCEL_BIAS + Noise(0.3f);
}

bool SensorsReadBaro(float *const baroAltitude) {
    if ((tick % (SENSORS_RATE / SENSORS_BARO_RATE)) != 0u) {
        return false;
    }
    const float fault = (tick >= BARO_FAULT_TICK) ? 40.0f : 0.0f; /* m */
    *baroAltitude = GROUND_ALTITUDE + altitude + fault + Noise(0.5f);
    return true;
}

uint32_t SensorsTimeMs(void) {
    return tick * (1000u / SENSORS_RATE);
}
