// The C++ wrapper (harmonic_planner.hpp) against the contract: errors as exceptions carrying
// the status, the no-throw try_ functions, a path checked on the grid, four std::threads
// planning from one planner. Compiled and run by tests/c_api.rs.

#include "harmonic_planner.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

namespace hp = harmonic_planner;

static int failures = 0;
#define CHECK(cond, what)                                                              \
  do {                                                                                 \
    if (!(cond)) {                                                                     \
      std::fprintf(stderr, "%s:%d: check failed: %s: %s\n", __FILE__, __LINE__, #cond, \
                   what);                                                              \
      failures++;                                                                      \
    }                                                                                  \
  } while (0)

// 40 x 30 cells of 0.05 m at the origin: Nav2-like inflation around a lethal block (columns
// 15..24, rows 10..19): 254 inside, 253 one cell around it, graded 128 two cells around.
constexpr int W = 40, H = 30;
constexpr double RES = 0.05;
static std::vector<uint8_t> costs(W *H, 0);

static HpPose centre(int mx, int my, double theta = 0.0) {
  return HpPose{(mx + 0.5) * RES, (my + 0.5) * RES, theta};
}

static bool clear_segment(const HpPose &a, const HpPose &b) {
  double len = std::hypot(b.x - a.x, b.y - a.y);
  int n = static_cast<int>(std::ceil(len / (0.01 * RES))) + 1;
  for (int k = 0; k <= n; k++) {
    double t = static_cast<double>(k) / n;
    int mx = static_cast<int>(std::floor((a.x + t * (b.x - a.x)) / RES));
    int my = static_cast<int>(std::floor((a.y + t * (b.y - a.y)) / RES));
    if (mx < 0 || my < 0 || mx >= W || my >= H || costs[my * W + mx] >= 253) return false;
  }
  return true;
}

int main() {
  for (int my = 8; my <= 21; my++)
    for (int mx = 13; mx <= 26; mx++) {
      bool core = mx >= 15 && mx <= 24 && my >= 10 && my <= 19;
      bool ring = mx >= 14 && mx <= 25 && my >= 9 && my <= 20;
      costs[my * W + mx] = core ? 254 : ring ? 253 : 128;
    }
  HpCostmap map{W, H, RES, 0.0, 0.0, costs.data()};
  HpPose goal = centre(35, 15, 0.5);

  // An exception carries the status and the message.
  try {
    hp::Planner bad(map, centre(20, 15));
    CHECK(false, "a goal in the lethal block must throw");
  } catch (const hp::Error &e) {
    CHECK(e.status() == HP_GOAL_OCCUPIED, e.what());
    CHECK(std::strlen(e.what()) > 0, "message");
  }
  hp::Planner none;
  std::string message;
  CHECK(hp::Planner::try_create(map, centre(99, 15), hp::default_options(), none, &message) ==
            HP_GOAL_OUTSIDE_MAP,
        message.c_str());
  CHECK(!none, "no planner after a failure");

  hp::Planner planner(map, goal);
  CHECK(static_cast<bool>(planner), "planner");
  hp::Path path;
  CHECK(planner.try_plan(centre(20, 15), path, &message) == HP_START_OCCUPIED, message.c_str());
  try {
    planner.plan(centre(-3, 15));
    CHECK(false, "a start outside must throw");
  } catch (const hp::Error &e) {
    CHECK(e.status() == HP_START_OUTSIDE_MAP, e.what());
  }

  std::vector<HpPose> starts{centre(2, 15), centre(5, 2, 1.0), centre(5, 27, -1.0),
                             centre(30, 28)};
  std::vector<double> lengths;
  for (const HpPose &s : starts) {
    hp::Path p = planner.plan(s);
    CHECK(p.poses.size() >= 2, "poses");
    CHECK(p.poses.front().x == s.x && p.poses.front().y == s.y, "first pose is the start");
    CHECK(std::fabs(p.poses.back().x - goal.x) < 1e-9 && std::fabs(p.poses.back().y - goal.y) < 1e-9,
          "last pose is the goal");
    CHECK(p.poses.back().theta == goal.theta, "goal heading");
    for (size_t k = 0; k + 1 < p.poses.size(); k++)
      CHECK(clear_segment(p.poses[k], p.poses[k + 1]), "segment on clear cells");
    lengths.push_back(p.length);
  }
  CHECK(std::isnan(planner.potential(centre(20, 15).x, centre(20, 15).y)), "NaN in the block");
  double phi = planner.potential(starts[0].x, starts[0].y);
  CHECK(phi > 0.0 && phi < 1.0, "potential in free space");

  std::vector<std::thread> threads;
  std::vector<double> got(starts.size(), -1.0);
  for (size_t i = 0; i < starts.size(); i++)
    threads.emplace_back([&, i] {
      for (int round = 0; round < 20; round++) got[i] = planner.plan(starts[i]).length;
    });
  for (auto &t : threads) t.join();
  for (size_t i = 0; i < starts.size(); i++) CHECK(got[i] == lengths[i], "threads agree");

  if (failures == 0) std::printf("all C++ checks passed\n");
  return failures == 0 ? 0 : 1;
}
