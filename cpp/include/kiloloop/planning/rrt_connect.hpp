#pragma once
// RRT-Connect (Kuffner & LaValle 2000) in joint space, then random shortcutting, then
// time-parameterization by the synchronized trapezoid (trajectory/trapezoid.hpp).
// Not on the 1 kHz path: planning allocates (the trees). It is bounded (max_iterations, shortcut
// iterations) and deterministic: one seeded splitmix64 generator, no clock, no unordered
// containers, so the same inputs give the same path on every platform.
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "kiloloop/planning/arm_collision.hpp"
#include "kiloloop/trajectory/trapezoid.hpp"

namespace kiloloop {

struct RrtConfig {
  int max_iterations = 20000;       // RRT-Connect iterations (one sample each) before giving up
  double extend_step = 0.2;         // [rad] max joint-space step (inf-norm) of one tree extension
  double collision_step = 0.02;     // [rad] edges' grid step (inf-norm); the gaps between grid
                                    // samples are then proved free (ArmCollisionChecker::segment_free)
  int shortcut_iterations = 300;    // random shortcut attempts after a path is found
  std::uint64_t seed = 1;           // the only source of randomness
  Eigen::VectorXd lower, upper;     // (nq) [rad] sampling box; empty: the model's joint limits
};

Status validate(const RrtConfig& config, int nq, std::string* why);

// Deterministic 64-bit generator (splitmix64) with uniform doubles in [0, 1).
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() noexcept {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() noexcept { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

struct PlanStats {
  int iterations = 0;            // RRT-Connect iterations used
  int tree_nodes = 0;            // nodes in both trees
  int raw_waypoints = 0;         // path length before shortcutting
  int waypoints = 0;             // after shortcutting
  double raw_length = 0.0;       // [rad] joint-space length (2-norm) before shortcutting
  double length = 0.0;           // [rad] after
  unsigned long long collision_checks = 0;
};

// A collision-free joint path from q_start to q_goal; path: (nq, m) columns, first = start,
// last = goal. kInfeasible when start or goal collides, kIterationLimit (path empty) when no
// path was found within max_iterations.
Status plan_rrt_connect(ArmCollisionChecker& checker, const RrtConfig& config,
                        const Eigen::VectorXd& q_start, const Eigen::VectorXd& q_goal,
                        Eigen::MatrixXd* path, PlanStats* stats, std::string* why);

// Random shortcutting: pick two points on the path (anywhere along its segments), replace what
// lies between by a straight segment when that is collision-free; then drop waypoints whose
// neighbours see each other. Every segment of the path stays collision-free (segment_free).
void shortcut_path(ArmCollisionChecker& checker, int iterations, double collision_step,
                   std::uint64_t seed, Eigen::MatrixXd* path);

// plan_rrt_connect + shortcut_path + TrapezoidTrajectory through the waypoints (each segment a
// straight joint-space line, rest at every waypoint, within v_max and a_max), starting at t0.
Status plan_trajectory(ArmCollisionChecker& checker, const RrtConfig& config,
                       const Eigen::VectorXd& q_start, const Eigen::VectorXd& q_goal,
                       const Eigen::VectorXd& v_max, const Eigen::VectorXd& a_max, double t0,
                       TrapezoidTrajectory* trajectory, Eigen::MatrixXd* path, PlanStats* stats,
                       std::string* why);

}  // namespace kiloloop
