/* Goes east; robot 1 never returns from its call at t = 0.3 s (step 3). */
#include "mimics.h"

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    if (robot->id == 1 && robot->time > 0.25) {
        for (;;) {
        }
    }
    out->speed = 0.5;
    out->heading = 0.0;
    return 0;
}
