// The team form in C++: never returns from its call at t = 0.1 s (step 1).
#include "mimics.h"

extern "C" int mimics_team_step(const mimics_team *team, double *speed, double *heading) {
    if (team->time > 0.05) {
        volatile bool spinning = true;
        while (spinning) {
        }
    }
    for (int k = 0; k < team->count; k++) {
        speed[k] = 0.5;
        heading[k] = 0.0;
    }
    return 0;
}
