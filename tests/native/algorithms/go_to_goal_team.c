/*
 * go_to_goal in the team form: the whole team's arrays in one call. The team's
 * memory block holds a mark set by mimics_team_reset, checked at every step.
 */
#include <math.h>

#include "mimics.h"

#define MARK 0x5eed

int mimics_team_reset(const mimics_team *team) {
    *(int *)team->memory = MARK;
    return 0;
}

int mimics_team_step(const mimics_team *team, double *speed, double *heading) {
    if (*(int *)team->memory != MARK) return 7;  /* the memory did not persist */
    for (int k = 0; k < team->count; k++) {
        const double *pose = team->pose + 3 * k, *goal = team->goal + 2 * k;
        if (isnan(goal[0])) {
            speed[k] = 0.0;
            heading[k] = pose[2];
            continue;
        }
        double to_goal = atan2(goal[1] - pose[1], goal[0] - pose[0]);
        double alignment = cos(to_goal - pose[2]);
        speed[k] = team->max_speed[k] * (0.0 > alignment ? 0.0 : alignment);
        heading[k] = to_goal;
    }
    return 0;
}
