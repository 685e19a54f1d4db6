// Capsule-box distance: closed-form cases, and agreement with brute force (dense sampling of the
// segment, point-to-box by clamping) and with a converged ternary search on random cases.
#include "kiloloop/planning/capsule_box.hpp"

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {

// Point-to-box distance written independently of the library: closest point by clamping.
double brute_point(const Eigen::Vector3d& p, const OrientedBox& box) {
  const Eigen::Vector3d local = box.rotation.transpose() * (p - box.center);
  Eigen::Vector3d closest;
  for (int i = 0; i < 3; ++i)
    closest[i] = std::min(std::max(local[i], -box.half_extents[i]), box.half_extents[i]);
  return (local - closest).norm();
}

double brute_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const OrientedBox& box,
                     int samples) {
  double best = INFINITY;
  for (int i = 0; i <= samples; ++i)
    best = std::min(best, brute_point(a + (double(i) / samples) * (b - a), box));
  return best;
}

// The distance along the segment is convex in t: ternary search converges to the minimum.
double ternary_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const OrientedBox& box) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 200; ++it) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (brute_point(a + m1 * (b - a), box) < brute_point(a + m2 * (b - a), box)) hi = m2;
    else lo = m1;
  }
  return brute_point(a + 0.5 * (lo + hi) * (b - a), box);
}

OrientedBox unit_box() {
  OrientedBox box;
  box.half_extents = Eigen::Vector3d::Ones();
  return box;
}

TEST(CapsuleBox, ClosedFormCases) {
  const OrientedBox box = unit_box();
  // Parallel to a face, 0.5 m above it.
  EXPECT_NEAR(segment_box_distance({-3, 0, 1.5}, {3, 0, 1.5}, box), 0.5, 1e-15);
  // Through the box.
  EXPECT_EQ(segment_box_distance({-3, 0.2, 0.1}, {3, -0.2, 0.3}, box), 0.0);
  // Skew to an edge: the line x = 2, y = 2 is sqrt(2) from the edge x = y = 1.
  EXPECT_NEAR(segment_box_distance({2, 2, -5}, {2, 2, 5}, box), std::sqrt(2.0), 1e-15);
  // Toward a corner, ending short of it.
  EXPECT_NEAR(segment_box_distance({3, 3, 3}, {2, 2, 2}, box), std::sqrt(3.0), 1e-15);
  // Degenerate segment = point.
  EXPECT_NEAR(segment_box_distance({0, 0, 4}, {0, 0, 4}, box), 3.0, 1e-15);
  // Capsule: radius subtracted; negative when overlapping.
  EXPECT_NEAR(capsule_box_distance({-3, 0, 1.5}, {3, 0, 1.5}, 0.2, box), 0.3, 1e-15);
  EXPECT_LT(capsule_box_distance({-3, 0, 1.5}, {3, 0, 1.5}, 0.7, box), 0.0);
  // A rotated box: 45 deg about z brings a corner to x = sqrt(2).
  OrientedBox rot = box;
  rot.rotation = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  rot.center = Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR(segment_box_distance({1 + std::sqrt(2.0) + 0.25, -1, 0}, {1 + std::sqrt(2.0) + 0.25, 1, 0}, rot),
              0.25, 1e-12);
}

TEST(CapsuleBox, MatchesBruteForceOnRandomCases) {
  const unsigned seed = 17;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), h(0.05, 0.6);
  double worst_gap = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    OrientedBox box;
    box.center = Eigen::Vector3d(u(rng), u(rng), u(rng));
    box.half_extents = Eigen::Vector3d(h(rng), h(rng), h(rng));
    box.rotation = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d a = 1.5 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const Eigen::Vector3d b = 1.5 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const double exact = segment_box_distance(a, b, box);
    const int samples = 20000;
    const double brute = brute_segment(a, b, box, samples);
    // Sampling can only overestimate, by at most half a sample spacing.
    ASSERT_LE(exact, brute + 1e-12) << "seed " << seed << " trial " << trial;
    ASSERT_LE(brute - exact, 0.5 * (b - a).norm() / samples + 1e-12) << "seed " << seed << " trial " << trial;
    const double ternary = ternary_segment(a, b, box);
    ASSERT_NEAR(exact, ternary, 1e-9) << "seed " << seed << " trial " << trial;
    worst_gap = std::max(worst_gap, std::fabs(exact - ternary));
  }
  std::printf("capsule-box: worst |exact - ternary| over 2000 cases = %.3g m\n", worst_gap);
}

TEST(CapsuleBox, IsAllocationFree) {
  const OrientedBox box = unit_box();
  testing::AllocationScope scope;
  double sum = 0.0;
  for (int k = 0; k < 1000; ++k) sum += segment_box_distance({-3, 0, 1.0 + k * 1e-3}, {3, 0.1, 1.5}, box);
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace kiloloop
