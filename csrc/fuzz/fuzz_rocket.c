/**
 * @file fuzz_rocket.c
 * @brief libFuzzer target for fusion_altitude_rocket.h (the rocket flight
 * layer), built with clang under AddressSanitizer + UndefinedBehaviorSanitizer
 * by csrc/firmware/Makefile (FUZZERS), seeds in csrc/fuzz/corpus_rocket/
 * (make_seeds_rocket.py).
 *
 * The input is a sequence of calls; floats are raw bytes (any bit pattern):
 *   opcode & 3:
 *   0 initialise with the working settings (opcode & 4: with NULL, the defaults)
 *   1 edit the working settings: a word index byte (mod
 *     FUSION_ALTITUDE_ROCKET_SETTINGS_WORDS, rocket_settings_words.h: the five
 *     observer settings, then the 16 rocket settings), 4 raw bytes
 *   2 update with every argument raw: accel, baro, dt (opcode & 4: the
 *     vertical-accel update of an INS)
 *   3 update with bytes scaled into a plausible range (sane): accel in
 *     [-300, 300] m/s^2, a flags byte, baro in [-1e4, 1e5] m, dt in a range
 *     the flags choose (opcode & 4: vertical-accel update). Flags: bit 0 a
 *     baro sample (else NaN), bit 1 no accel sample (NaN: baro-led from
 *     then on), bits 2-3 the dt range: 0 [1e-3, 0.05] s (the seeds'), 1
 *     [1e-4, 10] s (any step, gaps of seconds), 2 [0.1, 4] s (telemetry
 *     packets and their gaps), 3 [1e-4, 0.05] s
 *
 * Asserted after every call (abort, so libFuzzer reports a crash):
 *   - a rejected call leaves the rocket estimator bit-identical (memcmp, padding
 *     included); an update returns FusionAltitudeRocketCheckInputs of its
 *     inputs, an initialise FusionAltitudeRocketSettingsCheck of its settings;
 *   - the phase never goes back and a declared event (but maximum speed, a
 *     running maximum) is never rewritten between initialisations;
 *   - apogee is declared only after launch, and either outside the baro
 *     lockout with the velocity below -apogeeMargin or with the baro more
 *     than spikeThreshold below its peak (a coast the baro contradicts);
 *   - while the run is sane (every accepted update scaled as above, at most
 *     20000 updates, settings in use within plausible bounds, the observer
 *     gains stable at the rocket estimator's gap period too), height, velocity,
 *     bias, pad altitude, time, baro offsets and baro peak are finite, and
 *     bounded: |velocity| <= 1e9 m/s and |height| <= 1e14 m (300 m/s^2 held
 *     over 20000 steps of 10 s reaches 6e7 m/s and 6e12 m).
 */

#include "fusion_altitude_rocket.h"
#include "fuzz_common.h"
#include "tests/vectors/rocket_settings_words.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_STEPS (20000)

/* A byte pair scaled to [minimum, maximum]. */
static bool ReadScaled(Reader *const reader, const float minimum, const float maximum, float *const value) {
    uint16_t raw;
    if (!ReadBytes(reader, &raw, sizeof(raw))) {
        return false;
    }
    *value = minimum + ((float) raw / 65535.0f) * (maximum - minimum);
    return true;
}

/* Plausible settings: gains the observer validates at the sane dt range, and bounded thresholds. */
static bool SaneSettings(const FusionAltitudeRocketSettings *const s) {
    const bool gains = (FusionAltitudeSettingsValidate(&s->observer, 1e-3f) == FusionAltitudeStatusOk) &&
                       (FusionAltitudeSettingsValidate(&s->observer, 0.05f) == FusionAltitudeStatusOk) &&
                       InRange(s->gapPeriod, 1e-4f, 10.0f) &&
                       (FusionAltitudeSettingsValidate(&s->observer, s->gapPeriod) == FusionAltitudeStatusOk) &&
                       InRange(s->observer.positionGain, 0.0f, 100.0f) && InRange(s->observer.velocityGain, 0.0f, 1e3f) &&
                       InRange(s->observer.biasGain, 0.0f, 1e3f);
    return gains && InRange(s->stationaryAccel, 0.0f, 1e3f) && InRange(s->calibrationWindow, 0.0f, 1e3f) &&
           InRange(s->launchAccel, 0.0f, 1e3f) && InRange(s->launchTime, 0.0f, 1e3f) && InRange(s->burnoutAccel, -1e3f, 1e3f) &&
           InRange(s->burnoutTime, 0.0f, 1e3f) && InRange(s->apogeeMargin, 0.0f, 1e3f) && InRange(s->lockoutSpeed, 0.0f, 1e4f) &&
           InRange(s->spikeThreshold, 0.0f, 1e5f) && InRange(s->spikeTime, 0.0f, 1e3f) && InRange(s->mainAltitude, 0.0f, 1e5f) &&
           InRange(s->landedSpeed, 0.0f, 1e3f) && InRange(s->landedTime, 0.0f, 1e3f) && InRange(s->baroLaunchHeight, 0.0f, 1e5f);
}

static void CheckState(const FusionAltitudeRocket *const rocket, const FusionAltitudeRocket *const before, const bool sane) {
    CHECK(rocket->phase >= before->phase);
    for (int i = 0; i < FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS; i++) {
        if (before->events[i].occurred && (i != (int) FusionAltitudeRocketEventMaxSpeed)) { /* max speed: a running maximum */
            CHECK(memcmp(&rocket->events[i], &before->events[i], sizeof(rocket->events[i])) == 0);
        }
    }
    const FusionAltitudeRocketEvent apogee = FusionAltitudeRocketGetEvent(rocket, FusionAltitudeRocketEventApogee);
    if (apogee.occurred && !before->events[FusionAltitudeRocketEventApogee].occurred) {
        CHECK(before->events[FusionAltitudeRocketEventLaunch].occurred);
        const bool contradicted = rocket->lastBaro < (rocket->baroPeak - rocket->settings.spikeThreshold);
        CHECK(contradicted || (!FusionAltitudeRocketIsLockedOut(rocket) && (apogee.velocity < -rocket->settings.apogeeMargin)));
    }
    if (sane) {
        CHECK(FusionAltitudeIsFinite(FusionAltitudeRocketGetHeight(rocket)));
        CHECK(FusionAltitudeIsFinite(FusionAltitudeRocketGetVerticalVelocity(rocket)));
        CHECK(FusionAltitudeIsFinite(FusionAltitudeRocketGetAccelBias(rocket)));
        CHECK(FusionAltitudeIsFinite(FusionAltitudeRocketGetPadAltitude(rocket)));
        CHECK(FusionAltitudeIsFinite(FusionAltitudeRocketGetTime(rocket)));
        CHECK(FusionAltitudeIsFinite(rocket->baroOffset) && FusionAltitudeIsFinite(rocket->offsetApplied));
        CHECK(FusionAltitudeIsFinite(rocket->baroPeak));
        const float velocity = FusionAltitudeRocketGetVerticalVelocity(rocket);
        const float height = FusionAltitudeRocketGetHeight(rocket);
        CHECK((velocity <= 1e9f) && (velocity >= -1e9f) && (height <= 1e14f) && (height >= -1e14f));
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Reader reader = {data, size};
    FusionAltitudeRocket rocket;
    memset(&rocket, 0, sizeof(rocket));
    CHECK(FusionAltitudeRocketInitialise(&rocket, NULL) == FusionAltitudeRocketStatusOk);
    FusionAltitudeRocketSettings working = FusionAltitudeRocketSettingsDefault();
    bool sane = true;
    int steps = 0;
    uint8_t opcode;
    while (ReadBytes(&reader, &opcode, 1)) {
        FusionAltitudeRocket before;
        memcpy(&before, &rocket, sizeof(rocket));
        bool initialised = false;
        switch (opcode & 3) {
            case 0: {
                const FusionAltitudeRocketSettings *const settings = (opcode & 4) ? NULL : &working;
                const FusionAltitudeRocketSettings defaults = FusionAltitudeRocketSettingsDefault();
                const FusionAltitudeRocketStatus status = FusionAltitudeRocketInitialise(&rocket, settings);
                CHECK(status == FusionAltitudeRocketSettingsCheck(settings == NULL ? &defaults : settings));
                if (status == FusionAltitudeRocketStatusOk) {
                    sane = SaneSettings(settings == NULL ? &defaults : settings);
                    steps = 0;
                    initialised = true;
                } else {
                    CHECK(memcmp(&rocket, &before, sizeof(rocket)) == 0);
                }
                break;
            }
            case 1: {
                uint8_t field;
                uint32_t word;
                if (!ReadBytes(&reader, &field, 1) || !ReadBytes(&reader, &word, sizeof(word))) {
                    return 0;
                }
                FusionAltitudeRocketSettingsSetWord(&working, field % FUSION_ALTITUDE_ROCKET_SETTINGS_WORDS, word);
                break;
            }
            default: {
                float accel, baro, dt;
                if ((opcode & 3) == 2) {
                    if (!ReadFloat(&reader, &accel) || !ReadFloat(&reader, &baro) || !ReadFloat(&reader, &dt)) {
                        return 0;
                    }
                } else {
                    uint8_t flags;
                    if (!ReadScaled(&reader, -300.0f, 300.0f, &accel) || !ReadBytes(&reader, &flags, 1) ||
                        !ReadScaled(&reader, -1e4f, 1e5f, &baro)) {
                        return 0;
                    }
                    static const float dtRanges[4][2] = {{1e-3f, 0.05f}, {1e-4f, 10.0f}, {0.1f, 4.0f}, {1e-4f, 0.05f}};
                    const int range = (flags >> 2) & 3;
                    if (!ReadScaled(&reader, dtRanges[range][0], dtRanges[range][1], &dt)) {
                        return 0;
                    }
                    if (!(flags & 1)) {
                        baro = FUSION_ALTITUDE_NO_BARO;
                    }
                    if (flags & 2) {
                        accel = FUSION_ALTITUDE_NO_BARO; /* NaN: no accelerometer sample */
                    }
                }
                const FusionAltitudeRocketStatus status = (opcode & 4) ? FusionAltitudeRocketUpdateWithVerticalAccel(&rocket, accel, baro, dt)
                                                                       : FusionAltitudeRocketUpdate(&rocket, accel, baro, dt);
                CHECK(status == FusionAltitudeRocketCheckInputs(accel, baro, dt));
                if (status != FusionAltitudeRocketStatusOk) {
                    CHECK(memcmp(&rocket, &before, sizeof(rocket)) == 0);
                } else {
                    sane = sane && (FusionAltitudeIsNaN(accel) || InRange(accel, -300.0f, 300.0f)) &&
                           (FusionAltitudeIsNaN(baro) || InRange(baro, -1e4f, 1e5f)) && InRange(dt, 1e-4f, 10.0f) &&
                           (++steps <= MAX_STEPS);
                }
                break;
            }
        }
        CheckState(&rocket, initialised ? &rocket : &before, sane);
    }
    return 0;
}
