// Sequential request latency against the running TrailScope server over loopback (one keep-alive
// connection, one request at a time; wrk measures throughput separately).
//
//   http_bench --base http://127.0.0.1:PORT --path /api/v1/datasets/demo/summary?... [--label NAME]
//              [--reps 30] [--warmup 2] [--vary NAME=START]
//
// --vary appends &NAME=START+i to request i (warm-ups included), so that every request misses the
// server's caches (e.g. t1 beyond the data: a new cache key, the same answer): a "cold" series.
// One record {"bench":"http", "label", "path", "status", "bytes", "ms_p50", ...}. Exits 1 when a response
// is not 200.
#include "bench_util.hpp"

using namespace bench;

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const std::string base = a.get("base"), path = a.get("path");
    if (base.empty() || path.empty()) {
      std::cerr << "usage: http_bench --base URL --path PATH [--label NAME] [--reps N] [--warmup N] [--vary "
                   "NAME=START]\n";
      return 2;
    }
    const int reps = static_cast<int>(a.num("reps", 30)), warmup = static_cast<int>(a.num("warmup", 2));
    std::string vary_name;
    long long vary_start = 0;
    if (a.has("vary")) {
      const std::string v = a.get("vary");
      const auto eq = v.find('=');
      vary_name = v.substr(0, eq);
      vary_start = std::stoll(v.substr(eq + 1));
    }
    HttpClient http(base);
    std::vector<double> ms;
    std::size_t bytes = 0;
    int status = 0;
    for (int i = 0; i < warmup + reps; ++i) {
      std::string target = path;
      if (!vary_name.empty())
        target += (target.find('?') == std::string::npos ? "?" : "&") + vary_name + "=" +
                  std::to_string(vary_start + i);
      const auto t0 = Clock::now();
      const HttpResponse r = http.request("GET", target);
      const double t = ms_since(t0);
      status = r.status, bytes = r.body.size();
      if (r.status != 200) {
        std::cerr << "http_bench: " << target << " answered " << r.status << ": " << r.body.substr(0, 500)
                  << "\n";
        return 1;
      }
      if (i >= warmup) ms.push_back(t);
    }
    json rec = {{"bench", "http"},
                {"label", a.get("label", path)},
                {"path", path},
                {"status", status},
                {"bytes", bytes},
                {"reps", reps},
                {"cold", !vary_name.empty()}};
    Stats::of(ms).put(rec, "ms_");
    emit(rec);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "http_bench: " << e.what() << "\n";
    return 1;
  }
}
