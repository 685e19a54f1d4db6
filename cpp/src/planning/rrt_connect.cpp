#include "kiloloop/planning/rrt_connect.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace kiloloop {
namespace {

struct Tree {
  std::vector<Eigen::VectorXd> nodes;
  std::vector<int> parent;

  int add(const Eigen::VectorXd& q, int p) {
    nodes.push_back(q);
    parent.push_back(p);
    return static_cast<int>(nodes.size()) - 1;
  }
  // Nearest node in the Euclidean norm (linear scan: the trees stay small; first wins ties).
  int nearest(const Eigen::VectorXd& q) const {
    int best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const double d = (nodes[i] - q).squaredNorm();
      if (d < best_d) best_d = d, best = static_cast<int>(i);
    }
    return best;
  }
};

enum class Extend { kTrapped, kAdvanced, kReached };

// One step from the nearest node toward q (at most `step` in the inf-norm).
Extend extend(Tree& tree, const Eigen::VectorXd& q, ArmCollisionChecker& checker, const RrtConfig& c,
              int* new_index) {
  const int near = tree.nearest(q);
  const Eigen::VectorXd& from = tree.nodes[near];
  const Eigen::VectorXd delta = q - from;
  const double span = delta.cwiseAbs().maxCoeff();
  const bool reaches = span <= c.extend_step;
  const Eigen::VectorXd to = reaches ? q : Eigen::VectorXd(from + (c.extend_step / span) * delta);
  if (!checker.segment_free(from, to, c.collision_step)) return Extend::kTrapped;
  *new_index = tree.add(to, near);
  return reaches ? Extend::kReached : Extend::kAdvanced;
}

double path_length(const Eigen::MatrixXd& path) {
  double len = 0.0;
  for (Eigen::Index k = 1; k < path.cols(); ++k) len += (path.col(k) - path.col(k - 1)).norm();
  return len;
}

}  // namespace

Status validate(const RrtConfig& c, int nq, std::string* why) {
  const char* msg = nullptr;
  if (c.max_iterations < 1) msg = "max_iterations must be >= 1";
  else if (!(c.extend_step > 0.0) || !std::isfinite(c.extend_step)) msg = "extend_step must be > 0";
  else if (!(c.collision_step > 0.0) || !std::isfinite(c.collision_step)) msg = "collision_step must be > 0";
  else if (c.shortcut_iterations < 0) msg = "shortcut_iterations must be >= 0";
  else if (c.lower.size() != c.upper.size() || (c.lower.size() != 0 && c.lower.size() != nq))
    msg = "lower and upper must both be empty or have nq entries";
  else if (c.lower.size() && (!c.lower.allFinite() || !c.upper.allFinite() ||
                              (c.upper.array() < c.lower.array()).any()))
    msg = "lower and upper must be finite with lower <= upper";
  if (msg == nullptr) return Status::kOk;
  if (why) *why = msg;
  return Status::kInvalidConfig;
}

Status plan_rrt_connect(ArmCollisionChecker& checker, const RrtConfig& config,
                        const Eigen::VectorXd& q_start, const Eigen::VectorXd& q_goal,
                        Eigen::MatrixXd* path, PlanStats* stats, std::string* why) {
  const int n = checker.nq();
  Status s = validate(config, n, why);
  if (failed(s)) return s;
  if (q_start.size() != n || q_goal.size() != n) {
    if (why) *why = "q_start and q_goal must have nq entries";
    return Status::kBadSize;
  }
  if (!q_start.allFinite() || !q_goal.allFinite()) {
    if (why) *why = "q_start and q_goal must be finite";
    return Status::kNonFiniteReference;
  }
  Eigen::VectorXd lower = config.lower, upper = config.upper;
  if (lower.size() == 0) {
    // Infinite model limits (continuous joints) fall back to one turn either way.
    lower = checker.model().lower().cwiseMax(-M_PI);
    upper = checker.model().upper().cwiseMin(M_PI);
  }
  const unsigned long long checks0 = checker.checks();
  PlanStats st;
  if (!checker.is_free(q_start) || !checker.is_free(q_goal)) {
    if (why) *why = checker.is_free(q_start) ? "q_goal is in collision" : "q_start is in collision";
    if (stats) *stats = st;
    return Status::kInfeasible;
  }
  Tree a, b;  // a grows from the start, b from the goal; they swap roles every iteration
  a.add(q_start, -1);
  b.add(q_goal, -1);
  bool a_is_start = true;
  SplitMix64 rng(config.seed);
  Eigen::VectorXd sample(n);
  int a_end = -1, b_end = -1;
  for (int it = 0; it < config.max_iterations; ++it) {
    st.iterations = it + 1;
    for (int j = 0; j < n; ++j) sample[j] = lower[j] + rng.uniform() * (upper[j] - lower[j]);
    int new_a = -1;
    if (extend(a, sample, checker, config, &new_a) != Extend::kTrapped) {
      // CONNECT: extend b toward the new node until it is reached or trapped.
      const Eigen::VectorXd target = a.nodes[new_a];
      Extend e;
      int new_b = -1;
      do {
        e = extend(b, target, checker, config, &new_b);
      } while (e == Extend::kAdvanced);
      if (e == Extend::kReached) {
        a_end = new_a;
        b_end = new_b;
        break;
      }
    }
    std::swap(a, b);
    a_is_start = !a_is_start;
  }
  st.tree_nodes = static_cast<int>(a.nodes.size() + b.nodes.size());
  if (a_end < 0) {
    st.collision_checks = checker.checks() - checks0;
    if (stats) *stats = st;
    path->resize(n, 0);
    if (why) *why = "no path found within max_iterations";
    return Status::kIterationLimit;
  }
  if (!a_is_start) {
    std::swap(a, b);
    std::swap(a_end, b_end);
  }
  // Start tree root -> a_end, then b_end -> goal tree root (a_end and b_end are the same point).
  std::vector<int> head, tail;
  for (int i = a_end; i >= 0; i = a.parent[i]) head.push_back(i);
  for (int i = b.parent[b_end]; i >= 0; i = b.parent[i]) tail.push_back(i);
  path->resize(n, static_cast<Eigen::Index>(head.size() + tail.size()));
  Eigen::Index col = 0;
  for (auto it = head.rbegin(); it != head.rend(); ++it) path->col(col++) = a.nodes[*it];
  for (int i : tail) path->col(col++) = b.nodes[i];
  st.raw_waypoints = st.waypoints = static_cast<int>(path->cols());
  st.raw_length = st.length = path_length(*path);
  st.collision_checks = checker.checks() - checks0;
  if (stats) *stats = st;
  return Status::kOk;
}

void shortcut_path(ArmCollisionChecker& checker, int iterations, double collision_step,
                   std::uint64_t seed, Eigen::MatrixXd* path) {
  SplitMix64 rng(seed ^ 0x5eed5eed5eed5eedULL);
  Eigen::MatrixXd& p = *path;
  for (int it = 0; it < iterations && p.cols() > 2; ++it) {
    // Two points on the path: segment index + fraction, in order along the path.
    const Eigen::Index segs = p.cols() - 1;
    Eigen::Index i = static_cast<Eigen::Index>(rng.next() % segs);
    Eigen::Index j = static_cast<Eigen::Index>(rng.next() % segs);
    if (i > j) std::swap(i, j);
    if (j - i < 1) continue;  // same segment: already straight
    const Eigen::VectorXd qa = p.col(i) + rng.uniform() * (p.col(i + 1) - p.col(i));
    const Eigen::VectorXd qb = p.col(j) + rng.uniform() * (p.col(j + 1) - p.col(j));
    if (!checker.segment_free(qa, qb, collision_step)) continue;
    // New path: 0..i, qa, qb, j+1..end.
    Eigen::MatrixXd next(p.rows(), (i + 1) + 2 + (p.cols() - j - 1));
    next.leftCols(i + 1) = p.leftCols(i + 1);
    next.col(i + 1) = qa;
    next.col(i + 2) = qb;
    next.rightCols(p.cols() - j - 1) = p.rightCols(p.cols() - j - 1);
    p = next;
  }
  // Drop waypoints whose neighbours see each other directly.
  for (Eigen::Index k = 1; k + 1 < p.cols();) {
    if (checker.segment_free(p.col(k - 1), p.col(k + 1), collision_step)) {
      Eigen::MatrixXd next(p.rows(), p.cols() - 1);
      next.leftCols(k) = p.leftCols(k);
      next.rightCols(p.cols() - k - 1) = p.rightCols(p.cols() - k - 1);
      p = next;
    } else {
      ++k;
    }
  }
}

Status plan_trajectory(ArmCollisionChecker& checker, const RrtConfig& config,
                       const Eigen::VectorXd& q_start, const Eigen::VectorXd& q_goal,
                       const Eigen::VectorXd& v_max, const Eigen::VectorXd& a_max, double t0,
                       TrapezoidTrajectory* trajectory, Eigen::MatrixXd* path, PlanStats* stats,
                       std::string* why) {
  PlanStats st;
  Status s = plan_rrt_connect(checker, config, q_start, q_goal, path, &st, why);
  if (s != Status::kOk) {
    if (stats) *stats = st;
    return s;
  }
  const unsigned long long checks0 = checker.checks();
  shortcut_path(checker, config.shortcut_iterations, config.collision_step, config.seed, path);
  st.waypoints = static_cast<int>(path->cols());
  st.length = path_length(*path);
  st.collision_checks += checker.checks() - checks0;
  if (stats) *stats = st;
  return TrapezoidTrajectory::configure(*path, v_max, a_max, t0, trajectory, why);
}

}  // namespace kiloloop
