/* Goes to the goal, but robot 1 writes through a null pointer at step 4 (t = 0.3 s). */
#include <math.h>
#include <stddef.h>

#include "mimics.h"

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    if (robot->id == 1 && robot->time > 0.25) {
        volatile int *volatile nowhere = NULL;  /* volatile: a real store, not a trap */
        *nowhere = 1;
    }
    out->speed = robot->max_speed;
    out->heading = robot->pose[2];
    return 0;
}
