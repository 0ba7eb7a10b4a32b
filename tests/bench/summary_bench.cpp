// Summary latency: trailscope::summarize() over the generated demo day (≥ 10 M points), for a few
// airspace windows, p50/p95 over repeated runs; and, with --clickhouse, the same summaries computed by
// ClickHouse 18.16 over the same points (checked to agree), with the TrailScope/ClickHouse ratio.
//
//   summary_bench --flights 14000 [--seed 42] [--reps 30] [--clickhouse http://127.0.0.1:18123]
//                 [--ch-reps 10] [--demo-source DIR]
//
// Records: {"bench":"dataset"} (what was generated), {"bench":"summary","impl":"trailscope",...} per
// window, {"bench":"peer_load"}, {"bench":"summary","impl":"clickhouse","layout",...} per window × layout,
// {"bench":"summary_peer"} per window (TrailScope p50 vs the best ClickHouse layout's p50).
#include <cmath>

#include "bench_util.hpp"

using namespace bench;

struct Window {
  std::string name, label;
  std::map<std::string, std::string> params;
};

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const auto flights = static_cast<std::size_t>(a.num("flights", 14000));
    const auto seed = static_cast<std::uint64_t>(a.num("seed", 42));
    const int reps = static_cast<int>(a.num("reps", 30));
    const int ch_reps = static_cast<int>(a.num("ch-reps", 10));

    double gen_s = 0;
    const trailscope::TrailSet set = generate_demo(demo_source(a), flights, seed, &gen_s);
    emit({{"bench", "dataset"},
          {"name", "demo"},
          {"flights", set.num_flights()},
          {"points", set.num_points()},
          {"generate_s", gen_s},
          {"seed", seed},
          {"peak_rss_mib", std::round(peak_rss_mib())}});
    if (set.num_points() < 10'000'000) log("WARNING: fewer than 10 M points; raise --flights");

    const long long day = static_cast<long long>(std::floor(set.t_min() / 86400.0)) * 86400;
    const auto at = [&](int hour) { return std::to_string(day + hour * 3600LL); };
    const std::vector<Window> windows = {
        {"whole_day", "whole day, no filter", {}},
        {"window_2h", "2-hour window 14:00-16:00 UTC", {{"t0", at(14)}, {"t1", at(16)}}},
        {"bbox_alt",
         "bbox -90,35,-70,45 (US north-east) + FL100-FL300, whole day",
         {{"bbox", "-90,35,-70,45"}, {"alt_min", "10000"}, {"alt_max", "30000"}}},
        {"bbox_alt_2h",
         "same bbox + band, 14:00-16:00 UTC",
         {{"bbox", "-90,35,-70,45"},
          {"alt_min", "10000"},
          {"alt_max", "30000"},
          {"t0", at(14)},
          {"t1", at(16)}}},
    };

    std::map<std::string, trailscope::Summary> results;
    std::map<std::string, double> ts_p50;
    for (const Window& w : windows) {
      const trailscope::Query q = trailscope::parse_query(w.params);
      for (int i = 0; i < 3; ++i) results[w.name] = trailscope::summarize(set, q);  // warm-up
      std::vector<double> ms;
      for (int i = 0; i < reps; ++i) {
        const auto t0 = Clock::now();
        trailscope::Summary s = trailscope::summarize(set, q);
        ms.push_back(ms_since(t0));
        if (s.points != results[w.name].points) throw std::runtime_error("summary not deterministic");
      }
      const trailscope::Summary& s = results[w.name];
      const Stats st = Stats::of(ms);
      ts_p50[w.name] = st.p50;
      json rec = {{"bench", "summary"},
                  {"impl", "trailscope"},
                  {"window", w.name},
                  {"label", w.label},
                  {"params", w.params},
                  {"dataset_points", set.num_points()},
                  {"points", s.points},
                  {"flights", s.flights},
                  {"time_bins", s.time_histogram.counts.size()},
                  {"alt_bins", s.altitude_histogram.counts.size()},
                  {"reps", reps}};
      st.put(rec, "ms_");
      emit(rec);
      log("summary " + w.name + ": " + std::to_string(s.points) + " points, p50 " + std::to_string(st.p50) +
          " ms");
    }

    if (!a.has("clickhouse")) return 0;
    ClickHouse ch(a.get("clickhouse"));
    json load = load_peer(ch, "demo", set);
    load["clickhouse_version"] = ch.version();
    emit(load);

    for (const Window& w : windows) {
      const trailscope::Query q = trailscope::parse_query(w.params);
      const trailscope::Summary& ours = results[w.name];
      double best = INFINITY, best_wall = INFINITY;
      std::string best_layout;
      bool all_match = true;
      for (const auto& l : peer_layouts()) {
        for (const bool key : {false, true}) {
          if (key && !q.bbox) continue;
          const std::string table = std::string("demo_") + l.suffix;
          const auto sql = peer_summary_sql(table, q, ours, key);
          std::vector<double> wall, server;
          std::vector<std::string> diff;
          for (int i = -1; i < ch_reps; ++i) {  // run -1 is the warm-up, and the one checked
            const auto r1 = ch.query(sql[0]);
            const auto r2 = ch.query(sql[1]);
            const auto r3 = ch.query(sql[2]);
            if (i < 0) {
              diff = compare_summary(ours, r1.result, r2.result, r3.result);
              continue;
            }
            wall.push_back(r1.wall_ms + r2.wall_ms + r3.wall_ms);
            server.push_back(r1.server_ms + r2.server_ms + r3.server_ms);
          }
          const std::string variant = std::string(l.suffix) + (key ? "+morton" : "");
          json rec = {{"bench", "summary"}, {"impl", "clickhouse"}, {"window", w.name}, {"layout", variant},
                      {"table", table},     {"reps", ch_reps},      {"sql", sql}};
          const Stats sw = Stats::of(wall), ss = Stats::of(server);
          sw.put(rec, "wall_ms_");
          ss.put(rec, "server_ms_");
          report_match(rec, diff, "summary " + w.name + " on " + variant);
          all_match = all_match && diff.empty();
          emit(rec);
          log("clickhouse summary " + w.name + " " + variant + ": server p50 " + std::to_string(ss.p50) +
              " ms, wall p50 " + std::to_string(sw.p50) + " ms" + (diff.empty() ? "" : "  MISMATCH"));
          if (ss.p50 < best) best = ss.p50, best_layout = variant;
          best_wall = std::min(best_wall, sw.p50);
        }
      }
      emit({{"bench", "summary_peer"},
            {"window", w.name},
            {"label", w.label},
            {"trailscope_ms_p50", std::round(ts_p50[w.name] * 1000) / 1000},
            {"clickhouse_server_ms_p50", std::round(best * 1000) / 1000},
            {"clickhouse_wall_ms_p50", std::round(best_wall * 1000) / 1000},
            {"clickhouse_layout", best_layout},
            {"speedup", std::round(best / ts_p50[w.name] * 100) / 100},
            {"match", all_match}});
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "summary_bench: " << e.what() << "\n";
    return 1;
  }
}
