/* harmonic-planner's C interface: a costmap and a goal in, poses out.
 * Generated from crates/capi/src/lib.rs by cbindgen; do not edit (the crate's tests check it). */

#ifndef HARMONIC_PLANNER_H
#define HARMONIC_PLANNER_H

#include <stddef.h>
#include <stdint.h>

/**
 * What a call did.
 */
typedef enum HpStatus {
  /**
   * Done.
   */
  HP_OK = 0,
  /**
   * A null pointer, a size of 0, a number not finite, a resolution ≤ 0, …
   */
  HP_INVALID_ARGUMENT = 1,
  /**
   * The start's cell is blocked (cost ≥ obstacle_cost) or closer than the robot radius to
   * one.
   */
  HP_START_OCCUPIED = 2,
  /**
   * Likewise for the goal, after goal_tolerance.
   */
  HP_GOAL_OCCUPIED = 3,
  /**
   * The start lies outside the costmap.
   */
  HP_START_OUTSIDE_MAP = 4,
  /**
   * The goal lies outside the costmap.
   */
  HP_GOAL_OUTSIDE_MAP = 5,
  /**
   * The start is not connected to the goal through clear cells.
   */
  HP_NO_VALID_PATH = 6,
  /**
   * The cancel callback asked to stop.
   */
  HP_CANCELLED = 7,
  /**
   * A bug: the message says what; never a crash.
   */
  HP_INTERNAL = 8,
} HpStatus;

/**
 * A planned path (opaque).
 */
typedef struct HpPath HpPath;

/**
 * A planner for one goal on one costmap (opaque; immutable after creation).
 */
typedef struct HpPlanner HpPlanner;

/**
 * How to build a planner ([`hp_options_default`] gives the defaults).
 */
typedef struct HpOptions {
  /**
   * Metres kept from blocked cells; 0 for a costmap already inflated.
   */
  double robot_radius;
  /**
   * Cells with a cost at least this are blocked (default 253).
   */
  uint8_t obstacle_cost;
  /**
   * 0 (default): cost 255 is blocked; 1: it is free.
   */
  int unknown_is_free;
  /**
   * 0: graded costs ignored; > 0: graded costs (1..252) shape the field, a cell of cost c
   * conducting 1 / (1 + w·0.016·c) of a free cell's flow (default 1, NavFn's weighting)
   * and absorbing w·0.016·c·(c/252)³ / (0.05 m)²; at most 1e6.
   */
  double cost_weight;
  /**
   * Metres: a blocked goal moves to the nearest clear cell within this distance (default 0).
   */
  double goal_tolerance;
  /**
   * 1 (default): the last pose's theta is the goal's; 0: the path's tangent.
   */
  int use_goal_heading;
  /**
   * Optional: asked at each stage of the build (meshing, assembling, solving); non-zero
   * cancels.
   */
  int (*cancel)(void *user);
  /**
   * Passed to `cancel`.
   */
  void *cancel_user;
  /**
   * Threads for the build; 0 (default): all cores (`RAYON_NUM_THREADS` respected).
   */
  uint32_t threads;
} HpOptions;

/**
 * A costmap in Nav2's `Costmap2D` layout: `data[my * size_x + mx]`, row 0 the lowest y.
 */
typedef struct HpCostmap {
  /**
   * Cells along x.
   */
  uint32_t size_x;
  /**
   * Cells along y.
   */
  uint32_t size_y;
  /**
   * Metres per cell.
   */
  double resolution;
  /**
   * World x of cell (0, 0)'s lower-left corner.
   */
  double origin_x;
  /**
   * World y of cell (0, 0)'s lower-left corner.
   */
  double origin_y;
  /**
   * `size_x * size_y` costs.
   */
  const uint8_t *data;
} HpCostmap;

/**
 * A pose in the map frame: metres, radians.
 */
typedef struct HpPose {
  /**
   * x, metres.
   */
  double x;
  /**
   * y, metres.
   */
  double y;
  /**
   * Heading, radians.
   */
  double theta;
} HpPose;

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

/**
 * The default options: radius 0, obstacle cost 253, unknown blocked, cost weight 1, goal
 * tolerance 0, goal heading used, no cancel callback, all cores.
 */
struct HpOptions hp_options_default(void);

/**
 * The library's version, a static string such as "0.1.0".
 */
const char *hp_version(void);

/**
 * Why the last call on this thread failed, in one line ("" after a success); valid until the
 * next call on this thread.
 */
const char *hp_last_error(void);

/**
 * Builds the field for one goal on one costmap: the costly step (mesh, assemble, solve). The
 * costmap is copied; the caller may free it afterwards. On failure `*out` is NULL.
 *
 * # Safety
 * `map` must point to a valid [`HpCostmap`] whose `data` holds `size_x * size_y` bytes,
 * `options` to a valid [`HpOptions`] or be NULL (the defaults), `out` to writable storage.
 */
enum HpStatus hp_planner_new(const struct HpCostmap *map,
                             struct HpPose goal,
                             const struct HpOptions *options,
                             struct HpPlanner **out);

/**
 * A path from `start` to the goal: the field is only traced (milliseconds). Poses carry the
 * path's tangent heading; the first is the start, the last the goal position (its heading
 * per `use_goal_heading`). Safe to call from several threads on the same planner at once. On
 * failure `*out` is NULL.
 *
 * # Safety
 * `planner` must come from [`hp_planner_new`] and not be freed, `out` must be writable.
 */
enum HpStatus hp_planner_plan(const struct HpPlanner *planner,
                              struct HpPose start,
                              struct HpPath **out);

/**
 * The number of poses of `path` (0 for NULL).
 *
 * # Safety
 * `path` must come from [`hp_planner_plan`] and not be freed, or be NULL.
 */
size_t hp_path_size(const struct HpPath *path);

/**
 * The poses of `path` (NULL for NULL), valid until [`hp_path_free`].
 *
 * # Safety
 * As [`hp_path_size`].
 */
const struct HpPose *hp_path_poses(const struct HpPath *path);

/**
 * The length of `path` in metres (NaN for NULL).
 *
 * # Safety
 * As [`hp_path_size`].
 */
double hp_path_length(const struct HpPath *path);

/**
 * The smallest distance from `path` to a blocked cell, in metres (NaN for NULL).
 *
 * # Safety
 * As [`hp_path_size`].
 */
double hp_path_min_clearance(const struct HpPath *path);

/**
 * Frees `path` (NULL is fine).
 *
 * # Safety
 * `path` must come from [`hp_planner_plan`] and not be freed already, or be NULL.
 */
void hp_path_free(struct HpPath *path);

/**
 * Frees `planner` (NULL is fine).
 *
 * # Safety
 * `planner` must come from [`hp_planner_new`], not be freed already and not be in use by
 * another thread, or be NULL.
 */
void hp_planner_free(struct HpPlanner *planner);

/**
 * The potential φ at `(x, y)` (0 at the goal, 1 at blocked cells), NaN outside the free
 * space or for NULL: for pictures and debugging.
 *
 * # Safety
 * `planner` must come from [`hp_planner_new`] and not be freed, or be NULL.
 */
double hp_planner_potential(const struct HpPlanner *planner, double x, double y);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* HARMONIC_PLANNER_H */
