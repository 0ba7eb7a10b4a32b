#include "render.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

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

// The centre ray of every pixel of `scene`; with `counts`, the ground truth's per-teat pixel counts on the
// way. Per row, each primitive's exact span of columns (row_interval), so that a pixel tests only the two
// or three surfaces its ray can meet.
std::vector<Hit> cast_centres(const SceneFrame& scene, const Intrinsics& k, const Caster& caster,
                              std::array<TeatCount, kTeatCount>* counts) {
  const int W = k.width, H = k.height;
  std::vector<Hit> hits(static_cast<std::size_t>(W) * H);
  const auto& prims = scene.prims;
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
        if (counts && p.object == Object::teat) {
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
          TeatCount& c = (*counts)[t];
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
  return hits;
}

void fill_truth(const SceneFrame& scene, const Intrinsics& k, const std::vector<Hit>& hits,
                const std::array<TeatCount, kTeatCount>& counts, FrameTruth& truth) {
  const int W = k.width, H = k.height;
  const auto& prims = scene.prims;
  for (int t = 0; t < kTeatCount; ++t) {
    const TeatView& tv = scene.teats[t];
    const TeatCount& c = counts[t];
    TeatTruth& x = truth.teats[t];
    x.tip_mm = {tv.apex.x(), tv.apex.y(), tv.apex.z()};
    x.cup_attached = tv.cup_on;
    x.visible_fraction = c.all > 0 ? static_cast<double>(c.visible) / c.all : 0.0;
    if (c.all > 0)
      x.box_px = BoxPx{c.umin - 0.5, c.vmin - 0.5, double(c.umax - c.umin + 1), double(c.vmax - c.vmin + 1)};
    x.visible = false;
    if (tv.apex.z() > kNearMm) {
      const double pu = k.fx * tv.apex.x() / tv.apex.z() + k.cx, pv = k.fy * tv.apex.y() / tv.apex.z() + k.cy;
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

using Phasor = std::complex<double>;

// e^{i k_phase x / 2} for path lengths x (mm) by table: the multipath sum takes one per pair of surface
// points, and a sine and cosine each would be most of its time. Steps of 0.25 mm of path (0.13 mm of
// range, far below the noise) up to the longest path that can return (3 * max range).
class PathPhase {
 public:
  PathPhase(double k_phase, double max_path_mm) : table_(static_cast<std::size_t>(max_path_mm / kStep) + 2) {
    for (std::size_t i = 0; i < table_.size(); ++i) table_[i] = std::polar(1.0, 0.5 * k_phase * kStep * i);
  }
  Phasor operator()(double path_mm) const {
    const auto i = static_cast<std::size_t>(path_mm / kStep + 0.5);
    return table_[std::min(i, table_.size() - 1)];
  }

 private:
  static constexpr double kStep = 0.25;
  std::vector<Phasor> table_;
};

// Single-bounce multipath (synth.hpp): the indirect phasor each pixel receives, in amplitude units. The
// secondary sources are the visible surface points on a coarse grid (about kPatches of them, each standing
// for the stride x stride pixels around it): a Lambertian patch lit by the camera's source re-emits
// reflectivity * irradiance / pi per unit area towards the pixel's surface point, which reflects it to the
// camera like its direct light. A patch of pixel footprint area S at range r, lit at incidence cos, takes
// cos / r^2 * S = stride^2 / (fx fy |d|^3) of the source (d the pixel's ray with z = 1), whatever its
// distance and tilt. The sum is evaluated exactly on a grid of receivers (every `rs` px) and spread to the
// other pixels from the receivers of the same surface around them (a pixel with none gets its own sum):
// indirect light varies slowly along a surface. Occlusion between patch and receiver is not traced.
std::vector<Phasor> multipath(const SceneFrame& scene, const std::vector<Hit>& hits, const Intrinsics& k,
                              const Caster& caster, const ToFSensor& sensor, const PathPhase& phase) {
  constexpr double kPatches = 100, kReceiversAcross = 44;
  const int W = k.width, H = k.height;
  const std::size_t N = static_cast<std::size_t>(W) * H;
  std::vector<Phasor> out(N);
  if (sensor.multipath <= 0) return out;
  const auto& prims = scene.prims;
  const auto surface = [&](int u, int v, Vec3* x, Vec3* n, double* range) {
    const Hit& h = hits[static_cast<std::size_t>(v) * W + u];
    if (h.prim < 0) return false;
    const Vec3 d = caster.ray(u, v);
    *x = h.t * d;
    *range = h.t * d.norm();
    if (*range > sensor.max_range_mm) return false;
    *n = normal_at(prims[h.prim], *x).normalized();
    if (n->dot(*x) > 0) *n = -*n;  // the side the camera sees
    return true;
  };
  struct Patch {
    Vec3 x, n;
    double weight, range, area;
  };
  std::vector<Patch> patches;
  const int stride = std::max(2, static_cast<int>(std::lround(std::sqrt(N / kPatches))));
  for (int v = stride / 2; v < H; v += stride)
    for (int u = stride / 2; u < W; u += stride) {
      Patch p;
      if (!surface(u, v, &p.x, &p.n, &p.range)) continue;
      const double dn = caster.ray(u, v).norm();
      const double s2 = static_cast<double>(stride) * stride;
      p.weight = prims[hits[static_cast<std::size_t>(v) * W + u].prim].reflectivity * s2 /
                 (k.fx * k.fy * dn * dn * dn) / std::numbers::pi;
      p.area = s2 * p.x.z() * p.x.z() / (k.fx * k.fy);  // the patch's footprint, head-on, mm^2
      patches.push_back(p);
    }
  if (patches.empty()) return out;
  // Irradiance phasor at surface point x (normal n) from every patch, per unit of a0 * 1e6 (the units
  // of the direct amplitude's cos / r^2), with the phase of the path source -> patch -> x.
  const auto received = [&](const Vec3& x, const Vec3& n) {
    Phasor e = 0;
    for (const Patch& p : patches) {
      const Vec3 to = x - p.x;
      const double d2 = to.squaredNorm();
      const double out_cos = p.n.dot(to), in_cos = -n.dot(to);  // both times |to|
      if (out_cos <= 0 || in_cos <= 0) continue;
      const double d = std::sqrt(d2);
      // Nearer than its own size a patch is no point source: its pull is capped at that distance.
      e += p.weight * out_cos * in_cos / (d2 * std::max(d2, p.area)) * phase(p.range + d);
    }
    return e;
  };
  const int rs = std::max(1, static_cast<int>(std::lround(W / kReceiversAcross)));
  const int gw = (W - 1) / rs + 1, gh = (H - 1) / rs + 1;
  std::vector<Phasor> grid(static_cast<std::size_t>(gw) * gh);
  for (int gv = 0; gv < gh; ++gv)
    for (int gu = 0; gu < gw; ++gu) {
      Vec3 x, n;
      double r;
      if (surface(gu * rs, gv * rs, &x, &n, &r))
        grid[static_cast<std::size_t>(gv) * gw + gu] = received(x, n);
    }
  const double scale = sensor.multipath * sensor.a0 * 1e6;
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const Hit& h = hits[i];
      if (h.prim < 0) continue;
      // The surface point and its normal are needed only where no receiver stands for the pixel.
      const double r = h.t * caster.ray(u, v).norm();
      if (r > sensor.max_range_mm) continue;
      Phasor e = 0;
      if (u % rs == 0 && v % rs == 0) {
        e = grid[static_cast<std::size_t>(v / rs) * gw + u / rs];
      } else {
        // Bilinear over the surrounding receivers on the same surface at about the same depth.
        const int gu = u / rs, gv = v / rs;
        const double fu = static_cast<double>(u % rs) / rs, fv = static_cast<double>(v % rs) / rs;
        double wsum = 0;
        for (int j = 0; j < 4; ++j) {
          const int cu = gu + (j & 1), cv = gv + (j >> 1);
          if (cu >= gw || cv >= gh || cu * rs >= W || cv * rs >= H) continue;
          const Hit& o = hits[static_cast<std::size_t>(cv * rs) * W + cu * rs];
          if (o.prim != h.prim || std::abs(o.t - h.t) > sensor.edge_mm) continue;
          const double w = ((j & 1) ? fu : 1 - fu) * ((j >> 1) ? fv : 1 - fv) + 1e-9;
          e += w * grid[static_cast<std::size_t>(cv) * gw + cu];
          wsum += w;
        }
        if (wsum > 0) {
          e /= wsum;
        } else {
          Vec3 x, n;
          double range;
          surface(u, v, &x, &n, &range);
          e = received(x, n);
        }
      }
      out[i] = scale * prims[h.prim].reflectivity * e * phase(r);
    }
  return out;
}
}  // namespace

void render_frame(const SceneFrame& scene, const SceneFrame* first, const SceneFrame* last,
                  const Intrinsics& k, const ToFSensor& sensor, bool noise_free, Rng& rng, DepthFrame& frame,
                  FrameTruth* truth) {
  const int W = k.width, H = k.height;
  const std::size_t N = static_cast<std::size_t>(W) * H;
  const Caster caster(scene, k);
  std::array<TeatCount, kTeatCount> counts{};
  const std::vector<Hit> hits = cast_centres(scene, k, caster, truth ? &counts : nullptr);
  if (truth) fill_truth(scene, k, hits, counts, *truth);

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

  const double k_phase = 4.0 * std::numbers::pi * sensor.modulation_hz / kLightMmPerS;  // rad per mm of range
  const PathPhase phase(k_phase, 3 * sensor.max_range_mm);
  const std::vector<Phasor> indirect = multipath(scene, hits, k, caster, sensor, phase);

  // The scene at the two instants of the exposure: centre rays only (their own casters, same rays).
  std::vector<Hit> hits_first, hits_last;
  std::optional<Caster> caster_first, caster_last;
  if (first && last) {
    caster_first.emplace(*first, k), caster_last.emplace(*last, k);
    hits_first = cast_centres(*first, k, *caster_first, nullptr);
    hits_last = cast_centres(*last, k, *caster_last, nullptr);
  }
  // Direct return of a centre hit: amplitude and range (0, 0 when none within range).
  const auto direct = [&](const Caster& c, const Hit& h, const Vec3& d, double* range, double* cosi) {
    if (h.prim < 0) return 0.0;
    double range2;
    const double a = c.amplitude(h, d, sensor.a0, cosi, &range2);
    if (range2 > max_range2) return 0.0;
    *range = std::sqrt(range2);
    return a;
  };

  // The direct return of pixel (u, v) in a scene (its centre hits `sh`, cast by `c`) as a phasor
  // (amplitude units, phase k_phase * range). A pixel at a depth edge (a 4-neighbour misses or differs
  // by more than edge_mm) is a mixed pixel: 2x2 sub-rays (the centres of its quarters; 3x3 doubled the
  // synthesis time for no visible gain) whose returns add as phasors. A sub-ray is tested against the
  // surfaces that the centre rays of this pixel and its 8 neighbours see: anything else would be a
  // sliver thinner than a pixel, which a mixed pixel cannot resolve anyway. *cosi: the centre hit's
  // incidence (1 at an edge).
  const auto pixel_return = [&](const Caster& c, const std::vector<Hit>& sh, int u, int v, double* cosi) {
    const Hit& centre = sh[static_cast<std::size_t>(v) * W + u];
    bool edge = false;
    constexpr int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
    for (int n = 0; n < 4 && !edge; ++n) {
      const int x = u + du[n], y = v + dv[n];
      if (x < 0 || x >= W || y < 0 || y >= H) continue;
      const Hit& o = sh[static_cast<std::size_t>(y) * W + x];
      edge = (o.prim < 0) != (centre.prim < 0) ||
             (centre.prim >= 0 && std::abs(o.t - centre.t) > sensor.edge_mm);
    }
    *cosi = 1;
    double r = 0;
    if (!edge) {
      const double a = direct(c, centre, c.ray(u, v), &r, cosi);
      return a > 0 ? std::polar(a, k_phase * r) : Phasor(0);
    }
    int candidates[9], n = 0;
    for (int y = std::max(0, v - 1); y <= std::min(H - 1, v + 1); ++y)
      for (int x = std::max(0, u - 1); x <= std::min(W - 1, u + 1); ++x) {
        const int prim = sh[static_cast<std::size_t>(y) * W + x].prim;
        if (prim >= 0 && std::find(candidates, candidates + n, prim) == candidates + n)
          candidates[n++] = prim;
      }
    Phasor sum = 0;
    constexpr int m = 2;
    for (int sy = 0; sy < m; ++sy)
      for (int sx = 0; sx < m; ++sx) {
        const Vec3 ds = c.ray(u + (sx + 0.5) / m - 0.5, v + (sy + 0.5) / m - 0.5);
        double ci;
        const double as = direct(c, c.cast(ds, candidates, n), ds, &r, &ci);
        if (as > 0) sum += std::polar(as / (m * m), k_phase * r);
      }
    return sum;
  };
  const double g = sensor.electrons_per_unit, offset = 1.0 / sensor.demod_contrast;
  const double read2 = sensor.read_noise_e * sensor.read_noise_e;
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const Vec3 d = caster.ray(u, v);
      double cosi;
      const Phasor mid = pixel_return(caster, hits, u, v, &cosi);
      const bool hit = std::abs(mid) > 0;
      // The pixel's two taps integrate in antiphase, so samples 0 and 180 deg are taken at one instant
      // (a quarter of the exposure before the frame's timestamp) and 90 and 270 deg at the next (a
      // quarter after), each of the scene as it is then. The indirect part moves too slowly to matter.
      Phasor at[4] = {mid, mid, mid, mid};
      if (caster_first) {
        double ci;
        at[0] = at[2] = pixel_return(*caster_first, hits_first, u, v, &ci);
        at[1] = at[3] = pixel_return(*caster_last, hits_last, u, v, &ci);
      }
      for (Phasor& p : at) p += indirect[i];
      // Correlation samples in electrons: offset (signal / contrast + ambient) plus the demodulated
      // part cos(phase + k 90 deg) = Re, -Im, -Re, Im; then shot and read noise on each.
      double c[4];
      bool saturated = false;
      for (int s = 0; s < 4; ++s) {
        const double part = s == 0   ? at[s].real()
                            : s == 1 ? -at[s].imag()
                            : s == 2 ? -at[s].real()
                                     : at[s].imag();
        const double mean = g * (std::abs(at[s]) * offset + part) + sensor.ambient_e;
        saturated = saturated || mean >= sensor.full_well_e;
        c[s] = mean + std::sqrt(mean + read2) * rng.normal();
      }
      const double re = (c[0] - c[2]) / (2 * g), im = (c[3] - c[1]) / (2 * g);
      const double a_meas = std::sqrt(re * re + im * im);
      const double drop = rng.uniform();
      frame.amplitude[i] = static_cast<float>(std::min(a_meas, kAmplitudeMax));
      if (!hit || saturated || cosi < sensor.grazing_cos || a_meas < sensor.min_amplitude ||
          drop < sensor.dropout)
        continue;
      double ph = std::atan2(im, re);
      if (ph < 0) ph += 2 * std::numbers::pi;
      const double z = ph / k_phase / d.norm();  // range -> z
      if (z > kNearMm) frame.depth_mm[i] = static_cast<float>(z);
    }
  }
}

}  // namespace trailscope::tof::synth
