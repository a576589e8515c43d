/* Calls abort() at its first step (SIGABRT), as a failed assert would. */
#include <stdlib.h>

#include "mimics.h"

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    (void)robot;
    (void)out;
    abort();
}
