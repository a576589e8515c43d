/*
 * Stands still, and exercises the rest of the ABI: counts its steps in its memory
 * block, broadcasts its id each step, logs what it received and how many robots
 * it sees in comms. Robot 0 reports an error (code 3) at its 5th step; robot 2
 * returns NaN at its 8th.
 */
#include <math.h>
#include <string.h>

#include "mimics.h"

typedef struct memory { int steps; } memory;

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    memory *kept = (memory *)robot->memory;
    kept->steps++;
    int id = robot->id;
    mimics_send(out, MIMICS_BROADCAST, &id, sizeof id);
    int first = -1;
    if (robot->inbox_count > 0 && robot->inbox[0].size == sizeof first)
        memcpy(&first, robot->inbox[0].data, sizeof first);
    mimics_log(out, "step %d inbox %d from %d comms %d", kept->steps, robot->inbox_count, first,
               robot->comms_count);
    out->speed = 0.0;
    out->heading = robot->pose[2];
    if (id == 0 && kept->steps == 5) {
        mimics_log(out, "giving up");
        return 3;
    }
    if (id == 2 && kept->steps == 8) out->speed = NAN;
    return 0;
}
