// CUBu bundling benchmark: full bundlings of the data sets at the default parameters (512 px,
// h = 32, 15 iterations), on the OpenCL path and on the single-threaded C++ reference, per phase.
//
//   bundle_bench --graph PATH [--nodes PATH] --label NAME [--reps 9] [--ref-reps 3]
//   bundle_bench --so6 PATH --label europe_so6_trails [--reps 5] [--ref-reps 1]
//   bundle_bench --random-edges N --label generated_1m [--reps 3] [--ref-reps 1]
//
// One JSON record per backend: {"bench":"bundle","label","backend":"opencl"|"cpu","edges","points",
// "ms_p50", per phase "<phase>_ms_p50", quality figures, "device"}; then one "bundle_compare" record
// saying whether both paths gave the same bytes. --ref-reps 0 skips the reference (its time is then
// not reported). Generated graphs are deterministic (seeded): a few hundred Gaussian node clusters, edges
// between random nodes, so that there is structure to bundle.
#include <optional>
#include <random>

#include "bench_util.hpp"
#include "trailscope/bundling/bundle.hpp"
#include "trailscope/bundling/flight_trails.hpp"
#include "trailscope/bundling/graph_io.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/ocl_info.hpp"

using namespace bench;
namespace ts = trailscope;
namespace bd = trailscope::bundling;

namespace {

bd::Polylines random_graph(std::size_t edges, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1000.0);
  std::normal_distribution<double> spread(0.0, 12.0);
  const std::size_t clusters = 300, per_cluster = 20;
  std::vector<double> nx, ny;
  for (std::size_t c = 0; c < clusters; ++c) {
    const double cx = uni(rng), cy = uni(rng) * 0.6;
    for (std::size_t k = 0; k < per_cluster; ++k)
      nx.push_back(cx + spread(rng)), ny.push_back(cy + spread(rng));
  }
  std::uniform_int_distribution<std::size_t> pick(0, nx.size() - 1);
  bd::Polylines g;
  g.x.reserve(2 * edges), g.y.reserve(2 * edges), g.offsets.reserve(edges + 1);
  while (g.size() < edges) {
    const std::size_t a = pick(rng), b = pick(rng);
    if (a / per_cluster == b / per_cluster) continue;  // no edges inside a cluster
    g.add_edge(nx[a], ny[a], nx[b], ny[b]);
  }
  return g;
}

struct Run {
  std::vector<double> total, resample, splat, convolve, advect, smooth, endpoints, post;
  bd::Bundled last;
};

Run time_runs(const bd::Polylines& px, const bd::Frame& frame, const bd::BundleParams& p, ts::Backend backend,
              int reps) {
  Run r;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    bd::Bundled b =
        backend == ts::Backend::cpu ? bd::bundle_ref(px, frame, p) : bd::bundle(px, frame, p, backend);
    r.total.push_back(ms_since(t0));
    r.resample.push_back(b.times.resample_ms), r.splat.push_back(b.times.splat_ms);
    r.convolve.push_back(b.times.convolve_ms), r.advect.push_back(b.times.advect_ms);
    r.smooth.push_back(b.times.smooth_ms), r.endpoints.push_back(b.times.endpoints_ms);
    r.post.push_back(b.times.post_ms);
    r.last = std::move(b);
  }
  return r;
}

void emit_run(const std::string& label, const std::string& backend, const bd::Polylines& px, const Run& r) {
  json j{{"bench", "bundle"},
         {"label", label},
         {"backend", backend},
         {"path", r.last.path},
         {"device", r.last.device},
         {"edges", px.size()},
         {"input_points", px.points()},
         {"bundled_points", r.last.lines.points()},
         {"size", r.last.params.size},
         {"h", r.last.params.h},
         {"iterations", r.last.params.iterations},
         {"ink_reduction", r.last.quality.ink_reduction},
         {"mean_displacement_px", r.last.quality.mean_displacement_px},
         {"max_displacement_px", r.last.quality.max_displacement_px},
         {"peak_rss_mib", peak_rss_mib()}};
  Stats::of(r.total).put(j, "ms_");
  const std::pair<const char*, const std::vector<double>*> phases[] = {
      {"resample", &r.resample}, {"splat", &r.splat},   {"convolve", &r.convolve},
      {"advect", &r.advect},     {"smooth", &r.smooth}, {"endpoints", &r.endpoints},
      {"post", &r.post}};
  for (const auto& [name, v] : phases) j[std::string(name) + "_ms_p50"] = Stats::of(*v).p50;
  emit(j);
}

bool same_points(const bd::Bundled& a, const bd::Bundled& b) {
  return a.lines.offsets == b.lines.offsets && a.lines.x == b.lines.x && a.lines.y == b.lines.y;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const std::string label = a.get("label", "bundle");
    const int reps = static_cast<int>(a.num("reps", 9));
    const int ref_reps = static_cast<int>(a.num("ref-reps", 3));
    bd::BundleParams params;  // the defaults: 512 px, h = 32, 15 iterations
    for (const std::string& kv : a.all("param")) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos) throw std::invalid_argument("--param wants name=value: " + kv);
      params.set(kv.substr(0, eq), kv.substr(eq + 1));
    }

    bd::Polylines px;
    bd::Frame frame;
    std::string source;
    const auto t_load = Clock::now();
    if (a.has("graph")) {
      const bd::Graph g = bd::read_graph(a.get("graph"), a.get("nodes"));
      frame = bd::Frame::fit(g.edges, params.size, params.border, g.y_up);
      px = frame.to_pixels(g.edges);
      source = a.get("graph");
    } else if (a.has("so6")) {
      const ts::TrailSet set = ts::ingest::ingest_file(a.get("so6"));
      const ts::Query all;
      // SO6 is Douglas-Peucker simplified: long cruise legs are not gaps.
      bd::FlightTrails ft = bd::flight_trails(set, all, params.size, std::numeric_limits<double>::infinity());
      frame = ft.frame;
      px = frame.to_pixels(ft.lines);
      source = a.get("so6");
    } else if (a.has("random-edges")) {
      const auto n = static_cast<std::size_t>(a.num("random-edges", 100000));
      const bd::Polylines g = random_graph(n, static_cast<std::uint64_t>(a.num("seed", 7)));
      frame = bd::Frame::fit(g, params.size, params.border);
      px = frame.to_pixels(g);
      source = "generated, " + std::to_string(n) + " edges, seed " + a.get("seed", "7");
    } else {
      throw std::invalid_argument("one of --graph, --so6, --random-edges is required");
    }
    log(label + ": " + std::to_string(px.size()) + " polylines, " + std::to_string(px.points()) +
        " points, loaded in " + std::to_string(static_cast<int>(ms_since(t_load))) + " ms");

    // OpenCL: one untimed run builds the programs (and PoCL's work-group specialisations).
    const ts::OpenClInfo info = ts::opencl_info();
    std::optional<Run> ocl;
    if (info.available) {
      (void)bd::bundle(px, frame, params, ts::Backend::opencl);
      ocl = time_runs(px, frame, params, ts::Backend::opencl, reps);
      emit_run(label, "opencl", px, *ocl);
      log(label + " opencl p50 " + std::to_string(Stats::of(ocl->total).p50) + " ms on " + ocl->last.device);
    } else {
      log("OpenCL unavailable: " + info.error);
    }
    std::optional<Run> ref;
    if (ref_reps > 0) {
      ref = time_runs(px, frame, params, ts::Backend::cpu, ref_reps);
      emit_run(label, "cpu", px, *ref);
      log(label + " reference p50 " + std::to_string(Stats::of(ref->total).p50) + " ms");
    }
    json cmp{{"bench", "bundle_compare"}, {"label", label}, {"source", source}, {"edges", px.size()}};
    if (ocl && ref) {
      cmp["identical"] = same_points(ocl->last, ref->last);
      cmp["speedup"] = Stats::of(ref->total).p50 / Stats::of(ocl->total).p50;
    }
    emit(cmp);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bundle_bench: " << e.what() << "\n";
    return 1;
  }
}
