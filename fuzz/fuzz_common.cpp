#include "fuzz_common.hpp"

#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace kiloloop::fuzz {

double nonfinite_value(Rng& r) {
  switch (r.below(3)) {
    case 0: return std::numeric_limits<double>::quiet_NaN();
    case 1: return std::numeric_limits<double>::infinity();
    default: return -std::numeric_limits<double>::infinity();
  }
}

double extreme_value(Rng& r) {
  static const double kValues[] = {1e308,   -1e308,   DBL_MAX, -DBL_MAX, 4.9e-324, -4.9e-324,
                                   1e-310,  DBL_MIN,  -DBL_MIN, 0.0,     -0.0,     1e30,
                                   -1e30,   1e154,    -1e154,   1e12};
  return kValues[r.below(sizeof(kValues) / sizeof(kValues[0]))];
}

void Desc::add(const char* fmt, ...) {
  if (len_ >= static_cast<int>(sizeof(buf_)) - 2) return;
  if (len_ > 0) buf_[len_++] = ';', buf_[len_++] = ' ';
  va_list ap;
  va_start(ap, fmt);
  const int w = std::vsnprintf(buf_ + len_, sizeof(buf_) - len_, fmt, ap);
  va_end(ap);
  if (w > 0) len_ = std::min<int>(len_ + w, sizeof(buf_) - 1);
}

bool poke(Rng& r, double* v, int n, bool nonfinite, Desc& d, const char* name) {
  if (n <= 0) return false;
  const int i = r.below(n);
  v[i] = nonfinite ? nonfinite_value(r) : extreme_value(r);
  d.add("%s[%d]=%.17g", name, i, v[i]);
  return !std::isfinite(v[i]);
}

bool all_finite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

void mutate_time(Rng& r, double max_age, const StampModel& m, double* t, double* stamp, Desc& d) {
  switch (r.below(7)) {
    case 0:
      *stamp = *t - max_age * r.uniform(1.01, 1000.0);
      d.add("stale stamp=t-%.17g", *t - *stamp);
      break;
    case 1:
      *stamp = *t + max_age * r.uniform(1.01, 1000.0);
      d.add("future stamp=t+%.17g", *stamp - *t);
      break;
    case 2: {  // time going backwards: t and stamp before the newest accepted stamp
      const double back = r.uniform(1e-6, 0.5);
      const double base = m.has_newest ? m.newest : *t;
      *t = base - back;
      *stamp = *t;
      d.add("time backwards t=stamp=%.17g (newest accepted %.17g)", *t, base);
      break;
    }
    case 3:
      *t = nonfinite_value(r);
      d.add("t=%g", *t);
      break;
    case 4:
      *stamp = nonfinite_value(r);
      d.add("stamp=%g", *stamp);
      break;
    case 5:
      *t = extreme_value(r);
      d.add("t=%.17g", *t);
      break;
    default:
      *stamp = extreme_value(r);
      d.add("stamp=%.17g", *stamp);
      break;
  }
}

void Tally::fail(std::uint64_t index, const Desc& d, std::uint64_t* counter, const char* fmt, ...) {
  ++*counter;
  // The first few of each kind (bad outputs, missed statuses, known failures).
  int& shown = counter == &bad_outputs ? printed : counter == &missed_status ? printed_status
                                                                             : printed_known;
  if (shown >= 6) return;
  ++shown;
  char what[512];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(what, sizeof(what), fmt, ap);
  va_end(ap);
  std::printf("  [%s] input #%llu: %s\n      input: %s\n", target,
              static_cast<unsigned long long>(index), what, d.str());
  std::fflush(stdout);
}

std::string models_dir() {
  const char* env = std::getenv("KILOLOOP_MODELS_DIR");
  if (env && *env) return env;
#ifdef KILOLOOP_MODELS_DIR
  return KILOLOOP_MODELS_DIR;
#else
  return "models";
#endif
}

}  // namespace kiloloop::fuzz
