/*
 * The host side of a compiled algorithm: linked with the user's object file
 * into one Python extension (cffi, API mode). It fills each robot's
 * mimics_robot from the world's arrays and calls mimics_step for all robots
 * of a step in one go, timing each call on its own, so that Python pays one
 * call per step, not one per robot.
 */
#define MIMICS_HOST 1
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <string.h>
#include <time.h>

#include "mimics.h"

/* Weak: a file may define only some entry points (their address is then NULL). */
extern int mimics_step(const mimics_robot *robot, mimics_output *out) __attribute__((weak));
extern int mimics_reset(const mimics_robot *robot, mimics_output *out) __attribute__((weak));
extern int mimics_team_step(const mimics_team *team, double *speed, double *heading)
    __attribute__((weak));
extern int mimics_team_reset(const mimics_team *team) __attribute__((weak));
extern int mimics_abi_version(void) __attribute__((weak));

typedef struct mimics_host_world {
    int beams;                  /* B: columns of scan and beam_offsets */
    double time, dt, comm_range;
    const double *measured_pose, *pose, *measured_velocity, *velocity, *measured_acceleration;
    const double *odometry, *goal, *scan, *beam_offsets;
    const int64_t *beam_count;
    const double *max_range, *half_length, *half_width, *kv;
    const unsigned char *stalled;  /* (n) booleans */
    int comms_count;
    const double *comms;        /* the whole comms table of this step */
    double *comms_scratch;      /* rows within range of the robot being called */
    double *reference;          /* (n, 2) written for robots whose call succeeded */
    double *user_time;          /* (n) seconds per call */
    int64_t *current;           /* the robot being called (-1: none), for crash reports */
} mimics_host_world;

enum { FLAG_ERROR = 1, FLAG_NOT_FINITE = 2, FLAG_LOG = 4, FLAG_SENT = 8 };

static int mimics_host_entry_points(void) {
    return (mimics_step ? 1 : 0) | (mimics_reset ? 2 : 0) | (mimics_team_step ? 4 : 0)
         | (mimics_team_reset ? 8 : 0);
}

/* The ABI version the user's file was compiled against; -1 if it did not include mimics.h. */
static int mimics_host_abi(void) { return mimics_abi_version ? mimics_abi_version() : -1; }

/* Cutting a call that does not return (the wall-limit watchdog, mimics/engine/user_code/watchdog.py):
 * the watchdog sends a signal to the thread running the user's code; while that thread is
 * inside a host call below, the handler jumps back to the host, which returns -1. Outside,
 * the signal is ignored. Per thread, so that each thread's calls are cut on their own. */
static __thread sigjmp_buf cut_point;
static __thread volatile sig_atomic_t cut_armed;
static __thread int was_cut;

static void cut_handler(int signum) {
    (void)signum;
    if (cut_armed) {
        cut_armed = 0;
        siglongjmp(cut_point, 1);
    }
}

/* Install the handler of `signum` (SA_NODEFER: the signal is not left blocked by the jump);
 * returns 0, or -1 with errno set. */
static int mimics_host_arm_cuts(int signum) {
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = cut_handler;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_NODEFER | SA_RESTART;
    return sigaction(signum, &action, NULL);
}

/* Whether this thread's last host call was cut (its result is then meaningless). */
static int mimics_host_was_cut(void) { return was_cut; }

static double seconds_now(void) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

static void copy(double *to, const double *from, int count) {
    for (int j = 0; j < count; j++) to[j] = from[j];
}

static void fill_robot(const mimics_host_world *w, mimics_robot *r, int64_t i) {
    r->id = (int)i;
    r->time = w->time;
    r->dt = w->dt;
    copy(r->pose, w->measured_pose + 3 * i, 3);
    copy(r->true_pose, w->pose + 3 * i, 3);
    copy(r->velocity, w->measured_velocity + 2 * i, 2);
    copy(r->true_velocity, w->velocity + 2 * i, 2);
    copy(r->acceleration, w->measured_acceleration + 2 * i, 2);
    copy(r->odometry, w->odometry + 3 * i, 3);
    copy(r->goal, w->goal + 2 * i, 2);
    r->has_goal = !isnan(r->goal[0]);
    r->length = 2.0 * w->half_length[i];
    r->width = 2.0 * w->half_width[i];
    r->max_speed = w->kv[i];
    r->beam_count = (int)w->beam_count[i];
    r->ranges = w->scan + (int64_t)w->beams * i;
    r->angles = w->beam_offsets + (int64_t)w->beams * i;
    r->max_range = w->max_range[i];
    r->stalled = w->stalled[i] != 0;
    if (isinf(w->comm_range)) {
        r->comms = w->comms;
        r->comms_count = w->comms_count;
    } else {  /* as robot.comms: rows within range of the measured position */
        int kept = 0;
        for (int row = 0; row < w->comms_count; row++) {
            const double *c = w->comms + MIMICS_COMMS_COLUMNS * row;
            if (hypot(c[1] - r->pose[0], c[2] - r->pose[1]) <= w->comm_range) {
                copy(w->comms_scratch + MIMICS_COMMS_COLUMNS * kept, c, MIMICS_COMMS_COLUMNS);
                kept++;
            }
        }
        r->comms = w->comms_scratch;
        r->comms_count = kept;
    }
}

/* Call mimics_step (or mimics_reset) for robots ids[0..k-1] in turn.
 * flags[j] and codes[j] describe call j; returns how many calls have flags. */
static int mimics_host_run(mimics_host_world *w, mimics_robot *robots, mimics_output *outputs,
                           const int64_t *ids, int k, int reset, int *flags, int *codes) {
    was_cut = 0;
    if (sigsetjmp(cut_point, 0)) {  /* cut: w->current still names the robot being called */
        was_cut = 1;
        return -1;
    }
    cut_armed = 1;
    int flagged = 0;
    for (int j = 0; j < k; j++) {
        int64_t i = ids[j];
        mimics_robot *r = &robots[i];
        mimics_output *out = &outputs[i];
        fill_robot(w, r, i);
        out->speed = NAN;  /* a call that forgets to answer returns non-finite references */
        out->heading = NAN;
        out->log_size = 0;
        out->log[0] = '\0';
        out->outbox_count = 0;
        w->current[0] = i;
        double start = seconds_now();
        int code = reset ? (mimics_reset ? mimics_reset(r, out) : 0) : mimics_step(r, out);
        w->user_time[i] = seconds_now() - start;
        int flag = 0;
        codes[j] = code;
        if (code != 0) {
            flag |= FLAG_ERROR;
        } else if (!reset) {
            if (isfinite(out->speed) && isfinite(out->heading)) {
                w->reference[2 * i] = out->speed;
                w->reference[2 * i + 1] = out->heading;
            } else {
                flag |= FLAG_NOT_FINITE;
            }
        }
        if (out->log_size > 0) flag |= FLAG_LOG;
        if (out->outbox_count > 0) flag |= FLAG_SENT;
        flags[j] = flag;
        if (flag) flagged++;
    }
    cut_armed = 0;
    w->current[0] = -1;
    return flagged;
}

static int mimics_host_team(const mimics_team *team, double *speed, double *heading, int reset) {
    was_cut = 0;
    if (sigsetjmp(cut_point, 0)) {
        was_cut = 1;
        return -1;
    }
    cut_armed = 1;
    int code = reset ? (mimics_team_reset ? mimics_team_reset(team) : 0)
                     : mimics_team_step(team, speed, heading);
    cut_armed = 0;
    return code;
}
