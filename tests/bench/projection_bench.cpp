// Projection benchmark: PCA, MDS, t-SNE and LAMP on seeded Gaussian clusters of 50 dimensions at 1k, 5k,
// 20k and 100k points, on the OpenCL path and (up to --ref-max rows) the C++ reference, with the
// quality (trustworthiness, continuity at k = 10, sampled above limits::kMaxQualitySample rows). The
// data (standardised, float32 little-endian, row-major) goes to --data-dir for the npm peers
// (projection_peers.mjs), whose layouts this program then scores with the same metric code.
//
//   projection_bench --data-dir DIR [--sizes 1000,5000,20000,100000] [--dims 50] [--methods
//   pca,mds,tsne,lamp]
//                    [--ref-max 5000] [--budget-s 60]
//   projection_bench --data-dir DIR --score-peers PEERS.jsonl
//
// Records: {"bench":"projection","impl":"trailscope"|<npm package>,"backend","method","variant","n","dims",
// "ms","trustworthiness","continuity","queries"} or the same with "skipped": reason. A run that would exceed
// --budget-s (estimated from the cost model in `estimate_s`, calibrated on this machine) is skipped and
// says so.
#include <fstream>
#include <random>
#include <sstream>

#include "bench_util.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/ocl_info.hpp"
#include "trailscope/projection/projection.hpp"
#include "trailscope/projection/quality.hpp"

using namespace bench;
namespace ts = trailscope;
namespace pj = trailscope::projection;

namespace {

// 10 isotropic clusters (std 1) with centres uniform in [0, 3]^dims: separated in 50 dimensions (centre
// distances ~9) but with overlapping tails, so neighbourhoods are not trivially perfect.
pj::Table clusters(std::size_t n, std::size_t dims, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto normal = [&] {
    const double a = 1.0 - u(rng), b = u(rng);
    return std::sqrt(-2.0 * std::log(a)) * std::cos(6.283185307179586 * b);
  };
  const int k = 10;
  std::vector<double> centres(k * dims);
  for (double& c : centres) c = 3.0 * u(rng);
  pj::Table t;
  t.rows = n, t.cols = dims;
  t.values.resize(n * dims);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t d = 0; d < dims; ++d)
      t.values[r * dims + d] = static_cast<float>(centres[(r % k) * dims + d] + normal());
  pj::standardize(t);
  return t;
}

std::string data_path(const std::string& dir, std::size_t n, std::size_t dims) {
  return dir + "/proj_" + std::to_string(n) + "x" + std::to_string(dims) + ".f32";
}

pj::Table read_f32(const std::string& path, std::size_t n, std::size_t dims) {
  pj::Table t;
  t.rows = n, t.cols = dims;
  t.values.resize(n * dims);
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(t.values.data()), static_cast<std::streamsize>(n * dims * 4)))
    throw std::runtime_error("cannot read " + path);
  return t;
}

// Seconds a run is expected to take on the 2-core machine (PoCL), from measured constants: the
// exact kNN of t-SNE (N²·D, a float GEMM on both paths) dominates above ~20k points; exact MDS is
// capped at 3000 rows.
double estimate_s(const std::string& method, std::size_t n, std::size_t dims, bool reference) {
  const double nn = static_cast<double>(n), d = static_cast<double>(dims);
  // kNN (N²·D) plus 750 FFT-interpolation iterations, ~0.2 µs per point and iteration (0.3 µs for
  // the double reference).
  if (method == "tsne") return nn * nn * d * 1.5e-10 + nn * 750 * (reference ? 0.3e-6 : 0.2e-6);
  if (method == "mds") return nn * ts::limits::kMdsLandmarks * d * 2e-9 + 2.0;
  if (method == "lamp") return nn * std::sqrt(nn) * d * 3 * 2e-9 + 0.5;
  return nn * d * d * 1e-9;
}

void score(json& j, const pj::Table& t, const std::vector<double>& xy) {
  pj::QualityOptions q;
  q.k = 10;
  q.backend = ts::Backend::auto_;
  const auto t0 = Clock::now();
  const pj::Quality r = pj::quality(t, xy, q);
  j["trustworthiness"] = std::round(r.trustworthiness * 1e5) / 1e5;
  j["continuity"] = std::round(r.continuity * 1e5) / 1e5;
  j["queries"] = r.queries;
  j["quality_ms"] = std::round(ms_since(t0));
}

pj::Embedding run_method(const std::string& m, const pj::Table& t, ts::Backend b) {
  if (m == "pca") return b == ts::Backend::cpu ? pj::pca_ref(t) : pj::pca(t, b);
  if (m == "mds") return b == ts::Backend::cpu ? pj::mds_ref(t, 42) : pj::mds(t, 42, b);
  if (m == "lamp") return b == ts::Backend::cpu ? pj::lamp_ref(t, 42) : pj::lamp(t, 42, b);
  pj::TsneOptions o;  // the defaults: perplexity 30, 250 + 500 iterations (FIt-SNE's count)
  return b == ts::Backend::cpu ? pj::tsne_ref(t, o) : pj::tsne(t, o, b);
}

std::vector<std::size_t> parse_sizes(const std::string& s) {
  std::vector<std::size_t> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::stoull(item));
  return out;
}

int score_peers(const Args& a) {
  const std::string dir = a.get("data-dir");
  std::ifstream in(a.get("score-peers"));
  if (!in) throw std::runtime_error("cannot read " + a.get("score-peers"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] != '{') continue;
    json p = json::parse(line);
    const std::size_t n = p.at("n"), dims = p.at("dims");
    json j = {{"bench", "projection"},
              {"impl", p.at("peer")},
              {"backend", "node"},
              {"method", p.at("method")},
              {"n", n},
              {"dims", dims}};
    if (p.contains("skipped")) {
      j["skipped"] = p["skipped"];
      emit(j);
      continue;
    }
    const std::vector<double> xy = p.at("coords").get<std::vector<double>>();
    j["ms"] = p.at("ms");
    if (p.contains("version")) j["version"] = p["version"];
    if (p.contains("params")) j["params"] = p["params"];
    score(j, read_f32(data_path(dir, n, dims), n, dims), xy);
    emit(j);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) try {
  const Args a(argc, argv);
  if (!a.has("data-dir")) throw std::invalid_argument("--data-dir is required");
  if (a.has("score-peers")) return score_peers(a);
  const std::string dir = a.get("data-dir");
  std::filesystem::create_directories(dir);
  const std::vector<std::size_t> sizes = parse_sizes(a.get("sizes", "1000,5000,20000,100000"));
  const auto dims = static_cast<std::size_t>(a.num("dims", 50));
  const auto ref_max = static_cast<std::size_t>(a.num("ref-max", 5000));
  const double budget = static_cast<double>(a.num("budget-s", 60));
  std::vector<std::string> methods;
  {
    std::stringstream ss(a.get("methods", "pca,mds,tsne,lamp"));
    std::string m;
    while (std::getline(ss, m, ',')) methods.push_back(m);
  }
  const ts::OpenClInfo info = ts::opencl_info();
  const std::string device = info.available ? info.device : "none (" + info.error + ")";
  if (info.available) {
    ts::opencl_warm_up();
    // PoCL compiles a kernel again for its first launch at a new work-group/grid configuration: one
    // untimed run of every method (t-SNE shortened) keeps that out of the timings.
    const pj::Table w = clusters(1000, dims, 1);
    for (const std::string& m : methods) {
      if (m != "tsne") {
        (void)run_method(m, w, ts::Backend::opencl);
        continue;
      }
      pj::TsneOptions o;
      o.iterations = 5, o.exaggeration_iterations = 5;
      (void)pj::tsne(w, o, ts::Backend::opencl);
    }
  }
  for (std::size_t n : sizes) {
    const pj::Table t = clusters(n, dims, 42 + n);
    {
      std::ofstream out(data_path(dir, n, dims), std::ios::binary);
      out.write(reinterpret_cast<const char*>(t.values.data()),
                static_cast<std::streamsize>(t.values.size() * 4));
    }
    log("projection data " + std::to_string(n) + " x " + std::to_string(dims) + " → " +
        data_path(dir, n, dims));
    for (const std::string& m : methods)
      for (ts::Backend b : {ts::Backend::opencl, ts::Backend::cpu}) {
        if (b == ts::Backend::opencl && !info.available) continue;
        json j = {{"bench", "projection"},
                  {"impl", "trailscope"},
                  {"backend", ts::to_string(b)},
                  {"method", m},
                  {"n", n},
                  {"dims", dims},
                  {"device", b == ts::Backend::opencl ? device : "cpu"}};
        if (b == ts::Backend::cpu && n > ref_max) continue;  // the reference is timed up to --ref-max rows
        const double est = estimate_s(m, n, dims, b == ts::Backend::cpu);
        if (m == "tsne" && n > ts::limits::kMaxTsneRows) {
          j["skipped"] = "above limits::kMaxTsneRows";
        } else if (est > budget) {
          std::ostringstream why;
          why << "estimated " << std::round(est) << " s > budget " << budget << " s";
          j["skipped"] = why.str();
        }
        if (j.contains("skipped")) {
          log("skip " + m + " " + std::to_string(n) + ": " + j["skipped"].get<std::string>());
          emit(j);
          continue;
        }
        const auto t0 = Clock::now();
        const pj::Embedding e = run_method(m, t, b);
        j["ms"] = std::round(ms_since(t0) * 10) / 10;
        j["variant"] = e.variant;
        j["path"] = e.path;
        for (const auto& [phase, ms] : e.timings_ms) j["phase_ms"][phase] = std::round(ms * 10) / 10;
        score(j, t, e.xy);
        log(m + " " + std::to_string(n) + " " + ts::to_string(b) + ": " +
            std::to_string(j["ms"].get<double>()) +
            " ms, T(10) = " + std::to_string(j["trustworthiness"].get<double>()));
        emit(j);
      }
  }
  return 0;
} catch (const std::exception& e) {
  std::cerr << "projection_bench: " << e.what() << std::endl;
  return 1;
}
