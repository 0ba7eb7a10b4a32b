// Animation chunks (GET /api/v1/datasets/{dataset}/animation, proto/animation_chunks.md): the server's
// chunk throughput and the time to scrub to any instant of a 24 h day, on a day of real or generated
// traffic.
//
//   anim_bench --so6 FILE --label europe_so6_day                  # the Europe SO6 day
//   anim_bench --demo-flights 250000 --sample-s 30,60 --label demo_25k  # generated traffic
//              [--duration 300] [--scrubs 60] [--seed 1] [--demo-source DIR]
//              [--base http://127.0.0.1:PORT --dataset ID [--http-only]]  # the scrubs over HTTP too (only)
//
// Records (one JSON line each):
//  - {"bench":"anim_data", label, flights, points, peak_concurrent, mean_concurrent, ...}: the day, with its
//    peak number of aircraft in the air at once (a sweep over the flights' time extents);
//  - {"bench":"anim_throughput", label, chunks, chunks_per_s, mb_per_s, ...}: every chunk of the day, one
//    after another, selected (compute/.../trails/animation_chunk.hpp) and encoded as TSAN
//    (server/src/formats/animation_chunk.hpp), the work of a cache miss;
//  - {"bench":"anim_scrub", label, mode: "cold"|"warm", via: "route"|"http", ms_p50, ms_p95, ...}: a scrub to
//    a random instant of the day = the chunk holding it plus the one before (a player's trail tails reach
//    back into it), asked one after the other. "route" calls the server's router in process (parameter
//    parsing, cache, selection, encoding: everything but the socket); "http" asks a running server over
//    loopback. Cold: the server's chunk cache holds neither chunk (emptied before each scrub in process;
//    over HTTP every scrub asks with its own origin, a new cache key); warm: both were asked just before.
#include <time.h>

#include <random>
#include <set>

#include "bench_util.hpp"
#include "formats/animation_chunk.hpp"
#include "limits.hpp"
#include "params/tile_params.hpp"
#include "routes/app.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/animation_chunk.hpp"

using namespace bench;
namespace ts = trailscope;
namespace srv = trailscope::server;

namespace {

// The store of one dataset held in memory: the bench measures the route, not the disk.
class MemoryStore final : public srv::DatasetStore {
 public:
  explicit MemoryStore(std::shared_ptr<const srv::Dataset> ds) : ds_(std::move(ds)) {}
  std::vector<std::shared_ptr<const srv::Dataset>> list() const override { return {ds_}; }
  std::shared_ptr<const srv::Dataset> get(const std::string& id) const override {
    if (id != ds_->id) throw ts::not_found("dataset", "no dataset '" + id + "'");
    return ds_;
  }
  bool contains(const std::string& id) const override { return id == ds_->id; }
  void put(std::shared_ptr<const srv::Dataset>, const ts::ProgressFn&) override {}
  void remove(const std::string&) override {}

 private:
  std::shared_ptr<const srv::Dataset> ds_;
};

// Peak and mean number of flights in the air at once: +1 at t_min, -1 after t_max.
std::pair<std::size_t, double> concurrency(const ts::TrailSet& set, double day0) {
  std::vector<std::pair<double, int>> ev;
  ev.reserve(2 * set.num_flights());
  double airtime = 0;
  for (const auto& f : set.flights()) {
    ev.emplace_back(f.t_min, +1), ev.emplace_back(f.t_max, -1);
    airtime += std::max(0.0, std::min(f.t_max, day0 + 86400) - std::max(f.t_min, day0));
  }
  std::sort(ev.begin(), ev.end(), [](auto& a, auto& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  });
  long long now = 0, peak = 0;
  for (const auto& [t, d] : ev) peak = std::max(peak, now += d);
  return {static_cast<std::size_t>(peak), airtime / 86400.0};
}

// CPU time of the whole process (all threads), ms. On a machine shared with other work the wall time of a
// scrub stretches with the load; its CPU time does not, and bounds the wall time on an idle core.
double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const double duration = static_cast<double>(a.num("duration", ts::limits::kDefaultAnimationChunkSeconds));
    const int scrubs = static_cast<int>(a.num("scrubs", 60));
    const std::uint64_t seed = static_cast<std::uint64_t>(a.num("seed", 1));
    std::string label = a.get("label");
    ts::TrailSet set;
    double load_s = 0;
    std::string source;
    const auto t_load = Clock::now();
    if (a.has("so6")) {
      set = ts::ingest::ingest_file(a.get("so6"));
      source = "so6";
      if (label.empty()) label = "so6";
    } else if (a.has("demo-flights")) {
      ts::ingest::DemoOptions o;
      const std::string dir = demo_source(a);
      o.airports_csv = dir + "/airports.csv", o.routes_csv = dir + "/flights-airport.csv";
      o.flights = static_cast<std::size_t>(a.num("demo-flights", 250000));
      o.seed = seed;
      const std::string s = a.get("sample-s", "30,60");
      o.sample_min_s = std::stod(s.substr(0, s.find(','))),
      o.sample_max_s = std::stod(s.substr(s.find(',') + 1));
      set = ts::ingest::generate_demo_traffic(o);
      source = "demo";
      if (label.empty()) label = "demo";
    } else {
      std::cerr << "usage: anim_bench (--so6 FILE | --demo-flights N [--sample-s MIN,MAX]) [--label L] "
                   "[--duration S] [--scrubs N] [--base URL --dataset ID]\n";
      return 2;
    }
    load_s = ms_since(t_load) / 1000;
    // The day: 24 h from the midnight (UTC) at or before the first sample.
    const double day0 = std::floor(set.t_min() / 86400) * 86400;
    const auto [peak, mean] = concurrency(set, day0);
    log(label + ": " + std::to_string(set.num_flights()) + " flights, " + std::to_string(set.num_points()) +
        " points, peak " + std::to_string(peak) + " aircraft at once");
    emit({{"bench", "anim_data"},
          {"label", label},
          {"source", source},
          {"flights", set.num_flights()},
          {"points", set.num_points()},
          {"peak_concurrent", peak},
          {"mean_concurrent", std::round(mean)},
          {"load_s", std::round(load_s * 100) / 100},
          {"rss_mib", std::round(peak_rss_mib())}});

    auto ds = std::make_shared<srv::Dataset>();
    ds->id = "bench", ds->name = label, ds->format = source, ds->created = "2026-01-01T00:00:00Z";
    ds->trails = std::make_shared<const ts::TrailSet>(std::move(set));
    const ts::TrailSet& trails = *ds->trails;
    const srv::AnimationOrigin origin = srv::default_animation_origin(trails);

    const bool http_only = a.has("http-only");
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 86400);
    std::vector<double> instants;
    for (int i = 0; i < scrubs; ++i) instants.push_back(day0 + u(rng));
    const auto chunk_start = [&](double instant) { return std::floor(instant / duration) * duration; };

    // 1. Throughput: every chunk of the day, selected and encoded, one after another.
    if (!http_only) {
      std::vector<double> ms;
      std::size_t bytes = 0, samples = 0, max_bytes = 0;
      const double cpu0 = process_cpu_ms();
      const auto t0 = Clock::now();
      for (double t = day0; t < day0 + 86400; t += duration) {
        const auto c0 = Clock::now();
        const ts::AnimationChunk c =
            ts::animation_chunk(trails, t, duration, ts::Query{}, ts::limits::kMaxAnimationChunkSamples);
        const std::string b = srv::encode_animation_chunk(trails, c, origin);
        ms.push_back(ms_since(c0));
        bytes += b.size(), samples += c.samples, max_bytes = std::max(max_bytes, b.size());
      }
      const double s = ms_since(t0) / 1000, cpu_s = (process_cpu_ms() - cpu0) / 1000;
      json rec = {
          {"bench", "anim_throughput"},
          {"cpu_seconds", std::round(cpu_s * 1000) / 1000},
          {"label", label},
          {"duration_s", static_cast<long long>(duration)},
          {"chunks", ms.size()},
          {"seconds", std::round(s * 1000) / 1000},
          {"chunks_per_s", std::round(static_cast<double>(ms.size()) / s * 10) / 10},
          {"mb_per_s", std::round(static_cast<double>(bytes) / 1e6 / s * 10) / 10},
          {"mean_chunk_mb",
           std::round(static_cast<double>(bytes) / 1e6 / static_cast<double>(ms.size()) * 1000) / 1000},
          {"max_chunk_mb", std::round(static_cast<double>(max_bytes) / 1e6 * 1000) / 1000},
          {"mean_chunk_samples", samples / ms.size()}};
      Stats::of(ms).put(rec, "chunk_ms_");
      emit(rec);
      log("throughput: " + rec.dump());
    }

    // 2. Scrubs through the router, in process.
    srv::App app(std::make_shared<MemoryStore>(ds), {}, {}, ts::limits::kTileCacheBytes);
    srv::Router router = srv::make_router(app);
    // Access control is on: a reader's token, verified once and then found in the cache of verified tokens.
    const std::string token = app.access->tokens().create("bench", srv::Role::reader).token;
    const auto fetch = [&](double start) {
      srv::Request r;
      r.method = "GET", r.path = "/api/v1/datasets/bench/animation";
      r.headers["authorization"] = "Bearer " + token;
      r.query = {{"t", ts::format_double(start)},
                 {"duration", std::to_string(static_cast<long long>(duration))}};
      const srv::Response res = router.handle(r);
      if (res.status != 200)
        throw std::runtime_error("animation answered " + std::to_string(res.status) + ": " + res.body);
      return res.bytes().size();
    };
    for (const bool warm : {false, true}) {
      if (http_only) break;
      std::vector<double> ms, cpu;
      std::size_t bytes = 0;
      for (const double instant : instants) {
        const double start = chunk_start(instant);
        app.animation_chunks.erase_prefix(srv::params::dataset_cache_prefix("bench"));
        if (warm) fetch(start), fetch(start - duration);
        const double c0 = process_cpu_ms();
        const auto t0 = Clock::now();
        bytes += fetch(start) + fetch(start - duration);
        ms.push_back(ms_since(t0));
        cpu.push_back(process_cpu_ms() - c0);
      }
      json rec = {{"bench", "anim_scrub"},
                  {"label", label},
                  {"mode", warm ? "warm" : "cold"},
                  {"via", "route"},
                  {"duration_s", static_cast<long long>(duration)},
                  {"mean_mb", std::round(static_cast<double>(bytes) / 1e6 / scrubs * 1000) / 1000}};
      Stats::of(ms).put(rec, "ms_");
      Stats::of(cpu).put(rec, "cpu_ms_");
      emit(rec);
      log("scrub: " + rec.dump());
    }

    // 3. The same over HTTP against a running server that holds the same data as `--dataset`.
    if (a.has("base")) {
      HttpClient http(a.get("base"));
      const std::string path = "/api/v1/datasets/" + a.get("dataset", "europe") + "/animation";
      const auto get = [&](double start, const std::string& extra) {
        const HttpResponse r =
            http.request("GET", path + "?t=" + ts::format_double(start) +
                                    "&duration=" + std::to_string(static_cast<long long>(duration)) + extra);
        if (r.status != 200)
          throw std::runtime_error("HTTP animation answered " + std::to_string(r.status) + ": " +
                                   r.body.substr(0, 300));
        return r.body.size();
      };
      for (const bool warm : {false, true}) {
        std::vector<double> ms;
        std::size_t bytes = 0;
        for (int i = 0; i < scrubs; ++i) {
          const double start = chunk_start(instants[static_cast<std::size_t>(i)]);
          // A new origin (a few micro-degrees apart) is a new cache key, so a cold scrub misses.
          const std::string o =
              "&origin=" + ts::format_double(origin.lon + 1e-6 * (i + 1) + (warm ? 0.5 : 0)) + "," +
              ts::format_double(origin.lat);
          if (warm) get(start, o), get(start - duration, o);
          const auto t0 = Clock::now();
          bytes += get(start, o) + get(start - duration, o);
          ms.push_back(ms_since(t0));
        }
        json rec = {{"bench", "anim_scrub"},
                    {"label", label},
                    {"mode", warm ? "warm" : "cold"},
                    {"via", "http"},
                    {"duration_s", static_cast<long long>(duration)},
                    {"mean_mb", std::round(static_cast<double>(bytes) / 1e6 / scrubs * 1000) / 1000}};
        Stats::of(ms).put(rec, "ms_");
        emit(rec);
        log("scrub over HTTP: " + rec.dump());
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "anim_bench: " << e.what() << "\n";
    return 1;
  }
}
