/*
 * mimics.h: what an algorithm written in C or C++ sees and returns.
 *
 * Define one of these entry points (C linkage; in C++ wrap them in extern "C"):
 *
 *   int mimics_step(const mimics_robot *robot, mimics_output *out);
 *       Called for each active robot in turn, every step. Write the speed
 *       reference (m/s) and the absolute heading reference (rad) into
 *       out->speed and out->heading. Return 0, or any other number to report
 *       an error (the text given to mimics_log goes with it).
 *   int mimics_reset(const mimics_robot *robot, mimics_output *out);
 *       Optional: called once per robot before its first step.
 *
 *   int mimics_team_step(const mimics_team *team, double *speed, double *heading);
 *       The team form: once per step for all active robots; fill speed[k]
 *       and heading[k] for k = 0 .. team->count - 1 (rows of team->ids).
 *   int mimics_team_reset(const mimics_team *team);
 *       Optional: called once before the first team step.
 *
 * A file that defines mimics_team_step is a team algorithm (as a Python file
 * defining team_step). Everything is read-only except the memory blocks and
 * the output. Arrays are row-major; "(k, 3)" means k rows of 3 doubles.
 * mimics compiles with -ffp-contract=off so that a*b+c rounds as in NumPy.
 *
 * Documentation: docs/how-to/c-algorithms.md.
 */
#ifndef MIMICS_H
#define MIMICS_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* Raised whenever a field below changes meaning; mimics refuses a build of another version. */
#define MIMICS_ABI_VERSION 1

#define MIMICS_MEMORY_BYTES 8192   /* each robot's persistent memory block (zeroed at start) */
#define MIMICS_TEAM_MEMORY_BYTES 65536
#define MIMICS_LOG_BYTES 256       /* text of mimics_log per robot and step */
#define MIMICS_OUTBOX_SLOTS 4      /* messages a robot may send per step */
#define MIMICS_MESSAGE_BYTES 256   /* bytes per message */
#define MIMICS_BROADCAST (-1)      /* mimics_send to everyone within range */
#define MIMICS_COMMS_COLUMNS 6     /* a comms row: id, x, y, theta, v, w */

#ifdef __cplusplus
extern "C" {
#endif

/* A message received this step (sent by another robot at the previous step). */
typedef struct mimics_message {
    int sender;                 /* the sender's robot id */
    int size;                   /* bytes in data */
    const unsigned char *data;
} mimics_message;

/* One robot, as a Python algorithm's `robot`. */
typedef struct mimics_robot {
    int id;                     /* robot index in the scenario */
    double time;                /* simulated time (s) */
    double dt;                  /* simulation step (s) */
    double pose[3];             /* measured x, y, theta (positioning noise of its type) */
    double true_pose[3];        /* ground truth x, y, theta */
    double velocity[2];         /* measured v (m/s), w (rad/s) */
    double true_velocity[2];
    double acceleration[2];     /* measured dv/dt, dw/dt */
    double odometry[3];         /* the odometer's x, y, theta */
    int has_goal;               /* 0: no goal, goal[] is NaN */
    double goal[2];
    double length, width;       /* of its type (m) */
    double max_speed;           /* of its type (m/s) */
    int beam_count;             /* laser beams (0: no laser) */
    const double *ranges;       /* (beam_count) distances (m); max_range when nothing hit */
    const double *angles;       /* (beam_count) beam angles relative to the heading, right to left */
    double max_range;           /* the laser's range (m) */
    int comms_count;            /* rows of comms: active robots within communication range */
    const double *comms;        /* (comms_count, 6) rows id, x, y, theta, v, w (measured) */
    int inbox_count;
    const mimics_message *inbox;
    void *memory;               /* MIMICS_MEMORY_BYTES kept between this robot's calls */
    int stalled;                /* 1: its last move was undone against a wall or a robot
                                   (on_collision = "stall"; it stays active), else 0 */
} mimics_robot;

/* A message to send: filled by mimics_send. */
typedef struct mimics_outgoing {
    int to;                     /* a robot id, or MIMICS_BROADCAST */
    int size;
    unsigned char data[MIMICS_MESSAGE_BYTES];
} mimics_outgoing;

/* What one call returns. */
typedef struct mimics_output {
    double speed;               /* speed reference (m/s) */
    double heading;             /* absolute heading reference (rad) */
    int log_size;               /* filled by mimics_log */
    char log[MIMICS_LOG_BYTES];
    int outbox_count;           /* filled by mimics_send */
    mimics_outgoing outbox[MIMICS_OUTBOX_SLOTS];
} mimics_output;

/* All active robots at once, as a Python algorithm's `team` (row k is robot ids[k]). */
typedef struct mimics_team {
    int count;                  /* k: active robots */
    int beams;                  /* B: columns of ranges and angles (the most beams of any robot) */
    double time, dt;
    const int64_t *ids;         /* (k) robot indices */
    const double *pose;         /* (k, 3) measured */
    const double *true_pose;    /* (k, 3) */
    const double *velocity;     /* (k, 2) measured */
    const double *odometry;     /* (k, 3) */
    const double *goal;         /* (k, 2), NaN rows for robots without a goal */
    const double *ranges;       /* (k, B), NaN beyond a robot's beam count */
    const double *angles;       /* (k, B), NaN beyond a robot's beam count */
    const int64_t *beam_count;  /* (k) */
    const double *max_range;    /* (k) */
    const double *max_speed;    /* (k) */
    const double *length;       /* (k) */
    const double *width;        /* (k) */
    int comms_count;
    const double *comms;        /* (comms_count, 6) all active robots */
    void *memory;               /* MIMICS_TEAM_MEMORY_BYTES kept between calls */
    const int64_t *stalled;     /* (k) 1: stalled, as robot.stalled */
} mimics_team;

/* Entry points (define mimics_step or mimics_team_step; the resets are optional). */
int mimics_step(const mimics_robot *robot, mimics_output *out);
int mimics_reset(const mimics_robot *robot, mimics_output *out);
int mimics_team_step(const mimics_team *team, double *speed, double *heading);
int mimics_team_reset(const mimics_team *team);

/* The ABI this file was compiled against; mimics checks it when loading the build. */
#ifndef MIMICS_HOST
#if defined(__GNUC__) || defined(__clang__)
__attribute__((weak, visibility("default")))
#endif
int mimics_abi_version(void) { return MIMICS_ABI_VERSION; }
#endif

/* Add printf-style text to this step's user_msg log column (truncated to MIMICS_LOG_BYTES). */
static inline void mimics_log(mimics_output *out, const char *format, ...) {
    int room = MIMICS_LOG_BYTES - 1 - out->log_size;
    if (room <= 0) return;
    if (out->log_size > 0 && room > 3) {  /* messages are separated as robot.log does */
        memcpy(out->log + out->log_size, " | ", 3);
        out->log_size += 3;
        room -= 3;
    }
    va_list args;
    va_start(args, format);
    int written = vsnprintf(out->log + out->log_size, (size_t)room + 1, format, args);
    va_end(args);
    if (written > 0) out->log_size += written < room ? written : room;
}

/* Send size bytes to robot `to` (or MIMICS_BROADCAST); they arrive next step.
 * Returns 0, or -1 when the outbox is full or the message too long. */
static inline int mimics_send(mimics_output *out, int to, const void *data, int size) {
    if (out->outbox_count >= MIMICS_OUTBOX_SLOTS || size < 0 || size > MIMICS_MESSAGE_BYTES)
        return -1;
    mimics_outgoing *message = &out->outbox[out->outbox_count++];
    message->to = to;
    message->size = size;
    if (size > 0) memcpy(message->data, data, (size_t)size);
    return 0;
}

#ifdef __cplusplus
}
#endif

#endif /* MIMICS_H */
