#pragma once
// Seeded, portable random numbers for the native SIL loop's noise models.
// xoshiro256** (Blackman & Vigna) seeded through SplitMix64, and standard normals by Marsaglia's
// polar method (only +, *, log and sqrt; no std::normal_distribution, whose output differs
// between standard libraries). Same seed -> same stream on any thread, any thread count.
#include <cmath>
#include <cstdint>

namespace kiloloop::sil {

class Rng {
 public:
  explicit Rng(std::uint64_t seed = 0) noexcept { reseed(seed); }

  void reseed(std::uint64_t seed) noexcept {
    std::uint64_t x = seed;
    for (auto& s : s_) s = splitmix64(x);
  }

  std::uint64_t next() noexcept {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  // Uniform in [0, 1): the top 53 bits.
  double uniform() noexcept { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  // One standard normal sample. The polar method makes a pair; the second is dropped so that
  // each call consumes whole draws only (simpler to mirror in a reference implementation).
  double normal() noexcept {
    double u, s;
    polar_point(u, s);
    return u * std::sqrt(-2.0 * std::log(s) / s);
  }

  // Consumes exactly the draws normal() would and returns +1 or -1, the sign of the sample it
  // skips (that of u: the factor sqrt(..) is > 0), without its log and sqrt. For an element
  // whose sigma is 0: sigma * normal() is then the same signed zero as sigma * normal_sign(),
  // and the stream stays that of normal() for the elements after it.
  double normal_sign() noexcept {
    double u, s;
    polar_point(u, s);
    return std::copysign(1.0, u);
  }

 private:
  // The polar method's rejection loop, shared by normal() and normal_sign(): a point (u, v) drawn
  // uniformly in the square until it lies inside the unit disc (not at its centre); s = u^2 + v^2.
  void polar_point(double& u, double& s) noexcept {
    for (;;) {
      u = 2.0 * uniform() - 1.0;
      const double v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
      if (s > 0.0 && s < 1.0) return;
    }
  }
  static std::uint64_t rotl(std::uint64_t x, int k) noexcept { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix64(std::uint64_t& x) noexcept {
    std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  std::uint64_t s_[4];
};

}  // namespace kiloloop::sil
