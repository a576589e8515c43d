/* A missing semicolon on line 8. */
#include "mimics.h"

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    out->speed = 0.0;
    out->heading = robot->pose[2];
    undeclared_name = 3;
    return 0
}
