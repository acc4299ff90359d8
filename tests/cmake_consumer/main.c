/* A consumer of the installed (or vendored) headers: one observer step at rest,
 * the version macros, and the INS header (sqrtf: linked with libm by the target). */
#include "fusion_altitude.h"
#include "fusion_altitude_ins.h"

#include <stdio.h>

int main(void) {
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    if (FusionAltitudeUpdate(&altitude, 0.0f, 100.0f, 0.01f) != FusionAltitudeStatusOk) {
        return 1;
    }
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    printf("fusion_altitude %s (%d.%d.%d)\n", FUSION_ALTITUDE_VERSION_STRING, FUSION_ALTITUDE_VERSION_MAJOR,
           FUSION_ALTITUDE_VERSION_MINOR, FUSION_ALTITUDE_VERSION_PATCH);
    return 0;
}
