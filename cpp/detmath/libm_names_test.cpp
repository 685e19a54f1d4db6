// The libm names bind to musl's functions in a program linked with kiloloop::core (this test binary is one):
// std::sin, std::atan2, ... return musl's bits, and sin(x), cos(x) of one argument, which GCC
// merges into one sincos call, return the same bits as two separate calls.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "musl_functions.h"

namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(LibmNames, CallsReturnMuslBits) {
  std::mt19937_64 rng(31);  // seed 31
  std::uniform_real_distribution<double> angle(-10.0, 10.0), unit(-1.0, 1.0), pos(1e-6, 1e3);
  for (int i = 0; i < 20000; ++i) {
    volatile double a = angle(rng), u = unit(rng), p = pos(rng), b = angle(rng);
    ASSERT_EQ(bits(std::sin(a)), bits(kiloloop_musl_sin(a))) << a;
    ASSERT_EQ(bits(std::cos(a)), bits(kiloloop_musl_cos(a))) << a;
    ASSERT_EQ(bits(std::tan(a)), bits(kiloloop_musl_tan(a))) << a;
    ASSERT_EQ(bits(std::asin(u)), bits(kiloloop_musl_asin(u))) << u;
    ASSERT_EQ(bits(std::acos(u)), bits(kiloloop_musl_acos(u))) << u;
    ASSERT_EQ(bits(std::atan2(a, b)), bits(kiloloop_musl_atan2(a, b))) << a << " " << b;
    ASSERT_EQ(bits(std::tanh(a)), bits(kiloloop_musl_tanh(a))) << a;
    ASSERT_EQ(bits(std::exp(a)), bits(kiloloop_musl_exp(a))) << a;
    ASSERT_EQ(bits(std::log(p)), bits(kiloloop_musl_log(p))) << p;
    ASSERT_EQ(bits(std::pow(p, a)), bits(kiloloop_musl_pow(p, a))) << p << " " << a;
    ASSERT_EQ(bits(std::cbrt(a)), bits(kiloloop_musl_cbrt(a))) << a;
    ASSERT_EQ(bits(std::hypot(a, b)), bits(kiloloop_musl_hypot(a, b))) << a << " " << b;
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
    ASSERT_EQ(bits(s), bits(kiloloop_musl_sin(a))) << a;
    ASSERT_EQ(bits(c), bits(kiloloop_musl_cos(a))) << a;
  }
}

}  // namespace
