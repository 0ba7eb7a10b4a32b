#include "render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace trailscope::tof::synth {
namespace {
constexpr double kLightMmPerS = 299'792'458e3;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Hit {
  double t = kNoHit;
  int prim = -1;
};

// Per-teat pixel counts for the ground truth.
struct TeatCount {
  int all = 0, visible = 0, tip_all = 0, tip_visible = 0;
  int umin = 1 << 30, umax = -1, vmin = 1 << 30, vmax = -1;
};

class Caster {
 public:
  Caster(const SceneFrame& scene, const Intrinsics& k)
      : scene_(scene), cx_(k.cx), cy_(k.cy), ifx_(1.0 / k.fx), ify_(1.0 / k.fy) {}

  // Multiplying by the reciprocal focal lengths: two divisions per ray were a tenth of the frame time.
  Vec3 ray(double u, double v) const { return Vec3((u - cx_) * ifx_, (v - cy_) * ify_, 1.0); }

  // Nearest hit of the ray d among the primitives `candidates` (n of them).
  Hit cast(const Vec3& d, const int* candidates, int n) const {
    const double dd = d.squaredNorm();
    Hit best;
    for (int j = 0; j < n; ++j) {
      const double t = intersect(scene_.prims[candidates[j]], d, dd);
      if (t < best.t) best = {t, candidates[j]};
    }
    return best;
  }

  // Amplitude of a hit: a0 * reflectivity * cos(incidence) / (range in m)^2; also gives cos and range^2
  // (mm^2). One square root and two divisions: cos = |n.d| / sqrt(|n|^2 |d|^2), range^2 = t^2 |d|^2.
  double amplitude(const Hit& h, const Vec3& d, double a0, double* cos_out, double* range2_out) const {
    const Primitive& p = scene_.prims[h.prim];
    const double dd = d.squaredNorm();
    const Vec3 n = normal_at(p, h.t * d);
    const double c = std::abs(n.dot(d)) / std::sqrt(n.squaredNorm() * dd);
    const double range2 = h.t * h.t * dd;
    if (cos_out) *cos_out = c;
    if (range2_out) *range2_out = range2;
    return a0 * 1e6 * p.reflectivity * c / range2;
  }

  const SceneFrame& scene() const { return scene_; }

 private:
  const SceneFrame& scene_;
  double cx_, cy_, ifx_, ify_;
};
}  // namespace

void render_frame(const SceneFrame& scene, const Intrinsics& k, const SensorParams& sensor, bool noise_free,
                  Rng& rng, DepthFrame& frame, FrameTruth* truth) {
  const int W = k.width, H = k.height;
  const std::size_t N = static_cast<std::size_t>(W) * H;
  const Caster caster(scene, k);
  std::vector<Hit> hits(N);
  std::array<TeatCount, kTeatCount> counts{};
  const auto& prims = scene.prims;

  // Pass 1: the centre ray of every pixel; ground-truth bookkeeping on the teat capsules on the way.
  // Per row, each primitive's exact span of columns (row_interval), so that a pixel tests only the
  // two or three surfaces its ray can meet.
  struct Span {
    int prim, u0, u1;
  };
  std::vector<Span> active;
  active.reserve(prims.size());
  for (int v = 0; v < H; ++v) {
    active.clear();
    const double b = (v - k.cy) / k.fy;
    for (std::size_t i = 0; i < prims.size(); ++i) {
      const Primitive& p = prims[i];
      double a_lo, a_hi;
      if (v < p.v0 || v > p.v1 || !row_interval(p, b, 1.0 / k.fx, &a_lo, &a_hi)) continue;
      const double u_lo = std::max(k.fx * a_lo + k.cx, -1.0), u_hi = std::min(k.fx * a_hi + k.cx, double(W));
      const int u0 = std::max(p.u0, static_cast<int>(std::floor(u_lo))),
                u1 = std::min(p.u1, static_cast<int>(std::ceil(u_hi)));
      if (u0 <= u1) active.push_back({static_cast<int>(i), u0, u1});
    }
    for (int u = 0; u < W; ++u) {
      const Vec3 d = caster.ray(u, v);
      const double dd = d.squaredNorm();
      Hit best;
      int teat_hits = 0, tip_hits = 0;  // bit k: the ray meets teat k (below the udder) / its tip region
      for (const Span& span : active) {
        if (u < span.u0 || u > span.u1) continue;
        const int i = span.prim;
        const Primitive& p = prims[i];
        const double t = intersect(p, d, dd);
        if (t == kNoHit) continue;
        if (truth && p.object == Object::teat) {
          const TeatView& tv = scene.teats[p.teat];
          const Vec3 x = t * d;
          if ((x - tv.surface).dot(tv.dir) >= 0) {
            teat_hits |= 1 << p.teat;
            if ((x - tv.apex).norm() <= tv.r) tip_hits |= 1 << p.teat;
          }
        }
        if (t < best.t) best = {t, i};
      }
      hits[static_cast<std::size_t>(v) * W + u] = best;
      if (teat_hits) {
        for (int t = 0; t < kTeatCount; ++t) {
          if (!(teat_hits & (1 << t))) continue;
          TeatCount& c = counts[t];
          const bool seen =
              best.prim >= 0 && prims[best.prim].object == Object::teat && prims[best.prim].teat == t;
          ++c.all;
          c.visible += seen;
          c.umin = std::min(c.umin, u), c.umax = std::max(c.umax, u);
          c.vmin = std::min(c.vmin, v), c.vmax = std::max(c.vmax, v);
          if (tip_hits & (1 << t)) {
            ++c.tip_all;
            c.tip_visible += seen;
          }
        }
      }
    }
  }

  if (truth) {
    for (int t = 0; t < kTeatCount; ++t) {
      const TeatView& tv = scene.teats[t];
      const TeatCount& c = counts[t];
      TeatTruth& x = truth->teats[t];
      x.tip_mm = {tv.apex.x(), tv.apex.y(), tv.apex.z()};
      x.cup_attached = tv.cup_on;
      x.visible_fraction = c.all > 0 ? static_cast<double>(c.visible) / c.all : 0.0;
      if (c.all > 0)
        x.box_px =
            BoxPx{c.umin - 0.5, c.vmin - 0.5, double(c.umax - c.umin + 1), double(c.vmax - c.vmin + 1)};
      x.visible = false;
      if (tv.apex.z() > kNearMm) {
        const double pu = k.fx * tv.apex.x() / tv.apex.z() + k.cx,
                     pv = k.fy * tv.apex.y() / tv.apex.z() + k.cy;
        x.tip_px = std::array<double, 2>{pu, pv};
        const long iu = std::lround(pu), iv = std::lround(pv);
        if (iu >= 0 && iu < W && iv >= 0 && iv < H) {
          const Hit& h = hits[static_cast<std::size_t>(iv) * W + iu];
          const bool tip_pixel_seen =
              h.prim >= 0 && prims[h.prim].object == Object::teat && prims[h.prim].teat == t;
          x.visible = tip_pixel_seen && c.tip_visible >= 2 && 2 * c.tip_visible >= c.tip_all;
        }
      }
    }
  }

  const double max_range2 = sensor.max_range_mm * sensor.max_range_mm;
  frame.depth_mm.assign(N, kNaN);
  frame.amplitude.assign(N, 0.0f);
  if (noise_free) {
    for (std::size_t i = 0; i < N; ++i) {
      const Hit& h = hits[i];
      if (h.prim < 0) continue;
      const int u = static_cast<int>(i % W), v = static_cast<int>(i / W);
      double range2;
      const double a = caster.amplitude(h, caster.ray(u, v), sensor.a0, nullptr, &range2);
      if (range2 > max_range2) continue;
      frame.depth_mm[i] = static_cast<float>(h.t);
      frame.amplitude[i] = static_cast<float>(a);
    }
    return;
  }

  // Pass 2 and 3: flying pixels at depth edges, then holes and noise.
  const double k_phase = 4.0 * std::numbers::pi * sensor.modulation_hz / kLightMmPerS;  // rad per mm of range
  const auto is_edge = [&](int u, int v) {
    const Hit& c = hits[static_cast<std::size_t>(v) * W + u];
    constexpr int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
    for (int n = 0; n < 4; ++n) {
      const int x = u + du[n], y = v + dv[n];
      if (x < 0 || x >= W || y < 0 || y >= H) continue;
      const Hit& o = hits[static_cast<std::size_t>(y) * W + x];
      if ((o.prim < 0) != (c.prim < 0)) return true;
      if (c.prim >= 0 && std::abs(o.t - c.t) > sensor.edge_mm) return true;
    }
    return false;
  };
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const Vec3 d = caster.ray(u, v);
      double z_true = 0, a = 0, cosi = 1;  // the (mixed) depth before noise
      bool hit = false;
      if (is_edge(u, v)) {
        // 2x2 sub-rays (the centres of the pixel's quarters; 3x3 doubled the synthesis time for no visible
        // gain); their returns add as phasors of phase 2 * range * 2 pi f / c. A sub-ray is tested
        // against the surfaces that the centre rays of this pixel and its 8 neighbours see: anything
        // else would be a sliver thinner than a pixel, which a mixed pixel cannot resolve anyway.
        int candidates[9], n = 0;
        for (int y = std::max(0, v - 1); y <= std::min(H - 1, v + 1); ++y)
          for (int x = std::max(0, u - 1); x <= std::min(W - 1, u + 1); ++x) {
            const int prim = hits[static_cast<std::size_t>(y) * W + x].prim;
            if (prim >= 0 && std::find(candidates, candidates + n, prim) == candidates + n)
              candidates[n++] = prim;
          }
        double re = 0, im = 0;
        for (int sy = -1; sy <= 1; sy += 2)
          for (int sx = -1; sx <= 1; sx += 2) {
            const Vec3 ds = caster.ray(u + sx / 4.0, v + sy / 4.0);
            const Hit h = caster.cast(ds, candidates, n);
            if (h.prim < 0) continue;
            double rs2;
            const double as = caster.amplitude(h, ds, sensor.a0, nullptr, &rs2);
            if (rs2 > max_range2) continue;
            const double rs = std::sqrt(rs2);
            re += as * std::cos(k_phase * rs);
            im += as * std::sin(k_phase * rs);
          }
        re /= 4, im /= 4;
        a = std::sqrt(re * re + im * im);
        if (a > 0) {
          double phase = std::atan2(im, re);
          if (phase < 0) phase += 2 * std::numbers::pi;
          z_true = phase / k_phase * std::sqrt(1.0 / d.squaredNorm());  // range -> z
          hit = true;
        }
      } else if (hits[i].prim >= 0) {
        double range2;
        a = caster.amplitude(hits[i], d, sensor.a0, &cosi, &range2);
        hit = range2 <= max_range2;
        z_true = hits[i].t;
      }
      // Amplitude noise, then the reasons for no return, then depth noise.
      const double a_meas = std::max(0.0, a + (1.0 + 0.01 * a) * rng.normal());
      const double drop = rng.uniform();
      frame.amplitude[i] = static_cast<float>(std::min(a_meas, sensor.saturation));
      if (!hit || cosi < sensor.grazing_cos || a_meas < sensor.min_amplitude || a_meas >= sensor.saturation ||
          drop < sensor.dropout)
        continue;
      const double sigma = sensor.sigma_floor_mm + sensor.sigma_gain_mm * std::sqrt(1000.0 / a_meas);
      const double z = z_true + sigma * rng.normal();
      if (z > kNearMm) frame.depth_mm[i] = static_cast<float>(z);
    }
  }
}

}  // namespace trailscope::tof::synth
