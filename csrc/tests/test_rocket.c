/**
 * @file test_rocket.c
 * @brief Unit tests of fusion_altitude_rocket.h (pad calibration, baro gate,
 * flight phases), built by tests/test_c_core.py with gcc and clang (C99 and as
 * C++), strict warnings, and under ASan + UBSan. Prints "N passed, M failed".
 */

#include "fusion_altitude_rocket.h"
#include "test_harness.h"

#include <string.h>

#define DT (0.01f)
#define G (FUSION_ALTITUDE_GRAVITY)
#define PAD_ALTITUDE (1400.0f)

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static bool SameBits(const FusionAltitudeRocket *const a, const FusionAltitudeRocket *const b) {
    return memcmp(a, b, sizeof(*a)) == 0;
}

static FusionAltitudeRocket NewRocket(const FusionAltitudeRocketSettings *const settings) {
    FusionAltitudeRocket rocket;
    memset(&rocket, 0, sizeof(rocket));
    (void) FusionAltitudeRocketInitialise(&rocket, settings);
    return rocket;
}

/* A synthetic flight without drag: pad 2 s, boost at +50 m/s^2 net for
 * 5 s (250 m/s), coast at -g to apogee, drogue at -20 m/s, main at -6 m/s,
 * landing, rest. Truth height/velocity at step k (time (k+1)*DT). Accel input
 * has a +0.3 m/s^2 bias; baro has no noise. */
typedef struct {
    float height;
    float velocity;
    float accel;     /* input: measured long-axis accel minus g */
    float baro;      /* input: pressure altitude */
} Sample;

static Sample Truth(int step, float *const stateHeight, float *const stateVelocity) {
    const float t = (float) (step + 1) * DT;
    float a;
    if (t <= 2.0f) {
        a = 0.0f;
    } else if (t <= 7.0f) {
        a = 50.0f;
    } else if ((*stateVelocity > 0.0f) && (*stateHeight > 100.0f)) {
        a = -G;
    } else if (*stateHeight > 250.0f) {
        a = (-20.0f - *stateVelocity) * 2.0f;
    } else if (*stateHeight > 0.0f) {
        a = (-6.0f - *stateVelocity) * 2.0f;
    } else {
        a = 0.0f;
        *stateVelocity = 0.0f;
    }
    *stateVelocity += a * DT;
    *stateHeight += *stateVelocity * DT;
    if ((*stateHeight < 0.0f) && (t > 7.0f)) {
        *stateHeight = 0.0f;
        *stateVelocity = 0.0f;
    }
    Sample sample;
    sample.height = *stateHeight;
    sample.velocity = *stateVelocity;
    sample.accel = a + 0.3f;
    sample.baro = PAD_ALTITUDE + *stateHeight;
    return sample;
}

static void DefaultsPassTheirCheck(void) {
    const FusionAltitudeRocketSettings settings = FusionAltitudeRocketSettingsDefault();
    CHECK(FusionAltitudeRocketSettingsCheck(&settings) == FusionAltitudeRocketStatusOk);
    CHECK(settings.observer.positionGain == 1.4f);
    CHECK(settings.observer.velocityGain == 1.0f);
    CHECK(settings.observer.biasGain == 0.0f);
    CHECK(settings.lockoutSpeed == 100.0f);
}

static void EachBadSettingIsRejectedWithItsOwnStatus(void) {
    /* fields after the observer, in check order, each with a bad value */
    FusionAltitudeRocketSettings settings = FusionAltitudeRocketSettingsDefault();
    float *const fields[] = {&settings.stationaryAccel, &settings.calibrationWindow, &settings.launchAccel, &settings.launchTime,
                             &settings.burnoutAccel, &settings.burnoutTime, &settings.apogeeMargin, &settings.lockoutSpeed,
                             &settings.spikeThreshold, &settings.spikeTime, &settings.offsetRate, &settings.mainAltitude,
                             &settings.landedSpeed, &settings.landedTime, &settings.gapPeriod};
    const int count = (int) (sizeof(fields) / sizeof(fields[0]));
    for (int index = 0; index < count; index++) {
        settings = FusionAltitudeRocketSettingsDefault();
        *fields[index] = FusionAltitudeNaN();
        CHECK(FusionAltitudeRocketSettingsCheck(&settings) ==
              (FusionAltitudeRocketStatus) ((int) FusionAltitudeRocketStatusInvalidStationaryAccel + index));
    }
    settings = FusionAltitudeRocketSettingsDefault();
    settings.observer.velocityGain = -1.0f;
    CHECK(FusionAltitudeRocketSettingsCheck(&settings) == FusionAltitudeRocketStatusInvalidObserverSettings);
    settings = FusionAltitudeRocketSettingsDefault();
    settings.offsetRate = 1.5f;
    CHECK(FusionAltitudeRocketSettingsCheck(&settings) == FusionAltitudeRocketStatusInvalidOffsetRate);
    settings = FusionAltitudeRocketSettingsDefault();
    settings.gapPeriod = Infinity();
    CHECK(FusionAltitudeRocketSettingsCheck(&settings) == FusionAltitudeRocketStatusOk);
    settings.burnoutAccel = -5.0f;
    CHECK(FusionAltitudeRocketSettingsCheck(&settings) == FusionAltitudeRocketStatusOk);
}

static void InitialiseWithBadSettingsLeavesTheStateUntouched(void) {
    FusionAltitudeRocket rocket;
    memset(&rocket, 0xA5, sizeof(rocket));
    FusionAltitudeRocket before;
    memcpy(&before, &rocket, sizeof(rocket));
    FusionAltitudeRocketSettings settings = FusionAltitudeRocketSettingsDefault();
    settings.lockoutSpeed = 0.0f;
    CHECK(FusionAltitudeRocketInitialise(&rocket, &settings) == FusionAltitudeRocketStatusInvalidLockoutSpeed);
    CHECK(SameBits(&rocket, &before));
    CHECK(FusionAltitudeRocketInitialise(&rocket, NULL) == FusionAltitudeRocketStatusOk);
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhasePad);
}

static void BadInputsReturnAStatusAndLeaveTheStateBitIdentical(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 1000; step++) { /* into the coast */
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
    }
    CHECK(FusionAltitudeRocketGetPhase(&rocket) != FusionAltitudeRocketPhasePad);
    FusionAltitudeRocket before;
    memcpy(&before, &rocket, sizeof(rocket));
    CHECK(FusionAltitudeRocketUpdate(&rocket, Infinity(), 1500.0f, DT) == FusionAltitudeRocketStatusInvalidAccel); /* NaN: no sample */
    CHECK(FusionAltitudeRocketUpdate(&rocket, 0.0f, Infinity(), DT) == FusionAltitudeRocketStatusInvalidBaroAltitude);
    CHECK(FusionAltitudeRocketUpdate(&rocket, 0.0f, 1500.0f, 0.0f) == FusionAltitudeRocketStatusInvalidDt);
    CHECK(FusionAltitudeRocketUpdateWithVerticalAccel(&rocket, 0.0f, 1500.0f, -DT) == FusionAltitudeRocketStatusInvalidDt);
    CHECK(FusionAltitudeRocketUpdate(&rocket, 0.0f, 1500.0f, FusionAltitudeNaN()) == FusionAltitudeRocketStatusInvalidDt);
    CHECK(SameBits(&rocket, &before));
}

static void PadCalibrationLearnsBiasAndPadAltitudeFromStationaryWindows(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    CHECK(!FusionAltitudeRocketIsCalibrated(&rocket));
    for (int step = 0; step < 300; step++) { /* 3 s: six 0.5 s windows */
        const float wobble = ((step % 2) == 0) ? 0.5f : -0.5f;
        (void) FusionAltitudeRocketUpdate(&rocket, 0.25f + wobble, PAD_ALTITUDE + 0.4f * wobble, DT);
    }
    CHECK(FusionAltitudeRocketIsCalibrated(&rocket));
    /* 0.01 s steps sum to 0.5 s after 51 samples in float32: an odd count, so the mean is 0.25 +- 0.5/51 */
    CHECK(FusionAltitudeRocketGetAccelBias(&rocket) > 0.239f && FusionAltitudeRocketGetAccelBias(&rocket) < 0.261f);
    CHECK(FusionAltitudeRocketGetPadAltitude(&rocket) > PAD_ALTITUDE - 0.01f && FusionAltitudeRocketGetPadAltitude(&rocket) < PAD_ALTITUDE + 0.01f);
    CHECK(FusionAltitudeRocketGetHeight(&rocket) == 0.0f);
    CHECK(FusionAltitudeRocketGetVerticalVelocity(&rocket) == 0.0f);
}

static void AShakenWindowNeverEntersTheCalibration(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    for (int step = 0; step < 100; step++) { /* stationary at 0.2 m/s^2: windows end after samples 51 and 102 */
        (void) FusionAltitudeRocketUpdate(&rocket, 0.2f, PAD_ALTITUDE, DT);
    }
    const float bias = FusionAltitudeRocketGetAccelBias(&rocket);
    for (int step = 0; step < 50; step++) { /* shaken: 6 m/s^2 off with a 15 m/s^2 knock; both windows it touches are discarded */
        (void) FusionAltitudeRocketUpdate(&rocket, (step == 25) ? 15.0f : 6.2f, PAD_ALTITUDE + 30.0f, DT);
    }
    CHECK(FusionAltitudeRocketGetAccelBias(&rocket) == bias);
    CHECK(FusionAltitudeRocketGetPadAltitude(&rocket) == PAD_ALTITUDE);
}

static void TheLaunchTransientNeverEntersTheBias(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    for (int step = 0; step < 200; step++) {
        (void) FusionAltitudeRocketUpdate(&rocket, 0.3f, PAD_ALTITUDE, DT);
    }
    const float bias = FusionAltitudeRocketGetAccelBias(&rocket);
    /* a ramp from 0.3 to 60 m/s^2 over 0.1 s, starting just before a window ends */
    for (int step = 0; step < 30; step++) {
        const float accel = 0.3f + 6.0f * (float) ((step < 10) ? step : 10);
        (void) FusionAltitudeRocketUpdate(&rocket, accel, PAD_ALTITUDE, DT);
    }
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseBoost);
    CHECK(FusionAltitudeRocketGetAccelBias(&rocket) == bias);
}

static void LaunchIsDatedAtTheFirstSampleAboveTheThreshold(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    for (int step = 0; step < 100; step++) {
        (void) FusionAltitudeRocketUpdate(&rocket, 0.0f, PAD_ALTITUDE, DT);
    }
    for (int step = 0; step < 4; step++) { /* 0.04 s < launchTime 0.05 s: no launch */
        (void) FusionAltitudeRocketUpdate(&rocket, 40.0f, PAD_ALTITUDE, DT);
    }
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhasePad);
    (void) FusionAltitudeRocketUpdate(&rocket, 0.0f, PAD_ALTITUDE, DT); /* the knock ends: candidate dropped */
    CHECK(FusionAltitudeRocketGetHeight(&rocket) == 0.0f);
    for (int step = 0; step < 10; step++) {
        (void) FusionAltitudeRocketUpdate(&rocket, 40.0f, PAD_ALTITUDE, DT);
    }
    const FusionAltitudeRocketEvent launch = FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventLaunch);
    CHECK(launch.occurred);
    CHECK(launch.sample == 105u);
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseBoost);
    CHECK(FusionAltitudeRocketGetVerticalVelocity(&rocket) > 3.99f && FusionAltitudeRocketGetVerticalVelocity(&rocket) < 4.01f);
}

static void ASyntheticFlightDeclaresEveryEventInOrderAndApogeeJustAfterTheTruth(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    float apogeeTime = 0.0f;
    float apogeeHeight = 0.0f;
    float maxHeightSoFar = 0.0f;
    float largestDrop = 0.0f;
    bool lockoutEvent = false;
    for (int step = 0; step < 30000; step++) {
        const FusionAltitudeRocketPhase before = FusionAltitudeRocketGetPhase(&rocket);
        const Sample s = Truth(step, &h, &v);
        if (h > apogeeHeight) {
            apogeeHeight = h;
            apogeeTime = (float) (step + 1) * DT;
        }
        CHECK(FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT) == FusionAltitudeRocketStatusOk);
        const FusionAltitudeRocketPhase after = FusionAltitudeRocketGetPhase(&rocket);
        if ((after != before) && (after >= FusionAltitudeRocketPhaseDrogue) && FusionAltitudeRocketIsLockedOut(&rocket)) {
            lockoutEvent = true;
        }
        const float estimate = FusionAltitudeRocketGetHeight(&rocket);
        if ((after == FusionAltitudeRocketPhaseBoost) || (after == FusionAltitudeRocketPhaseCoast)) {
            maxHeightSoFar = (estimate > maxHeightSoFar) ? estimate : maxHeightSoFar;
            largestDrop = ((maxHeightSoFar - estimate) > largestDrop) ? (maxHeightSoFar - estimate) : largestDrop;
        }
    }
    CHECK(!lockoutEvent);
    CHECK(largestDrop < 1.0f);
    for (int event = 0; event < FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS; event++) {
        CHECK(FusionAltitudeRocketGetEvent(&rocket, (FusionAltitudeRocketEventId) event).occurred);
    }
    const FusionAltitudeRocketEvent launch = FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventLaunch);
    const FusionAltitudeRocketEvent burnout = FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventBurnout);
    const FusionAltitudeRocketEvent apogee = FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventApogee);
    const FusionAltitudeRocketEvent mainEvent = FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventMain);
    const FusionAltitudeRocketEvent landed = FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventLanded);
    CHECK(launch.time > 2.0f && launch.time < 2.02f);
    CHECK(burnout.time > 7.0f && burnout.time < 7.02f);
    CHECK(apogee.time > apogeeTime && apogee.time < apogeeTime + 0.5f);
    CHECK(apogee.height > 0.99f * apogeeHeight && apogee.height < 1.01f * apogeeHeight);
    CHECK(mainEvent.height <= 250.0f && mainEvent.height > 240.0f);
    CHECK(landed.time > mainEvent.time);
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseLanded);
}

static void TheBaroIsLockedOutAboveMachWhateverTheSetting(void) {
    FusionAltitudeRocketSettings settings = FusionAltitudeRocketSettingsDefault();
    settings.lockoutSpeed = 1000.0f;
    FusionAltitudeRocket rocket = NewRocket(&settings);
    float h = 0.0f;
    float v = 0.0f;
    bool fusedAboveMach = false;
    bool lockedOut = false;
    for (int step = 0; step < 1500; step++) {
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
        const float speed = FusionAltitudeRocketGetVerticalVelocity(&rocket);
        if ((speed > FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT) && (FusionAltitudeRocketGetBaro(&rocket) == FusionAltitudeRocketBaroFused)) {
            fusedAboveMach = true;
        }
        lockedOut = lockedOut || (FusionAltitudeRocketGetBaro(&rocket) == FusionAltitudeRocketBaroLockedOut &&
                                  FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseCoast);
    }
    CHECK(!fusedAboveMach);
    CHECK(lockedOut);
}

static void NoApogeeWhileLockedOutEvenIfTheBaroFalls(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    for (int step = 0; step < 100; step++) {
        (void) FusionAltitudeRocketUpdate(&rocket, 0.0f, PAD_ALTITUDE, DT);
    }
    for (int step = 0; step < 300; step++) { /* 3 s at 60 m/s^2: 180 m/s */
        (void) FusionAltitudeRocketUpdate(&rocket, 60.0f, PAD_ALTITUDE + 5.0f, DT);
    }
    for (int step = 0; step < 300; step++) { /* coasting at constant speed, the baro reads ever lower */
        (void) FusionAltitudeRocketUpdate(&rocket, -0.1f, PAD_ALTITUDE - 10.0f * (float) step, DT);
        CHECK(FusionAltitudeRocketGetBaro(&rocket) != FusionAltitudeRocketBaroFused);
    }
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseCoast);
    CHECK(!FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventApogee).occurred);
}

static void ASingleBaroSpikeIsRejected(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 4000; step++) { /* into the drogue descent */
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
    }
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseDrogue);
    const Sample s = Truth(4000, &h, &v);
    const float before = FusionAltitudeRocketGetHeight(&rocket);
    (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro - 300.0f, DT);
    CHECK(FusionAltitudeRocketGetBaro(&rocket) == FusionAltitudeRocketBaroSpike);
    const float after = FusionAltitudeRocketGetHeight(&rocket);
    CHECK(after - before > -1.0f && after - before < 0.0f);
}

static void ALastingBaroStepIsAcceptedAfterSpikeTime(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 4000; step++) {
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
    }
    int spikes = 0;
    for (int step = 4000; step < 4100; step++) {
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro + 50.0f, DT);
        spikes += (FusionAltitudeRocketGetBaro(&rocket) == FusionAltitudeRocketBaroSpike) ? 1 : 0;
    }
    CHECK(spikes >= 19 && spikes <= 21); /* spikeTime 0.2 s at 100 Hz */
    CHECK(FusionAltitudeRocketGetBaro(&rocket) == FusionAltitudeRocketBaroFused);
}

static void AfterApogeeTheAccelIsIgnoredWithoutAnIns(void) {
    FusionAltitudeRocket plain = NewRocket(NULL);
    FusionAltitudeRocket tumbling = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 6000; step++) {
        const Sample s = Truth(step, &h, &v);
        const bool descending = FusionAltitudeRocketGetPhase(&plain) >= FusionAltitudeRocketPhaseDrogue;
        const float junk = descending ? 30.0f * (float) ((step % 7) - 3) : s.accel;
        (void) FusionAltitudeRocketUpdate(&plain, s.accel, s.baro, DT);
        (void) FusionAltitudeRocketUpdate(&tumbling, junk, s.baro, DT);
    }
    CHECK(FusionAltitudeRocketGetHeight(&plain) == FusionAltitudeRocketGetHeight(&tumbling));
    CHECK(FusionAltitudeRocketGetVerticalVelocity(&plain) == FusionAltitudeRocketGetVerticalVelocity(&tumbling));
}

static void WithAVerticalAccelTheDescentUsesIt(void) {
    FusionAltitudeRocket plain = NewRocket(NULL);
    FusionAltitudeRocket ins = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 6000; step++) { /* after apogee both get 5 m/s^2 more than the truth */
        const Sample s = Truth(step, &h, &v);
        const float accel = (FusionAltitudeRocketGetPhase(&plain) >= FusionAltitudeRocketPhaseDrogue) ? s.accel + 5.0f : s.accel;
        (void) FusionAltitudeRocketUpdate(&plain, accel, s.baro, DT);
        (void) FusionAltitudeRocketUpdateWithVerticalAccel(&ins, accel, s.baro, DT);
    }
    CHECK(FusionAltitudeRocketGetHeight(&plain) != FusionAltitudeRocketGetHeight(&ins));
    CHECK(FusionAltitudeRocketGetEvent(&plain, FusionAltitudeRocketEventApogee).sample ==
          FusionAltitudeRocketGetEvent(&ins, FusionAltitudeRocketEventApogee).sample);
}

static void TheBiasIsFrozenFromApogeeEvenWithABiasGain(void) {
    FusionAltitudeRocketSettings settings = FusionAltitudeRocketSettingsDefault();
    settings.observer.biasGain = 0.1f;
    FusionAltitudeRocket rocket = NewRocket(&settings);
    float h = 0.0f;
    float v = 0.0f;
    float biasAtApogee = 0.0f;
    bool seen = false;
    for (int step = 0; step < 8000; step++) {
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro + ((step % 3) == 0 ? 2.0f : -1.0f), DT);
        if (!seen && (FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseDrogue)) {
            biasAtApogee = FusionAltitudeRocketGetAccelBias(&rocket);
            seen = true;
        }
    }
    CHECK(seen);
    CHECK(FusionAltitudeRocketGetAccelBias(&rocket) == biasAtApogee);
}

static void GapsInTheCoastAreCountedAndExtrapolatedBallisticallyUpTo4s(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 1200; step++) { /* coasting at ~ 200 m/s, locked out */
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
    }
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseCoast);
    const float height = FusionAltitudeRocketGetHeight(&rocket);
    const float velocity = FusionAltitudeRocketGetVerticalVelocity(&rocket);
    const float accel = -G; /* a gap in the lockout: baro-led from here, the ballistic input (bias - g) is held */
    CHECK(FusionAltitudeRocketUpdate(&rocket, -G, FUSION_ALTITUDE_NO_BARO, 2.0f) == FusionAltitudeRocketStatusOk);
    CHECK(FusionAltitudeRocketGetGapCount(&rocket) == 1u);
    const float expectedVelocity = velocity + 2.0f * accel;
    CHECK(FusionAltitudeRocketGetVerticalVelocity(&rocket) > expectedVelocity - 0.01f &&
          FusionAltitudeRocketGetVerticalVelocity(&rocket) < expectedVelocity + 0.01f);
    const float expected = height + 2.0f * velocity + 2.5f * accel; /* 4 sub-steps of 0.5 s, semi-implicit Euler: a dt^2 (1+2+3+4) */
    CHECK(FusionAltitudeRocketGetHeight(&rocket) > expected - 0.1f && FusionAltitudeRocketGetHeight(&rocket) < expected + 0.1f);
}

static void AGapLongerThan4sIsExtrapolatedAtConstantVelocity(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 1200; step++) {
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
    }
    const float height = FusionAltitudeRocketGetHeight(&rocket);
    const float velocity = FusionAltitudeRocketGetVerticalVelocity(&rocket);
    CHECK(FusionAltitudeRocketUpdate(&rocket, -G, FUSION_ALTITUDE_NO_BARO, 6.0f) == FusionAltitudeRocketStatusOk);
    CHECK(FusionAltitudeRocketGetVerticalVelocity(&rocket) == velocity);
    const float expected = height + 6.0f * velocity;
    CHECK(FusionAltitudeRocketGetHeight(&rocket) > expected - 0.1f && FusionAltitudeRocketGetHeight(&rocket) < expected + 0.1f);
}

static void ALongGapInTheDescentIsReAdmittedThroughTheOffsetWithoutALockout(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 5000; step++) { /* into the drogue descent at -20 m/s */
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
    }
    CHECK(FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseDrogue);
    for (int step = 5000; step < 9000; step++) { /* 40 s of truth the estimator never sees */
        (void) Truth(step, &h, &v);
    }
    (void) FusionAltitudeRocketUpdate(&rocket, 0.0f, FUSION_ALTITUDE_NO_BARO, 40.0f);
    CHECK(FusionAltitudeRocketGetGapCount(&rocket) == 1u);
    bool lockedOut = false;
    for (int step = 9000; step < 9200; step++) {
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
        lockedOut = lockedOut || FusionAltitudeRocketIsLockedOut(&rocket);
    }
    CHECK(!lockedOut);
    const float error = FusionAltitudeRocketGetHeight(&rocket) - h;
    CHECK(error > -2.0f && error < 2.0f);
}

static void ALastingBaroStepMovesTheHeightNotTheVelocity(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    float h = 0.0f;
    float v = 0.0f;
    for (int step = 0; step < 5000; step++) {
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro, DT);
    }
    float largestVelocityError = 0.0f;
    for (int step = 5000; step < 5500; step++) { /* the baro steps up by 60 m and stays there */
        const Sample s = Truth(step, &h, &v);
        (void) FusionAltitudeRocketUpdate(&rocket, s.accel, s.baro + 60.0f, DT);
        const float error = FusionAltitudeRocketGetVerticalVelocity(&rocket) - v;
        largestVelocityError = (error > largestVelocityError) ? error : ((-error > largestVelocityError) ? -error : largestVelocityError);
    }
    CHECK(largestVelocityError < 1.0f);
    const float error = FusionAltitudeRocketGetHeight(&rocket) - (h + 60.0f);
    CHECK(error > -1.0f && error < 1.0f);
}

static void APadGapDiscardsTheCalibrationWindow(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    for (int step = 0; step < 40; step++) {
        (void) FusionAltitudeRocketUpdate(&rocket, 0.5f, PAD_ALTITUDE, DT);
    }
    (void) FusionAltitudeRocketUpdate(&rocket, 0.5f, PAD_ALTITUDE, 1.0f);
    CHECK(FusionAltitudeRocketGetGapCount(&rocket) == 1u);
    for (int step = 0; step < 40; step++) { /* 0.4 s: the window restarted, so not complete */
        (void) FusionAltitudeRocketUpdate(&rocket, 0.5f, PAD_ALTITUDE, DT);
    }
    CHECK(!FusionAltitudeRocketIsCalibrated(&rocket));
}

static void TimeIsTheCompensatedSumOfDt(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    for (int step = 0; step < 100000; step++) {
        (void) FusionAltitudeRocketUpdate(&rocket, 0.0f, PAD_ALTITUDE, DT);
    }
    CHECK(FusionAltitudeRocketGetTime(&rocket) > 999.99f && FusionAltitudeRocketGetTime(&rocket) < 1000.01f);
}

static void AnUnknownEventIdHasNotOccurred(void) {
    FusionAltitudeRocket rocket = NewRocket(NULL);
    CHECK(!FusionAltitudeRocketGetEvent(&rocket, (FusionAltitudeRocketEventId) FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS).occurred);
    CHECK(!FusionAltitudeRocketGetEvent(&rocket, FusionAltitudeRocketEventApogee).occurred);
}

static void EveryStatusHasAMessage(void) {
    for (int status = 0; status <= (int) FusionAltitudeRocketStatusInvalidGapPeriod; status++) {
        const char *const message = FusionAltitudeRocketStatusMessage((FusionAltitudeRocketStatus) status);
        CHECK(message != NULL && strcmp(message, "unknown status") != 0);
    }
}

int main(void) {
    RUN(DefaultsPassTheirCheck);
    RUN(EachBadSettingIsRejectedWithItsOwnStatus);
    RUN(InitialiseWithBadSettingsLeavesTheStateUntouched);
    RUN(BadInputsReturnAStatusAndLeaveTheStateBitIdentical);
    RUN(PadCalibrationLearnsBiasAndPadAltitudeFromStationaryWindows);
    RUN(AShakenWindowNeverEntersTheCalibration);
    RUN(TheLaunchTransientNeverEntersTheBias);
    RUN(LaunchIsDatedAtTheFirstSampleAboveTheThreshold);
    RUN(ASyntheticFlightDeclaresEveryEventInOrderAndApogeeJustAfterTheTruth);
    RUN(TheBaroIsLockedOutAboveMachWhateverTheSetting);
    RUN(NoApogeeWhileLockedOutEvenIfTheBaroFalls);
    RUN(ASingleBaroSpikeIsRejected);
    RUN(ALastingBaroStepIsAcceptedAfterSpikeTime);
    RUN(AfterApogeeTheAccelIsIgnoredWithoutAnIns);
    RUN(WithAVerticalAccelTheDescentUsesIt);
    RUN(TheBiasIsFrozenFromApogeeEvenWithABiasGain);
    RUN(GapsInTheCoastAreCountedAndExtrapolatedBallisticallyUpTo4s);
    RUN(AGapLongerThan4sIsExtrapolatedAtConstantVelocity);
    RUN(ALongGapInTheDescentIsReAdmittedThroughTheOffsetWithoutALockout);
    RUN(ALastingBaroStepMovesTheHeightNotTheVelocity);
    RUN(APadGapDiscardsTheCalibrationWindow);
    RUN(TimeIsTheCompensatedSumOfDt);
    RUN(AnUnknownEventIdHasNotOccurred);
    RUN(EveryStatusHasAMessage);
    return TestSummary();
}
