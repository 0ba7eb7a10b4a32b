// The embedded store at 100 M points: a generated week of dense traffic (generate_demo_traffic's fleet
// mode, demo_traffic.hpp: --aircraft aircraft flying leg after leg for 7 days, a sample every 120–180 s)
// built in memory as the embedded store holds a loaded dataset (server/src/store/embedded_store.hpp: the
// columnar TrailSet with its Web Mercator columns and time index, which its loader builds exactly so from
// the column files), then queried: 1-hour window summaries (random hours, not aligned), the whole-week
// summary, cold 1-hour density tiles (a new renderer each time, so the shared colour span is computed too,
// and a new hour each time), each also by the plain scan (summarize_scan) for comparison. Memory per point is
// the resident set's growth over the dataset (RSS before and after) divided by its points, and the largest
// dataset a machine holds follows from it.
//
//   week_bench [--aircraft 32000] [--days 7] [--seed 42] [--reps 30] [--demo-source DIR] [--host-gib 24]
//              [--compare-tiles]
//
// Records: {"bench":"week_dataset"}, {"bench":"week_read","read":
// "summary_1h"|"summary_week"|"tile_1h_cold"|..., "impl":"indexed"|"scan"}, {"bench":"week_memory"}.
#include <fstream>
#include <limits>
#include <random>
#include <sys/resource.h>
#include <unistd.h>

#include "bench_util.hpp"
#include "trailscope/density/aggregate.hpp"
#include "trailscope/density/renderer.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/time_index.hpp"

using namespace bench;
namespace ts = trailscope;

namespace {

// Resident set now (not the peak), MiB, from /proc/self/statm.
double rss_mib() {
  std::ifstream in("/proc/self/statm");
  long long size = 0, resident = 0;
  in >> size >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// CPU time of this process so far (all threads), ms: on a shared machine the wall time of a read also
// holds the time its threads waited for a core.
double cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
          static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e3);
}

// The 1-minute load average.
double load1() {
  std::ifstream in("/proc/loadavg");
  double l = 0;
  in >> l;
  return l;
}

ts::geo::TileId tile_at(double lon, double lat, int z) {
  const double n = std::ldexp(1.0, z);
  const double x = (lon + 180) / 360 * n;
  const double r = lat * M_PI / 180;
  const double y = (1 - std::log(std::tan(r) + 1 / std::cos(r)) / M_PI) / 2 * n;
  return {z, static_cast<int>(x), static_cast<int>(y)};
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const auto aircraft = static_cast<std::size_t>(a.num("aircraft", 32000));
    const int days = static_cast<int>(a.num("days", 7));
    const auto seed = static_cast<std::uint64_t>(a.num("seed", 42));
    const int reps = static_cast<int>(a.num("reps", 30));
    const double host_gib = static_cast<double>(a.num("host-gib", 24));
    const std::string src = demo_source(a);

    ts::ingest::DemoOptions o;
    o.airports_csv = src + "/airports.csv";
    o.routes_csv = src + "/flights-airport.csv";
    o.aircraft = aircraft, o.days = days, o.seed = seed;
    o.sample_min_s = 120, o.sample_max_s = 180;
    const double rss0 = rss_mib();
    auto t = Clock::now();
    const auto set = std::make_shared<const ts::TrailSet>(ts::ingest::generate_demo_traffic(o));
    const double gen_s = ms_since(t) / 1000.0;
    const double rss1 = rss_mib();
    const std::size_t points = set->num_points(), flights = set->num_flights();
    log("generated " + std::to_string(flights) + " legs, " + std::to_string(points) + " points in " +
        std::to_string(gen_s) + " s; RSS " + std::to_string(rss1) + " MiB");

    // Aircraft in the air (or taxiing) at 200 instants over the span.
    std::vector<double> in_progress;
    for (int k = 0; k < 200; ++k) {
      const double at = set->t_min() + (set->t_max() - set->t_min()) * (k + 0.5) / 200;
      std::size_t n = 0;
      for (const auto& f : set->flights()) n += f.t_min <= at && at <= f.t_max;
      in_progress.push_back(static_cast<double>(n));
    }
    const Stats sim = Stats::of(in_progress);
    const double index_bytes = static_cast<double>(set->time_index().bytes());
    emit({{"bench", "week_dataset"},
          {"aircraft", aircraft},
          {"days", days},
          {"seed", seed},
          {"sample_s", "120-180"},
          {"flights", flights},
          {"points", points},
          {"generate_s", gen_s},
          {"points_per_s", static_cast<double>(points) / gen_s},
          {"simultaneous_p50", sim.p50},
          {"simultaneous_min", sim.min},
          {"simultaneous_max", sim.max},
          {"index_bytes", index_bytes},
          {"rss_before_mib", rss0},
          {"rss_after_mib", rss1}});

    const double rss_loaded = rss1, rss_base = rss0;
    const ts::TrailSet& week = *set;

    // Random hours (not aligned to the hour) inside the span, the same list for both implementations.
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(week.t_min(), week.t_max() - 3600);
    std::vector<double> starts(static_cast<std::size_t>(reps));
    for (double& s : starts) s = u(rng);
    const auto hour = [&](int i) {
      ts::Query q;
      q.t0 = starts[static_cast<std::size_t>(i) % starts.size()], q.t1 = *q.t0 + 3600;
      return q;
    };
    std::uint64_t check = 0;
    const auto timed = [&](const std::string& read, const std::string& impl, int n, auto&& fn) {
      std::vector<double> v, cpu;
      const double load = load1();
      for (int i = 0; i < n; ++i) {
        const double c0 = cpu_ms();
        const auto t0 = Clock::now();
        check += fn(i);
        v.push_back(ms_since(t0));
        cpu.push_back(cpu_ms() - c0);
      }
      const Stats s = Stats::of(v), c = Stats::of(cpu);
      emit({{"bench", "week_read"},
            {"read", read},
            {"impl", impl},
            {"reps", n},
            {"ms_p50", s.p50},
            {"ms_p95", s.p95},
            {"ms_min", s.min},
            {"ms_max", s.max},
            {"cpu_ms_p50", c.p50},
            {"load1", load}});
      log(read + " " + impl + ": p50 " + std::to_string(s.p50) + " ms (CPU " + std::to_string(c.p50) +
          " ms, load " + std::to_string(load) + ")");
      return s;
    };
    // What a 1-hour window reads: the flights of the time index's range (flight_range) and, of them, the
    // flights with a point in the window.
    {
      std::vector<double> ranged, inside;
      for (int i = 0; i < reps; ++i) {
        const ts::Query q = hour(i);
        const auto [fb, fe] = week.time_index().flight_range(*q.t0, *q.t1);
        std::size_t n = 0;
        for (std::size_t f = fb; f < fe; ++f) n += q.may_match(week.flights()[f]);
        ranged.push_back(static_cast<double>(fe - fb));
        inside.push_back(static_cast<double>(n));
      }
      emit({{"bench", "week_window"},
            {"range_flights_p50", Stats::of(ranged).p50},
            {"window_flights_p50", Stats::of(inside).p50}});
      log("1-hour window: " + std::to_string(Stats::of(ranged).p50) + " flights in the index range, " +
          std::to_string(Stats::of(inside).p50) + " meet the window");
    }
    // The indexed path must answer what the scan answers (points and flights of a few windows).
    for (int i = 0; i < 3; ++i) {
      const ts::Summary x = ts::summarize(week, hour(i)), y = ts::summarize_scan(week, hour(i));
      if (x.points != y.points || x.flights != y.flights ||
          x.time_histogram.counts != y.time_histogram.counts)
        throw std::runtime_error("indexed and scanned summaries differ");
    }
    timed("summary_1h", "indexed", reps, [&](int i) { return ts::summarize(week, hour(i)).points; });
    timed("summary_1h", "scan", std::max(3, reps / 10),
          [&](int i) { return ts::summarize_scan(week, hour(i)).points; });
    timed("summary_week", "indexed", reps, [&](int) { return ts::summarize(week, {}).points; });
    timed("summary_week", "scan", std::max(3, reps / 10),
          [&](int) { return ts::summarize_scan(week, {}).points; });

    // Cold 1-hour tiles over the dense US east (z 5 around Chicago, 256 px, count, eq_hist).
    ts::density::TileRequest req;
    req.tile = tile_at(-87.6, 41.9, 5);
    req.backend = ts::Backend::cpu;
    req.max_gap_seconds =
        std::numeric_limits<double>::infinity();  // as the tile route asks (routes/tiles.cpp)
    timed("tile_1h_cold", "indexed", reps, [&](int i) {
      ts::density::DensityRenderer r;
      return r.render_tile(week, "week", hour(i), req).png.size();
    });
    // The cold tile's two parts: the shared colour span (the coarse aggregate of the whole window,
    // renderer.hpp) and the tile's own aggregate.
    timed("tile_1h_span", "indexed", reps, [&](int i) {
      return static_cast<std::uint64_t>(ts::density::estimate_span(week, hour(i), req.value, req.tile.z,
                                                                   req.size, req.kernel_radius,
                                                                   req.max_gap_seconds, req.backend)
                                            .samples);
    });
    timed("tile_1h_aggregate", "indexed", reps, [&](int i) {
      ts::density::AggregateOptions ao;
      ao.backend = req.backend;
      ao.max_gap_seconds = req.max_gap_seconds;
      return static_cast<std::uint64_t>(
          ts::density::aggregate(week, hour(i), ts::density::Canvas::for_tile(req.tile, req.size), ao)
              .max_count);
    });
    ts::TrailSet unindexed;  // the same points and flights with no index: flights in reverse order
    {
      std::vector<ts::Flight> rev(week.flights().rbegin(), week.flights().rend());
      // Not built by default: it doubles the memory. --compare-tiles asks for it.
      if (a.has("compare-tiles")) unindexed = ts::TrailSet(week.points(), std::move(rev));
    }
    if (unindexed.num_points())
      timed("tile_1h_cold", "scan", std::max(3, reps / 10), [&](int i) {
        ts::density::DensityRenderer r;
        return r.render_tile(unindexed, "week-scan", hour(i), req).png.size();
      });

    // Memory per point and the largest dataset one machine holds: the dataset's RSS growth per point;
    // a host keeps ~4 GiB for the system and the server's caches, and a dataset holds at most 2^32 − 1
    // points (32-bit point ranges).
    const double bytes_per_point = (rss_loaded - rss_base) * 1024 * 1024 / static_cast<double>(points);
    const auto largest = [&](double gib) {
      return std::min(4294967295.0, (gib - 4) * 1024 * 1024 * 1024 / bytes_per_point);
    };
    emit({{"bench", "week_memory"},
          {"points", points},
          {"bytes_per_point", bytes_per_point},
          {"column_bytes_per_point", 33 + 8},
          {"index_bytes_per_point", index_bytes / static_cast<double>(points)},
          {"host_gib", host_gib},
          {"largest_points_host", largest(host_gib)},
          {"largest_points_128gib", largest(128)},
          {"peak_rss_mib", peak_rss_mib()},
          {"check", check}});
  } catch (const std::exception& e) {
    std::cerr << "week_bench: " << e.what() << "\n";
    return 1;
  }
}
