/* The team form: returns 7 (an error) from its call at t = 0.2 s (step 2). */
#include "mimics.h"

int mimics_team_step(const mimics_team *team, double *speed, double *heading) {
    if (team->time > 0.15) return 7;
    for (int k = 0; k < team->count; k++) {
        speed[k] = 0.5;
        heading[k] = 0.0;
    }
    return 0;
}
