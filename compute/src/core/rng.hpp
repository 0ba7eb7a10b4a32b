#pragma once
// The one family of seeded random generators of compute/: splitmix64 (Steele, Lea, Flood, "Fast
// splittable pseudorandom number generators", OOPSLA 2014) and xoshiro256** (Blackman, Vigna,
// "Scrambled linear pseudorandom number generators", ACM TOMS 47(4), 2021), seeded through splitmix64
// as its authors recommend. Both are fully specified, so a seed gives the same numbers on every
// platform and standard library (std::*_distribution is implementation-defined); every result that a
// seed reproduces (bundling jitter, projections, sweeps, forests, demo traffic, synthetic videos) and
// the golden files of the tests depend on these exact sequences: do not change them.
#include <cstdint>

namespace trailscope::rng {

/// The splitmix64 increment (2^64 / golden ratio).
inline constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;

/// One splitmix64 step: advances `state` by kGolden and returns the mixed new state.
constexpr std::uint64_t splitmix64(std::uint64_t& state) noexcept {
  std::uint64_t z = (state += kGolden);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// Stateless form: the value a splitmix64 at `state` returns next, i.e. a well-mixed hash of `state`
/// (bundling chains it over (seed, iteration, edge, sample) so that no result depends on threads).
constexpr std::uint64_t splitmix64_hash(std::uint64_t state) noexcept {
  return splitmix64(state);
}

/// The top 53 bits of `bits` as a double in [0, 1).
constexpr double unit_double(std::uint64_t bits) noexcept {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

/// splitmix64 as a generator: the state starts at `state` as given (no scrambling of the seed).
class SplitMix64 {
 public:
  explicit constexpr SplitMix64(std::uint64_t state) noexcept : s_(state) {}
  constexpr std::uint64_t next() noexcept { return splitmix64(s_); }
  /// Uniform in [0, 1), 53 bits.
  constexpr double uniform() noexcept { return unit_double(next()); }

 private:
  std::uint64_t s_;
};

/// xoshiro256**, its four state words the first four splitmix64 outputs from `seed`.
class Xoshiro256ss {
 public:
  explicit constexpr Xoshiro256ss(std::uint64_t seed = 0) noexcept {
    for (auto& w : s_) w = splitmix64(seed);
  }
  constexpr std::uint64_t next() noexcept {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9, t = s_[1] << 17;
    s_[2] ^= s_[0], s_[3] ^= s_[1], s_[1] ^= s_[2], s_[0] ^= s_[3], s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  /// Uniform in [0, 1), 53 bits.
  constexpr double uniform() noexcept { return unit_double(next()); }
  /// Uniform in [lo, hi).
  constexpr double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * uniform(); }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) noexcept { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4] = {};
};

}  // namespace trailscope::rng
