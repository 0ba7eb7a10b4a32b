// Congestion counts on the Europe SO6 day (congestion/counts.hpp), and the same occupancy counts computed
// by ClickHouse in SQL as the peer.
//
//   congestion_bench --so6 PATH [--reps 5] [--clickhouse URL] [--ch-reps 5]
//
// Records: {"bench":"dataset"}, {"bench":"congestion","impl":"trailscope","case":...} for
//   - "grid_full": occupancy (method=interpolated, 1-min periods of 1 min) + rolling entry counts (60/20
//     min) + the PRU complexity per cell-hour, on the 20 NM x 20 NM x 3,000 ft grid (whole world extent,
//     0-60,000 ft), the whole day;
//   - "grid_samples": the occupancy by samples (method=samples, no complexity): what the peer computes;
// and, with --clickhouse, {"bench":"peer_load"} and {"bench":"congestion","impl":"clickhouse",
// "case":"grid_samples"} with "equal" (every (cell, period, count) the same as ours) and the ratio.
//
// The peer: ClickHouse 18.16 has no window functions, and the interpolated trajectory needs the
// sample after each sample; method=samples is what SQL expresses directly: each sample's cell (row,
// column, layer) from the same formulas as volumes.hpp (the row's column width is passed in as an array
// literal, so both sides divide by the same double) and its 1-min period, then uniqExact(flight) per
// (cell, period). Timed by ClickHouse's own statistics.elapsed (server side), best layout.
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "bench_util.hpp"
#include "trailscope/congestion/counts.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace ts = trailscope;
namespace cg = trailscope::congestion;
using namespace bench;

namespace {

// CPU seconds (user + system, all threads) of this process so far: the figure that stays meaningful
// when other work shares the machine.
double cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e3;
}

constexpr double kDay = 1514764800.0;  // 2018-01-01T00:00:00Z, the SO6 file's day

cg::CountsRequest grid_request(cg::Method m, bool complexity) {
  cg::CountsRequest r;
  r.query.t0 = kDay;
  r.query.t1 = kDay + 86400;
  r.method = m;
  r.complexity = complexity;
  return r;
}

// The peer's SQL over table `t`: per (row, col, layer, period) the number of distinct flights with a
// sample there, for samples with t in [t0, t1), a known altitude and a layer in [0, 20] (0-60,000 ft).
std::string peer_sql(const std::string& table) {
  std::string widths = "[", cols = "[";
  for (int r = 0; r < cg::kGridRows; ++r) {
    if (r) widths += ',', cols += ',';
    ts::append_shortest(widths, cg::grid_column_width(r));
    cols += std::to_string(cg::grid_columns(r));
  }
  widths += ']', cols += ']';
  const std::string H = ts::format_double(cg::kGridLayerMetres), T0 = ts::format_double(kDay);
  return "SELECT r, c, l, k, uniqExact(flight_id) AS n FROM ("
         " SELECT flight_id, toFloat64(lat) AS la, toFloat64(lon) AS lo0, toFloat64(alt) AS al,"
         " if(lo0 >= 180, -180., lo0) AS lo,"
         " toInt32(floor((la + 90) * 3)) AS r0,"
         " if(la >= 90, 539, r0 - toInt32(la < -90 + r0 / 3) + toInt32(la >= -90 + (r0 + 1) / 3)) AS r,"
         " arrayElement(" +
         widths +
         ", r + 1) AS w,"
         " arrayElement(" +
         cols +
         ", r + 1) AS ncol,"
         " greatest(0, least(ncol - 1, toInt32(floor((lo + 180) / w)))) AS c0,"
         " c0 - toInt32(c0 > 0 AND lo < -180 + c0 * w) + toInt32(c0 + 1 < ncol AND lo >= -180 + (c0 + 1) * "
         "w) AS c,"
         " toInt32(floor(al / " +
         H +
         ")) AS l0,"
         " l0 - toInt32(al < l0 * " +
         H + ") + toInt32(al >= (l0 + 1) * " + H +
         ") AS l,"
         " toInt32(floor((t - " +
         T0 +
         ") / 60)) AS k0,"
         " k0 - toInt32(t < " +
         T0 + " + k0 * 60) + toInt32(t >= " + T0 +
         " + (k0 + 1) * 60) AS k"
         " FROM " +
         table + " WHERE t >= " + T0 + " AND t < " + ts::format_double(kDay + 86400) +
         " AND isFinite(alt)"
         ") WHERE l >= 0 AND l <= 20 GROUP BY r, c, l, k";
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    if (!a.has("so6")) {
      std::cerr << "usage: congestion_bench --so6 PATH [--reps N] [--clickhouse URL] [--ch-reps N]\n";
      return 2;
    }
    const int reps = static_cast<int>(a.num("reps", 5));
    const int ch_reps = static_cast<int>(a.num("ch-reps", 5));
    const ts::TrailSet set = ts::ingest::ingest_file(a.get("so6"));
    emit({{"bench", "dataset"},
          {"name", "europe"},
          {"file", a.get("so6")},
          {"flights", set.num_flights()},
          {"points", set.num_points()}});

    cg::CountsResult samples_result;
    for (const auto& [name, method, complexity] : {std::tuple{"grid_full", cg::Method::interpolated, true},
                                                   std::tuple{"grid_samples", cg::Method::samples, false}}) {
      const cg::CountsRequest req = grid_request(method, complexity);
      std::vector<double> ms, cpu;
      cg::CountsResult res;
      for (int i = 0; i < reps + 1; ++i) {  // the first run warms caches and TBB's threads
        const double c0 = cpu_ms();
        const auto t0 = Clock::now();
        res = cg::count(set, req);
        if (i > 0) ms.push_back(ms_since(t0)), cpu.push_back(cpu_ms() - c0);
      }
      const Stats s = Stats::of(ms);
      std::uint64_t occ = 0, ent = 0;
      for (const auto& v : res.volumes) occ += v.occupancy.sum(), ent += v.entries.sum();
      json rec = {{"bench", "congestion"},
                  {"impl", "trailscope"},
                  {"case", name},
                  {"method", cg::to_string(method)},
                  {"complexity", complexity},
                  {"reps", s.n},
                  {"ms_p50", s.p50},
                  {"ms_min", s.min},
                  {"ms_max", s.max},
                  {"cells", res.volumes.size()},
                  {"occupancy_sum", occ},
                  {"entries_sum", ent},
                  {"flights", res.flights},
                  {"cpu_ms_p50", Stats::of(cpu).p50}};
      if (complexity) {
        rec["cell_hours"] = res.complexity.size();
        rec["complexity_score"] = res.complexity_total.score();
        rec["adjusted_density"] = res.complexity_total.adjusted_density();
        rec["structural_index"] = res.complexity_total.structural_index();
      }
      emit(rec);
      log(std::string("congestion ") + name + ": p50 " + std::to_string(s.p50) + " ms over " +
          std::to_string(res.volumes.size()) + " cells");
      if (method == cg::Method::samples) samples_result = std::move(res);
    }

    if (!a.has("clickhouse")) return 0;
    ClickHouse ch(a.get("clickhouse"));
    json load = load_peer(ch, "europe", set);
    load["clickhouse_version"] = ch.version();
    emit(load);
    // Ours as a set of (row, col, layer, period) -> count.
    std::map<std::tuple<int, int, int, std::uint32_t>, std::uint32_t> ours;
    for (const auto& v : samples_result.volumes) {
      const cg::GridCell c = cg::parse_grid_cell_id(v.id);
      for (std::size_t i = 0; i < v.occupancy.index.size(); ++i)
        ours[{c.row, c.col, c.layer, v.occupancy.index[i]}] = v.occupancy.value[i];
    }
    double best = std::numeric_limits<double>::infinity(), best_wall = 0;
    std::string best_layout;
    bool equal = true;
    std::size_t peer_rows = 0, mismatches = 0;
    for (const auto& l : peer_layouts()) {
      const std::string sql = peer_sql(std::string("europe_") + l.suffix);
      std::vector<double> server, wall;
      json rows;
      for (int i = 0; i < ch_reps + 1; ++i) {
        auto tq = ch.query(sql);
        if (i > 0) server.push_back(tq.server_ms), wall.push_back(tq.wall_ms);
        if (i == 0) rows = std::move(tq.result["data"]);
      }
      // Equal results: every row of the peer is ours, and as many.
      peer_rows = rows.size();
      std::size_t bad = 0;
      for (const auto& row : rows) {
        const auto key =
            std::tuple{row[0].get<int>(), row[1].get<int>(), row[2].get<int>(), row[3].get<std::uint32_t>()};
        const auto it = ours.find(key);
        if (it == ours.end() || it->second != row[4].get<std::uint32_t>()) ++bad;
      }
      if (rows.size() != ours.size())
        bad += rows.size() > ours.size() ? rows.size() - ours.size() : ours.size() - rows.size();
      if (bad) equal = false;
      mismatches = std::max(mismatches, bad);
      const Stats ss = Stats::of(server), sw = Stats::of(wall);
      log(std::string("clickhouse congestion ") + l.suffix + ": server p50 " + std::to_string(ss.p50) +
          " ms, " + std::to_string(rows.size()) + " rows, " + std::to_string(bad) + " differ");
      if (ss.p50 < best) best = ss.p50, best_wall = sw.p50, best_layout = l.suffix;
    }
    double our_samples_ms = 0;
    {
      std::vector<double> ms;
      for (int i = 0; i < reps; ++i) {
        const auto t0 = Clock::now();
        cg::count(set, grid_request(cg::Method::samples, false));
        ms.push_back(ms_since(t0));
      }
      our_samples_ms = Stats::of(ms).p50;
    }
    emit({{"bench", "congestion"},
          {"impl", "clickhouse"},
          {"case", "grid_samples"},
          {"reps", ch_reps},
          {"clickhouse_server_ms_p50", best},
          {"clickhouse_wall_ms_p50", best_wall},
          {"clickhouse_layout", best_layout},
          {"trailscope_ms_p50", our_samples_ms},
          {"ratio", best / our_samples_ms},
          {"rows", peer_rows},
          {"ours_rows", ours.size()},
          {"mismatches", mismatches},
          {"equal", equal}});
    return 0;  // a mismatch is reported ("equal": false) and marked in BENCHMARKS.md
  } catch (const std::exception& e) {
    std::cerr << "congestion_bench: " << e.what() << "\n";
    return 1;
  }
}
