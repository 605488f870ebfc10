/* The robot link for robots whose software is C: the same code as retreat::robot::RobotLink
 * (retreat/robot/robot_link.hpp), behind plain C functions. Link with retreat_robot_c (a shared
 * library). docs/robot-guide.md walks through it.
 *
 * Every function is safe to call with a NULL robot (it then does nothing and returns 0, -1 or
 * 0.0). Not thread-safe per robot: call one robot's functions from one thread. */
#ifndef RETREAT_ROBOT_H
#define RETREAT_ROBOT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Phases (docs/protocol.md §4). */
#define RETREAT_PHASE_WAITING 0
#define RETREAT_PHASE_INSIDE 1
#define RETREAT_PHASE_RETREATING 2
#define RETREAT_PHASE_DEPARTED 3

typedef struct retreat_robot retreat_robot;

/* How a robot joins. With `scenario` set (the swarm's scenario file), the DDS settings and the
 * time mode come from it and the fields below it are ignored. */
typedef struct retreat_robot_options {
  uint32_t robot_id;
  const char* scenario; /* path of the swarm's scenario (YAML), or NULL */
  const char* vendor;   /* "fastdds" or "cyclonedds"; NULL: "cyclonedds" */
  int domain;           /* DDS domain id, 0..232 */
  const char* prefix;   /* topic prefix; NULL: "retreat" */
  const char* profile;  /* vendor XML profile; NULL: built-in loopback-only settings */
  int lockstep;         /* 1: lockstep (await answers, re-send), 0: real time */
  int tracked;          /* 1: a real robot of a mixed swarm: report poses, the arena writes frames */
} retreat_robot_options;

typedef struct retreat_robot_counters {
  uint64_t frames_sent;
  uint64_t frames_resent;
  uint64_t reports_refused;
  uint64_t write_failures;
  uint64_t decisions_accepted;
  uint64_t decisions_future;
  uint64_t decisions_stale;
  uint64_t decisions_invalid;
} retreat_robot_counters;

/* Fills *options with the defaults (robot 0, Cyclone DDS, domain 0, prefix "retreat", real time,
 * not tracked). With a scenario, tracked follows it: robots 0 .. arena.external_robots-1 are. */
void retreat_robot_options_init(retreat_robot_options* options);

/* Why retreat_robot_join failed. */
#define RETREAT_ROBOT_OK 0
#define RETREAT_ROBOT_BAD_OPTIONS 1 /* a bad option or scenario value: fix the input */
#define RETREAT_ROBOT_MIDDLEWARE 2  /* the DDS participant or its endpoints could not be made */
typedef struct retreat_robot_error {
  int code;           /* RETREAT_ROBOT_OK, _BAD_OPTIONS or _MIDDLEWARE */
  char message[512];  /* one line naming the bad value and what is allowed, or the middleware's error */
} retreat_robot_error;

/* Joins the swarm as robot options->robot_id. Returns NULL on failure and fills *error (when not
 * NULL). */
retreat_robot* retreat_robot_join(const retreat_robot_options* options, retreat_robot_error* error);

/* Waits up to timeout_s seconds for the robot's agent; 1 when it has matched, else 0. */
int retreat_robot_wait_for_agent(retreat_robot* robot, double timeout_s);

/* Publishes the proximity signal at the robot's own time [s] as the next frame. Returns the
 * frame's tick (>= 0), or -1 when the report is refused (time not finite, negative or going back,
 * phase > 3, a report after departed): counted, and its onsets go with the next report. */
int64_t retreat_robot_report(retreat_robot* robot, double time, uint8_t phase, int in_contact,
                             uint32_t new_onsets);

/* A tracked robot (mixed swarm) publishes its pose: its own time [s], x, y [m] in the arena's frame
 * (origin at the centre of the region), heading theta [rad]. Returns the pose's sequence number,
 * or -1 when refused (not tracked, time not finite, negative or going back, NaN): counted. */
int64_t retreat_robot_report_pose(retreat_robot* robot, double time, double x, double y, double theta);

/* 1 when the link is tracked (a real robot of a mixed swarm), else 0. */
int retreat_robot_tracked(const retreat_robot* robot);

/* Takes the decisions that arrived; 1 when the newest frame has been answered, else 0. */
int retreat_robot_poll(retreat_robot* robot);

/* Waits up to timeout_s for the newest frame's answer, re-sending it every 200 ms; 1 if it came. */
int retreat_robot_await_answer(retreat_robot* robot, double timeout_s);

/* 1 once the agent has decided that the robot leaves the region (sticky), else 0. */
int retreat_robot_retreat(const retreat_robot* robot);

/* 1 when the link runs in lockstep (await each answer), 0 in real time. */
int retreat_robot_lockstep(const retreat_robot* robot);

/* Seconds since the robot joined (a monotonic clock starting at 0). */
double retreat_robot_now(const retreat_robot* robot);

/* The link's counters; the reason of the last refused report (a static empty string if none). */
void retreat_robot_get_counters(const retreat_robot* robot, retreat_robot_counters* counters);
const char* retreat_robot_refused_reason(const retreat_robot* robot);

/* Leaves the swarm and frees the robot. */
void retreat_robot_leave(retreat_robot* robot);

#ifdef __cplusplus
}
#endif

#endif /* RETREAT_ROBOT_H */
