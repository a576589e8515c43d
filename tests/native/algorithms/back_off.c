/*
 * Drive east; a robot whose last move was undone (robot->stalled, on_collision =
 * "stall") backs off for that step. As back_off in test_stall.py, in Python.
 */
#include "mimics.h"

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    out->speed = robot->stalled ? -0.3 : 0.6;
    out->heading = 0.0;
    return 0;
}
