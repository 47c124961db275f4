/* The C interface against its contract, in C99: a costmap built in memory, every status, the
 * goal tolerance, a path checked on the grid, the potential, and four threads planning from one
 * planner at once. Compiled and run by tests/c_api.rs; exits non-zero on the first failure. */

#include "harmonic_planner.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond, ...)                                                                   \
  do {                                                                                     \
    if (!(cond)) {                                                                         \
      fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond);             \
      fprintf(stderr, __VA_ARGS__);                                                        \
      fprintf(stderr, " (last error: %s)\n", hp_last_error());                             \
      failures++;                                                                          \
    }                                                                                      \
  } while (0)

/* 60 x 40 cells of 0.1 m from (-1, -2): a lethal wall at column 30 with a one-cell door at
 * row 20, a closed pocket (a ring of lethal cells around rows 4..8, columns 4..8), an unknown
 * block at columns 50..55, rows 30..35, a graded band (cost 100) at column 15. */
enum { W = 60, H = 40 };
static uint8_t costs[W * H];
static const double RES = 0.1, OX = -1.0, OY = -2.0;

static void build_costmap(void) {
  memset(costs, 0, sizeof costs);
  for (int my = 0; my < H; my++) {
    if (my != 20) costs[my * W + 30] = 254;
    costs[my * W + 15] = 100;
  }
  for (int my = 3; my <= 9; my++)
    for (int mx = 3; mx <= 9; mx++)
      if (my == 3 || my == 9 || mx == 3 || mx == 9) costs[my * W + mx] = 254;
  for (int my = 30; my <= 35; my++)
    for (int mx = 50; mx <= 55; mx++) costs[my * W + mx] = 255;
}

static HpCostmap costmap(void) {
  HpCostmap m;
  m.size_x = W;
  m.size_y = H;
  m.resolution = RES;
  m.origin_x = OX;
  m.origin_y = OY;
  m.data = costs;
  return m;
}

static HpPose pose(double mx, double my, double theta) { /* a cell's centre */
  HpPose p;
  p.x = OX + (mx + 0.5) * RES;
  p.y = OY + (my + 0.5) * RES;
  p.theta = theta;
  return p;
}

/* Whether every point of the segment a-b lies on cells of cost below 253 (sampled at a
 * hundredth of a cell; the grid check is the test's own, not the planner's). */
static int segment_clear(HpPose a, HpPose b) {
  double len = hypot(b.x - a.x, b.y - a.y);
  int n = (int)ceil(len / (0.01 * RES)) + 1;
  for (int k = 0; k <= n; k++) {
    double t = (double)k / n;
    double x = a.x + t * (b.x - a.x), y = a.y + t * (b.y - a.y);
    int mx = (int)floor((x - OX) / RES), my = (int)floor((y - OY) / RES);
    if (mx < 0 || my < 0 || mx >= W || my >= H) return 0;
    if (costs[my * W + mx] >= 253) return 0;
  }
  return 1;
}

static int never_cancel(void *user) {
  (*(int *)user)++;
  return 0;
}
static int always_cancel(void *user) {
  (void)user;
  return 1;
}

struct job {
  const HpPlanner *planner;
  HpPose start;
  HpStatus status;
  double length;
  size_t size;
};

static void *plan_job(void *arg) {
  struct job *j = (struct job *)arg;
  for (int round = 0; round < 20; round++) {
    HpPath *path = NULL;
    j->status = hp_planner_plan(j->planner, j->start, &path);
    j->length = hp_path_length(path);
    j->size = hp_path_size(path);
    hp_path_free(path);
  }
  return NULL;
}

int main(void) {
  build_costmap();
  HpCostmap map = costmap();
  HpOptions opts = hp_options_default();
  CHECK(opts.obstacle_cost == 253 && opts.cost_weight == 1.0 && opts.use_goal_heading == 1 &&
            opts.threads == 0 && opts.cancel == NULL,
        "defaults");
  CHECK(strlen(hp_version()) > 0, "version");

  HpPose goal = pose(45, 10, 1.25);
  HpPlanner *planner = NULL;

  /* Bad arguments: a status and a one-line message, *out left NULL. */
  CHECK(hp_planner_new(NULL, goal, &opts, &planner) == HP_INVALID_ARGUMENT, "null map");
  CHECK(planner == NULL && strlen(hp_last_error()) > 0, "message for a null map");
  CHECK(hp_planner_new(&map, goal, &opts, NULL) == HP_INVALID_ARGUMENT, "null out");
  HpCostmap bad = map;
  bad.resolution = 0.0;
  CHECK(hp_planner_new(&bad, goal, &opts, &planner) == HP_INVALID_ARGUMENT, "resolution 0");
  bad = map;
  bad.size_x = 0;
  CHECK(hp_planner_new(&bad, goal, &opts, &planner) == HP_INVALID_ARGUMENT, "size 0");
  bad = map;
  bad.data = NULL;
  CHECK(hp_planner_new(&bad, goal, &opts, &planner) == HP_INVALID_ARGUMENT, "null data");
  HpPose nan_goal = goal;
  nan_goal.x = NAN;
  CHECK(hp_planner_new(&map, nan_goal, &opts, &planner) == HP_INVALID_ARGUMENT, "NaN goal");
  HpOptions neg = opts;
  neg.robot_radius = -1.0;
  CHECK(hp_planner_new(&map, goal, &neg, &planner) == HP_INVALID_ARGUMENT, "radius < 0");

  /* Goals outside the map and on blocked cells; a goal tolerance moves a blocked goal. */
  CHECK(hp_planner_new(&map, pose(80, 10, 0), &opts, &planner) == HP_GOAL_OUTSIDE_MAP,
        "goal outside");
  CHECK(planner == NULL, "no planner for a goal outside");
  CHECK(hp_planner_new(&map, pose(30, 10, 0), &opts, &planner) == HP_GOAL_OCCUPIED,
        "goal on the wall");
  CHECK(strstr(hp_last_error(), "goal") != NULL, "the message names the goal: %s",
        hp_last_error());
  CHECK(hp_planner_new(&map, pose(52, 32, 0), &opts, &planner) == HP_GOAL_OCCUPIED,
        "goal on an unknown cell");
  HpOptions tolerant = opts;
  tolerant.goal_tolerance = 0.25;
  CHECK(hp_planner_new(&map, pose(30, 10, 0), &tolerant, &planner) == HP_OK,
        "goal on the wall with a tolerance");
  hp_planner_free(planner);
  planner = NULL;
  HpOptions unknown_free = opts;
  unknown_free.unknown_is_free = 1;
  CHECK(hp_planner_new(&map, pose(52, 32, 0), &unknown_free, &planner) == HP_OK,
        "goal on an unknown cell when unknown is free");
  hp_planner_free(planner);
  planner = NULL;

  /* Cancelled at the first stage: no planner. */
  HpOptions cancelled = opts;
  cancelled.cancel = always_cancel;
  CHECK(hp_planner_new(&map, goal, &cancelled, &planner) == HP_CANCELLED, "cancel");
  CHECK(planner == NULL, "no planner after cancel");

  /* The planner, with a cancel callback that lets it run (and is asked at every stage), on
   * two threads, with a robot radius of one cell. */
  int asked = 0;
  HpOptions run = opts;
  run.cancel = never_cancel;
  run.cancel_user = &asked;
  run.threads = 2;
  CHECK(hp_planner_new(&map, goal, &run, &planner) == HP_OK, "build");
  CHECK(planner != NULL && asked >= 2, "asked %d times", asked);
  CHECK(strcmp(hp_last_error(), "") == 0, "no error after a success");
  if (planner == NULL) return 1;

  /* Starts: outside, occupied, in the closed pocket, and good ones. */
  HpPath *path = NULL;
  CHECK(hp_planner_plan(NULL, goal, &path) == HP_INVALID_ARGUMENT, "null planner");
  CHECK(hp_planner_plan(planner, goal, NULL) == HP_INVALID_ARGUMENT, "null out path");
  CHECK(hp_planner_plan(planner, pose(-5, 10, 0), &path) == HP_START_OUTSIDE_MAP,
        "start outside");
  CHECK(path == NULL, "no path for a start outside");
  CHECK(hp_planner_plan(planner, pose(30, 5, 0), &path) == HP_START_OCCUPIED, "start on wall");
  CHECK(hp_planner_plan(planner, pose(6, 6, 0), &path) == HP_NO_VALID_PATH, "start in pocket");
  CHECK(strlen(hp_last_error()) > 0, "message for no path");

  HpPose starts[4] = {pose(2, 35, 0.0), pose(20, 2, 0.5), pose(12, 25, -1.0), pose(58, 38, 3.0)};
  double lengths[4];
  for (int s = 0; s < 4; s++) {
    path = NULL;
    HpStatus status = hp_planner_plan(planner, starts[s], &path);
    CHECK(status == HP_OK, "start %d: status %d", s, (int)status);
    size_t n = hp_path_size(path);
    const HpPose *poses = hp_path_poses(path);
    CHECK(n >= 2 && poses != NULL, "start %d: %zu poses", s, n);
    if (n < 2 || poses == NULL) continue;
    CHECK(poses[0].x == starts[s].x && poses[0].y == starts[s].y &&
              poses[0].theta == starts[s].theta,
          "start %d: the first pose is the start", s);
    CHECK(fabs(poses[n - 1].x - goal.x) < 1e-9 && fabs(poses[n - 1].y - goal.y) < 1e-9,
          "start %d: ends at (%g, %g), the goal is (%g, %g)", s, poses[n - 1].x, poses[n - 1].y,
          goal.x, goal.y);
    CHECK(poses[n - 1].theta == goal.theta, "start %d: the last pose carries the goal heading",
          s);
    double length = 0.0;
    for (size_t k = 0; k + 1 < n; k++) {
      CHECK(segment_clear(poses[k], poses[k + 1]), "start %d: segment %zu leaves the clear cells",
            s, k);
      length += hypot(poses[k + 1].x - poses[k].x, poses[k + 1].y - poses[k].y);
      if (k > 0 && k + 1 < n - 1) {
        double tangent = atan2(poses[k + 1].y - poses[k].y, poses[k + 1].x - poses[k].x);
        double d = fabs(remainder(poses[k].theta - tangent, 2.0 * 3.14159265358979323846));
        CHECK(d < 1.6, "start %d: pose %zu heading %g far from the path's %g", s, k,
              poses[k].theta, tangent);
      }
    }
    CHECK(fabs(length - hp_path_length(path)) < 1e-6, "start %d: length %g vs %g", s, length,
          hp_path_length(path));
    CHECK(hp_path_min_clearance(path) >= 0.0, "start %d: clearance", s);
    lengths[s] = hp_path_length(path);
    hp_path_free(path);
  }
  hp_path_free(NULL);

  /* The potential: 0 at the goal, between 0 and 1 in free space, NaN on a wall and outside. */
  double at_goal = hp_planner_potential(planner, goal.x, goal.y);
  double free_space = hp_planner_potential(planner, starts[0].x, starts[0].y);
  CHECK(fabs(at_goal) < 1e-9, "phi at the goal %g", at_goal);
  CHECK(free_space > 0.0 && free_space < 1.0, "phi in free space %g", free_space);
  CHECK(isnan(hp_planner_potential(planner, pose(30, 5, 0).x, pose(30, 5, 0).y)), "phi on wall");
  CHECK(isnan(hp_planner_potential(planner, 100.0, 100.0)), "phi outside");
  CHECK(isnan(hp_planner_potential(NULL, 0.0, 0.0)), "phi of NULL");

  /* Four threads on the one planner at once: the same paths as one at a time. */
  pthread_t threads[4];
  struct job jobs[4];
  for (int s = 0; s < 4; s++) {
    jobs[s].planner = planner;
    jobs[s].start = starts[s];
    pthread_create(&threads[s], NULL, plan_job, &jobs[s]);
  }
  for (int s = 0; s < 4; s++) {
    pthread_join(threads[s], NULL);
    CHECK(jobs[s].status == HP_OK && jobs[s].length == lengths[s],
          "thread %d: status %d, length %g vs %g", s, (int)jobs[s].status, jobs[s].length,
          lengths[s]);
  }

  hp_planner_free(planner);
  hp_planner_free(NULL);
  if (failures == 0) printf("all C checks passed\n");
  return failures == 0 ? 0 : 1;
}
