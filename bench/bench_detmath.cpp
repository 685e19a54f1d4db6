// kiloloop_bench_detmath: accuracy and speed of the deterministic math (SLEEF's scalar functions,
// kiloloop_sleef) beside the C library's (glibc, with whatever code path it picks on this CPU).
//   kiloloop_bench_detmath [--args N] [--calls N] [--repeats N] [--seed S]     (--args 0: speed only)
// Accuracy: N seeded arguments per function over the ranges the real-time code uses; each
// result's error against a quadruple-precision reference (libquadmath, 113-bit significand:
// its own error is ~2^-60 of a double's ulp), in ulps of the double nearest the exact value.
// Prints the largest error, and how many results are not the correctly rounded double.
// Speed: median ns per call over `repeats` timed loops of `calls` calls on distinct arguments.
// Output: one markdown table (scripts/detmath_results.py puts it into bench/RESULTS.md).
// This program links kiloloop_sleef only, not kiloloop_detmath: here `sin` is the C library's.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

extern "C" {
#include <quadmath.h>
}

#include "sleef_functions.h"

namespace {

using Clock = std::chrono::steady_clock;
using F1 = double (*)(double);
using F2 = double (*)(double, double);
using Q1 = __float128 (*)(__float128);
using Q2 = __float128 (*)(__float128, __float128);

// How an argument is drawn: uniform in [lo, hi], or log-uniform in [lo, hi] (lo > 0).
struct Range {
  double lo, hi;
  bool log_uniform = false;
  double draw(std::mt19937_64& rng) const {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double t = u(rng);
    if (log_uniform) return lo * std::pow(hi / lo, t);
    return lo + (hi - lo) * t;
  }
  std::string text() const {
    char buf[96];
    std::snprintf(buf, sizeof buf, log_uniform ? "[%g, %g] log" : "[%g, %g]", lo, hi);
    return buf;
  }
};

struct Function {
  const char* name;
  F1 sleef1 = nullptr, libc1 = nullptr;
  Q1 ref1 = nullptr;
  F2 sleef2 = nullptr, libc2 = nullptr;
  Q2 ref2 = nullptr;
  Range x, y{0, 0};
};

// The C library's functions through pointers: the compiler can neither fold nor inline them.
double libc_sin(double x) { return std::sin(x); }
double libc_cos(double x) { return std::cos(x); }
double libc_tan(double x) { return std::tan(x); }
double libc_asin(double x) { return std::asin(x); }
double libc_acos(double x) { return std::acos(x); }
double libc_atan(double x) { return std::atan(x); }
double libc_atan2(double y, double x) { return std::atan2(y, x); }
double libc_sinh(double x) { return std::sinh(x); }
double libc_cosh(double x) { return std::cosh(x); }
double libc_tanh(double x) { return std::tanh(x); }
double libc_exp(double x) { return std::exp(x); }
double libc_expm1(double x) { return std::expm1(x); }
double libc_log(double x) { return std::log(x); }
double libc_log1p(double x) { return std::log1p(x); }
double libc_pow(double x, double y) { return std::pow(x, y); }
double libc_cbrt(double x) { return std::cbrt(x); }
double libc_hypot(double x, double y) { return std::hypot(x, y); }

// Error of y against the exact value r, in ulps of the double nearest r (subnormals: 2^-1074).
double ulp_error(double y, __float128 r) {
  if (std::isnan(y) || isnanq(r)) return (std::isnan(y) && isnanq(r)) ? 0.0 : INFINITY;
  const double rd = static_cast<double>(r);
  if (std::isinf(rd)) return y == rd ? 0.0 : INFINITY;
  int e = 0;
  std::frexp(rd == 0.0 ? 0x1p-1022 : rd, &e);  // |rd| in [2^(e-1), 2^e)
  const double ulp = std::ldexp(1.0, std::max(e - 53, -1074));
  return static_cast<double>(fabsq(static_cast<__float128>(y) - r) / ulp);
}

struct Accuracy {
  double max_ulp = 0.0, max_at_x = 0.0, max_at_y = 0.0;
  long not_rounded = 0;  // results that are not the correctly rounded double
};

void account(Accuracy& a, double y, __float128 r, double x, double x2) {
  const double err = ulp_error(y, r);
  if (err > a.max_ulp) a.max_ulp = err, a.max_at_x = x, a.max_at_y = x2;
  if (!(y == static_cast<double>(r)) && !(std::isnan(y) && isnanq(r))) ++a.not_rounded;
}

// Median ns per call of f over the arguments, `repeats` loops of xs.size() calls.
template <class Call>
double median_ns(Call call, std::size_t n, int repeats) {
  std::vector<double> ns;
  volatile double sink = 0.0;
  for (int r = 0; r < repeats + 1; ++r) {  // the first loop warms caches and is not counted
    double acc = 0.0;
    const auto t0 = Clock::now();
    for (std::size_t i = 0; i < n; ++i) acc += call(i);
    const auto t1 = Clock::now();
    sink = sink + acc;
    if (r > 0) ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / n);
  }
  std::nth_element(ns.begin(), ns.begin() + ns.size() / 2, ns.end());
  return ns[ns.size() / 2];
}

long arg_value(int argc, char** argv, const char* flag, long fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], flag) == 0) return std::atol(argv[i + 1]);
  return fallback;
}

}  // namespace

int main(int argc, char** argv) {
  const long n_args = arg_value(argc, argv, "--args", 2000000);
  const long n_calls = arg_value(argc, argv, "--calls", 100000);
  const int repeats = static_cast<int>(arg_value(argc, argv, "--repeats", 15));
  const unsigned long seed = static_cast<unsigned long>(arg_value(argc, argv, "--seed", 20261127));
  const double pi = 3.141592653589793;
  // The ranges the real-time code calls them on: angles (joint angles, attitude errors, yaw),
  // unit-interval cosines, ratios of Cartesian and velocity quantities, decay factors exp(-dt/tau),
  // Box-Muller's log(u), saturation curves (tanh).
  const std::vector<Function> functions = {
      {"sin", Sleef_sin_u10, libc_sin, sinq, nullptr, nullptr, nullptr, {-4 * pi, 4 * pi}},
      {"cos", Sleef_cos_u10, libc_cos, cosq, nullptr, nullptr, nullptr, {-4 * pi, 4 * pi}},
      {"tan", Sleef_tan_u10, libc_tan, tanq, nullptr, nullptr, nullptr, {-1.5, 1.5}},
      {"asin", Sleef_asin_u10, libc_asin, asinq, nullptr, nullptr, nullptr, {-1, 1}},
      {"acos", Sleef_acos_u10, libc_acos, acosq, nullptr, nullptr, nullptr, {-1, 1}},
      {"atan", Sleef_atan_u10, libc_atan, atanq, nullptr, nullptr, nullptr, {-50, 50}},
      {"atan2", nullptr, nullptr, nullptr, Sleef_atan2_u10, libc_atan2, atan2q, {-10, 10}, {-10, 10}},
      {"sinh", Sleef_sinh_u10, libc_sinh, sinhq, nullptr, nullptr, nullptr, {-10, 10}},
      {"cosh", Sleef_cosh_u10, libc_cosh, coshq, nullptr, nullptr, nullptr, {-10, 10}},
      {"tanh", Sleef_tanh_u10, libc_tanh, tanhq, nullptr, nullptr, nullptr, {-20, 20}},
      {"exp", Sleef_exp_u10, libc_exp, expq, nullptr, nullptr, nullptr, {-50, 10}},
      {"expm1", Sleef_expm1_u10, libc_expm1, expm1q, nullptr, nullptr, nullptr, {-1, 1}},
      {"log", Sleef_log_u10, libc_log, logq, nullptr, nullptr, nullptr, {1e-12, 1e6, true}},
      {"log1p", Sleef_log1p_u10, libc_log1p, log1pq, nullptr, nullptr, nullptr, {-0.5, 1}},
      {"pow", nullptr, nullptr, nullptr, Sleef_pow_u10, libc_pow, powq, {1e-3, 1e3, true}, {-4, 4}},
      {"cbrt", Sleef_cbrt_u10, libc_cbrt, cbrtq, nullptr, nullptr, nullptr, {-1e3, 1e3}},
      {"hypot", nullptr, nullptr, nullptr, Sleef_hypot_u05, libc_hypot, hypotq, {-10, 10}, {-10, 10}},
  };
  std::printf("| function | arguments | range | SLEEF max ulp | SLEEF not correctly rounded | "
              "glibc max ulp | glibc not correctly rounded | SLEEF ns | glibc ns | SLEEF / glibc |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  bool ok = true;
  for (const Function& f : functions) {
    std::mt19937_64 rng(seed);
    Accuracy sleef, libc;
    const bool two = f.sleef2 != nullptr;
    for (long i = 0; i < n_args; ++i) {
      const double x = f.x.draw(rng), y = two ? f.y.draw(rng) : 0.0;
      if (two) {
        const __float128 r = f.ref2(x, y);
        account(sleef, f.sleef2(x, y), r, x, y);
        account(libc, f.libc2(x, y), r, x, y);
      } else {
        const __float128 r = f.ref1(x);
        account(sleef, f.sleef1(x), r, x, 0.0);
        account(libc, f.libc1(x), r, x, 0.0);
      }
    }
    std::vector<double> xs(n_calls), ys(n_calls);
    for (long i = 0; i < n_calls; ++i) xs[i] = f.x.draw(rng), ys[i] = two ? f.y.draw(rng) : 0.0;
    double t_sleef, t_libc;
    if (two) {
      t_sleef = median_ns([&](std::size_t i) { return f.sleef2(xs[i], ys[i]); }, n_calls, repeats);
      t_libc = median_ns([&](std::size_t i) { return f.libc2(xs[i], ys[i]); }, n_calls, repeats);
    } else {
      t_sleef = median_ns([&](std::size_t i) { return f.sleef1(xs[i]); }, n_calls, repeats);
      t_libc = median_ns([&](std::size_t i) { return f.libc1(xs[i]); }, n_calls, repeats);
    }
    std::string range = f.x.text();
    if (two) range = "x " + range + ", y " + f.y.text();
    const double per = n_args > 0 ? 100.0 / n_args : 0.0;  // --args 0: speed only
    std::printf("| %s | %ld | %s | %.3f | %.2f %% | %.3f | %.2f %% | %.1f | %.1f | %.2f |\n", f.name,
                n_args, range.c_str(), sleef.max_ulp, per * sleef.not_rounded, libc.max_ulp,
                per * libc.not_rounded, t_sleef, t_libc, t_sleef / t_libc);
    std::fflush(stdout);
    if (!(sleef.max_ulp <= 1.0)) ok = false;
  }
  // Exit 1 if any SLEEF function is off by more than 1 ulp (its documented bound).
  return ok ? 0 : 1;
}
