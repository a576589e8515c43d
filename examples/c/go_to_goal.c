/*
 * go_to_goal.c: drive straight to the goal, turning on the spot first if needed.
 *
 * The C port of the built-in Python go_to_goal (mimics/algorithms/go_to_goal.py),
 * line for line: full speed when facing the goal, slower the more it is off.
 *
 *   mimics run line examples/c/go_to_goal.c --robots 10
 */
#include <math.h>

#include "mimics.h"

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    if (!robot->has_goal) {
        out->speed = 0.0;
        out->heading = robot->pose[2];
        return 0;
    }
    double x = robot->pose[0], y = robot->pose[1], theta = robot->pose[2];
    double heading = atan2(robot->goal[1] - y, robot->goal[0] - x);
    double alignment = cos(heading - theta);
    out->speed = robot->max_speed * (0.0 > alignment ? 0.0 : alignment);  /* max(alignment, 0) */
    out->heading = heading;
    return 0;
}
