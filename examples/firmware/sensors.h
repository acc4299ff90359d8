/**
 * @file sensors.h
 * @brief The board interface the example needs. Replace sensors_sim.c with
 * your drivers: an earth-frame vertical acceleration (from the AHRS, gravity
 * removed), a barometric altitude and a 100 Hz tick.
 */

#ifndef SENSORS_H
#define SENSORS_H

#include <stdbool.h>
#include <stdint.h>

#define SENSORS_RATE (100) /* Hz, the loop and accelerometer rate */
#define SENSORS_BARO_RATE (25) /* Hz, the barometer rate */

/** Blocks until the next 100 Hz tick. @return false when the (simulated) flight is over. */
bool SensorsWaitForTick(void);

/** @return vertical acceleration, m/s^2, earth frame, +up, gravity removed. */
float SensorsReadAccel(void);

/** @return true and the barometric altitude (m) when a new baro sample is ready this tick. */
bool SensorsReadBaro(float *const altitude);

/** @return the time since start-up, ms (for log messages only). */
uint32_t SensorsTimeMs(void);

#endif
