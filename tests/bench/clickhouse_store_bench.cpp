// The server's overhead on the ClickHouse store: the Europe SO6 day put into a cluster (--store, e.g. the
// URL tests/cluster/cluster.sh prints), then, for each read the routes push down to the shards (a
// whole-day and a 1-hour summary, a 1-hour flight list, positions at an instant, a density tile), three
// timings:
//  - trailscope: the store's answer as the route serialises it (ClickHouseStore's DatasetReads call and
//    to_json().dump(): the SQL, the merge with compute/'s finishing code, and what stays on the server —
//    the summary's position jumps on the server's copy, the JSON);
//  - clickhouse: the same SQL the store sent, run alone through a plain client: ClickHouse's own time for
//    the same result, over the same HTTP interface;
//  - embedded: compute/ on the same trails in this process (LocalReads), for scale.
// overhead = trailscope p50 / clickhouse p50 − 1. Each answer is checked to be the embedded store's bytes.
// The tile (z4 over Europe, count, no filter: the case the store aggregates on the shards) is timed with
// its level's span already cached, as every tile of a zoom after the first.
//
//   clickhouse_store_bench --so6 PATH --store clickhouse://HOST:PORT[,...]/DB?cluster=NAME [--reps 15]
//
// Records: {"bench":"clickhouse_store_put"} (rows/s of the ingest into the cluster) and one
// {"bench":"clickhouse_store_read","read",...} per read.
#include <cmath>

#include "bench_util.hpp"
#include "store/clickhouse_store.hpp"
#include "store/dataset_reads.hpp"
#include "trailscope/ingest/ingest.hpp"

using namespace bench;
using namespace trailscope;
using trailscope::server::ClickHouseClient;
using trailscope::server::ClickHouseStore;
using trailscope::server::ClickHouseUrl;
using trailscope::server::Dataset;
using trailscope::server::DatasetReads;
using trailscope::server::LocalReads;

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const std::string so6 = a.get("so6"), url_text = a.get("store");
    const int reps = static_cast<int>(a.num("reps", 15));
    if (so6.empty() || url_text.empty() || reps < 1) {
      std::cerr << "usage: clickhouse_store_bench --so6 PATH --store clickhouse://... [--reps 15]\n";
      return 2;
    }
    const ClickHouseUrl url = ClickHouseUrl::parse(url_text);
    ingest::IngestReport report;
    auto ds = std::make_shared<Dataset>();
    ds->trails = std::make_shared<const TrailSet>(ingest::ingest_file(so6, {}, &report));
    ds->id = "bench-europe", ds->name = "Europe 2018-01-01", ds->format = "so6";
    ds->created = "2026-11-26T00:00:00Z", ds->ingest = report.to_json();
    const TrailSet& t = *ds->trails;

    ClickHouseStore store(url, true);
    if (store.contains(ds->id)) store.remove(ds->id);
    auto t0 = Clock::now();
    store.put(ds);
    const double put_ms = ms_since(t0);
    emit({{"bench", "clickhouse_store_put"},
          {"dataset", "so6_europe_day"},
          {"points", t.num_points()},
          {"flights", t.num_flights()},
          {"nodes", url.hosts.size()},
          {"put_ms", std::round(put_ms)},
          {"points_per_s", std::round(t.num_points() / (put_ms / 1000))}});
    log("put " + std::to_string(t.num_points()) + " points in " + std::to_string(put_ms / 1000) + " s");

    // The store as a server holds it after a restart: a fresh open, the dataset fetched once.
    ClickHouseStore fresh(url);
    const auto held = fresh.get(ds->id);
    std::vector<std::string> sqls;
    fresh.on_read([&](const std::string& sql, double) { sqls.push_back(sql); });
    ClickHouseClient plain(url.hosts);
    const ClickHouseClient::Settings settings = {{"max_query_size", std::to_string(64u << 20)}};
    const LocalReads local;
    // A density tile over Europe (z4, 256 px, count, eq_hist): its level's span is computed once and cached
    // by the renderer, so the timings are the tile's aggregate, shading and PNG.
    density::DensityRenderer renderer;
    density::TileRequest tile;
    tile.tile = geo::TileId{4, 8, 5};
    tile.max_gap_seconds = std::numeric_limits<double>::infinity();  // as the tile route draws stored flights

    const double mid = std::floor((t.t_min() + t.t_max()) / 2 / 3600) * 3600;
    Query hour;
    hour.t0 = mid, hour.t1 = mid + 3600;
    struct Read {
      std::string name;
      std::function<std::string(const DatasetReads&)> run;
    };
    const std::vector<Read> reads = {
        {"summary_whole_day",
         [&](const DatasetReads& r) { return r.summarize(*held, {}, {}).to_json().dump(); }},
        {"summary_1h", [&](const DatasetReads& r) { return r.summarize(*held, hour, {}).to_json().dump(); }},
        {"flights_1h_page",
         [&](const DatasetReads& r) { return r.list_flights(*held, hour, 0, 100, {}).to_json().dump(); }},
        {"positions_at",
         [&](const DatasetReads& r) {
           return r.positions_at(*held, mid + 1800, {}, 100000).to_json().dump();
         }},
        {"tile_4_8_5",
         [&](const DatasetReads& r) { return r.density_tile(*held, renderer, "europe", {}, tile); }},
    };
    for (const Read& rd : reads) {
      sqls.clear();
      const std::string ours = rd.run(fresh);
      const std::vector<std::string> captured = sqls;
      const bool match = ours == rd.run(local);
      std::vector<double> ts, ch, em;
      for (int i = 0; i < reps; ++i) {
        t0 = Clock::now();
        (void)rd.run(fresh);
        ts.push_back(ms_since(t0));
        t0 = Clock::now();
        for (const auto& sql : captured) (void)plain.query(sql, settings);
        ch.push_back(ms_since(t0));
        t0 = Clock::now();
        (void)rd.run(local);
        em.push_back(ms_since(t0));
      }
      const Stats s_ts = Stats::of(ts), s_ch = Stats::of(ch), s_em = Stats::of(em);
      json rec = {{"bench", "clickhouse_store_read"},
                  {"dataset", "so6_europe_day"},
                  {"read", rd.name},
                  {"reps", reps},
                  {"sql_queries", captured.size()},
                  {"answer_bytes", ours.size()},
                  {"match_embedded", match},
                  {"overhead", std::round((s_ts.p50 / s_ch.p50 - 1) * 1000) / 1000}};
      s_ts.put(rec, "trailscope_ms_");
      s_ch.put(rec, "clickhouse_ms_");
      s_em.put(rec, "embedded_ms_");
      emit(rec);
      log(rd.name + ": trailscope p50 " + std::to_string(s_ts.p50) + " ms, clickhouse's SQL " +
          std::to_string(s_ch.p50) + " ms, embedded " + std::to_string(s_em.p50) + " ms" +
          (match ? "" : "  MISMATCH with the embedded store"));
    }
    store.remove(ds->id);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "clickhouse_store_bench: " << e.what() << "\n";
    return 1;
  }
}
