// Streaming CUBu bundling benchmark (trailscope/bundling/streaming.hpp): a clock moving over a generated
// day of US traffic, the window's trails (~40k at the measured instant) kept bundled, one update per
// clock step, on each backend asked for.
//
//   stream_bundle_bench [--flights 175000] [--window-s 7200] [--step-s 30] [--settle 30] [--updates 60]
//                       [--backends cpu,opencl] [--match 1] [--demo-source DIR]
//
// The day: generate_demo_traffic (demo_traffic.hpp) with --flights flights sampled every 30–60 s (the
// bundler resamples every trail at 15 px when it enters, so finer sampling changes nothing but memory).
// The stream: flight_stream_source over every flight, the frame the data's extent in Web Mercator on
// 512 px, default StreamParams except the window (--window-s). The clock starts --settle steps before
// 19:00 UTC (the US evening peak) and advances --step-s per update: --settle updates bring the bundles
// in, then --updates updates are timed.
//
// Records (JSON lines):
//   {"bench":"stream_bundle","backend","path","flights","window_s","step_s","iterations","h","eps",
//    "trails_mean","trails_min","trails_max","points_mean","added_mean","removed_mean",
//    "ms_<stats>" (wall per update), "updates_per_s" (1000 / mean ms), per phase "<phase>_ms_mean",
//    "drift_px_mean", "drift_px_p95", "drift_px_max" (per update: mean displacement of the persistent
//    trails' points; p95 / max over the updates), "max_point_drift_px" (largest single point's move)}
//   {"bench":"stream_bundle_match","trails","points","hold_updates","scratch_updates","shape_mean_px",
//    "shape_p95_px","point_mean_px","point_p95_px","bundled_mean_px"}: with --match 1, after the timed
//    updates the clock is held until the mean drift is below 0.05 px per update (at most 400 updates),
//    and the state is compared with a from-scratch bundling of the same window (a fresh bundler at the
//    same instant, updated hold + 100 times), as tests/compute/bundling/stream_bundle_test.cpp measures
//    it: shape = each point's distance to the same trail's from-scratch polyline, point = to the same
//    point; bundled_mean_px is how far bundling moved the points from their unbundled positions.
#include <algorithm>
#include <limits>
#include <cmath>
#include <sstream>

#include "bench_util.hpp"
#include "trailscope/bundling/streaming.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/ocl_info.hpp"

using namespace bench;
namespace ts = trailscope;
namespace bd = trailscope::bundling;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty()) out.push_back(part);
  return out;
}

bd::Frame data_frame(const ts::TrailSet& set, int size) {
  const auto [x0, x1] = std::minmax_element(set.merc_x().begin(), set.merc_x().end());
  const auto [y0, y1] = std::minmax_element(set.merc_y().begin(), set.merc_y().end());
  return bd::Frame::view(*x0, *y0, *x1, *y1, size);
}

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / static_cast<double>(v.size());
}

// Per point of `a`, its distance to the same point of `b` (matched by trail id and index); with `shape`,
// to the closest point of the same trail's polyline in `b` instead.
std::vector<double> point_distances(const bd::StreamUpdate& a, const bd::StreamUpdate& b,
                                    bool shape = false) {
  std::map<std::uint64_t, std::size_t> where;
  for (std::size_t e = 0; e < b.id.size(); ++e) where[b.id[e]] = e;
  std::vector<double> d;
  for (std::size_t e = 0; e < a.id.size(); ++e) {
    const auto it = where.find(a.id[e]);
    if (it == where.end()) continue;
    const std::size_t f = it->second;
    if (a.lines.end(e) - a.lines.begin(e) != b.lines.end(f) - b.lines.begin(f)) continue;
    for (std::size_t k = 0; k < a.lines.end(e) - a.lines.begin(e); ++k) {
      const std::size_t i = a.lines.begin(e) + k, j = b.lines.begin(f) + k;
      if (!shape) {
        d.push_back(std::hypot(a.lines.x[i] - b.lines.x[j], a.lines.y[i] - b.lines.y[j]));
        continue;
      }
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t q = b.lines.begin(f); q + 1 < b.lines.end(f); ++q) {
        const double ax = b.lines.x[q], ay = b.lines.y[q];
        const double bx = b.lines.x[q + 1] - ax, by = b.lines.y[q + 1] - ay, len2 = bx * bx + by * by;
        const double u =
            len2 > 0 ? std::clamp(((a.lines.x[i] - ax) * bx + (a.lines.y[i] - ay) * by) / len2, 0.0, 1.0)
                     : 0.0;
        best = std::min(best, std::hypot(a.lines.x[i] - ax - u * bx, a.lines.y[i] - ay - u * by));
      }
      d.push_back(best);
    }
  }
  return d;
}

}  // namespace

int main(int argc, char** argv) try {
  const Args args(argc, argv);
  const std::size_t flights = static_cast<std::size_t>(args.num("flights", 175000));
  const double window_s = static_cast<double>(args.num("window-s", 7200));
  const double step_s = static_cast<double>(args.num("step-s", 30));
  const int settle = static_cast<int>(args.num("settle", 30));
  const int updates = static_cast<int>(args.num("updates", 60));
  const bool match = args.num("match", 1) != 0;
  const std::vector<std::string> backends = split(args.get("backends", "cpu,opencl"));

  ts::ingest::DemoOptions o;
  const std::string src = demo_source(args);
  o.airports_csv = src + "/airports.csv";
  o.routes_csv = src + "/flights-airport.csv";
  o.flights = flights;
  o.sample_min_s = 30, o.sample_max_s = 60;
  const auto g0 = Clock::now();
  const ts::TrailSet set = ts::ingest::generate_demo_traffic(o);
  log("generated " + std::to_string(set.num_flights()) + " flights, " + std::to_string(set.num_points()) +
      " points in " + std::to_string(ms_since(g0) / 1000) + " s");

  const bd::StreamSource source = bd::flight_stream_source(set, ts::Query{});
  bd::StreamParams params;
  params.window_s = window_s;
  const bd::Frame frame = data_frame(set, params.size);
  const double t_peak = o.day_start + 19 * 3600.0;
  const double t_start = t_peak - settle * step_s;

  bool matched = false;
  for (const std::string& name : backends) {
    const ts::Backend backend = name == "opencl" ? ts::Backend::opencl : ts::Backend::cpu;
    if (backend == ts::Backend::opencl && !ts::opencl_available()) {
      emit({{"bench", "stream_bundle"}, {"backend", name}, {"skipped", "no OpenCL device"}});
      continue;
    }
    bd::StreamingBundler b(frame, params, backend);
    double t = t_start;
    for (int i = 0; i < settle; ++i, t += step_s) b.update(t, source);
    std::vector<double> ms, drift, trails, points, added, removed;
    double splat = 0, conv = 0, adv = 0, smooth = 0, select = 0, output = 0, max_point = 0;
    std::string path;
    bd::StreamUpdate last;
    for (int i = 0; i < updates; ++i, t += step_s) {
      const auto c0 = Clock::now();
      last = b.update(t, source);
      ms.push_back(ms_since(c0));
      drift.push_back(last.drift_px);
      max_point = std::max(max_point, last.max_drift_px);
      trails.push_back(static_cast<double>(last.id.size()));
      points.push_back(static_cast<double>(last.lines.points()));
      added.push_back(static_cast<double>(last.added)), removed.push_back(static_cast<double>(last.removed));
      splat += last.times.splat_ms, conv += last.times.convolve_ms, adv += last.times.advect_ms;
      smooth += last.times.smooth_ms, select += last.times.select_ms, output += last.times.output_ms;
      path = last.path;
    }
    const Stats s = Stats::of(ms), d = Stats::of(drift), tr = Stats::of(trails);
    const auto r3 = [](double x) { return std::round(x * 1000.0) / 1000.0; };
    json j{{"bench", "stream_bundle"},
           {"backend", name},
           {"path", path},
           {"device", path == "opencl" ? ts::opencl_info().device : ""},
           {"flights", set.num_flights()},
           {"window_s", window_s},
           {"step_s", step_s},
           {"iterations", params.iterations},
           {"h", params.h},
           {"eps", params.eps},
           {"trails_mean", r3(tr.mean)},
           {"trails_min", tr.min},
           {"trails_max", tr.max},
           {"points_mean", r3(mean_of(points))},
           {"added_mean", r3(mean_of(added))},
           {"removed_mean", r3(mean_of(removed))},
           {"updates_per_s", r3(1000.0 / s.mean)},
           {"select_ms_mean", r3(select / updates)},
           {"splat_ms_mean", r3(splat / updates)},
           {"convolve_ms_mean", r3(conv / updates)},
           {"advect_ms_mean", r3(adv / updates)},
           {"smooth_ms_mean", r3(smooth / updates)},
           {"output_ms_mean", r3(output / updates)},
           {"drift_px_mean", r3(d.mean)},
           {"drift_px_p95", r3(d.p95)},
           {"drift_px_max", r3(d.max)},
           {"max_point_drift_px", r3(max_point)}};
    s.put(j, "ms_");
    emit(j);

    if (match && !matched) {
      matched = true;
      const double t_hold = t - step_s;
      int hold = 0;
      bd::StreamUpdate held = last;
      while (hold < 400) {
        held = b.update(t_hold, source);
        ++hold;
        if (held.drift_px < 0.05) break;
      }
      bd::StreamingBundler fresh(frame, params, backend);
      bd::StreamUpdate scratch;
      const int scratch_updates = hold + 100;
      for (int i = 0; i < scratch_updates; ++i) scratch = fresh.update(t_hold, source);
      std::vector<double> dist = point_distances(held, scratch);
      std::vector<double> shape = point_distances(held, scratch, true);
      std::sort(dist.begin(), dist.end());
      std::sort(shape.begin(), shape.end());
      bd::StreamParams still = params;
      still.iterations = 1, still.eps = 1e-9, still.anchor = 0;
      bd::StreamingBundler raw(frame, still, ts::Backend::cpu);
      const std::vector<double> moved = point_distances(held, raw.update(t_hold, source));
      emit({{"bench", "stream_bundle_match"},
            {"backend", name},
            {"trails", held.id.size()},
            {"points", dist.size()},
            {"hold_updates", hold},
            {"hold_final_drift_px", r3(held.drift_px)},
            {"scratch_updates", scratch_updates},
            {"shape_mean_px", r3(mean_of(shape))},
            {"shape_p95_px", r3(Stats::percentile(shape, 0.95))},
            {"point_mean_px", r3(mean_of(dist))},
            {"point_p95_px", r3(Stats::percentile(dist, 0.95))},
            {"bundled_mean_px", r3(mean_of(moved))}});
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::cerr << "stream_bundle_bench: " << e.what() << "\n";
  return 1;
}
