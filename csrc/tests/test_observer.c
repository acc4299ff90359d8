/**
 * @file test_observer.c
 * @brief Unit tests of fusion_altitude.h, built by tests/test_c_core.py with
 * gcc and clang (C99 and as C++), strict warnings, and under ASan + UBSan.
 * Prints "N passed, M failed" and exits non-zero on any failure.
 */

#include "fusion_altitude.h"
#include "test_harness.h"

#include <string.h>

/* Struct sizes a firmware engineer budgets for (checked at compile time). */
typedef char estimatorFitsIn60Bytes[(sizeof(FusionAltitude) <= 60u) ? 1 : -1];
typedef char settingsAre20Bytes[(sizeof(FusionAltitudeSettings) == 20u) ? 1 : -1];

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static bool SameBits(const FusionAltitude *const a, const FusionAltitude *const b) {
    return memcmp(a, b, sizeof(*a)) == 0;
}

static float Absolute(const float value) {
    return value < 0.0f ? -value : value;
}

/* An estimator in the middle of a run, for the rejection tests. */
static FusionAltitude RunningEstimator(void) {
    FusionAltitude altitude;
    memset(&altitude, 0, sizeof(altitude)); /* padding bytes too, so memcmp compares state only */
    FusionAltitudeInitialise(&altitude);
    for (int i = 0; i < 100; i++) {
        (void) FusionAltitudeUpdate(&altitude, 0.3f, 10.0f + 0.01f * (float) i, 0.01f);
    }
    return altitude;
}

static void InitialiseUsesDefaultGainsAndNoReference(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    const FusionAltitudeSettings settings = FusionAltitudeGetSettings(&altitude);
    CHECK(settings.positionGain == 2.40f);
    CHECK(settings.velocityGain == 2.88f);
    CHECK(settings.biasGain == 0.675f);
    CHECK(!FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) == 0.0f);
}

static void FirstBaroSampleOnlySetsTheReference(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    CHECK(FusionAltitudeUpdate(&altitude, 5.0f, 123.5f, 0.01f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == 123.5f);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) == 0.0f);
}

static void MissingBaroBeforeReferenceChangesOnlyTheResidual(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    CHECK(FusionAltitudeUpdate(&altitude, 5.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeStatusOk);
    CHECK(!FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == 0.0f);
    CHECK(FusionAltitudeIsNaN(FusionAltitudeGetBaroResidual(&altitude)));
}

static void UpdateFollowsTheDocumentedEquations(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    (void) FusionAltitudeReset(&altitude, 10.0f);
    altitude.verticalVelocity = 0.5f;
    altitude.accelBias = 0.1f;
    const float a = 0.7f, z = 10.25f, dt = 0.02f;
    const float r = z - 10.0f;
    const float v = 0.5f + ((a - 0.1f) + 2.88f * r) * dt;
    const float h = 10.0f + (v + 2.40f * r) * dt;
    const float b = 0.1f - (0.675f * r) * dt;
    CHECK(FusionAltitudeUpdate(&altitude, a, z, dt) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == v);
    CHECK(FusionAltitudeGetAltitude(&altitude) == h);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == b);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) == r);
}

static void MissingBaroIntegratesAndKeepsBias(void) {
    FusionAltitude altitude = RunningEstimator();
    const float h0 = altitude.altitude, v0 = altitude.verticalVelocity, b0 = altitude.accelBias;
    CHECK(FusionAltitudeUpdate(&altitude, 1.5f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeStatusOk);
    const float v = v0 + (1.5f - b0) * 0.01f;
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == v);
    CHECK(FusionAltitudeGetAltitude(&altitude) == h0 + v * 0.01f);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == b0);
    CHECK(FusionAltitudeIsNaN(FusionAltitudeGetBaroResidual(&altitude)));
}

static void ResetKeepsBiasAndZeroesVelocityAndResidual(void) {
    FusionAltitude altitude = RunningEstimator();
    const float bias = altitude.accelBias;
    CHECK(bias != 0.0f);
    CHECK(FusionAltitudeReset(&altitude, -3.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetAltitude(&altitude) == -3.0f);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == bias);
}

static void WarmStartSetsBias(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    CHECK(FusionAltitudeResetWithBias(&altitude, 50.0f, 0.12f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == 50.0f);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == 0.12f);
}

static void RejectedInputsLeaveStateBitIdentical(void) {
    const float inf = Infinity();
    const float nan = FusionAltitudeNaN();
    const FusionAltitude before = RunningEstimator();
    FusionAltitude altitude = before;
    CHECK(FusionAltitudeUpdate(&altitude, nan, 1.0f, 0.01f) == FusionAltitudeStatusInvalidAccel);
    CHECK(FusionAltitudeUpdate(&altitude, inf, 1.0f, 0.01f) == FusionAltitudeStatusInvalidAccel);
    CHECK(FusionAltitudeUpdate(&altitude, -inf, nan, 0.01f) == FusionAltitudeStatusInvalidAccel);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, inf, 0.01f) == FusionAltitudeStatusInvalidBaroAltitude);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, -inf, 0.01f) == FusionAltitudeStatusInvalidBaroAltitude);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 1.0f, 0.0f) == FusionAltitudeStatusInvalidDt);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 1.0f, -0.0f) == FusionAltitudeStatusInvalidDt);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 1.0f, -0.01f) == FusionAltitudeStatusInvalidDt);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, nan, nan) == FusionAltitudeStatusInvalidDt);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 1.0f, inf) == FusionAltitudeStatusInvalidDt);
    CHECK(FusionAltitudeReset(&altitude, nan) == FusionAltitudeStatusInvalidBaroAltitude);
    CHECK(FusionAltitudeReset(&altitude, inf) == FusionAltitudeStatusInvalidBaroAltitude);
    CHECK(FusionAltitudeResetWithBias(&altitude, 1.0f, nan) == FusionAltitudeStatusInvalidAccelBias);
    CHECK(FusionAltitudeResetWithBias(&altitude, nan, 0.0f) == FusionAltitudeStatusInvalidBaroAltitude);
    const FusionAltitudeSettings negative = {-1.0f, 2.88f, 0.675f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    const FusionAltitudeSettings notFinite = {2.4f, nan, 0.675f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    const FusionAltitudeSettings unstable = {1.0f, 1.0f, 2.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    CHECK(FusionAltitudeSetSettings(&altitude, &negative) == FusionAltitudeStatusInvalidGain);
    CHECK(FusionAltitudeSetSettings(&altitude, &notFinite) == FusionAltitudeStatusInvalidGain);
    CHECK(FusionAltitudeSetSettings(&altitude, &unstable) == FusionAltitudeStatusUnstableGains);
    CHECK(SameBits(&altitude, &before));
}

static void FirstSampleStillChecksAllInputs(void) {
    FusionAltitude altitude;
    memset(&altitude, 0, sizeof(altitude));
    FusionAltitudeInitialise(&altitude);
    const FusionAltitude before = altitude;
    CHECK(FusionAltitudeUpdate(&altitude, Infinity(), 1.0f, 0.01f) == FusionAltitudeStatusInvalidAccel);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 1.0f, 0.0f) == FusionAltitudeStatusInvalidDt);
    CHECK(SameBits(&altitude, &before));
}

static void SettingsCheckAppliesRouthHurwitz(void) {
    const FusionAltitudeSettings stable = {2.0f, 1.0f, 1.9f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    const FusionAltitudeSettings boundary = {2.0f, 1.0f, 2.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    const FusionAltitudeSettings noBias = {2.0f, 1.0f, 0.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    const FusionAltitudeSettings undamped = {0.0f, 1.0f, 0.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    const FusionAltitudeSettings inertialOnly = {0.0f, 0.0f, 0.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    CHECK(FusionAltitudeSettingsCheck(&stable) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSettingsCheck(&boundary) == FusionAltitudeStatusUnstableGains);
    CHECK(FusionAltitudeSettingsCheck(&noBias) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSettingsCheck(&undamped) == FusionAltitudeStatusUnstableGains);
    CHECK(FusionAltitudeSettingsCheck(&inertialOnly) == FusionAltitudeStatusOk);
}

static void DiscreteValidationRejectsLongSteps(void) {
    const FusionAltitudeSettings defaults = FusionAltitudeSettingsDefault();
    CHECK(FusionAltitudeSettingsValidate(&defaults, 0.01f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSettingsValidate(&defaults, 0.5f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSettingsValidate(&defaults, 1.0f) == FusionAltitudeStatusUnstableDiscrete);
    CHECK(FusionAltitudeSettingsValidate(&defaults, 0.0f) == FusionAltitudeStatusInvalidDt);
    CHECK(FusionAltitudeSettingsValidate(&defaults, FusionAltitudeNaN()) == FusionAltitudeStatusInvalidDt);
    FusionAltitudeSettings racing;
    CHECK(FusionAltitudeSettingsFromPreset(&racing, FusionAltitudePresetRacing) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSettingsValidate(&racing, 0.01f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSettingsValidate(&racing, 0.25f) == FusionAltitudeStatusUnstableDiscrete);
}

static void BandwidthFormulasGiveThePresetsWithinOneUlp(void) {
    const float omegas[4] = {0.2f, 0.5f, 1.5f, 5.0f};
    for (int i = 0; i < 4; i++) {
        FusionAltitudeSettings fromPreset = {0.0f, 0.0f, 0.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
        FusionAltitudeSettings fromBandwidth = {0.0f, 0.0f, 0.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
        CHECK(FusionAltitudeSettingsFromPreset(&fromPreset, (FusionAltitudePreset) i) == FusionAltitudeStatusOk);
        CHECK(FusionAltitudeSettingsFromBandwidth(&fromBandwidth, omegas[i], 0.7f, omegas[i] / 5.0f) == FusionAltitudeStatusOk);
        const float pairs[3][2] = {{fromPreset.positionGain, fromBandwidth.positionGain},
                                   {fromPreset.velocityGain, fromBandwidth.velocityGain},
                                   {fromPreset.biasGain, fromBandwidth.biasGain}};
        for (int j = 0; j < 3; j++) {
            const int32_t ulps = (int32_t) FusionAltitudeFloatBits(pairs[j][0]) - (int32_t) FusionAltitudeFloatBits(pairs[j][1]);
            CHECK(ulps >= -1 && ulps <= 1);
        }
    }
    FusionAltitudeSettings untouched = {1.0f, 2.0f, 3.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    CHECK(FusionAltitudeSettingsFromBandwidth(&untouched, -1.0f, 0.7f, 0.1f) == FusionAltitudeStatusInvalidBandwidth);
    CHECK(FusionAltitudeSettingsFromBandwidth(&untouched, 1.0f, 0.0f, 0.1f) == FusionAltitudeStatusInvalidBandwidth);
    int unknownPreset = (int) FusionAltitudePresetRocket + 1;
    CHECK(FusionAltitudeSettingsFromPreset(&untouched, (FusionAltitudePreset) unknownPreset) == FusionAltitudeStatusInvalidPreset);
    CHECK(untouched.positionGain == 1.0f && untouched.velocityGain == 2.0f && untouched.biasGain == 3.0f);
}

static void StationaryEstimateConvergesToBaro(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    (void) FusionAltitudeReset(&altitude, 0.0f);
    for (int i = 0; i < 6000; i++) { /* 60 s at 100 Hz after a 2 m baro step */
        (void) FusionAltitudeUpdate(&altitude, 0.0f, 2.0f, 0.01f);
    }
    CHECK(Absolute(FusionAltitudeGetAltitude(&altitude) - 2.0f) < 1e-3f);
    CHECK(Absolute(FusionAltitudeGetVerticalVelocity(&altitude)) < 1e-3f);
}

static void ConstantAccelBiasIsEstimatedWithNoAltitudeError(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    const float bias = 0.012f * FUSION_ALTITUDE_GRAVITY;
    for (int i = 0; i < 6000; i++) { /* 60 s at 100 Hz */
        (void) FusionAltitudeUpdate(&altitude, bias, 20.0f, 0.01f);
    }
    CHECK(Absolute(FusionAltitudeGetAccelBias(&altitude) - bias) < 1e-3f);
    CHECK(Absolute(FusionAltitudeGetAltitude(&altitude) - 20.0f) < 1e-3f);
}

static void StatusMessagesExistForEveryStatus(void) {
    for (int status = 0; status <= (int) FusionAltitudeStatusInvalidPreset; status++) {
        const char *const message = FusionAltitudeStatusMessage((FusionAltitudeStatus) status);
        CHECK(message != NULL && message[0] != '\0');
    }
    CHECK(strcmp(FusionAltitudeStatusMessage(FusionAltitudeStatusOk), "ok") == 0);
}

static void FloatClassificationNeedsNoLibm(void) {
    CHECK(FusionAltitudeIsFinite(0.0f) && FusionAltitudeIsFinite(-3.4e38f) && FusionAltitudeIsFinite(1e-45f));
    CHECK(!FusionAltitudeIsFinite(Infinity()) && !FusionAltitudeIsFinite(-Infinity()));
    CHECK(!FusionAltitudeIsFinite(FusionAltitudeNaN()) && FusionAltitudeIsNaN(FusionAltitudeNaN()));
    CHECK(!FusionAltitudeIsNaN(Infinity()) && !FusionAltitudeIsNaN(1.0f));
}

static void DtAboveTheGapPeriodIsCountedAndNotIntegrated(void) {
    FusionAltitude altitude = RunningEstimator();
    const FusionAltitude before = altitude;
    CHECK(FusionAltitudeUpdate(&altitude, 50.0f, FUSION_ALTITUDE_NO_BARO, 2.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 1u);
    CHECK(!FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == before.altitude);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == before.verticalVelocity);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == before.accelBias);
    CHECK(FusionAltitudeIsNaN(FusionAltitudeGetBaroResidual(&altitude)));
}

static void DtEqualToTheGapPeriodIsIntegrated(void) {
    FusionAltitude altitude = RunningEstimator();
    const float h = altitude.altitude;
    CHECK(FusionAltitudeUpdate(&altitude, 1.0f, FUSION_ALTITUDE_NO_BARO, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 0u);
    CHECK(FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) != h);
}

static void NextBaroAfterAGapRestartsWithTheMeanVelocityAndKeepsTheBias(void) {
    FusionAltitude altitude = RunningEstimator();
    const float h = altitude.altitude;
    const float b = altitude.accelBias;
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, FUSION_ALTITUDE_NO_BARO, 2.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, FUSION_ALTITUDE_NO_BARO, 0.25f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, h + 4.5f, 0.25f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == h + 4.5f);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == ((h + 4.5f) - h) / 2.5f);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == b);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 1u);
}

static void GapStepWithABaroSampleRestartsOnIt(void) {
    FusionAltitude altitude = RunningEstimator();
    const float h = altitude.altitude;
    CHECK(FusionAltitudeUpdate(&altitude, 9.0f, h - 3.0f, 1.5f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeIsReferenceSet(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == h - 3.0f);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == ((h - 3.0f) - h) / 1.5f);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 1u);
}

static void GapBeforeTheReferenceIsNotCounted(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, FUSION_ALTITUDE_NO_BARO, 5.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 12.0f, 5.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 0u);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == 0.0f);
}

static void ResetCancelsAPendingRestart(void) {
    FusionAltitude altitude = RunningEstimator();
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, FUSION_ALTITUDE_NO_BARO, 3.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeReset(&altitude, 7.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeIsReferenceSet(&altitude) && (altitude.gapTime == 0.0f));
    const float b = altitude.accelBias;
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 7.0f, 0.01f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) == 0.0f);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == (0.0f - b) * 0.01f); /* a correction, not a restart */
    CHECK(FusionAltitudeGetGapCount(&altitude) == 1u);
}

static void GapPeriodMustBePositiveAndMayBeInfinite(void) {
    FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
    CHECK(settings.gapPeriod == 0.5f);
    settings.gapPeriod = 0.0f;
    CHECK(FusionAltitudeSettingsCheck(&settings) == FusionAltitudeStatusInvalidGapPeriod);
    settings.gapPeriod = -1.0f;
    CHECK(FusionAltitudeSettingsCheck(&settings) == FusionAltitudeStatusInvalidGapPeriod);
    settings.gapPeriod = FusionAltitudeNaN();
    CHECK(FusionAltitudeSettingsCheck(&settings) == FusionAltitudeStatusInvalidGapPeriod);
    FusionAltitude altitude = RunningEstimator();
    const FusionAltitude before = altitude;
    CHECK(FusionAltitudeSetSettings(&altitude, &settings) == FusionAltitudeStatusInvalidGapPeriod);
    CHECK(SameBits(&altitude, &before));
    settings.gapPeriod = Infinity();
    CHECK(FusionAltitudeSetSettings(&altitude, &settings) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, FUSION_ALTITUDE_NO_BARO, 100.0f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 0u);
    FusionAltitudeSettings balloon;
    CHECK(FusionAltitudeSettingsFromPreset(&balloon, FusionAltitudePresetBalloon) == FusionAltitudeStatusOk);
    CHECK(balloon.gapPeriod == 5.0f);
}

static void BiasIsHeldForEightOverKhAfterARestart(void) {
    FusionAltitude altitude = RunningEstimator();
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 20.0f, 2.0f) == FusionAltitudeStatusOk); /* gap, restart on this sample */
    const float b = FusionAltitudeGetAccelBias(&altitude);
    int heldSteps = 0;
    for (int i = 0; i < 500; i++) {
        CHECK(FusionAltitudeUpdate(&altitude, 0.0f, 21.0f, 0.01f) == FusionAltitudeStatusOk);
        heldSteps += (FusionAltitudeGetAccelBias(&altitude) == b) ? 1 : 0;
    }
    /* 8 / 2.4 = 3.33 s: the 333 steps with sinceRestart * Kh < 8 hold it (float32 sums of 0.01 give 333 or 334) */
    CHECK(heldSteps >= 332 && heldSteps <= 334);
    CHECK(FusionAltitudeGetAccelBias(&altitude) != b);
}

static FusionAltitude RunningWithPreset(const FusionAltitudePreset preset) {
    FusionAltitude altitude = RunningEstimator();
    FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
    (void) FusionAltitudeSettingsFromPreset(&settings, preset);
    settings.gapPeriod = Infinity(); /* only the stability rule can make a gap */
    (void) FusionAltitudeSetSettings(&altitude, &settings);
    return altitude;
}

static void OneSecondBaroStepIsAGapAtTheDefaultAndRacingGains(void) {
    const FusionAltitudePreset presets[2] = {FusionAltitudePresetVtol, FusionAltitudePresetRacing};
    for (int i = 0; i < 2; i++) {
        FusionAltitude altitude = RunningWithPreset(presets[i]);
        const float h = altitude.altitude;
        const float v = altitude.verticalVelocity;
        const float b = altitude.accelBias;
        CHECK(FusionAltitudeUpdate(&altitude, 0.0f, h + 2.0f, 1.0f) == FusionAltitudeStatusOk);
        CHECK(FusionAltitudeGetGapCount(&altitude) == 1u);
        CHECK(FusionAltitudeIsReferenceSet(&altitude));
        CHECK(FusionAltitudeGetAltitude(&altitude) == h + 2.0f); /* restarted on this step's sample */
        /* v moves toward the mean velocity over the 1 s interval, 2 m/s, by 1/(1 + Kh/Kv) */
        const float weight = 1.0f / (1.0f + altitude.settings.positionGain / altitude.settings.velocityGain);
        CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == v + ((2.0f + v * 0.0f) / 1.0f - v) * weight);
        CHECK(FusionAltitudeGetBaroResidual(&altitude) == 0.0f);
        CHECK(altitude.sinceRestart == 0.0f); /* the bias hold starts */
        CHECK(FusionAltitudeUpdate(&altitude, 0.0f, h + 2.0f, 0.01f) == FusionAltitudeStatusOk);
        CHECK(FusionAltitudeGetAccelBias(&altitude) == b);
    }
}

static void TwentyMillisecondStepIsNotAGapAtTheRacingGains(void) {
    FusionAltitude altitude = RunningWithPreset(FusionAltitudePresetRacing);
    CHECK(FusionAltitudeUpdate(&altitude, 0.0f, altitude.altitude + 0.1f, 0.02f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 0u);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) != 0.0f); /* a correction, not a restart */
}

static void StepStabilityLimitIsJurysAtOnePointFiveTimesTheStep(void) {
    FusionAltitudeSettings settings = FusionAltitudeSettingsDefault(); /* Jury's limit 0.620 s: 0.413 s */
    CHECK(FusionAltitudeSettingsValidate(&settings, 0.61f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSettingsValidate(&settings, 0.63f) == FusionAltitudeStatusUnstableDiscrete);
    CHECK(FusionAltitudeIsStepStable(&settings, 0.41f, 0.41f));
    CHECK(!FusionAltitudeIsStepStable(&settings, 0.42f, 0.42f));
    CHECK(FusionAltitudeIsStepStable(&settings, 1.0e-45f, 1.0e-45f)); /* underflow at a tiny dt is no gap */
    CHECK(FusionAltitudeSettingsFromPreset(&settings, FusionAltitudePresetRacing) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeIsStepStable(&settings, 0.1f, 0.1f));
    CHECK(!FusionAltitudeIsStepStable(&settings, 0.1f, 1.0f)); /* a 0.1 s correction after 0.9 s of dead reckoning */
    CHECK(FusionAltitudeSettingsFromPreset(&settings, FusionAltitudePresetBalloon) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeIsStepStable(&settings, 3.0f, 3.0f) && !FusionAltitudeIsStepStable(&settings, 3.2f, 3.2f));
}

/* A pseudo-random float in [0, 1) from a 32-bit LCG (no libm, same on every target). */
static float Random(uint32_t *const seed) {
    *seed = *seed * 1664525u + 1013904223u;
    return (float) (*seed >> 8) / 16777216.0f;
}

static void TelemetryLikeStepsStayFiniteAndBounded(void) {
    /* steps 0.1-4 s (most 0.1 s), baro on 90 % of them within 1 m of a true altitude that moves at most 3 m/s,
     * accel +-20 m/s^2 noise (no relation to the motion), default and racing gains, a 1 s gap period:
     * |h - truth| stays below 100 m */
    const FusionAltitudePreset presets[2] = {FusionAltitudePresetVtol, FusionAltitudePresetRacing};
    for (int i = 0; i < 2; i++) {
        FusionAltitude altitude = RunningWithPreset(presets[i]);
        altitude.settings.gapPeriod = 1.0f;
        uint32_t seed = 12345u + (uint32_t) i;
        float truth = altitude.altitude;
        float worst = 0.0f;
        for (int k = 0; k < 20000; k++) {
            const float u = Random(&seed);
            const float dt = (u < 0.6f) ? 0.1f : ((u < 0.85f) ? (0.1f + 0.9f * Random(&seed)) : (0.5f + 3.5f * Random(&seed)));
            truth += (6.0f * Random(&seed) - 3.0f) * dt;
            const float baro = (Random(&seed) < 0.9f) ? (truth + 2.0f * Random(&seed) - 1.0f) : FUSION_ALTITUDE_NO_BARO;
            CHECK(FusionAltitudeUpdate(&altitude, 40.0f * Random(&seed) - 20.0f, baro, dt) == FusionAltitudeStatusOk);
            const float error = altitude.altitude - truth;
            worst = (error > worst) ? error : ((-error > worst) ? -error : worst);
            CHECK(FusionAltitudeIsFinite(altitude.verticalVelocity) && FusionAltitudeIsFinite(altitude.accelBias));
        }
        CHECK(worst < 100.0f);
        CHECK(FusionAltitudeGetGapCount(&altitude) > 0u);
    }
}

static void BaroTimeoutFlagsCountsAndDecaysTheVelocity(void) {
    FusionAltitude altitude = RunningEstimator();
    int steps = 0;
    while (!FusionAltitudeIsBaroTimedOut(&altitude) && (steps < 1000)) {
        CHECK(FusionAltitudeUpdate(&altitude, 1.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeStatusOk);
        steps++;
    }
    CHECK(steps >= 200 && steps <= 201); /* 2 s of 0.01 s steps in float32 */
    CHECK(FusionAltitudeGetBaroTimeouts(&altitude) == 1u);
    const float v = altitude.verticalVelocity;
    const float h = altitude.altitude;
    CHECK(FusionAltitudeUpdate(&altitude, 50.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeStatusOk);
    const float decayed = v * (2.0f / (2.0f + 0.01f)); /* the accel is not integrated any more */
    CHECK(altitude.verticalVelocity == decayed);
    CHECK(altitude.altitude == h + decayed * 0.01f);
    for (int i = 0; i < 100000; i++) { /* 1000 s without baro: h moves less than |v| * 2 s further */
        CHECK(FusionAltitudeUpdate(&altitude, 50.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeStatusOk);
    }
    const float moved = altitude.altitude - h;
    CHECK((moved >= 0.0f) && (moved <= v * 2.0f + 0.01f));
    CHECK(FusionAltitudeGetBaroTimeouts(&altitude) == 1u);
}

static void FirstBaroAfterATimeoutRestartsAtItAndClearsTheFlag(void) {
    FusionAltitude altitude = RunningEstimator();
    for (int i = 0; i < 300; i++) {
        CHECK(FusionAltitudeUpdate(&altitude, 1.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeStatusOk);
    }
    CHECK(FusionAltitudeIsBaroTimedOut(&altitude));
    const float v = altitude.verticalVelocity;
    const float b = altitude.accelBias;
    CHECK(FusionAltitudeUpdate(&altitude, 1.0f, 42.0f, 0.01f) == FusionAltitudeStatusOk);
    CHECK(!FusionAltitudeIsBaroTimedOut(&altitude));
    CHECK(FusionAltitudeGetAltitude(&altitude) == 42.0f);
    CHECK(FusionAltitudeGetVerticalVelocity(&altitude) == v);
    CHECK(FusionAltitudeGetBaroResidual(&altitude) == 0.0f);
    CHECK(altitude.sinceRestart == 0.0f); /* the bias is held for 8/Kh s */
    CHECK(FusionAltitudeUpdate(&altitude, 1.0f, 42.0f, 0.01f) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeGetAccelBias(&altitude) == b);
    CHECK(FusionAltitudeGetBaroTimeouts(&altitude) == 1u);
    CHECK(FusionAltitudeGetGapCount(&altitude) == 0u);
}

static void BaroTimeoutMustBePositiveAndMayBeInfinite(void) {
    FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
    CHECK(settings.baroTimeout == 2.0f);
    settings.baroTimeout = 0.0f;
    CHECK(FusionAltitudeSettingsCheck(&settings) == FusionAltitudeStatusInvalidBaroTimeout);
    settings.baroTimeout = FusionAltitudeNaN();
    CHECK(FusionAltitudeSettingsCheck(&settings) == FusionAltitudeStatusInvalidBaroTimeout);
    FusionAltitude altitude = RunningEstimator();
    const FusionAltitude before = altitude;
    CHECK(FusionAltitudeSetSettings(&altitude, &settings) == FusionAltitudeStatusInvalidBaroTimeout);
    CHECK(SameBits(&altitude, &before));
    settings.baroTimeout = Infinity();
    CHECK(FusionAltitudeSetSettings(&altitude, &settings) == FusionAltitudeStatusOk);
    for (int i = 0; i < 1000; i++) {
        CHECK(FusionAltitudeUpdate(&altitude, 0.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeStatusOk);
    }
    CHECK(!FusionAltitudeIsBaroTimedOut(&altitude) && (FusionAltitudeGetBaroTimeouts(&altitude) == 0u));
}

int main(void) {
    RUN(InitialiseUsesDefaultGainsAndNoReference);
    RUN(FirstBaroSampleOnlySetsTheReference);
    RUN(MissingBaroBeforeReferenceChangesOnlyTheResidual);
    RUN(UpdateFollowsTheDocumentedEquations);
    RUN(MissingBaroIntegratesAndKeepsBias);
    RUN(ResetKeepsBiasAndZeroesVelocityAndResidual);
    RUN(WarmStartSetsBias);
    RUN(RejectedInputsLeaveStateBitIdentical);
    RUN(FirstSampleStillChecksAllInputs);
    RUN(SettingsCheckAppliesRouthHurwitz);
    RUN(DiscreteValidationRejectsLongSteps);
    RUN(BandwidthFormulasGiveThePresetsWithinOneUlp);
    RUN(StationaryEstimateConvergesToBaro);
    RUN(ConstantAccelBiasIsEstimatedWithNoAltitudeError);
    RUN(StatusMessagesExistForEveryStatus);
    RUN(FloatClassificationNeedsNoLibm);
    RUN(DtAboveTheGapPeriodIsCountedAndNotIntegrated);
    RUN(DtEqualToTheGapPeriodIsIntegrated);
    RUN(NextBaroAfterAGapRestartsWithTheMeanVelocityAndKeepsTheBias);
    RUN(GapStepWithABaroSampleRestartsOnIt);
    RUN(GapBeforeTheReferenceIsNotCounted);
    RUN(ResetCancelsAPendingRestart);
    RUN(GapPeriodMustBePositiveAndMayBeInfinite);
    RUN(BiasIsHeldForEightOverKhAfterARestart);
    RUN(OneSecondBaroStepIsAGapAtTheDefaultAndRacingGains);
    RUN(TwentyMillisecondStepIsNotAGapAtTheRacingGains);
    RUN(StepStabilityLimitIsJurysAtOnePointFiveTimesTheStep);
    RUN(TelemetryLikeStepsStayFiniteAndBounded);
    RUN(BaroTimeoutFlagsCountsAndDecaysTheVelocity);
    RUN(FirstBaroAfterATimeoutRestartsAtItAndClearsTheFlag);
    RUN(BaroTimeoutMustBePositiveAndMayBeInfinite);
    return TestSummary();
}
