/* retreat-robot-example: a stand-in for a real robot, written against the C robot link only
 * (retreat/robot/robot.h), as a robot's own software would be. It has its own control loop
 * (--rate Hz, each period drawn with +/- --jitter), its own clock, a noisy proximity sensor
 * (encounters arrive at --onset-rate per second; each is missed with probability --miss; false
 * onsets arrive at --false-rate per second) and a motion model: inside the region it works; told
 * to retreat, it drives out at --speed m/s from --distance m inside the boundary, then departs.
 *
 * Lockstep (the scenario's run.mode, or --lockstep): its clock is tick / rate and it waits for
 * each answer. Real time: it sleeps out each period and takes whatever answers arrived.
 *
 * Tracked (a real robot of a mixed swarm: the scenario's arena.external_robots, or --tracked): the
 * arena senses it from its pose, so it reports no proximity; it drives round the centre of the
 * region on a circle of radius --orbit m at --speed m/s and publishes its pose each period (with
 * --pose-noise m of tracking noise); told to retreat, it drives straight out until --exit-radius
 * m from the centre, publishes its pose there for one more second, and stops.
 *
 * --log FILE writes one CSV row per frame sent: tick, time, phase, in_contact, new_onsets and
 * the robot's retreat state after that frame's answer (lockstep) or poll (real time).
 *
 * Exit codes: 0 departed, or --max-time reached; 2 bad arguments; 1 the link failed or no agent
 * came within --agent-timeout seconds. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "retreat/robot/robot.h"

/* splitmix64: the robot's own seeded generator. */
static uint64_t next_u64(uint64_t* state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
static double uniform(uint64_t* state) { return (double)(next_u64(state) >> 11) * 0x1.0p-53; }

/* A Poisson draw with mean mu (small mu: inversion). */
static uint32_t poisson(uint64_t* state, double mu) {
  double p = exp(-mu), sum = p, u = uniform(state);
  uint32_t k = 0;
  while (u > sum && k < 1000) {
    ++k;
    p *= mu / k;
    sum += p;
  }
  return k;
}

static int parse_double(const char* name, const char* text, double low, double high, double* out) {
  char* end = NULL;
  errno = 0;
  double v = strtod(text, &end);
  if (errno != 0 || end == text || *end != '\0' || !isfinite(v) || v < low || v > high) {
    fprintf(stderr, "retreat-robot-example: %s '%s' is not a number in [%g, %g]\n", name, text, low, high);
    return 0;
  }
  *out = v;
  return 1;
}

/* A whole number in [0, high], in decimal digits only (no sign, no fraction, no 0x). */
static int parse_whole(const char* name, const char* text, unsigned long long high, unsigned long long* out) {
  char* end = NULL;
  errno = 0;
  const int digits = text[0] >= '0' && text[0] <= '9';
  const unsigned long long v = digits ? strtoull(text, &end, 10) : 0;
  if (!digits || errno != 0 || *end != '\0' || v > high) {
    fprintf(stderr, "retreat-robot-example: %s '%s' is not a whole number in [0, %llu]\n", name, text, high);
    return 0;
  }
  *out = v;
  return 1;
}

static void sleep_seconds(double s) {
  if (s <= 0) return;
  struct timespec ts;
  ts.tv_sec = (time_t)s;
  ts.tv_nsec = (long)((s - (double)ts.tv_sec) * 1e9);
  while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
  }
}

static double gaussian(uint64_t* state) {
  const double u = uniform(state), w = uniform(state);
  return sqrt(-2.0 * log(u > 0 ? u : 1e-300)) * cos(6.283185307179586 * w);
}

static void usage(FILE* out) {
  fprintf(out,
          "usage: retreat-robot-example --robot-id N (--scenario FILE | [--dds VENDOR] [--domain D] "
          "[--lockstep])\n"
          "       [--rate HZ] [--jitter F] [--onset-rate R] [--miss P] [--false-rate R] [--contact S]\n"
          "       [--speed V] [--distance M] [--seed S] [--max-time S] [--agent-timeout S] [--log FILE]\n"
          "       [--tracked] [--orbit R] [--exit-radius R] [--pose-noise S]\n");
}

/* A tracked robot: it moves, publishes its pose and obeys; the arena senses it. */
static int run_tracked(retreat_robot* link, uint64_t* rng, double rate, double jitter, double speed, double orbit,
                       double exit_radius, double pose_noise, double max_time, FILE* log) {
  if (log != NULL) fprintf(log, "seq,time,x,y,theta,retreat\n");
  double angle = 6.283185307179586 * uniform(rng), r = orbit, last = 0, out_since = -1;
  while (1) {
    const double period = (1.0 / rate) * (1.0 + jitter * (2.0 * uniform(rng) - 1.0));
    sleep_seconds(last + period - retreat_robot_now(link));
    const double now = retreat_robot_now(link), dt = now - last;
    last = now;
    retreat_robot_poll(link);
    double theta;
    if (!retreat_robot_retreat(link)) {
      if (orbit > 0) angle += speed * dt / orbit; /* round the centre, counter-clockwise */
      theta = angle + 1.5707963267948966;
    } else {
      r += speed * dt; /* straight out */
      theta = angle;
      if (r >= exit_radius && out_since < 0) out_since = now;
    }
    const double x = r * cos(angle) + pose_noise * gaussian(rng), y = r * sin(angle) + pose_noise * gaussian(rng);
    const int64_t seq = retreat_robot_report_pose(link, now, x, y, theta);
    if (seq < 0) {
      fprintf(stderr, "retreat-robot-example: pose refused: %s\n", retreat_robot_refused_reason(link));
      return 1;
    }
    if (log != NULL) fprintf(log, "%lld,%.17g,%.6f,%.6f,%.6f,%d\n", (long long)seq, now, x, y, theta, retreat_robot_retreat(link));
    if (out_since >= 0 && now - out_since >= 1.0) {
      fprintf(stderr, "retreat-robot-example: tracked robot left the region at t = %.2f s\n", out_since);
      return 0;
    }
    if (now >= max_time && !retreat_robot_retreat(link)) {
      fprintf(stderr, "retreat-robot-example: tracked robot still inside at --max-time %.1f s\n", max_time);
      return 0;
    }
  }
}

int main(int argc, char** argv) {
  retreat_robot_options options;
  retreat_robot_options_init(&options);
  double rate = 10, jitter = 0.2, onset_rate = 1.5, miss = 0, false_rate = 0, contact = 0.5;
  double speed = 0.2, distance = 0.4, max_time = 600, agent_timeout = 60;
  unsigned long long seed = 1, robot = 0, domain = 0;
  int have_robot = 0;
  double orbit = 0.5, exit_radius = 2.0, pose_noise = 0.0;
  const char* log_path = NULL;
  static const struct option longs[] = {
      {"robot-id", required_argument, 0, 'i'}, {"scenario", required_argument, 0, 's'},
      {"dds", required_argument, 0, 'v'},      {"domain", required_argument, 0, 'd'},
      {"lockstep", no_argument, 0, 'l'},       {"rate", required_argument, 0, 'r'},
      {"jitter", required_argument, 0, 'j'},   {"onset-rate", required_argument, 0, 'o'},
      {"miss", required_argument, 0, 'm'},     {"false-rate", required_argument, 0, 'f'},
      {"contact", required_argument, 0, 'c'},  {"speed", required_argument, 0, 'p'},
      {"distance", required_argument, 0, 'x'}, {"seed", required_argument, 0, 'e'},
      {"max-time", required_argument, 0, 't'}, {"agent-timeout", required_argument, 0, 'a'},
      {"log", required_argument, 0, 'g'},      {"help", no_argument, 0, 'h'},
      {"tracked", no_argument, 0, 'T'},        {"orbit", required_argument, 0, 'O'},
      {"exit-radius", required_argument, 0, 'X'}, {"pose-noise", required_argument, 0, 'N'},
      {0, 0, 0, 0}};
  int c;
  opterr = 0; /* getopt's own messages name the program by its path; ours are one line each */
  while ((c = getopt_long(argc, argv, "", longs, NULL)) != -1) {
    int ok = 1;
    switch (c) {
      case 'i': ok = have_robot = parse_whole("--robot-id", optarg, 4294967295ULL, &robot); break;
      case 's': options.scenario = optarg; break;
      case 'v': options.vendor = optarg; break;
      case 'd': ok = parse_whole("--domain", optarg, 232, &domain); break;
      case 'l': options.lockstep = 1; break;
      case 'r': ok = parse_double("--rate", optarg, 0.1, 1000, &rate); break;
      case 'j': ok = parse_double("--jitter", optarg, 0, 0.9, &jitter); break;
      case 'o': ok = parse_double("--onset-rate", optarg, 0, 1000, &onset_rate); break;
      case 'm': ok = parse_double("--miss", optarg, 0, 1, &miss); break;
      case 'f': ok = parse_double("--false-rate", optarg, 0, 1000, &false_rate); break;
      case 'c': ok = parse_double("--contact", optarg, 0, 60, &contact); break;
      case 'p': ok = parse_double("--speed", optarg, 1e-3, 10, &speed); break;
      case 'x': ok = parse_double("--distance", optarg, 0, 1000, &distance); break;
      case 'e': ok = parse_whole("--seed", optarg, 18446744073709551615ULL, &seed); break;
      case 't': ok = parse_double("--max-time", optarg, 0, 1e7, &max_time); break;
      case 'a': ok = parse_double("--agent-timeout", optarg, 0, 1e6, &agent_timeout); break;
      case 'g': log_path = optarg; break;
      case 'T': options.tracked = 1; break;
      case 'O': ok = parse_double("--orbit", optarg, 0, 1000, &orbit); break;
      case 'X': ok = parse_double("--exit-radius", optarg, 0, 1000, &exit_radius); break;
      case 'N': ok = parse_double("--pose-noise", optarg, 0, 10, &pose_noise); break;
      case 'h': usage(stdout); return 0;
      default:
        fprintf(stderr, "retreat-robot-example: '%s': an unknown option, or one without its value (--help lists them)\n",
                argv[optind - 1]);
        return 2;
    }
    if (!ok) return 2;
  }
  if (optind < argc) {
    fprintf(stderr, "retreat-robot-example: unexpected argument '%s'\n", argv[optind]);
    return 2;
  }
  if (!have_robot) {
    fprintf(stderr, "retreat-robot-example: --robot-id is required (--help lists the options)\n");
    return 2;
  }
  options.robot_id = (uint32_t)robot;
  options.domain = (int)domain;

  FILE* log = NULL;
  if (log_path != NULL && (log = fopen(log_path, "w")) == NULL) {
    fprintf(stderr, "retreat-robot-example: --log '%s' cannot be written: %s\n", log_path, strerror(errno));
    return 2;
  }
  retreat_robot_error error;
  retreat_robot* link = retreat_robot_join(&options, &error);
  if (link == NULL) {
    fprintf(stderr, "retreat-robot-example: %s\n", error.message);
    if (log != NULL) fclose(log);
    return error.code == RETREAT_ROBOT_BAD_OPTIONS ? 2 : 1;
  }
  if (!retreat_robot_wait_for_agent(link, agent_timeout)) {
    fprintf(stderr, "retreat-robot-example: robot %u: no agent matched within %g s\n", options.robot_id, agent_timeout);
    retreat_robot_leave(link);
    if (log != NULL) fclose(log);
    return 1;
  }
  if (log != NULL) fprintf(log, "tick,time,phase,in_contact,new_onsets,retreat\n");

  uint64_t rng = (uint64_t)seed * 0x2545f4914f6cdd1dULL + options.robot_id;
  if (retreat_robot_tracked(link)) {
    const int code = run_tracked(link, &rng, rate, jitter, speed, orbit, exit_radius, pose_noise, max_time, log);
    retreat_robot_leave(link);
    if (log != NULL) fclose(log);
    return code;
  }
  const int lockstep = retreat_robot_lockstep(link);
  uint8_t phase = RETREAT_PHASE_INSIDE;
  double now = 0, last = 0, contact_until = -1, to_boundary = distance;
  long long ticks = 0;
  int exit_code = 0;
  while (phase != RETREAT_PHASE_DEPARTED) {
    /* The period this loop iteration took: the nominal one, +/- jitter. */
    const double period = (1.0 / rate) * (1.0 + jitter * (2.0 * uniform(&rng) - 1.0));
    if (lockstep) {
      now = last + period; /* a virtual clock: lockstep runs as fast as the agent answers */
    } else {
      sleep_seconds(last + period - retreat_robot_now(link));
      now = retreat_robot_now(link);
    }
    const double dt = now - last;
    last = now;
    /* The sensor: true encounters, each missed with probability `miss`, plus false onsets. */
    uint32_t onsets = 0;
    if (phase == RETREAT_PHASE_INSIDE) {
      const uint32_t real = poisson(&rng, onset_rate * dt);
      for (uint32_t k = 0; k < real; ++k) onsets += uniform(&rng) >= miss ? 1u : 0u;
      onsets += poisson(&rng, false_rate * dt);
      if (real > 0) contact_until = now + contact;
    }
    /* The motion: driving out once told; departed at the boundary. */
    if (phase == RETREAT_PHASE_RETREATING) {
      to_boundary -= speed * dt;
      if (to_boundary <= 0) phase = RETREAT_PHASE_DEPARTED;
    }
    const int in_contact = phase == RETREAT_PHASE_INSIDE && now < contact_until;
    const int64_t tick = retreat_robot_report(link, now, phase, in_contact, onsets);
    if (tick < 0) {
      fprintf(stderr, "retreat-robot-example: report refused: %s\n", retreat_robot_refused_reason(link));
      exit_code = 1;
      break;
    }
    ++ticks;
    const uint8_t reported = phase;
    if (lockstep && phase != RETREAT_PHASE_DEPARTED) {
      if (!retreat_robot_await_answer(link, agent_timeout)) {
        fprintf(stderr, "retreat-robot-example: robot %u: no answer for tick %lld within %g s\n",
                options.robot_id, (long long)tick, agent_timeout);
        exit_code = 1;
        break;
      }
    } else {
      retreat_robot_poll(link);
    }
    if (phase == RETREAT_PHASE_INSIDE && retreat_robot_retreat(link)) phase = RETREAT_PHASE_RETREATING;
    if (log != NULL) {
      fprintf(log, "%lld,%.17g,%u,%d,%u,%d\n", (long long)tick, now, (unsigned)reported, in_contact, onsets,
              retreat_robot_retreat(link));
    }
    if (now >= max_time && phase == RETREAT_PHASE_INSIDE) break;
  }
  retreat_robot_counters counts;
  retreat_robot_get_counters(link, &counts);
  fprintf(stderr,
          "retreat-robot-example robot %u: %s after %lld frames at t = %.2f s; resent %llu, refused %llu, "
          "decisions %llu (stale %llu, future %llu, invalid %llu)\n",
          options.robot_id, phase == RETREAT_PHASE_DEPARTED ? "departed" : "stopped", ticks, now,
          (unsigned long long)counts.frames_resent, (unsigned long long)counts.reports_refused,
          (unsigned long long)counts.decisions_accepted, (unsigned long long)counts.decisions_stale,
          (unsigned long long)counts.decisions_future, (unsigned long long)counts.decisions_invalid);
  retreat_robot_leave(link);
  if (log != NULL) fclose(log);
  return exit_code;
}
