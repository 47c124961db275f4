// harmonic-planner's C++ interface: a header-only C++17 wrapper over harmonic_planner.h.
// RAII handles, std::vector of poses, and errors as harmonic_planner::Error (status and
// message) or, without exceptions, as a status from the try_ functions.
#ifndef HARMONIC_PLANNER_HPP
#define HARMONIC_PLANNER_HPP

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harmonic_planner.h"

namespace harmonic_planner {

/// A failed call: its status and the one-line message of hp_last_error().
class Error : public std::runtime_error {
 public:
  Error(HpStatus status, const std::string &message)
      : std::runtime_error(message), status_(status) {}
  HpStatus status() const noexcept { return status_; }

 private:
  HpStatus status_;
};

/// A planned path: poses from the start to the goal, its length and clearance (metres).
struct Path {
  std::vector<HpPose> poses;
  double length = 0.0;
  double min_clearance = 0.0;
};

/// The library's default options (hp_options_default).
inline HpOptions default_options() noexcept { return hp_options_default(); }

/// A planner for one goal on one costmap: built once, then planned from any number of starts,
/// from any number of threads at once. Movable, not copyable.
class Planner {
 public:
  /// Builds the field (mesh, assemble, solve); throws Error on failure.
  Planner(const HpCostmap &map, HpPose goal, const HpOptions &options = default_options()) {
    HpPlanner *raw = nullptr;
    HpStatus status = hp_planner_new(&map, goal, &options, &raw);
    if (status != HP_OK) throw Error(status, hp_last_error());
    handle_.reset(raw);
  }

  /// Builds without throwing: the status, and on HP_OK the planner in `out`.
  static HpStatus try_create(const HpCostmap &map, HpPose goal, const HpOptions &options,
                             Planner &out, std::string *message = nullptr) noexcept {
    HpPlanner *raw = nullptr;
    HpStatus status = hp_planner_new(&map, goal, &options, &raw);
    if (message != nullptr) *message = hp_last_error();
    if (status == HP_OK) out.handle_.reset(raw);
    return status;
  }

  Planner() = default;

  /// A path from `start`; throws Error on failure.
  Path plan(HpPose start) const {
    Path path;
    std::string message;
    HpStatus status = try_plan(start, path, &message);
    if (status != HP_OK) throw Error(status, message);
    return path;
  }

  /// A path from `start` without throwing: the status, and on HP_OK the path in `out`.
  HpStatus try_plan(HpPose start, Path &out, std::string *message = nullptr) const noexcept {
    HpPath *raw = nullptr;
    HpStatus status = hp_planner_plan(handle_.get(), start, &raw);
    if (message != nullptr) *message = hp_last_error();
    if (status == HP_OK) {
      const HpPose *poses = hp_path_poses(raw);
      try {
        out.poses.assign(poses, poses + hp_path_size(raw));
      } catch (...) {
        hp_path_free(raw);
        return HP_INTERNAL;
      }
      out.length = hp_path_length(raw);
      out.min_clearance = hp_path_min_clearance(raw);
    }
    hp_path_free(raw);
    return status;
  }

  /// The potential at (x, y): 0 at the goal, 1 at blocked cells, NaN outside free space.
  double potential(double x, double y) const noexcept {
    return hp_planner_potential(handle_.get(), x, y);
  }

  /// Whether this holds a planner.
  explicit operator bool() const noexcept { return static_cast<bool>(handle_); }

 private:
  struct Free {
    void operator()(HpPlanner *p) const noexcept { hp_planner_free(p); }
  };
  std::unique_ptr<HpPlanner, Free> handle_;
};

}  // namespace harmonic_planner

#endif  // HARMONIC_PLANNER_HPP
