/**
 * @file fuzz_observer.c
 * @brief libFuzzer target for fusion_altitude.h, built with clang under
 * AddressSanitizer + UndefinedBehaviorSanitizer (csrc/firmware/Makefile,
 * target fuzz-run).
 *
 * The input is a loop period followed by a sequence of calls; floats are raw
 * bytes (any bit pattern: NaNs, infinities, subnormals, huge values):
 *   bytes 0-3   loop dt (float, s)
 *   then, per call, one opcode byte and its float arguments (4 bytes each):
 *   opcode & 7: 0 initialise, 1 set settings (Kh, Kv, Kb; with bit 4: the baro
 *   timeout, s, from one float, the rest kept), 2 preset (1 byte),
 *   3 bandwidth (omega, zeta, omega_b), 4 reset (z), 5 reset with bias (z, b),
 *   6 update (a, z, dt), 7 update at the loop dt (a, z);
 *   opcode bit 3 replaces z of an update with FUSION_ALTITUDE_NO_BARO.
 *   Opcode 6 draws any step: the seeds (make_seeds_observer.py) hold step
 *   sequences of 0.1 ms to 10 s and telemetry-like 0.1-4 s mixes.
 *
 * Asserted after every call (abort, so libFuzzer reports a crash):
 *   - a rejected call leaves the estimator (and a rejected settings builder
 *     its output) bit-identical (memcmp);
 *   - FusionAltitudeCheckInputs returns what FusionAltitudeUpdate returned;
 *   - an accepted update's outputs follow its contract (residual z - h or the
 *     quiet NaN 0x7FC00000, reference set by the first baro sample; a gap by
 *     the gap period or by the stability rule, FusionAltitudeIsStepStable,
 *     counted and restarted as documented; a baro timeout counted once, the
 *     velocity decaying by T/(T + dt) while timed out);
 *   - the state stays finite and within MAX_STATE (1e9: m, m/s, m/s^2) while
 *     the run is "sane" (see below).
 *
 * Finite inputs are not enough for a finite state: |a| = 3e38 m/s^2 overflows
 * float32 in one step. A run is sane while every accepted input is physically
 * plausible: |accel| <= 1e3 m/s^2, |baro| and |reset altitude| <= 1e5 m,
 * |warm-start bias| <= 1e3 m/s^2, every step 1e-4 s <= dt <= 10 s (any
 * sequence: a baro step the gains cannot integrate stably is a gap, and no
 * baro sample for more than the baro timeout stops the dead reckoning), gains
 * Kh <= 100 1/s, Kv <= 1e3 1/s^2, Kb <= 1e3 1/s^3 and at most 4 gain changes
 * since the state was last fully set (initialise or reset with bias). Under
 * those bounds the state is bounded far below float32's 3.4e38; unlimited
 * switching between stable gains can still pump energy (switched systems),
 * hence the gain-change cap.
 */

#include "fusion_altitude.h"
#include "fuzz_common.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ACCEL (1e3f)         /* m/s^2 */
#define MAX_ALTITUDE (1e5f)      /* m */
#define MAX_BIAS (1e3f)          /* m/s^2 */
#define MIN_DT (1e-4f)           /* s */
#define MAX_DT (10.0f)           /* s */
#define MAX_GAIN_CHANGES (4)
#define MAX_STATE (1e9f)         /* m, m/s, m/s^2 */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static bool SameBits(const float a, const float b) {
    return FusionAltitudeFloatBits(a) == FusionAltitudeFloatBits(b);
}

/* True while every state variable is finite and within MAX_STATE (the residual may be the no-baro NaN). */
static bool StateFinite(const FusionAltitude *const altitude) {
    const float residual = FusionAltitudeGetBaroResidual(altitude);
    return Within(FusionAltitudeGetAltitude(altitude), MAX_STATE) && Within(FusionAltitudeGetVerticalVelocity(altitude), MAX_STATE) &&
           Within(FusionAltitudeGetAccelBias(altitude), MAX_STATE) &&
           (FusionAltitudeIsFinite(residual) || (FusionAltitudeFloatBits(residual) == 0x7FC00000u));
}

/* Gains a vehicle could use (the sanity bound on the settings). */
static bool PlausibleGains(const FusionAltitudeSettings *const settings) {
    return Within(settings->positionGain, 100.0f) && Within(settings->velocityGain, 1e3f) && Within(settings->biasGain, 1e3f);
}

/* The mean velocity of a restart (FusionAltitudeRestart): 0 when it overflows. */
static float RestartVelocity(const float baro, const float altitude, const float time) {
    const float velocity = (baro - altitude) / time;
    return FusionAltitudeIsFinite(velocity) ? velocity : 0.0f;
}

typedef struct {
    bool sane;         /* all accepted inputs physically plausible so far */
    bool loopDtSane;   /* the loop dt is plausible */
    int gainChanges;   /* accepted gain changes since the state was last fully set */
    float loopDt;      /* s */
} Run;

/* Applies an accepted gain change to the run's sanity. */
static void GainsChanged(Run *const run) {
    run->gainChanges++;
    if (run->gainChanges > MAX_GAIN_CHANGES) {
        run->sane = false;
    }
}

static void Update(FusionAltitude *const altitude, Run *const run, const float accel, const float baro, const float dt) {
    FusionAltitude before;
    memcpy(&before, altitude, sizeof(before)); /* with its padding bytes */
    const FusionAltitudeStatus status = FusionAltitudeUpdate(altitude, accel, baro, dt);
    CHECK(FusionAltitudeCheckInputs(accel, baro, dt) == status);
    if (status != FusionAltitudeStatusOk) {
        CHECK(memcmp(&before, altitude, sizeof(before)) == 0);
        return;
    }
    const bool baroMissing = FusionAltitudeIsNaN(baro);
    const bool gap = before.referenceSet && (dt > before.settings.gapPeriod);
    const bool stabilityGap = !gap && !baroMissing && before.referenceSet && !before.baroTimedOut &&
                              !FusionAltitudeIsStepStable(&before.settings, dt,
                                                          FusionAltitudeIsFinite(before.settings.baroTimeout) ? (before.sinceBaro + dt) : dt);
    CHECK(FusionAltitudeGetGapCount(altitude) == before.gapCount + ((gap || stabilityGap) ? 1u : 0u));
    CHECK((FusionAltitudeGetBaroTimeouts(altitude) - before.baroTimeouts) <= 1u);
    CHECK(!FusionAltitudeIsBaroTimedOut(altitude) || baroMissing); /* a baro sample always ends a timeout */
    const FusionAltitudeSettings settings = FusionAltitudeGetSettings(altitude);
    const bool plausible = Within(accel, MAX_ACCEL) && (baroMissing || Within(baro, MAX_ALTITUDE)) && (dt >= MIN_DT) &&
                           (dt <= MAX_DT) && PlausibleGains(&settings);
    run->sane = run->sane && plausible;
    if (gap) { /* not integrated: frozen until the next baro sample, which restarts h at it */
        CHECK(SameBits(altitude->accelBias, before.accelBias));
        if (baroMissing) {
            CHECK(!altitude->referenceSet && SameBits(altitude->altitude, before.altitude) &&
                  SameBits(altitude->verticalVelocity, before.verticalVelocity));
        } else {
            CHECK(altitude->referenceSet && SameBits(altitude->altitude, baro) && SameBits(altitude->baroResidual, 0.0f));
            CHECK(SameBits(altitude->verticalVelocity, RestartVelocity(baro, before.altitude, dt)));
        }
        return;
    }
    if (stabilityGap) { /* restarted at once: h = z, r = 0, the bias held */
        CHECK(altitude->referenceSet && SameBits(altitude->altitude, baro) && SameBits(altitude->baroResidual, 0.0f));
        CHECK(SameBits(altitude->accelBias, before.accelBias) && SameBits(altitude->sinceRestart, 0.0f));
        return;
    }
    if (baroMissing) {
        CHECK(FusionAltitudeFloatBits(FusionAltitudeGetBaroResidual(altitude)) == 0x7FC00000u);
        CHECK(SameBits(altitude->accelBias, before.accelBias));
        CHECK(altitude->referenceSet == before.referenceSet);
        if (!before.referenceSet) {
            CHECK(SameBits(altitude->altitude, before.altitude) && SameBits(altitude->verticalVelocity, before.verticalVelocity));
        } else if (before.baroTimedOut) { /* no dead reckoning: v decays */
            const float timeout = before.settings.baroTimeout;
            CHECK(SameBits(altitude->verticalVelocity, before.verticalVelocity * (timeout / (timeout + dt))));
        }
    } else if (!before.referenceSet) { /* auto-zero (v = 0) or the restart after a gap (v = mean velocity over it) */
        const float velocity = (before.gapTime > 0.0f) ? RestartVelocity(baro, before.altitude, before.gapTime + dt) : 0.0f;
        CHECK(SameBits(altitude->altitude, baro) && SameBits(altitude->verticalVelocity, velocity));
        CHECK(SameBits(altitude->baroResidual, 0.0f) && SameBits(altitude->accelBias, before.accelBias));
    } else if (before.baroTimedOut) { /* the restart after a timeout: h = z, v kept */
        CHECK(SameBits(altitude->altitude, baro) && SameBits(altitude->verticalVelocity, before.verticalVelocity));
        CHECK(SameBits(altitude->baroResidual, 0.0f));
    } else {
        CHECK(SameBits(altitude->baroResidual, baro - before.altitude));
    }
    CHECK(FusionAltitudeIsReferenceSet(altitude) == (before.referenceSet || !baroMissing));
}

/* Opcode 1: the gains (Kh, Kv, Kb), or with bit 4 the baro timeout (s), the rest kept. False when the input ends. */
static bool CallSetSettings(FusionAltitude *const altitude, Run *const run, Reader *const reader, const uint8_t opcode,
                            FusionAltitudeStatus *const status) {
    float x = 0.0f;
    float y = 0.0f;
    float z = 0.0f;
    FusionAltitudeSettings settings;
    memset(&settings, 0xA5, sizeof(settings));
    if ((opcode & 16u) != 0u) { /* the baro timeout, s */
        if (!ReadFloat(reader, &x)) {
            return false;
        }
        settings = FusionAltitudeGetSettings(altitude);
        settings.baroTimeout = x;
        *status = FusionAltitudeSetSettings(altitude, &settings);
        CHECK(*status == FusionAltitudeSettingsCheck(&settings));
        return true;
    }
    if (!ReadFloat(reader, &x) || !ReadFloat(reader, &y) || !ReadFloat(reader, &z)) {
        return false;
    }
    settings.positionGain = x;
    settings.velocityGain = y;
    settings.biasGain = z;
    settings.gapPeriod = FusionAltitudeGetSettings(altitude).gapPeriod;
    settings.baroTimeout = FusionAltitudeGetSettings(altitude).baroTimeout;
    *status = FusionAltitudeSetSettings(altitude, &settings);
    CHECK(*status == FusionAltitudeSettingsCheck(&settings));
    if (*status == FusionAltitudeStatusOk) {
        GainsChanged(run);
    }
    return true;
}

/* Opcodes 2 (a preset, 1 byte) and 3 (bandwidth omega, zeta, omega_b): a rejected builder leaves its output untouched;
 * accepted settings are set. False when the input ends. */
static bool CallBuildSettings(FusionAltitude *const altitude, Run *const run, Reader *const reader, const uint8_t opcode,
                              FusionAltitudeStatus *const status) {
    FusionAltitudeSettings settings;
    FusionAltitudeSettings untouched;
    memset(&settings, 0xA5, sizeof(settings));
    untouched = settings;
    if ((opcode & 7u) == 2u) {
        uint8_t preset;
        if (!ReadByte(reader, &preset)) {
            return false;
        }
        *status = FusionAltitudeSettingsFromPreset(&settings, (FusionAltitudePreset) (preset % 6u));
        CHECK((*status != FusionAltitudeStatusOk) || (FusionAltitudeSettingsCheck(&settings) == FusionAltitudeStatusOk));
    } else {
        float x = 0.0f;
        float y = 0.0f;
        float z = 0.0f;
        if (!ReadFloat(reader, &x) || !ReadFloat(reader, &y) || !ReadFloat(reader, &z)) {
            return false;
        }
        *status = FusionAltitudeSettingsFromBandwidth(&settings, x, y, z);
    }
    if (*status != FusionAltitudeStatusOk) {
        CHECK(memcmp(&settings, &untouched, sizeof(settings)) == 0);
        return true;
    }
    *status = FusionAltitudeSetSettings(altitude, &settings);
    CHECK(*status == FusionAltitudeStatusOk);
    GainsChanged(run);
    return true;
}

/* Opcodes 4 (reset at z, m) and 5 (reset at z with the bias b, m/s^2). False when the input ends. */
static bool CallReset(FusionAltitude *const altitude, Run *const run, Reader *const reader, const uint8_t opcode,
                      FusionAltitudeStatus *const status) {
    const float biasBefore = altitude->accelBias;
    float x = 0.0f;
    float y = 0.0f;
    if ((opcode & 7u) == 4u) {
        if (!ReadFloat(reader, &x)) {
            return false;
        }
        *status = FusionAltitudeReset(altitude, x);
        if (*status == FusionAltitudeStatusOk) {
            CHECK(SameBits(altitude->altitude, x) && SameBits(altitude->accelBias, biasBefore));
            run->sane = run->sane && Within(x, MAX_ALTITUDE);
        }
        return true;
    }
    if (!ReadFloat(reader, &x) || !ReadFloat(reader, &y)) {
        return false;
    }
    *status = FusionAltitudeResetWithBias(altitude, x, y);
    if (*status == FusionAltitudeStatusOk) {
        CHECK(SameBits(altitude->altitude, x) && SameBits(altitude->accelBias, y));
        run->sane = run->loopDtSane && Within(x, MAX_ALTITUDE) && Within(y, MAX_BIAS);
        run->gainChanges = 0;
    }
    return true;
}

/* Opcodes 6 (update: a, z, dt) and 7 (update at the loop dt: a, z); bit 3: no baro. False when the input ends. */
static bool CallUpdate(FusionAltitude *const altitude, Run *const run, Reader *const reader, const uint8_t opcode) {
    float x = 0.0f;
    float y = 0.0f;
    float z = run->loopDt;
    if (!ReadFloat(reader, &x) || !ReadFloat(reader, &y) || (((opcode & 7u) == 6u) && !ReadFloat(reader, &z))) {
        return false;
    }
    Update(altitude, run, x, ((opcode & 8u) != 0u) ? FUSION_ALTITUDE_NO_BARO : y, z);
    return true;
}

/* One call of the input (its opcode already read); false when the input ends before its arguments. */
static bool Call(FusionAltitude *const altitude, Run *const run, Reader *const reader, const uint8_t opcode,
                 FusionAltitudeStatus *const status) {
    switch (opcode & 7u) {
        case 0:
            FusionAltitudeInitialise(altitude);
            run->sane = run->loopDtSane;
            run->gainChanges = 0;
            return true;
        case 1:
            return CallSetSettings(altitude, run, reader, opcode, status);
        case 2:
        case 3:
            return CallBuildSettings(altitude, run, reader, opcode, status);
        case 4:
        case 5:
            return CallReset(altitude, run, reader, opcode, status);
        default:
            return CallUpdate(altitude, run, reader, opcode);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Reader reader = {data, size};
    Run run = {true, true, 0, 0.0f};
    if (!ReadFloat(&reader, &run.loopDt)) {
        return 0;
    }
    run.sane = (run.loopDt >= MIN_DT) && (run.loopDt <= MAX_DT);
    run.loopDtSane = run.sane;
    FusionAltitude altitude;
    memset(&altitude, 0, sizeof(altitude)); /* defined padding bytes for memcmp */
    FusionAltitudeInitialise(&altitude);
    uint8_t opcode;
    while (ReadByte(&reader, &opcode)) {
        FusionAltitude before;
        memcpy(&before, &altitude, sizeof(before));
        FusionAltitudeStatus status = FusionAltitudeStatusOk;
        if (!Call(&altitude, &run, &reader, opcode, &status)) {
            return 0;
        }
        if (status != FusionAltitudeStatusOk) {
            CHECK(memcmp(&before, &altitude, sizeof(before)) == 0);
        }
        (void) FusionAltitudeStatusMessage(status);
        if (run.sane) {
            CHECK(StateFinite(&altitude));
        }
    }
    return 0;
}
