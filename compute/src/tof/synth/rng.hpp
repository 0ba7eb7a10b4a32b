#pragma once
// The synthetic video's random numbers: xoshiro256** (core/rng.hpp) with a fully specified normal
// distribution, so that a seed gives the same video on every platform and standard library
// (std::normal_distribution and friends are implementation-defined). Internal.
#include <cmath>
#include <cstdint>

#include "core/rng.hpp"

namespace trailscope::tof::synth {

/// xoshiro256**, one independent stream per (seed, stream) pair.
class Rng : public rng::Xoshiro256ss {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream) : Xoshiro256ss(seed ^ (stream * 0xd1b54a32d192ed03ull)) {}
  /// Standard normal by the 256-layer ziggurat of Marsaglia & Tsang (2000), as in Rust's rand_distr:
  /// about 4x faster than Box-Muller, which matters at two draws per pixel.
  double normal();
};

namespace detail {
struct ZigguratTables {
  double x[257], f[257];
};
/// Built once (x[0] = V / f(R), x[1] = R, x[i+1] = sqrt(-2 ln(V / x[i] + f(x[i]))), x[256] = 0).
inline const ZigguratTables& ziggurat_tables() {
  static const ZigguratTables t = [] {
    constexpr double R = 3.654152885361008796, V = 0.00492867323399;
    ZigguratTables z;
    const auto pdf = [](double x) { return std::exp(-0.5 * x * x); };
    z.x[0] = V / pdf(R);
    z.x[1] = R;
    for (int i = 2; i < 256; ++i) z.x[i] = std::sqrt(-2.0 * std::log(V / z.x[i - 1] + pdf(z.x[i - 1])));
    z.x[256] = 0;
    for (int i = 0; i <= 256; ++i) z.f[i] = pdf(z.x[i]);
    return z;
  }();
  return t;
}
}  // namespace detail

inline double Rng::normal() {
  constexpr double R = 3.654152885361008796;
  const auto& z = detail::ziggurat_tables();
  while (true) {
    const std::uint64_t bits = next();
    const int i = static_cast<int>(bits & 0xff);
    const double u = 2.0 * (static_cast<double>(bits >> 11) * 0x1.0p-53) - 1.0;  // [-1, 1)
    const double x = u * z.x[i];
    if (std::abs(x) < z.x[i + 1]) return x;
    if (i == 0) {  // the tail beyond R
      double tx, ty;
      do {
        tx = std::log(1.0 - uniform()) / R;
        ty = std::log(1.0 - uniform());
      } while (-2.0 * ty < tx * tx);
      return u < 0 ? tx - R : R - tx;
    }
    if (z.f[i + 1] + (z.f[i] - z.f[i + 1]) * uniform() < std::exp(-0.5 * x * x)) return x;
  }
}

}  // namespace trailscope::tof::synth
