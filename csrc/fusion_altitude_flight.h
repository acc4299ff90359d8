/** @file fusion_altitude_flight.h
 * @brief Deprecated name, kept for one release: include fusion_altitude_rocket.h (the rocket estimator). */
#include "fusion_altitude_rocket.h"
