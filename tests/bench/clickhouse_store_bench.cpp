// The ClickHouse store against the embedded store and against ClickHouse's own SQL, on the Europe SO6 day
// (138,579 points; --scales, default 1) and on the demo day (--demo-flights, default 7,400 flights: 6.4M
// points; --demo-scales, default none: e.g. 1,8), a scale k being k copies of the day, each shifted by a
// day (×8 of that demo day: 51M points). Each set is put into an embedded store and into a cluster (--store,
// e.g. the URL tests/cluster/cluster.sh prints); then, for each read the routes push down to the shards (a
// whole-set and a 1-hour summary, a 1-hour flight list, positions at an instant, a density tile with its
// level's span cached, and a cold tile whose span is computed too), three timings:
//  - trailscope: the store's answer as the route serialises it (ClickHouseStore's DatasetReads call on
//    the described dataset, as the routes hold it, and to_json().dump(): the SQL, the merge with
//    compute/'s finishing code, and what stays on the server — the JSON, the smoothing, shading and PNG;
//    the summary's data-quality block and the cold tile's span are SQL on the shards too);
//  - clickhouse: the same SQL the store sent, run alone through a plain client: ClickHouse's own time for
//    the same result, over the same HTTP interface;
//  - embedded: compute/ in this process (LocalReads, the embedded store's reads) on the copy the
//    ClickHouse store fetched (bit for bit the set that was put: tests/cluster; the original is released
//    first, so that one copy is in memory at a time).
// overhead = trailscope p50 / clickhouse p50 − 1. Each answer is checked to be the embedded store's bytes.
// Also timed: the ingest into each store (points/s; the cluster's rows/s counts its segment and flight
// rows too), describe() of a freshly opened ClickHouse store (catalogue + flight table) and the fetch of
// the whole copy (get()); and the bytes per point on the cluster's disks (system.parts, every replica) and
// in the embedded store's folder.
//
//   clickhouse_store_bench --so6 PATH --store clickhouse://HOST:PORT[,...]/DB?cluster=NAME [--reps 15]
//       [--scales 1] [--demo-scales 1,8] [--demo-flights 7400] [--demo-source DIR] [--big-reps 3]
//       [--tmp DIR]
//
// Sets of more than 10M points are read --big-reps times instead of --reps.
// Records: {"bench":"clickhouse_store_put","set","scale",...} per set and one
// {"bench":"clickhouse_store_read","set","scale","read",...} per read and set.
#include <cmath>
#include <filesystem>
#include <sstream>

#include "bench_util.hpp"
#include "store/clickhouse_store.hpp"
#include "store/dataset_reads.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/ingest/ingest.hpp"

using namespace bench;
using namespace trailscope;
using trailscope::server::ClickHouseClient;
using trailscope::server::ClickHouseStore;
using trailscope::server::ClickHouseUrl;
using trailscope::server::Dataset;
using trailscope::server::DatasetReads;
using trailscope::server::EmbeddedStore;
using trailscope::server::LocalReads;
namespace fs = std::filesystem;

namespace {

/// `k` copies of `t`, copy c shifted by c days (points, flights and extents), one after the other.
TrailSet repeat_days(const TrailSet& t, int k) {
  const PointColumns& p = t.points();
  const std::size_t n = p.size();
  PointColumns out;
  out.reserve(n * k);
  std::vector<Flight> flights;
  flights.reserve(t.num_flights() * k);
  for (int c = 0; c < k; ++c) {
    const double dt = 86400.0 * c;
    for (std::size_t i = 0; i < n; ++i) {
      out.t.push_back(p.t[i] + dt);
      out.lat.push_back(p.lat[i]), out.lon.push_back(p.lon[i]), out.alt.push_back(p.alt[i]);
      out.speed.push_back(p.speed[i]), out.track.push_back(p.track[i]), out.vrate.push_back(p.vrate[i]);
      out.on_ground.push_back(p.on_ground[i]);
    }
    for (Flight f : t.flights()) {
      f.begin += static_cast<std::uint32_t>(n * c), f.end += static_cast<std::uint32_t>(n * c);
      f.t_min += dt, f.t_max += dt;
      flights.push_back(std::move(f));
    }
  }
  return TrailSet(std::move(out), std::move(flights));
}

std::uint64_t folder_bytes(const fs::path& dir) {
  std::uint64_t b = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) b += e.file_size();
  return b;
}

/// The cluster's bytes on disk for `table`_local rows of dataset `id`, over every replica.
std::uint64_t cluster_bytes(ClickHouseStore& s, const std::string& table, const std::string& id) {
  const std::string out = s.client().query(
      "SELECT sum(bytes_on_disk) FROM cluster(" + ClickHouseClient::quote(s.cluster()) +
      ", system, parts) WHERE database = " + ClickHouseClient::quote(s.database()) + " AND table = '" +
      table + "_local' AND active AND partition = " + ClickHouseClient::quote(id) + " FORMAT TSV");
  return std::stoull(out);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const std::string so6 = a.get("so6"), url_text = a.get("store");
    const int reps = static_cast<int>(a.num("reps", 15)), big_reps = static_cast<int>(a.num("big-reps", 3));
    auto list = [&](const std::string& key, const std::string& def) {
      std::vector<int> v;
      std::stringstream ss(a.get(key, def));
      for (std::string w; std::getline(ss, w, ',');)
        if (!w.empty()) v.push_back(std::stoi(w));
      return v;
    };
    const std::vector<int> scales = list("scales", "1"), demo_scales = list("demo-scales", "");
    const fs::path tmp = a.get("tmp", (fs::temp_directory_path() / "clickhouse_store_bench").string());
    if (so6.empty() || url_text.empty() || reps < 1 || big_reps < 1) {
      std::cerr
          << "usage: clickhouse_store_bench --so6 PATH --store clickhouse://... [--reps 15] [--scales 1] "
             "[--demo-scales 1,8] [--demo-source DIR] [--big-reps 3] [--tmp DIR]\n";
      return 2;
    }
    const ClickHouseUrl url = ClickHouseUrl::parse(url_text);
    ingest::IngestReport report;
    struct Set {
      std::string name;
      std::shared_ptr<const TrailSet> day;
      int scale;
    };
    std::vector<Set> sets;
    {
      const auto so6_day = std::make_shared<const TrailSet>(ingest::ingest_file(so6, {}, &report));
      for (const int k : scales) sets.push_back({"so6_europe_day", so6_day, k});
      if (!demo_scales.empty()) {
        const auto demo_day = std::make_shared<const TrailSet>(
            generate_demo(demo_source(a), static_cast<std::size_t>(a.num("demo-flights", 7400)), 42));
        for (const int k : demo_scales) sets.push_back({"demo_day", demo_day, k});
      }
    }
    while (!sets.empty()) {
      Set set = std::move(sets.front());
      sets.erase(sets.begin());
      const int scale = set.scale;
      auto ds = std::make_shared<Dataset>();
      ds->trails = scale == 1 ? set.day : std::make_shared<const TrailSet>(repeat_days(*set.day, scale));
      // The day stays only while a later set repeats it.
      if (std::none_of(sets.begin(), sets.end(), [&](const Set& s) { return s.day == set.day; }))
        set.day.reset();
      ds->id = "bench-" + set.name + "-x" + std::to_string(scale), ds->name = ds->id;
      ds->format = set.name == "demo_day" ? "demo" : "so6";
      ds->created = "2026-11-26T00:00:00Z", ds->ingest = report.to_json();
      const std::size_t num_points = ds->trails->num_points(), num_flights = ds->trails->num_flights();
      std::uint64_t segments = 0;
      for (const Flight& f : ds->trails->flights()) segments += f.size() > 1 ? f.size() - 1 : 0;
      const std::string label =
          set.name + " x" + std::to_string(scale) + " (" + std::to_string(num_points) + " points)";
      const int n_reps = num_points > 10'000'000 ? big_reps : reps;

      // The embedded store's ingest: its column files written (the parse is the same for both stores).
      fs::remove_all(tmp);
      double emb_put_ms = 0;
      std::uint64_t emb_bytes = 0;
      {
        EmbeddedStore emb(tmp / "embedded");
        const auto t0 = Clock::now();
        emb.put(ds);
        emb_put_ms = ms_since(t0);
        emb_bytes = folder_bytes(tmp / "embedded");
      }
      fs::remove_all(tmp);

      ClickHouseStore store(url, true);
      if (store.contains(ds->id)) store.remove(ds->id);
      auto t0 = Clock::now();
      store.put(ds);
      const double put_ms = ms_since(t0);
      const std::uint64_t pbytes = cluster_bytes(store, "points", ds->id),
                          sbytes = cluster_bytes(store, "segments", ds->id),
                          fbytes = cluster_bytes(store, "flights", ds->id),
                          ebytes = cluster_bytes(store, "events", ds->id);
      log(label + ": put " + std::to_string(put_ms / 1000) + " s into the cluster, " +
          std::to_string(emb_put_ms / 1000) + " s into the embedded store");
      ds.reset();  // one copy in memory at a time: the fetched one from here on

      // The store as a server holds it after a restart: a fresh open, the dataset described (no point
      // read), then its copy fetched once for the computations that need every point.
      ClickHouseStore fresh(url);
      const std::string id = "bench-" + set.name + "-x" + std::to_string(scale);
      t0 = Clock::now();
      const auto held = fresh.describe(id);
      const double describe_ms = ms_since(t0);
      t0 = Clock::now();
      const auto copy = fresh.get(id);
      const double fetch_ms = ms_since(t0);
      const TrailSet& t = *copy->trails;
      emit({{"bench", "clickhouse_store_put"},
            {"set", set.name},
            {"scale", scale},
            {"points", num_points},
            {"flights", num_flights},
            {"segments", segments},
            {"nodes", url.hosts.size()},
            {"put_ms", std::round(put_ms)},
            {"points_per_s", std::round(num_points / (put_ms / 1000))},
            {"rows_per_s", std::round((num_points + segments + num_flights) / (put_ms / 1000))},
            {"embedded_put_ms", std::round(emb_put_ms)},
            {"embedded_points_per_s", std::round(num_points / (emb_put_ms / 1000))},
            {"embedded_disk_bytes", emb_bytes},
            {"cluster_points_bytes", pbytes},
            {"cluster_segments_bytes", sbytes},
            {"cluster_flights_bytes", fbytes},
            {"cluster_events_bytes", ebytes},
            {"describe_ms", std::round(describe_ms * 10) / 10},
            {"fetch_ms", std::round(fetch_ms)},
            {"peak_rss_mib", std::round(peak_rss_mib())}});
      log(label + ": describe " + std::to_string(describe_ms) + " ms, fetch " + std::to_string(fetch_ms) +
          " ms");

      std::vector<std::string> sqls;
      fresh.on_read([&](const std::string& sql, double) { sqls.push_back(sql); });
      ClickHouseClient plain(url.hosts);
      const ClickHouseClient::Settings settings = {{"max_query_size", std::to_string(64u << 20)}};
      const LocalReads local;
      // A density tile over the data (z4, 256 px, count, eq_hist, no filter: a tile the store aggregates
      // on the shards): Europe's 4/8/5, the demo's (the United States) 4/3/6. Warm: its level's span
      // computed once and cached by the renderer, so the timings are the tile's aggregate, shading and PNG.
      // Cold: a new renderer each time, the span computed too.
      density::DensityRenderer renderer;
      density::TileRequest tile;
      tile.tile = set.name == "demo_day" ? geo::TileId{4, 3, 6} : geo::TileId{4, 8, 5};
      tile.max_gap_seconds =
          std::numeric_limits<double>::infinity();  // as the tile route draws stored flights

      const double mid = std::floor((t.t_min() + t.t_max()) / 2 / 3600) * 3600;
      Query hour;
      hour.t0 = mid, hour.t1 = mid + 3600;
      struct Read {
        std::string name;
        std::function<std::string(const DatasetReads&, const Dataset&)> run;
      };
      const std::vector<Read> reads = {
          {"summary_whole",
           [&](const DatasetReads& r, const Dataset& d) { return r.summarize(d, {}, {}).to_json().dump(); }},
          {"summary_1h", [&](const DatasetReads& r,
                             const Dataset& d) { return r.summarize(d, hour, {}).to_json().dump(); }},
          {"flights_1h_page",
           [&](const DatasetReads& r, const Dataset& d) {
             return r.list_flights(d, hour, 0, 100, {}).to_json().dump();
           }},
          {"positions_at",
           [&](const DatasetReads& r, const Dataset& d) {
             return r.positions_at(d, mid + 1800, {}, 100000).to_json().dump();
           }},
          {"tile_warm_span", [&](const DatasetReads& r,
                                 const Dataset& d) { return r.density_tile(d, renderer, id, {}, tile); }},
          {"tile_cold",
           [&](const DatasetReads& r, const Dataset& d) {
             density::DensityRenderer cold;
             return r.density_tile(d, cold, id, {}, tile);
           }},
      };
      for (const Read& rd : reads) {
        // Once before the SQL is captured, so that a read with a warm cache (the tile's span) is timed and
        // compared with the SQL it sends when warm, not with the span's SQL of its first call.
        (void)rd.run(fresh, *held);
        sqls.clear();
        const std::string ours = rd.run(fresh, *held);
        const std::vector<std::string> captured = sqls;
        const std::string theirs = rd.run(local, *copy);
        const bool match = ours == theirs;
        if (!match) {  // where the answers part, for the log
          std::size_t at = 0;
          while (at < ours.size() && at < theirs.size() && ours[at] == theirs[at]) ++at;
          const std::size_t from = at > 80 ? at - 80 : 0;
          log(label + " " + rd.name + ": the answers part at byte " + std::to_string(at) +
              ":\n  cluster:  " + ours.substr(from, 160) + "\n  embedded: " + theirs.substr(from, 160));
        }
        std::vector<double> ts, ch, em;
        for (int i = 0; i < n_reps; ++i) {
          t0 = Clock::now();
          (void)rd.run(fresh, *held);
          ts.push_back(ms_since(t0));
          t0 = Clock::now();
          for (const auto& sql : captured) (void)plain.query(sql, settings);
          ch.push_back(ms_since(t0));
          t0 = Clock::now();
          (void)rd.run(local, *copy);
          em.push_back(ms_since(t0));
        }
        const Stats s_ts = Stats::of(ts), s_ch = Stats::of(ch), s_em = Stats::of(em);
        json rec = {{"bench", "clickhouse_store_read"},
                    {"set", set.name},
                    {"scale", scale},
                    {"points", num_points},
                    {"read", rd.name},
                    {"tile", rd.name.rfind("tile", 0) == 0
                                 ? std::to_string(tile.tile.z) + "/" + std::to_string(tile.tile.x) + "/" +
                                       std::to_string(tile.tile.y)
                                 : ""},
                    {"reps", n_reps},
                    {"sql_queries", captured.size()},
                    {"answer_bytes", ours.size()},
                    {"match_embedded", match},
                    {"overhead", std::round((s_ts.p50 / s_ch.p50 - 1) * 1000) / 1000}};
        s_ts.put(rec, "trailscope_ms_");
        s_ch.put(rec, "clickhouse_ms_");
        s_em.put(rec, "embedded_ms_");
        emit(rec);
        log(label + " " + rd.name + ": trailscope p50 " + std::to_string(s_ts.p50) +
            " ms, clickhouse's SQL " + std::to_string(s_ch.p50) + " ms, embedded " +
            std::to_string(s_em.p50) + " ms" + (match ? "" : "  MISMATCH with the embedded store"));
      }
      store.remove(id);
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "clickhouse_store_bench: " << e.what() << "\n";
    return 1;
  }
}
