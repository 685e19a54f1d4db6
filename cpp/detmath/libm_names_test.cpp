// The libm names bind to SLEEF in a program linked with kiloloop::core (this test binary is one):
// std::sin, std::atan2, ... return SLEEF's bits, and sin(x), cos(x) of one argument, which GCC
// merges into one sincos call, return the same bits as two separate calls.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "sleef_functions.h"

namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(LibmNames, CallsReturnSleefBits) {
  std::mt19937_64 rng(31);  // seed 31
  std::uniform_real_distribution<double> angle(-10.0, 10.0), unit(-1.0, 1.0), pos(1e-6, 1e3);
  for (int i = 0; i < 20000; ++i) {
    volatile double a = angle(rng), u = unit(rng), p = pos(rng), b = angle(rng);
    ASSERT_EQ(bits(std::sin(a)), bits(Sleef_sin_u10(a))) << a;
    ASSERT_EQ(bits(std::cos(a)), bits(Sleef_cos_u10(a))) << a;
    ASSERT_EQ(bits(std::tan(a)), bits(Sleef_tan_u10(a))) << a;
    ASSERT_EQ(bits(std::asin(u)), bits(Sleef_asin_u10(u))) << u;
    ASSERT_EQ(bits(std::acos(u)), bits(Sleef_acos_u10(u))) << u;
    ASSERT_EQ(bits(std::atan2(a, b)), bits(Sleef_atan2_u10(a, b))) << a << " " << b;
    ASSERT_EQ(bits(std::tanh(a)), bits(Sleef_tanh_u10(a))) << a;
    ASSERT_EQ(bits(std::exp(a)), bits(Sleef_exp_u10(a))) << a;
    ASSERT_EQ(bits(std::log(p)), bits(Sleef_log_u10(p))) << p;
    ASSERT_EQ(bits(std::pow(p, a)), bits(Sleef_pow_u10(p, a))) << p << " " << a;
    ASSERT_EQ(bits(std::cbrt(a)), bits(Sleef_cbrt_u10(a))) << a;
    ASSERT_EQ(bits(std::hypot(a, b)), bits(Sleef_hypot_u05(a, b))) << a << " " << b;
  }
}

TEST(LibmNames, MergedSinCosEqualsTheSeparateCalls) {
  std::mt19937_64 rng(7);  // seed 7
  std::uniform_real_distribution<double> angle(-100.0, 100.0);
  for (int i = 0; i < 20000; ++i) {
    const double a = angle(rng);
    const double s = std::sin(a), c = std::cos(a);  // one sincos call at -O2
    volatile double v = a;                            // two separate calls
    ASSERT_EQ(bits(s), bits(std::sin(v))) << a;
    ASSERT_EQ(bits(c), bits(std::cos(v))) << a;
    ASSERT_EQ(bits(s), bits(Sleef_sin_u10(a))) << a;
    ASSERT_EQ(bits(c), bits(Sleef_cos_u10(a))) << a;
  }
}

}  // namespace
