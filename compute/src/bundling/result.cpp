// The shared frame of bundle() and bundle_ref(): checks, loop, and the post-processing of result.hpp.
#include "bundling/result.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bundling/endpoints.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::bundling::detail {
namespace {

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

Error unprocessable(const std::string& detail) {
  return Error(Error::Kind::unprocessable, "input", detail);
}

// Cumulative arc length of points b..end−1 of (x, y), starting at 0.
template <class T>
void cumulative(const std::vector<T>& x, const std::vector<T>& y, std::size_t b, std::size_t end,
                std::vector<double>& cum) {
  cum.assign(end - b, 0.0);
  for (std::size_t j = b + 1; j < end; ++j) {
    const double dx = static_cast<double>(x[j]) - static_cast<double>(x[j - 1]);
    const double dy = static_cast<double>(y[j]) - static_cast<double>(y[j - 1]);
    cum[j - b] = cum[j - b - 1] + std::sqrt(dx * dx + dy * dy);
  }
}

// Fills result.original/t/displacement/length/angle and applies direction separation to result.lines.
void post_process(const Polylines& in, const BundleParams& params, Bundled& r) {
  const std::size_t n = r.lines.points();
  r.original.offsets = r.lines.offsets;
  r.original.x.resize(n), r.original.y.resize(n);
  r.t.resize(n), r.displacement.resize(n);
  r.length.resize(in.size()), r.angle.resize(in.size());
  // Independent per polyline: parallel over fixed chunks (the result does not depend on the threads).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in.size(), 1024), [&](const auto& range) {
    std::vector<double> cb, co, sx, sy;
    for (std::size_t e = range.begin(); e < range.end(); ++e) {
      const std::size_t ib = in.begin(e), ie = in.end(e), b = r.lines.begin(e), end = r.lines.end(e);
      cumulative(in.x, in.y, ib, ie, co);
      cumulative(r.lines.x, r.lines.y, b, end, cb);
      const double lo = co.back(), lb = cb.back();
      r.length[e] = static_cast<float>(lo);
      r.angle[e] = static_cast<float>(std::atan2(in.y[ie - 1] - in.y[ib], in.x[ie - 1] - in.x[ib]));
      // Original point at the same arc-length fraction: the fractions grow along the polyline, so one
      // forward walk over the original's segments finds them all.
      std::size_t k = 0;
      for (std::size_t j = 0; j < end - b; ++j) {
        const double t = lb > 0 ? cb[j] / lb : (end - b > 1 ? static_cast<double>(j) / (end - b - 1) : 0.0);
        r.t[b + j] = static_cast<float>(t);
        const double s = t * lo;
        while (k + 2 < co.size() && co[k + 1] < s) ++k;
        double px = in.x[ib + k], py = in.y[ib + k];
        if (co.size() > 1) {
          const double seg = co[k + 1] - co[k];
          const double u = seg > 0 ? std::clamp((s - co[k]) / seg, 0.0, 1.0) : 0.0;
          px += u * (in.x[ib + k + 1] - in.x[ib + k]);
          py += u * (in.y[ib + k + 1] - in.y[ib + k]);
        }
        if (j == 0) px = in.x[ib], py = in.y[ib];
        if (j + 1 == end - b) px = in.x[ie - 1], py = in.y[ie - 1];
        r.original.x[b + j] = px, r.original.y[b + j] = py;
      }
      // Direction separation: interior points move sideways by tangent × ẑ = (t_y, −t_x) (pixels, y down:
      // to the left of the direction of travel on screen, to the right in a y-up source frame), tapering
      // to 0 at the ends, so the two directions of a bundle become two lanes.
      if (params.dir_separation > 0 && end - b > 2) {
        sx.assign(r.lines.x.begin() + b, r.lines.x.begin() + end);
        sy.assign(r.lines.y.begin() + b, r.lines.y.begin() + end);
        for (std::size_t j = 1; j + 1 < end - b; ++j) {
          const double tx = sx[j + 1] - sx[j - 1], ty = sy[j + 1] - sy[j - 1];
          const double tl = std::hypot(tx, ty);
          if (!(tl > 0)) continue;
          const double w = std::pow(1 - 2 * std::fabs(r.t[b + j] - 0.5), 0.4);
          r.lines.x[b + j] += params.dir_separation * w * (ty / tl);
          r.lines.y[b + j] += params.dir_separation * w * (-tx / tl);
        }
      }
      const double cap = params.max_displacement * lo;
      for (std::size_t j = b; j < end; ++j) {
        const double dx = r.lines.x[j] - r.original.x[j], dy = r.lines.y[j] - r.original.y[j];
        const double d = std::sqrt(dx * dx + dy * dy);
        r.displacement[j] = static_cast<float>(cap > 0 ? std::min(1.0, d / cap) : (d > 0 ? 1.0 : 0.0));
      }
    }
  });
}

}  // namespace

double polyline_length(const Polylines& p, std::size_t e) {
  double len = 0;
  for (std::size_t k = p.begin(e); k + 1 < p.end(e); ++k)
    len += std::hypot(p.x[k + 1] - p.x[k], p.y[k + 1] - p.y[k]);
  return len;
}

void check_input(const Polylines& in, const Frame& frame, const BundleParams& params) {
  params.validate();
  if (frame.size != params.size)
    throw invalid_argument("size", "the frame is for " + std::to_string(frame.size) + " px but size is " +
                                       std::to_string(params.size));
  if (in.offsets.empty() || in.offsets.front() != 0 || in.offsets.back() != in.x.size() ||
      in.x.size() != in.y.size() || !std::is_sorted(in.offsets.begin(), in.offsets.end()))
    throw invalid_argument("input", "malformed polylines: offsets must rise from 0 to the number of points");
  if (in.size() == 0) throw unprocessable("nothing to bundle: the input has no polylines");
  if (in.size() > limits::kMaxBundleEdges)
    throw Error(Error::Kind::payload_too_large, "input",
                std::to_string(in.size()) + " polylines exceed the limit of " +
                    std::to_string(limits::kMaxBundleEdges) + " (limits::kMaxBundleEdges)");
  if (in.points() > limits::kMaxBundleInputPoints)
    throw Error(Error::Kind::payload_too_large, "input",
                std::to_string(in.points()) + " points exceed the limit of " +
                    std::to_string(limits::kMaxBundleInputPoints) + " (limits::kMaxBundleInputPoints)");
  for (std::size_t e = 0; e < in.size(); ++e)
    if (in.end(e) - in.begin(e) < 2)
      throw unprocessable("polyline " + std::to_string(e) + " has " +
                          std::to_string(in.end(e) - in.begin(e)) + " point(s); at least 2 are needed");
  for (std::size_t i = 0; i < in.points(); ++i)
    if (!std::isfinite(in.x[i]) || !std::isfinite(in.y[i]))
      throw unprocessable("point " + std::to_string(i) + " is not finite");
}

Bundled run_bundle(const Polylines& input_px, const Frame& frame, const BundleParams& params,
                   const ProgressFn& progress, const CancelToken* cancel, const LoopFn& loop) {
  const double start = now_ms();
  check_input(input_px, frame, params);
  Bundled r;
  r.frame = frame;
  r.params = params;
  const std::vector<std::uint32_t> weights = edge_weights(input_px, params.density);
  Points pts = to_points(input_px);
  if (params.ms_iterations > 0) {
    const double t0 = now_ms();
    pts = cluster_endpoints(pts, params, weights, progress, cancel);
    r.times.endpoints_ms = now_ms() - t0;
  }
  Points out;
  LoopTimes lt;
  loop(pts, weights, out, lt);
  if (params.ms_iterations > 0) smooth_ends(out, params);
  r.times.resample_ms = lt.resample_ms, r.times.splat_ms = lt.splat_ms, r.times.convolve_ms = lt.convolve_ms;
  r.times.advect_ms = lt.advect_ms, r.times.smooth_ms = lt.smooth_ms;
  if (cancel) cancel->throw_if_cancelled();
  const double t0 = now_ms();
  if (progress) progress(1.0, "post");
  r.lines = to_polylines(out);
  post_process(input_px, params, r);
  r.quality = measure_quality(input_px, r);
  r.times.post_ms = now_ms() - t0;
  r.times.total_ms = now_ms() - start;
  return r;
}

}  // namespace trailscope::bundling::detail
