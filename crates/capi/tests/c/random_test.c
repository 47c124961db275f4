/* Random costmaps and poses against the C interface: sizes 1x1 to 300x300, random costs,
 * NaN and infinite poses, zero, negative, tiny and huge resolutions, random options. Every
 * call must return a status of the contract (never crash), leave *out NULL on failure, and
 * say why in hp_last_error. Seeded (argv[1], default 1); run by tests/c_api.rs. */

#include "harmonic_planner.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned long long state;
static unsigned long long next(void) { /* splitmix64 */
  unsigned long long z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
static double uniform(void) { return (double)(next() >> 11) / 9007199254740992.0; }
static int below(int n) { return (int)(next() % (unsigned long long)n); }

/* Whether this round keeps its numbers ordinary (most rounds) or mixes in odd ones. */
static int sane;

/* A number that is usually ordinary and, outside sane rounds, sometimes not. */
static double odd_number(double lo, double hi) {
  switch (sane ? 99 : below(12)) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return -INFINITY;
    case 3: return 1e300;
    case 4: return -1e300;
    default: return lo + (hi - lo) * uniform();
  }
}

static int valid(HpStatus s) { return (int)s >= 0 && (int)s <= 8; }

int main(int argc, char **argv) {
  state = argc > 1 ? strtoull(argv[1], NULL, 10) : 1;
  int failures = 0, built = 0, planned = 0;
  for (int round = 0; round < 60; round++) {
    sane = below(10) < 7;
    unsigned w = 1 + (unsigned)below(round % 5 == 0 ? 300 : 40);
    unsigned h = 1 + (unsigned)below(round % 7 == 0 ? 300 : 40);
    uint8_t *costs = malloc((size_t)w * h);
    int style = sane ? 1 + below(3) : below(4);
    for (size_t i = 0; i < (size_t)w * h; i++)
      costs[i] = style == 0 ? (uint8_t)below(256) /* anything */
                 : style == 1 ? (below(10) == 0 ? 254 : 0) /* sparse obstacles */
                 : style == 2 ? (uint8_t)(below(4) == 0 ? 254 : below(200))
                              : 0;
    double res_choices[] = {0.05, 0.1, 1.0, 0.0, -0.1, 1e-12, 1e9, NAN};
    HpCostmap map = {w, h, res_choices[below(sane ? 3 : 8)], odd_number(-50, 50),
                     odd_number(-50, 50), !sane && below(10) == 0 ? NULL : costs};
    if (!sane && below(10) == 0) map.size_x = 0;
    double span_x = map.resolution > 0 && isfinite(map.resolution) ? w * map.resolution : 1;
    double span_y = map.resolution > 0 && isfinite(map.resolution) ? h * map.resolution : 1;
    HpOptions o = hp_options_default();
    o.robot_radius = below(3) == 0 ? odd_number(0, 0.5) : 0.0;
    o.obstacle_cost = sane ? 253 : (uint8_t)below(256);
    o.unknown_is_free = below(2);
    o.cost_weight = below(3) == 0 ? odd_number(-1, 8) : uniform() * 4;
    o.goal_tolerance = below(3) == 0 ? odd_number(-1, 2) : 0.0;
    o.use_goal_heading = below(2);
    o.threads = (uint32_t)below(3);
    HpPose goal = {map.origin_x + odd_number(-0.2, 1.2) * span_x,
                   map.origin_y + odd_number(-0.2, 1.2) * span_y, odd_number(-4, 4)};
    HpPlanner *planner = (HpPlanner *)&map; /* not NULL: the call must clear it */
    HpStatus s = hp_planner_new(&map, goal, !sane && below(10) == 0 ? NULL : &o, &planner);
    if (!valid(s)) {
      fprintf(stderr, "round %d: status %d out of range\n", round, (int)s);
      failures++;
    }
    if (s != HP_OK && (planner != NULL || strlen(hp_last_error()) == 0)) {
      fprintf(stderr, "round %d: status %d with planner %p, message '%s'\n", round, (int)s,
              (void *)planner, hp_last_error());
      failures++;
    }
    if (s == HP_OK) {
      built++;
      for (int k = 0; k < 10; k++) {
        HpPose start = {map.origin_x + odd_number(-0.2, 1.2) * span_x,
                        map.origin_y + odd_number(-0.2, 1.2) * span_y, odd_number(-4, 4)};
        HpPath *path = (HpPath *)&map;
        HpStatus p = hp_planner_plan(planner, start, &path);
        if (!valid(p) || (p != HP_OK && path != NULL) || (p == HP_OK && path == NULL)) {
          fprintf(stderr, "round %d: plan status %d, path %p\n", round, (int)p, (void *)path);
          failures++;
        }
        if (p == HP_OK) {
          planned++;
          size_t n = hp_path_size(path);
          const HpPose *poses = hp_path_poses(path);
          for (size_t i = 0; i < n; i++)
            if (!isfinite(poses[i].x) || !isfinite(poses[i].y) || !isfinite(poses[i].theta)) {
              fprintf(stderr, "round %d: pose %zu not finite\n", round, i);
              failures++;
              break;
            }
        }
        hp_path_free(path == (HpPath *)&map ? NULL : path);
        (void)hp_planner_potential(planner, odd_number(-100, 100), odd_number(-100, 100));
      }
      hp_planner_free(planner);
    }
    free(costs);
  }
  printf("random: %d planners built, %d paths planned, %d failures\n", built, planned, failures);
  return failures == 0 ? 0 : 1;
}
