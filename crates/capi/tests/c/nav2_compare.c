/* Plans on a costmap file through the C interface and prints what tests/nav2_maps.rs compares.
 *
 *   nav2_compare COSTMAP ROBOT_RADIUS COST_WEIGHT GOAL_X GOAL_Y START_X START_Y [...]
 *
 * COSTMAP: a text line "size_x size_y resolution origin_x origin_y" and then size_x*size_y
 * cost bytes (Nav2's layout, row 0 the lowest y). Prints "build_ms T" (the best of three
 * builds), then per start "path STATUS LENGTH CLEARANCE N" and N lines "x y theta". */

#define _POSIX_C_SOURCE 199309L
#include "harmonic_planner.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

int main(int argc, char **argv) {
  if (argc < 8 || (argc - 6) % 2 != 0) {
    fprintf(stderr, "usage: %s COSTMAP RADIUS WEIGHT GX GY SX SY [SX SY]...\n", argv[0]);
    return 2;
  }
  FILE *f = fopen(argv[1], "rb");
  if (f == NULL) return 1;
  unsigned w, h;
  double res, ox, oy;
  if (fscanf(f, "%u %u %lf %lf %lf", &w, &h, &res, &ox, &oy) != 5 || fgetc(f) != '\n') return 1;
  uint8_t *data = malloc((size_t)w * h);
  if (data == NULL || fread(data, 1, (size_t)w * h, f) != (size_t)w * h) return 1;
  fclose(f);
  HpCostmap map = {w, h, res, ox, oy, data};
  HpOptions o = hp_options_default();
  o.robot_radius = atof(argv[2]);
  o.cost_weight = atof(argv[3]);
  HpPose goal = {atof(argv[4]), atof(argv[5]), 0.0};
  HpPlanner *planner = NULL;
  double best = 1e300;
  for (int run = 0; run < 3; run++) {
    hp_planner_free(planner);
    planner = NULL;
    double t0 = now_ms();
    HpStatus s = hp_planner_new(&map, goal, &o, &planner);
    double t = now_ms() - t0;
    if (s != HP_OK) {
      fprintf(stderr, "hp_planner_new: %d: %s\n", (int)s, hp_last_error());
      return 1;
    }
    if (t < best) best = t;
  }
  printf("build_ms %.4f\n", best);
  for (int k = 6; k + 1 < argc; k += 2) {
    HpPose start = {atof(argv[k]), atof(argv[k + 1]), 0.0};
    HpPath *path = NULL;
    HpStatus s = hp_planner_plan(planner, start, &path);
    size_t n = hp_path_size(path);
    printf("path %d %.12f %.12f %zu\n", (int)s, hp_path_length(path),
           hp_path_min_clearance(path), n);
    const HpPose *poses = hp_path_poses(path);
    for (size_t i = 0; i < n; i++) printf("%.9f %.9f %.9f\n", poses[i].x, poses[i].y, poses[i].theta);
    hp_path_free(path);
  }
  hp_planner_free(planner);
  free(data);
  return 0;
}
