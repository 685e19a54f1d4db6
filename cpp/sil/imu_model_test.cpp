// The IMU error model's statistics against its Allan-variance parameters, and the encoder-difference
// velocity. Bounds are 5 standard errors of the estimate, from the sample count (seeded: the
// streams are fixed, a bound only guards against a wrong model, not against bad luck).
#include "sil/imu_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "alloc_counter.hpp"

namespace kiloloop::sil {
namespace {

ImuModelConfig only(double n, double k, double b0, unsigned long long seed = 1) {
  ImuModelConfig c;
  c.gyro = c.accel = InertialNoise{n, k, b0};
  c.seed = seed;
  return c;
}

// Non-overlapping Allan variance of x (period dt) at cluster size m: 0.5 <(mean_{j+1} - mean_j)^2>.
double allan_variance(const std::vector<double>& x, int m) {
  const int clusters = static_cast<int>(x.size()) / m;
  std::vector<double> mean(clusters, 0.0);
  for (int c = 0; c < clusters; ++c) {
    for (int i = 0; i < m; ++i) mean[c] += x[c * m + i];
    mean[c] /= m;
  }
  double sum = 0.0;
  for (int c = 0; c + 1 < clusters; ++c) sum += (mean[c + 1] - mean[c]) * (mean[c + 1] - mean[c]);
  return 0.5 * sum / (clusters - 1);
}

TEST(ImuModel, SameSeedSameStreamOtherSeedOther) {
  ImuModel a, b, c;
  std::string why;
  ASSERT_TRUE(a.configure(ImuModelConfig{}, &why)) << why;
  ASSERT_TRUE(b.configure(ImuModelConfig{}, &why));
  ImuModelConfig other;
  other.seed = 1;
  ASSERT_TRUE(c.configure(other, &why));
  double x[6] = {0.1, -0.2, 0.3, 0.0, 0.0, 9.81}, ya[6], yb[6], yc[6];
  bool differs = false;
  for (int k = 0; k < 1000; ++k) {
    a.apply(x, ya);
    b.apply(x, yb);
    c.apply(x, yc);
    for (int i = 0; i < 6; ++i) {
      ASSERT_EQ(ya[i], yb[i]);  // bit-identical
      differs = differs || ya[i] != yc[i];
    }
  }
  EXPECT_TRUE(differs);
}

TEST(ImuModel, WhiteNoiseHasTheDensitysVarianceAndAllanSlope) {
  const double dt = 0.001, density = 2.44e-4;  // [rad/s/sqrt(Hz)]
  ImuModel m;
  std::string why;
  ASSERT_TRUE(m.configure(only(density, 0.0, 0.0), &why)) << why;
  const int n = 200000;
  std::vector<double> g(n);
  double x[6] = {}, y[6];
  for (int k = 0; k < n; ++k) {
    m.apply(x, y);
    g[k] = y[0];
  }
  const double sigma = density / std::sqrt(dt);
  double sum = 0.0, sq = 0.0;
  for (double v : g) sum += v, sq += v * v;
  EXPECT_NEAR(sum / n, 0.0, 5.0 * sigma / std::sqrt(n));
  EXPECT_NEAR(sq / n / (sigma * sigma), 1.0, 5.0 * std::sqrt(2.0 / n));
  // Allan deviation N / sqrt(tau) at tau = 1, 10, 100 ms; relative std of the AVAR estimate from
  // M clusters: sqrt(2 / (M - 1)).
  for (int m_cluster : {1, 10, 100}) {
    const double tau = m_cluster * dt, clusters = n / m_cluster;
    const double expected = density * density / tau;
    EXPECT_NEAR(allan_variance(g, m_cluster) / expected, 1.0, 5.0 * std::sqrt(2.0 / (clusters - 1)))
        << "tau " << tau;
  }
}

TEST(ImuModel, BiasRandomWalkGrowsAsKSquaredT) {
  // The bias after T seconds, across seeds: variance K^2 T (and turn-on 0, white 0).
  const double k_walk = 3e-4, dt = 0.001;
  const int seeds = 2000, ticks = 500;
  double sq = 0.0, sum = 0.0;
  double x[6] = {}, y[6];
  for (int s = 0; s < seeds; ++s) {
    ImuModel m;
    std::string why;
    ASSERT_TRUE(m.configure(only(0.0, k_walk, 0.0, s), &why));
    for (int k = 0; k < ticks; ++k) m.apply(x, y);
    sum += m.bias()[3];
    sq += m.bias()[3] * m.bias()[3];
  }
  const double var = k_walk * k_walk * ticks * dt;
  EXPECT_NEAR(sum / seeds, 0.0, 5.0 * std::sqrt(var / seeds));
  EXPECT_NEAR(sq / seeds / var, 1.0, 5.0 * std::sqrt(2.0 / seeds));
}

TEST(ImuModel, RandomWalkAllanDeviationRisesAsKSqrtTauOver3) {
  // One long record with the walk only: sigma_A^2(tau) = K^2 tau / 3. A random walk's Allan
  // variance converges slowly (few independent clusters): the bound is 5 x sqrt(2 / (M - 1))
  // with M clusters, checked at a tau leaving M = 400.
  const double k_walk = 2e-5, dt = 0.001;
  const int n = 400000, m_cluster = 1000;
  ImuModel m;
  std::string why;
  ASSERT_TRUE(m.configure(only(0.0, k_walk, 0.0, 3), &why));
  std::vector<double> g(n);
  double x[6] = {}, y[6];
  for (int k = 0; k < n; ++k) {
    m.apply(x, y);
    g[k] = y[1];
  }
  const double tau = m_cluster * dt, clusters = n / m_cluster;
  EXPECT_NEAR(allan_variance(g, m_cluster) / (k_walk * k_walk * tau / 3.0), 1.0,
              5.0 * std::sqrt(2.0 / (clusters - 1)));
}

TEST(ImuModel, TurnOnBiasIsASeededConstant) {
  const double b0 = 0.0196;
  const int seeds = 2000;
  double sq = 0.0;
  double x[6] = {0, 0, 0, 0, 0, 9.81}, y[6];
  for (int s = 0; s < seeds; ++s) {
    ImuModel m;
    std::string why;
    ASSERT_TRUE(m.configure(only(0.0, 0.0, b0, s), &why));
    m.apply(x, y);
    const double first = y[5] - 9.81;
    for (int k = 0; k < 100; ++k) m.apply(x, y);
    ASSERT_EQ(y[5] - 9.81, first);  // constant without a walk
    sq += first * first;
  }
  EXPECT_NEAR(sq / seeds / (b0 * b0), 1.0, 5.0 * std::sqrt(2.0 / seeds));
}

TEST(ImuModel, RejectsBadParameters) {
  ImuModel m;
  std::string why;
  EXPECT_FALSE(m.configure(only(-1.0, 0.0, 0.0), &why));
  EXPECT_FALSE(m.configure(only(0.0, NAN, 0.0), &why));
  ImuModelConfig c;
  c.dt = 0.0;
  EXPECT_FALSE(m.configure(c, &why));
}

TEST(EncoderVelocity, DifferencesQuantizedPositions) {
  EncoderVelocity e;
  std::string why;
  const double res = 1e-4, dt = 0.001, v = 0.37;  // [rad], [s], [rad/s]
  ASSERT_TRUE(e.configure(1, res, dt, &why)) << why;
  double qd = -1.0, sum = 0.0;
  const int n = 1000;
  for (int k = 0; k <= n; ++k) {
    const double q = 0.2 + v * k * dt;
    e.apply(&q, &qd);
    if (k == 0) EXPECT_EQ(qd, 0.0);  // no previous reading
    // Every reading is a whole number of quanta per tick.
    EXPECT_NEAR(qd * dt / res, std::nearbyint(qd * dt / res), 1e-6);
    if (k > 0) sum += qd;
  }
  // The differences telescope: the mean is exact to one quantum over the whole span.
  EXPECT_NEAR(sum / n, v, res / (n * dt));
  EXPECT_FALSE(e.configure(1, -1.0, dt, &why));
}

TEST(ImuModel, NoAllocationPerCall) {
  ImuModel m;
  EncoderVelocity e;
  std::string why;
  ASSERT_TRUE(m.configure(ImuModelConfig{}, &why));
  ASSERT_TRUE(e.configure(12, 1e-4, 0.001, &why));
  std::vector<double> x(6, 0.1), y(6), q(12, 0.5), qd(12);
  testing::AllocationScope scope;
  for (int k = 0; k < 1000; ++k) {
    m.apply(x.data(), y.data());
    e.apply(q.data(), qd.data());
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_TRUE(std::isfinite(y[0]));
}

}  // namespace
}  // namespace kiloloop::sil
