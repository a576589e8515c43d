/* back_off.c in the team form: team->stalled[k] for robot ids[k]. */
#include "mimics.h"

int mimics_team_step(const mimics_team *team, double *speed, double *heading) {
    for (int k = 0; k < team->count; k++) {
        speed[k] = team->stalled[k] ? -0.3 : 0.6;
        heading[k] = 0.0;
    }
    return 0;
}
