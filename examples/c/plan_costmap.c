/* A starting point for a navigation-stack plugin: read a map_server map (YAML and a binary
 * PGM, trinary mode), build a costmap the way Nav2's static and inflation layers do (254
 * lethal, 253 within the inscribed radius, exponentially decaying costs out to the inflation
 * radius, 255 unknown), plan with harmonic-planner's C interface and print the poses.
 *
 *   cargo build --release -p harmonic-planner-c
 *   cc -std=c99 -O2 examples/c/plan_costmap.c -Icrates/capi/include -Ltarget/release \
 *      -Wl,-rpath,$PWD/target/release -lharmonic_planner -lm -o plan_costmap
 *   ./plan_costmap meshes/warehouse_map.yaml 16.5 1.5 -0.75 -0.5 [ROBOT_RADIUS]
 */

#include "harmonic_planner.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Nav2's inflation layer defaults (nav2_params.yaml): costs fall off as
 * 252 * exp(-scaling * (d - inscribed)) out to the inflation radius. */
static const double INFLATION_RADIUS = 0.55;
static const double COST_SCALING = 3.0;

struct map_yaml {
  char image[1024];
  double resolution, origin[3], occupied_thresh, free_thresh;
  int negate;
};

static int read_yaml(const char *path, struct map_yaml *y) {
  FILE *f = fopen(path, "r");
  if (f == NULL) return 0;
  char line[2048];
  memset(y, 0, sizeof *y);
  y->occupied_thresh = 0.65;
  y->free_thresh = 0.196;
  while (fgets(line, sizeof line, f) != NULL) {
    char *p = line;
    while (*p == ' ') p++;
    if (strncmp(p, "image:", 6) == 0) {
      sscanf(p + 6, " %1023s", y->image);
    } else if (strncmp(p, "resolution:", 11) == 0) {
      y->resolution = atof(p + 11);
    } else if (strncmp(p, "origin:", 7) == 0) {
      sscanf(p + 7, " [ %lf , %lf , %lf ]", &y->origin[0], &y->origin[1], &y->origin[2]);
    } else if (strncmp(p, "negate:", 7) == 0) {
      y->negate = atoi(p + 7);
    } else if (strncmp(p, "occupied_thresh:", 16) == 0) {
      y->occupied_thresh = atof(p + 16);
    } else if (strncmp(p, "free_thresh:", 12) == 0) {
      y->free_thresh = atof(p + 12);
    }
  }
  fclose(f);
  return y->image[0] != 0 && y->resolution > 0.0;
}

/* A binary PGM (P5, maxval <= 255): width, height and the pixels, top row first. */
static unsigned char *read_pgm(const char *path, int *w, int *h) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  int maxval = 0;
  char magic[3] = {0};
  if (fscanf(f, "%2s", magic) != 1 || strcmp(magic, "P5") != 0) {
    fclose(f);
    return NULL;
  }
  int c;
  int *fields[3] = {w, h, &maxval};
  for (int k = 0; k < 3; k++) {
    while ((c = fgetc(f)) == '#' || c == ' ' || c == '\n' || c == '\r' || c == '\t')
      if (c == '#')
        while ((c = fgetc(f)) != '\n' && c != EOF) {
        }
    ungetc(c, f);
    if (fscanf(f, "%d", fields[k]) != 1) {
      fclose(f);
      return NULL;
    }
  }
  fgetc(f); /* the one whitespace after maxval */
  if (*w <= 0 || *h <= 0 || maxval <= 0 || maxval > 255) {
    fclose(f);
    return NULL;
  }
  unsigned char *pixels = malloc((size_t)*w * (size_t)*h);
  if (pixels == NULL || fread(pixels, 1, (size_t)*w * (size_t)*h, f) != (size_t)*w * (size_t)*h) {
    free(pixels);
    fclose(f);
    return NULL;
  }
  fclose(f);
  return pixels;
}

int main(int argc, char **argv) {
  if (argc < 6) {
    fprintf(stderr, "usage: %s MAP.yaml GOAL_X GOAL_Y START_X START_Y [ROBOT_RADIUS]\n", argv[0]);
    return 2;
  }
  double robot_radius = argc > 6 ? atof(argv[6]) : 0.22;
  struct map_yaml y;
  if (!read_yaml(argv[1], &y)) {
    fprintf(stderr, "%s: cannot read the map's YAML\n", argv[1]);
    return 1;
  }
  /* The image's path is relative to the YAML's directory. */
  char image[2048];
  const char *slash = strrchr(argv[1], '/');
  if (y.image[0] != '/' && slash != NULL)
    snprintf(image, sizeof image, "%.*s/%s", (int)(slash - argv[1]), argv[1], y.image);
  else
    snprintf(image, sizeof image, "%s", y.image);
  int w = 0, h = 0;
  unsigned char *pixels = read_pgm(image, &w, &h);
  if (pixels == NULL) {
    fprintf(stderr, "%s: cannot read the map image (a binary PGM)\n", image);
    return 1;
  }

  /* map_server's trinary reading, then Nav2's costs; row 0 of the costmap is the lowest y. */
  uint8_t *costs = malloc((size_t)w * (size_t)h);
  for (int r = 0; r < h; r++)
    for (int x = 0; x < w; x++) {
      double v = pixels[(size_t)r * w + x];
      double occupancy = y.negate ? v / 255.0 : (255.0 - v) / 255.0;
      uint8_t cost = occupancy > y.occupied_thresh ? 254 : occupancy < y.free_thresh ? 0 : 255;
      costs[(size_t)(h - 1 - r) * w + x] = cost;
    }
  free(pixels);
  /* Inflation around lethal cells: 253 within the robot radius, decaying costs beyond. */
  uint8_t *inflated = malloc((size_t)w * (size_t)h);
  memcpy(inflated, costs, (size_t)w * (size_t)h);
  int reach = (int)ceil(INFLATION_RADIUS / y.resolution);
  for (int my = 0; my < h; my++)
    for (int mx = 0; mx < w; mx++) {
      if (costs[(size_t)my * w + mx] != 254) continue;
      for (int dy = -reach; dy <= reach; dy++)
        for (int dx = -reach; dx <= reach; dx++) {
          int nx = mx + dx, ny = my + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          uint8_t *c = &inflated[(size_t)ny * w + nx];
          if (*c >= 253) continue;
          double d = hypot(dx, dy) * y.resolution;
          if (d > INFLATION_RADIUS) continue;
          uint8_t cost = d <= robot_radius
                             ? 253
                             : (uint8_t)(252.0 * exp(-COST_SCALING * (d - robot_radius)));
          if (cost > *c) *c = cost;
        }
    }
  free(costs);

  HpCostmap map = {(uint32_t)w, (uint32_t)h, y.resolution, y.origin[0], y.origin[1], inflated};
  HpOptions options = hp_options_default();
  options.robot_radius = 0.0; /* inflated: 253 marks where the centre may not go */
  options.goal_tolerance = 0.5;
  HpPose goal = {atof(argv[2]), atof(argv[3]), 0.0};
  HpPose start = {atof(argv[4]), atof(argv[5]), 0.0};
  HpPlanner *planner = NULL;
  HpStatus status = hp_planner_new(&map, goal, &options, &planner);
  free(inflated); /* the planner keeps its own copy */
  if (status != HP_OK) {
    fprintf(stderr, "hp_planner_new: status %d: %s\n", (int)status, hp_last_error());
    return 1;
  }
  HpPath *path = NULL;
  status = hp_planner_plan(planner, start, &path);
  if (status != HP_OK) {
    fprintf(stderr, "hp_planner_plan: status %d: %s\n", (int)status, hp_last_error());
    hp_planner_free(planner);
    return 1;
  }
  const HpPose *poses = hp_path_poses(path);
  printf("# %zu poses, %.3f m, clearance %.3f m (harmonic-planner %s)\n", hp_path_size(path),
         hp_path_length(path), hp_path_min_clearance(path), hp_version());
  for (size_t k = 0; k < hp_path_size(path); k++)
    printf("%.4f %.4f %.4f\n", poses[k].x, poses[k].y, poses[k].theta);
  hp_path_free(path);
  hp_planner_free(planner);
  return 0;
}
