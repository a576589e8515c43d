/*
 * deployment.c: spread out to fill the free space, steering by the laser.
 *
 * The C port of the built-in Python deployment (mimics/algorithms/deployment.py),
 * step for step, so that both give the same trajectories: each robot adds up
 * its range readings as vectors (the sum points to the most open space), turns
 * toward it, and drives at a constant speed only while it faces that way and
 * every beam reads more than a safety distance that grows toward the front.
 *
 *   mimics run cave examples/c/deployment.c --time 60
 */
#include <math.h>

#include "mimics.h"

#define SPEED (2.0 / 3.0)   /* cruising speed, as a fraction of the robot's top speed */
#define MAX_TURN 0.5        /* rad: drive only when the open space is at most this far off */
#define REACH 1.0           /* robot lengths of free space needed on every side */
#define AHEAD 2.0           /* extra room straight ahead: this many robot lengths, or... */
#define STOPPING 3.0        /* ...the distance covered in this many seconds at cruising speed */
#define AHEAD_RANGE 0.25    /* ...but at most this fraction of the laser's range */

#define MAX_BEAMS 500

/* Kept in the robot's memory block: the sine and cosine of its beam angles,
 * worked out at its first step (the trigonometry is most of the cost otherwise). */
typedef struct beam_geometry {
    int ready;
    double sin[MAX_BEAMS];
    double cos[MAX_BEAMS];
} beam_geometry;

typedef char memory_is_big_enough[sizeof(beam_geometry) <= MIMICS_MEMORY_BYTES ? 1 : -1];

/* NumPy's np.sum of products a[i] * b[i]: pairwise, in blocks of 8 partial sums, so
 * that the result is rounded exactly as the Python version's np.sum(ranges * sin). */
static double pairwise_dot(const double *a, const double *b, int n) {
    if (n < 8) {
        double sum = 0.0;
        for (int i = 0; i < n; i++) sum += a[i] * b[i];
        return sum;
    }
    if (n <= 128) {
        double r[8];
        int i;
        for (int j = 0; j < 8; j++) r[j] = a[j] * b[j];
        for (i = 8; i < n - (n % 8); i += 8)
            for (int j = 0; j < 8; j++) r[j] += a[i + j] * b[i + j];
        double sum = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for (; i < n; i++) sum += a[i] * b[i];
        return sum;
    }
    int half = n / 2;
    half -= half % 8;
    return pairwise_dot(a, b, half) + pairwise_dot(a + half, b + half, n - half);
}

int mimics_step(const mimics_robot *robot, mimics_output *out) {
    int beams = robot->beam_count;
    beam_geometry *kept = (beam_geometry *)robot->memory;
    if (beams > MAX_BEAMS) {
        mimics_log(out, "deployment.c handles at most %d beams, this robot has %d", MAX_BEAMS,
                   beams);
        return 1;
    }
    if (!kept->ready) {
        for (int b = 0; b < beams; b++) {
            kept->sin[b] = sin(robot->angles[b]);
            kept->cos[b] = cos(robot->angles[b]);
        }
        kept->ready = 1;
    }
    const double *ranges = robot->ranges;
    /* the readings as vectors in the robot's frame: their sum points to open space */
    double turn = atan2(0.0 + pairwise_dot(ranges, kept->sin, beams),
                        0.0 + pairwise_dot(ranges, kept->cos, beams));
    /* free space needed along each beam: REACH all round, more and more toward the front */
    double length = robot->length, cruise = SPEED * robot->max_speed;
    double ahead = AHEAD * length;
    if (STOPPING * cruise > ahead) ahead = STOPPING * cruise;            /* max(...) */
    if (AHEAD_RANGE * robot->max_range < ahead) ahead = AHEAD_RANGE * robot->max_range;
    int clear = 1;
    for (int b = 0; b < beams && clear; b++) {
        double front = kept->cos[b] > 0.0 ? kept->cos[b] : 0.0;
        double needed = REACH * length + ahead * front;
        clear = ranges[b] > needed;
    }
    out->speed = (fabs(turn) < MAX_TURN && clear) ? cruise : 0.0;
    out->heading = robot->pose[2] + turn;
    return 0;
}
