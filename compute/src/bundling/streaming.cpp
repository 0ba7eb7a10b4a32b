// Streaming CUBu bundling (streaming.hpp): the window's trails as one flat point set in the layout of the
// CUBu steps (steps.hpp), rebuilt at each update from the persistent trails' points and the entering
// trails' resampled ones, then a few fixed-kernel iterations on OpenCL (bundle_fixed_ocl) or the C++
// reference (run_fixed_ref) under the dispatch convention of ocl/dispatch.hpp (op name "bundle_stream").
#include "trailscope/bundling/streaming.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <unordered_map>

#include "bundling/bundle_ocl.hpp"
#include "bundling/steps.hpp"
#include "core/rng.hpp"
#include "ocl/dispatch.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::bundling {
namespace {

// Points from which `auto` runs the iterations on a CPU OpenCL device (the threshold bundle() uses;
// measurements of the streaming loop in tests/bench/stream_bundle_bench.cpp and BENCHMARKS.md).
constexpr std::size_t kAutoCpuMinPoints = 10000;

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void check_range(double v, double lo, double hi, const char* name, const std::string& what) {
  if (!(v >= lo && v <= hi))
    throw invalid_argument(name, std::string(name) + " must be " + what + ", got " + format_double(v));
}

}  // namespace

void StreamParams::validate() const {
  check_range(size, 64, 4096, "size", "in 64..4096 px");
  check_range(h, 2, 128, "h", "in 2..128 px");
  if (!(eps > 0 && eps <= 2))
    throw invalid_argument("eps", "eps must be in (0, 2], got " + format_double(eps));
  check_range(iterations, 1, limits::kMaxStreamIterations, "iterations",
              "in 1.." + std::to_string(limits::kMaxStreamIterations) + " (limits::kMaxStreamIterations)");
  check_range(lambda, 0, 1, "lambda", "in 0..1");
  check_range(smooth_kernel, 0, 0.5, "smooth_kernel", "in 0..0.5");
  if (!(smooth_iterations >= 1 && smooth_iterations <= 15 && smooth_iterations % 2 == 1))
    throw invalid_argument("smooth_iterations", "smooth_iterations must be odd, in 1..15, got " +
                                                    std::to_string(smooth_iterations));
  check_range(spl, 1, 256, "spl", "in 1..256 px");
  check_range(jitter, 0, 1, "jitter", "in 0..1");
  check_range(anchor, 0, 1, "anchor", "in 0..1");
  check_range(window_s, 60, limits::kMaxStreamWindowSeconds, "window_s",
              "in 60.." + std::to_string(static_cast<long long>(limits::kMaxStreamWindowSeconds)) +
                  " seconds (limits::kMaxStreamWindowSeconds)");
  check_range(fade_s, 0, window_s, "fade_s", "in 0..window_s seconds");
}

double stream_opacity(double t, double t0, double t1, double window_s, double fade_s) {
  const double in = t - t0, out = t1 + window_s - t;
  if (in < 0 || out < 0) return 0;
  if (!(fade_s > 0)) return 1;
  return std::clamp(std::min(in, out) / fade_s, 0.0, 1.0);
}

StreamingBundler::StreamingBundler(const Frame& frame, const StreamParams& params, Backend backend)
    : frame_(frame), params_(params), backend_(backend) {
  params_.validate();
  if (frame.size != params.size)
    throw invalid_argument("size", "the frame's size (" + std::to_string(frame.size) +
                                       ") differs from the parameters' size (" + std::to_string(params.size) +
                                       ")");
}

void StreamingBundler::set_window(double window_s, double fade_s) {
  StreamParams p = params_;
  p.window_s = window_s;
  p.fade_s = std::min(fade_s, window_s);
  p.validate();
  params_ = p;
}

void StreamingBundler::set_frame(const Frame& frame) {
  if (frame.size != params_.size)
    throw invalid_argument("size", "the frame's size (" + std::to_string(frame.size) +
                                       ") differs from the stream's size (" + std::to_string(params_.size) +
                                       ")");
  for (std::size_t i = 0; i < x_.size(); ++i) {
    x_[i] = static_cast<float>(frame.to_px_x(frame_.from_px_x(x_[i])));
    y_[i] = static_cast<float>(frame.to_px_y(frame_.from_px_y(y_[i])));
    ox_[i] = static_cast<float>(frame.to_px_x(frame_.from_px_x(ox_[i])));
    oy_[i] = static_cast<float>(frame.to_px_y(frame_.from_px_y(oy_[i])));
  }
  frame_ = frame;
  frame_changed_ = true;
}

void StreamingBundler::reset() {
  ids_.clear(), t0_.clear(), t1_.clear(), base_weight_.clear();
  x_.clear(), y_.clear(), z_.clear(), ox_.clear(), oy_.clear();
  offsets_.assign(1, 0);
}

StreamUpdate StreamingBundler::update(double t, const StreamSource& source) {
  if (!std::isfinite(t)) throw invalid_argument("t", "t must be a finite number of Unix seconds");
  const double start = now_ms();
  const double W = params_.window_s, F = params_.fade_s;
  StreamUpdate u;
  u.t = t;

  // 1. The present trails, counted before any geometry is read.
  std::unordered_map<std::uint64_t, std::size_t> present;  // id → index in source.trails
  for (std::size_t i = 0; i < source.trails.size(); ++i) {
    const StreamTrail& s = source.trails[i];
    if (s.t0 <= t && t <= s.t1 + W) {
      present.emplace(s.id, i);
      if (present.size() > limits::kMaxStreamTrails)
        throw Error(
            Error::Kind::payload_too_large, "window",
            "more than " + std::to_string(limits::kMaxStreamTrails) +
                " trails are in the window (limits::kMaxStreamTrails); shorten it or narrow the filters");
    }
  }

  // 2. The new state: persistent trails first (in their order), then the entering ones (in source order,
  // so that the result does not depend on hashing). Built aside, so that a throw leaves the state as it
  // was.
  std::vector<std::uint64_t> ids;
  std::vector<double> t0s, t1s;
  std::vector<float> base, xs, ys, zs, oxs, oys;
  std::vector<std::uint32_t> offsets{0};
  ids.reserve(present.size());
  std::vector<char> held(source.trails.size(), 0);
  std::size_t persistent_points = 0;
  for (std::size_t e = 0; e < ids_.size(); ++e) {
    const auto it = present.find(ids_[e]);
    if (it == present.end()) {
      ++u.removed;
      continue;
    }
    held[it->second] = 1;
    const StreamTrail& s = source.trails[it->second];
    ids.push_back(s.id), t0s.push_back(s.t0), t1s.push_back(s.t1), base.push_back(base_weight_[e]);
    xs.insert(xs.end(), x_.begin() + offsets_[e], x_.begin() + offsets_[e + 1]);
    ys.insert(ys.end(), y_.begin() + offsets_[e], y_.begin() + offsets_[e + 1]);
    zs.insert(zs.end(), z_.begin() + offsets_[e], z_.begin() + offsets_[e + 1]);
    oxs.insert(oxs.end(), ox_.begin() + offsets_[e], ox_.begin() + offsets_[e + 1]);
    oys.insert(oys.end(), oy_.begin() + offsets_[e], oy_.begin() + offsets_[e + 1]);
    offsets.push_back(static_cast<std::uint32_t>(xs.size()));
  }
  u.persistent = ids.size();
  persistent_points = xs.size();

  const std::vector<float> profile = detail::profile_table(params_.profile);
  std::vector<double> gx, gy;
  for (std::size_t i = 0; i < source.trails.size(); ++i) {
    const StreamTrail& s = source.trails[i];
    if (held[i] || !(s.t0 <= t && t <= s.t1 + W)) continue;
    gx.clear(), gy.clear();
    source.geometry(i, gx, gy);
    if (gx.size() < 2 || gx.size() != gy.size())
      throw Error(Error::Kind::unprocessable, "geometry",
                  "trail " + std::to_string(s.id) + " has fewer than 2 points");
    detail::Points one;
    one.x.resize(gx.size()), one.y.resize(gx.size()), one.z.assign(gx.size(), 1.0f);
    one.edge.assign(gx.size(), 0);
    one.offsets = {0, static_cast<std::uint32_t>(gx.size())};
    double length = 0;
    for (std::size_t k = 0; k < gx.size(); ++k) {
      if (!std::isfinite(gx[k]) || !std::isfinite(gy[k]))
        throw Error(Error::Kind::unprocessable, "geometry",
                    "trail " + std::to_string(s.id) + " has a non-finite point");
      one.x[k] = static_cast<float>(frame_.to_px_x(gx[k]));
      one.y[k] = static_cast<float>(frame_.to_px_y(gy[k]));
      if (k > 0)
        length += std::hypot(static_cast<double>(one.x[k]) - one.x[k - 1],
                             static_cast<double>(one.y[k]) - one.y[k - 1]);
    }
    // Resampled once, as bundle()'s first iteration does, with the jitter seeded by the trail's id so
    // that its samples do not depend on the other trails.
    detail::ResampleArgs a;
    a.spl = params_.spl, a.jitter = params_.jitter, a.iteration = 0,
    a.block_endpoints = params_.block_endpoints;
    a.seed = rng::splitmix64_hash(params_.seed ^ rng::splitmix64_hash(s.id));
    a.profile = profile.data();
    const std::uint64_t count = 2 + detail::interior_samples(length, params_.spl);
    if (xs.size() + count > limits::kMaxStreamPoints)
      throw Error(Error::Kind::payload_too_large, "window",
                  "the window's trails make more than " + std::to_string(limits::kMaxStreamPoints) +
                      " points (limits::kMaxStreamPoints); shorten the window, narrow the filters or use a "
                      "larger spl");
    const detail::Points r = detail::resample(one, a);
    ids.push_back(s.id), t0s.push_back(s.t0), t1s.push_back(s.t1);
    base.push_back(params_.density == DensityMode::count
                       ? 1.0f
                       : static_cast<float>(std::min(1.0, length / params_.size)));
    xs.insert(xs.end(), r.x.begin(), r.x.end());
    ys.insert(ys.end(), r.y.begin(), r.y.end());
    zs.insert(zs.end(), r.z.begin(), r.z.end());
    oxs.insert(oxs.end(), r.x.begin(), r.x.end());
    oys.insert(oys.end(), r.y.begin(), r.y.end());
    offsets.push_back(static_cast<std::uint32_t>(xs.size()));
    ++u.added;
  }
  ids_.swap(ids), t0_.swap(t0s), t1_.swap(t1s), base_weight_.swap(base);
  x_.swap(xs), y_.swap(ys), z_.swap(zs), offsets_.swap(offsets);
  ox_.swap(oxs), oy_.swap(oys);
  const double selected = now_ms();
  u.times.select_ms = selected - start;

  // 3. Weights: density weight × fade, in the fixed point of the splat (params.hpp, kSplatScale).
  const std::size_t n = ids_.size();
  u.opacity.resize(n);
  std::vector<std::uint32_t> weights(n);
  for (std::size_t e = 0; e < n; ++e) {
    const double o = stream_opacity(t, t0_[e], t1_[e], W, F);
    u.opacity[e] = static_cast<float>(o);
    weights[e] = static_cast<std::uint32_t>(std::nearbyint(base_weight_[e] * o * kSplatScale));
  }

  // 4. The iterations.
  detail::Points pts;
  pts.x.swap(x_), pts.y.swap(y_), pts.z.swap(z_);
  pts.offsets = offsets_;
  pts.edge.resize(pts.x.size());
  for (std::uint32_t e = 0; e < n; ++e)
    std::fill(pts.edge.begin() + offsets_[e], pts.edge.begin() + offsets_[e + 1], e);
  const std::vector<float> before_x(pts.x.begin(), pts.x.begin() + persistent_points);
  const std::vector<float> before_y(pts.y.begin(), pts.y.begin() + persistent_points);
  detail::FixedArgs fa;
  fa.size = params_.size, fa.radius = detail::kernel_radius(params_.h), fa.step = params_.eps * params_.h;
  BundleParams bp;
  bp.size = params_.size, bp.smooth_kernel = params_.smooth_kernel, bp.spl = params_.spl;
  fa.window = detail::smooth_window(bp);
  fa.lambda = params_.lambda, fa.passes = params_.smooth_iterations, fa.iterations = params_.iterations;
  detail::LoopTimes lt;
  // On a throw (strict mode, cancellation of the device) the held points go back where they were.
  struct Restore {
    detail::Points& pts;
    std::vector<float>&x, &y, &z;
    bool armed = true;
    ~Restore() {
      if (armed) x.swap(pts.x), y.swap(pts.y), z.swap(pts.z);
    }
  } restore{pts, x_, y_, z_};
  if (n > 0) {
    const bool worth =
        backend_ == Backend::auto_ && (ocl::device_is_gpu() || pts.size() >= kAutoCpuMinPoints);
    const ocl::Path p = ocl::dispatch(
        "bundle_stream", backend_, worth,
        [&]() -> std::string {
          detail::Points dev = pts;
          detail::LoopTimes t2;
          std::string why = ocl::bundle_fixed_ocl(dev, weights, fa, t2);
          if (why.empty()) pts = std::move(dev), lt = t2;
          return why;
        },
        [&] { detail::run_fixed_ref(pts, weights, fa, lt); });
    u.path = ocl::to_string(p);
  } else {
    u.path = "cpu";
  }
  restore.armed = false;
  x_.swap(pts.x), y_.swap(pts.y), z_.swap(pts.z);
  // The anchor: every point back by `anchor` of the way to its entry position (host side, after either
  // backend's iterations, so both give the same bits).
  if (params_.anchor > 0)
    for (std::size_t i = 0; i < x_.size(); ++i) {
      x_[i] = static_cast<float>(static_cast<double>(x_[i]) +
                                 params_.anchor * (static_cast<double>(ox_[i]) - x_[i]));
      y_[i] = static_cast<float>(static_cast<double>(y_[i]) +
                                 params_.anchor * (static_cast<double>(oy_[i]) - y_[i]));
    }
  u.times.splat_ms = lt.splat_ms, u.times.convolve_ms = lt.convolve_ms, u.times.advect_ms = lt.advect_ms;
  u.times.smooth_ms = lt.smooth_ms;
  const double iterated = now_ms();

  // 5. Drift of the persistent trails, and the output.
  if (!frame_changed_ && persistent_points > 0) {
    double sum = 0, mx = 0;
    for (std::size_t i = 0; i < persistent_points; ++i) {
      const double d =
          std::hypot(static_cast<double>(x_[i]) - before_x[i], static_cast<double>(y_[i]) - before_y[i]);
      sum += d, mx = std::max(mx, d);
    }
    u.drift_px = sum / static_cast<double>(persistent_points), u.max_drift_px = mx;
  }
  frame_changed_ = false;
  u.sequence = ++sequence_;
  u.id = ids_;
  u.lines.offsets = offsets_;
  u.lines.x.assign(x_.begin(), x_.end());
  u.lines.y.assign(y_.begin(), y_.end());
  const double end = now_ms();
  u.times.output_ms = end - iterated;
  u.times.total_ms = end - start;
  return u;
}

StreamSource flight_stream_source(const TrailSet& trails, const Query& filters) {
  Query q = filters;
  q.t0.reset(), q.t1.reset();  // the stream's window decides time
  StreamSource src;
  for (std::size_t fi = 0; fi < trails.num_flights(); ++fi) {
    const Flight& f = trails.flights()[fi];
    if (f.size() < 2 || !q.may_match(f)) continue;
    src.trails.push_back({static_cast<std::uint64_t>(fi), f.t_min, f.t_max});
  }
  // The geometry reads the flight named by the trail's id (its index in the TrailSet).
  std::vector<StreamTrail> ids = src.trails;
  src.geometry = [&trails, ids = std::move(ids)](std::size_t index, std::vector<double>& x,
                                                 std::vector<double>& y) {
    constexpr double kWorld = static_cast<double>(geo::kWorldUnits);
    const Flight& f = trails.flights()[ids[index].id];
    const auto& mx = trails.merc_x();
    const auto& my = trails.merc_y();
    x.reserve(f.size()), y.reserve(f.size());
    for (std::uint32_t i = f.begin; i < f.end; ++i) {
      double px = mx[i];
      // Unwrapped along the path, as flight_trails() does: across 180° the trail continues past the
      // world's edge instead of jumping back across the map.
      if (!x.empty()) px += std::round((x.back() - px) / kWorld) * kWorld;
      x.push_back(px), y.push_back(static_cast<double>(my[i]));
    }
  };
  return src;
}

}  // namespace trailscope::bundling
