// Density-tile latency: DensityRenderer::render_tile() (aggregate of line segments → shade → PNG) for
// 256 px tiles, cold (a new renderer: empty span cache, so the shared colour span is computed too) and
// with the span cached (the tile itself is never cached in-process: the server's LRU does that, measured
// by http_bench and wrk), on the CPU reference and on the OpenCL backend; a per-stage breakdown; and, with
// --clickhouse, the adsb.exposed-style tile in ClickHouse 18.16 (points per pixel by integer shifts of
// UInt32 Mercator columns, GROUP BY pixel) over the same points, checked against a C++ point raster
// (informational: not the same tile), and the LINE-density tile in ClickHouse (peer_line_tile_sql over a
// segment table: the same counts as TrailScope's aggregate, checked pixel for pixel against
// density_lines_ref on the tile's canvas), which the tile target compares with.
//
//   tile_bench [--so6 PATH] [--demo-flights N] [--reps 15] [--demo-reps 7] [--clickhouse URL] [--ch-reps 10]
//
// Data sets: the Europe SO6 day (--so6; drawn with max_gap = +inf: its Douglas-Peucker segments are
// long), and, with --demo-flights, the generated US day (default gap).
// Records: {"bench":"dataset"}, {"bench":"tile","impl":"trailscope","backend","mode":"cold"|"span_warm"},
// {"bench":"tile_first_call"} (the first OpenCL call of the process: context + kernel build),
// {"bench":"tile_stages"}, {"bench":"peer_load"}, {"bench":"tile","impl":"clickhouse"|"clickhouse_lines"},
// {"bench":"tile_peer"} (point tile), {"bench":"tile_peer_lines"} (line tile).
#include <cmath>
#include <limits>

#include "bench_util.hpp"
#include "store/clickhouse_tile_sql.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/density/density.hpp"
#include "trailscope/ingest/ingest.hpp"

using namespace bench;
namespace ts = trailscope;
namespace den = trailscope::density;

struct TileCase {
  ts::geo::TileId tile;
  std::string label;
};

struct DataCase {
  std::string name;
  ts::TrailSet set;
  double max_gap;
  std::vector<TileCase> tiles;
};

static den::TileRequest request(const TileCase& tc, const DataCase& d, ts::Backend b) {
  den::TileRequest r;
  r.tile = tc.tile;
  r.size = 256;
  r.value = den::DensityValue::count;
  r.how = den::How::eq_hist;
  r.cmap = "fire";
  r.max_gap_seconds = d.max_gap;
  r.backend = b;
  return r;
}

static std::string tile_name(const ts::geo::TileId& t) {
  return ts::geo::to_string(t);
}

/// The line-density count tile in ClickHouse over a peer segment table (peer_seg_layouts(): columns xa,
/// ya, xb, yb, their bbox xmin..ymax, seg, prev_dt): the SQL the ClickHouse store sends to its shards
/// (store/clickhouse_tile_sql.hpp line_tile_sql), with the peer table's run breaks: a segment continues a
/// run when it is not its flight's first and, with a finite `max_gap`, the step before it is at most
/// max_gap (longer steps are not drawn). Not covered: the extra copies of segments across 180° (none
/// meets the benchmark's tiles).
std::string peer_line_tile_sql(const std::string& table, const trailscope::geo::TileId& t, int size,
                               double max_gap) {
  namespace geo = trailscope::geo;
  const std::int64_t x0 = geo::tile_origin_x(t), y0 = geo::tile_origin_y(t), span = geo::tile_size_units(t.z);
  const std::int64_t P = span / size;
  const bool gap = std::isfinite(max_gap);
  return trailscope::server::line_tile_sql(
      {P, x0 / P, y0 / P, size, size}, gap ? "(seg > 0 AND prev_dt <= " + lit(max_gap) + ")" : "(seg > 0)",
      "xa", "ya", "xb", "yb",
      "FROM " + table + " WHERE xmax >= " + std::to_string(x0) + " AND xmin < " + std::to_string(x0 + span) +
          " AND ymax >= " + std::to_string(y0) + " AND ymin < " + std::to_string(y0 + span) +
          (gap ? " AND t1 - t0 <= " + lit(max_gap) : ""));
}

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const int reps_default = static_cast<int>(a.num("reps", 15));
    // The demo tiles cost up to seconds each when cold: fewer runs (--demo-reps) keep the script short.
    const int demo_reps = static_cast<int>(a.num("demo-reps", std::min(reps_default, 7)));
    const int ch_reps = static_cast<int>(a.num("ch-reps", 10));
    const ts::Query all;  // no filter: the whole day

    std::vector<DataCase> data;
    if (a.has("so6")) {
      ts::ingest::IngestReport rep;
      DataCase d{"europe",
                 ts::ingest::ingest_file(a.get("so6"), {}, &rep),
                 std::numeric_limits<double>::infinity(),
                 {}};
      d.tiles = {{{4, 8, 5}, "z4 central Europe (0-22.5E, 41-55.8N)"},
                 {{3, 4, 2}, "z3 north/central Europe (0-45E, 41-66.5N)"},
                 {{4, 7, 5}, "z4 western Europe (22.5W-0, 41-55.8N)"}};
      emit({{"bench", "dataset"},
            {"name", d.name},
            {"file", a.get("so6")},
            {"flights", d.set.num_flights()},
            {"points", d.set.num_points()}});
      data.push_back(std::move(d));
    }
    if (a.has("demo-flights")) {
      double gen_s = 0;
      DataCase d{"demo",
                 generate_demo(demo_source(a), static_cast<std::size_t>(a.num("demo-flights", 14000)),
                               static_cast<std::uint64_t>(a.num("seed", 42)), &gen_s),
                 ts::limits::kFlightGapSeconds,
                 {}};
      d.tiles = {{{4, 4, 6}, "z4 south-east US (90-67.5W, 22-41N)"},
                 {{3, 2, 3}, "z3 eastern US (90-45W, 0-41N)"}};
      emit({{"bench", "dataset"},
            {"name", d.name},
            {"flights", d.set.num_flights()},
            {"points", d.set.num_points()},
            {"generate_s", gen_s}});
      data.push_back(std::move(d));
    }
    if (data.empty()) {
      std::cerr << "usage: tile_bench [--so6 PATH] [--demo-flights N] [--reps N] [--clickhouse URL] "
                   "[--ch-reps N]\n";
      return 2;
    }

    // The first OpenCL call of the process pays for the context and the kernel build (PoCL caches the
    // compiled kernel in POCL_CACHE_DIR, so a second process is faster): reported on its own.
    {
      den::DensityRenderer r;
      const auto t0 = Clock::now();
      const auto res = r.render_tile(data[0].set, data[0].name, all,
                                     request(data[0].tiles[0], data[0], ts::Backend::opencl));
      emit({{"bench", "tile_first_call"},
            {"backend", "opencl"},
            {"path", res.path},
            {"ms", ms_since(t0)},
            {"pocl_cache_dir", std::getenv("POCL_CACHE_DIR") ? std::getenv("POCL_CACHE_DIR") : ""}});
    }

    std::map<std::string, double> ts_cold, ts_warm, ts_agg;  // "<data>/<tile>" → cpu p50
    for (const DataCase& d : data) {
      const int reps = d.name == "demo" ? demo_reps : reps_default;
      for (const TileCase& tc : d.tiles) {
        const std::string key = d.name + "/" + tile_name(tc.tile);
        for (const ts::Backend b : {ts::Backend::cpu, ts::Backend::opencl}) {
          const den::TileRequest req = request(tc, d, b);
          std::string path;
          std::uint64_t max_count = 0;
          std::size_t png_bytes = 0;
          // Cold: a new renderer each time (no span cached). Warm-up once (page faults, TBB arena).
          std::vector<double> cold, cold_inner;
          for (int i = -1; i < reps; ++i) {
            den::DensityRenderer r;
            const auto t0 = Clock::now();
            const den::TileResult res = r.render_tile(d.set, d.name, all, req);
            const double ms = ms_since(t0);
            if (res.span_cached) throw std::runtime_error("a new renderer reported a cached span");
            path = res.path, max_count = res.max_count, png_bytes = res.png.size();
            if (i >= 0) cold.push_back(ms), cold_inner.push_back(res.ms);
          }
          // Span warm: one renderer, span computed by the first call; the tile is rendered every time.
          std::vector<double> warm;
          den::DensityRenderer r;
          r.render_tile(d.set, d.name, all, req);
          for (int i = 0; i < reps; ++i) {
            const auto t0 = Clock::now();
            const den::TileResult res = r.render_tile(d.set, d.name, all, req);
            warm.push_back(ms_since(t0));
            if (!res.span_cached) throw std::runtime_error("span not cached on a repeated request");
          }
          for (const auto& [mode, v] : {std::pair{"cold", &cold}, std::pair{"span_warm", &warm}}) {
            json rec = {{"bench", "tile"},
                        {"impl", "trailscope"},
                        {"dataset", d.name},
                        {"tile", tile_name(tc.tile)},
                        {"label", tc.label},
                        {"size", 256},
                        {"backend", ts::to_string(b)},
                        {"path", path},
                        {"mode", mode},
                        {"max_count", max_count},
                        {"png_bytes", png_bytes},
                        {"reps", reps}};
            const Stats s = Stats::of(*v);
            s.put(rec, "ms_");
            emit(rec);
            log("tile " + key + " " + ts::to_string(b) + " (" + path + ") " + mode + ": p50 " +
                std::to_string(s.p50) + " ms");
            if (b == ts::Backend::cpu) (std::string(mode) == "cold" ? ts_cold : ts_warm)[key] = s.p50;
          }
        }

        // Where the time goes (CPU reference and OpenCL aggregate), each stage timed on its own.
        {
          const den::Canvas canvas = den::Canvas::for_tile(tc.tile, 256);
          std::vector<double> span_ms, prep_ms, lines_cpu_ms, lines_ocl_ms, shade_ms, png_ms;
          std::size_t segments = 0;
          for (int i = 0; i < reps; ++i) {
            auto t0 = Clock::now();
            const den::SpanStats span = den::estimate_span(d.set, all, den::DensityValue::count, tc.tile.z,
                                                           256, 0, d.max_gap, ts::Backend::cpu);
            span_ms.push_back(ms_since(t0));
            t0 = Clock::now();
            const den::LineSegments segs =
                den::prepare_line_segments(d.set, all, canvas, den::DensityValue::count, d.max_gap);
            prep_ms.push_back(ms_since(t0));
            segments = segs.size();
            t0 = Clock::now();
            const den::Aggregate agg = den::density_lines(segs, ts::Backend::cpu);
            lines_cpu_ms.push_back(ms_since(t0));
            t0 = Clock::now();
            const den::Aggregate agg2 = den::density_lines(segs, ts::Backend::opencl);
            lines_ocl_ms.push_back(ms_since(t0));
            if (!agg.same_numbers(agg2))
              throw std::runtime_error("OpenCL and CPU aggregates differ on " + key);
            t0 = Clock::now();
            den::ShadeOptions so;
            const den::Image img = den::shade(den::to_raster(agg, den::DensityValue::count), span, so);
            shade_ms.push_back(ms_since(t0));
            t0 = Clock::now();
            const std::string png = den::encode_png(img);
            png_ms.push_back(ms_since(t0));
          }
          json rec = {{"bench", "tile_stages"},
                      {"dataset", d.name},
                      {"tile", tile_name(tc.tile)},
                      {"segments", segments},
                      {"reps", reps}};
          rec["span_estimate_ms_p50"] = Stats::of(span_ms).p50;
          rec["prepare_segments_ms_p50"] = Stats::of(prep_ms).p50;
          rec["density_lines_cpu_ms_p50"] = Stats::of(lines_cpu_ms).p50;
          rec["density_lines_opencl_ms_p50"] = Stats::of(lines_ocl_ms).p50;
          rec["raster_shade_ms_p50"] = Stats::of(shade_ms).p50;
          rec["encode_png_ms_p50"] = Stats::of(png_ms).p50;
          ts_agg[key] = Stats::of(prep_ms).p50 + Stats::of(lines_cpu_ms).p50;
          emit(rec);
        }
      }
    }

    if (!a.has("clickhouse")) return 0;
    ClickHouse ch(a.get("clickhouse"));
    for (const DataCase& d : data) {
      json load = load_peer(ch, d.name, d.set);
      load["clickhouse_version"] = ch.version();
      emit(load);
      json seg_load = load_peer_segments(ch, d.name, d.set);
      emit(seg_load);
      for (const TileCase& tc : d.tiles) {
        const std::string key = d.name + "/" + tile_name(tc.tile);
        const auto t0 = Clock::now();
        const std::vector<std::uint32_t> ref = point_raster(d.set, tc.tile, 256);
        const double ref_ms = ms_since(t0);
        std::uint64_t in_tile = 0, nonzero = 0;
        for (auto c : ref) in_tile += c, nonzero += c != 0;
        double best = INFINITY, best_wall = INFINITY;
        std::string best_layout;
        bool all_match = true;
        for (const auto& l : peer_layouts()) {
          const std::string table = d.name + "_" + l.suffix;
          const std::string sql = peer_tile_sql(table, tc.tile, 256);
          std::vector<double> wall, server;
          std::vector<std::string> diff;
          for (int i = -1; i < ch_reps; ++i) {
            const auto r = ch.query(sql);
            if (i < 0)
              diff = compare_tile(ref, r.result);
            else
              wall.push_back(r.wall_ms), server.push_back(r.server_ms);
          }
          json rec = {{"bench", "tile"},           {"impl", "clickhouse"},
                      {"dataset", d.name},         {"tile", tile_name(tc.tile)},
                      {"layout", l.suffix},        {"table", table},
                      {"points_in_tile", in_tile}, {"pixels", nonzero},
                      {"reps", ch_reps},           {"sql", sql}};
          const Stats sw = Stats::of(wall), ss = Stats::of(server);
          sw.put(rec, "wall_ms_");
          ss.put(rec, "server_ms_");
          report_match(rec, diff, "tile " + key + " on " + l.suffix);
          all_match = all_match && diff.empty();
          emit(rec);
          log("clickhouse tile " + key + " " + l.suffix + ": server p50 " + std::to_string(ss.p50) +
              " ms, wall p50 " + std::to_string(sw.p50) + " ms" + (diff.empty() ? "" : "  MISMATCH"));
          if (ss.p50 < best) best = ss.p50, best_layout = l.suffix;
          best_wall = std::min(best_wall, sw.p50);
        }
        emit({{"bench", "tile_peer"},
              {"dataset", d.name},
              {"tile", tile_name(tc.tile)},
              {"label", tc.label},
              {"points_in_tile", in_tile},
              {"point_pixels", nonzero},
              {"bench_point_raster_ms", ref_ms},
              {"trailscope_cold_ms_p50", ts_cold[key]},
              {"trailscope_span_warm_ms_p50", ts_warm[key]},
              {"trailscope_count_only_ms_p50", ts_agg[key]},
              {"clickhouse_server_ms_p50", best},
              {"clickhouse_wall_ms_p50", best_wall},
              {"clickhouse_layout", best_layout},
              {"speedup_cold", std::round(best / ts_cold[key] * 100) / 100},
              {"speedup_span_warm", std::round(best / ts_warm[key] * 100) / 100},
              {"match", all_match}});

        // The LINE-density tile in ClickHouse (peer_line_tile_sql over the segment table), checked pixel
        // for pixel against TrailScope's count aggregate of the same tile (density_lines_ref).
        const den::Canvas canvas = den::Canvas::for_tile(tc.tile, 256);
        const den::Aggregate agg = den::density_lines_ref(
            den::prepare_line_segments(d.set, all, canvas, den::DensityValue::count, d.max_gap));
        std::vector<std::uint32_t> line_ref(agg.count.begin(), agg.count.end());
        std::uint64_t line_total = 0, line_nonzero = 0;
        for (auto c : line_ref) line_total += c, line_nonzero += c != 0;
        double lbest = INFINITY, lbest_wall = INFINITY;
        std::string lbest_layout;
        bool lall_match = true;
        std::vector<std::string> ldiff_any;
        for (const auto& l : peer_seg_layouts()) {
          const std::string table = d.name + "_seg_" + l.suffix;
          const std::string sql = peer_line_tile_sql(table, tc.tile, 256, d.max_gap);
          std::vector<double> wall, server;
          std::vector<std::string> diff;
          for (int i = -1; i < ch_reps; ++i) {
            const auto r = ch.query(sql);
            if (i < 0)
              diff = compare_tile(line_ref, r.result);
            else
              wall.push_back(r.wall_ms), server.push_back(r.server_ms);
          }
          json rec = {{"bench", "tile"},
                      {"impl", "clickhouse_lines"},
                      {"dataset", d.name},
                      {"tile", tile_name(tc.tile)},
                      {"layout", l.suffix},
                      {"table", table},
                      {"segment_pixels", line_total},
                      {"pixels", line_nonzero},
                      {"reps", ch_reps},
                      {"sql", sql}};
          const Stats sw = Stats::of(wall), ss = Stats::of(server);
          sw.put(rec, "wall_ms_");
          ss.put(rec, "server_ms_");
          report_match(rec, diff, "line tile " + key + " on " + l.suffix);
          if (!diff.empty()) ldiff_any = diff;
          lall_match = lall_match && diff.empty();
          emit(rec);
          log("clickhouse line tile " + key + " " + l.suffix + ": server p50 " + std::to_string(ss.p50) +
              " ms, wall p50 " + std::to_string(sw.p50) + " ms" +
              (diff.empty() ? "  (counts identical)" : "  MISMATCH"));
          if (ss.p50 < lbest) lbest = ss.p50, lbest_layout = l.suffix;
          lbest_wall = std::min(lbest_wall, sw.p50);
        }
        json lp = {{"bench", "tile_peer_lines"},
                   {"dataset", d.name},
                   {"tile", tile_name(tc.tile)},
                   {"label", tc.label},
                   {"segment_pixels", line_total},
                   {"pixels", line_nonzero},
                   {"trailscope_cold_ms_p50", ts_cold[key]},
                   {"trailscope_span_warm_ms_p50", ts_warm[key]},
                   {"trailscope_count_only_ms_p50", ts_agg[key]},
                   {"clickhouse_server_ms_p50", lbest},
                   {"clickhouse_wall_ms_p50", lbest_wall},
                   {"clickhouse_layout", lbest_layout},
                   {"speedup_cold", std::round(lbest / ts_cold[key] * 100) / 100},
                   {"speedup_span_warm", std::round(lbest / ts_warm[key] * 100) / 100},
                   {"speedup_count_only", std::round(lbest / ts_agg[key] * 100) / 100},
                   {"match", lall_match}};
        if (!ldiff_any.empty()) lp["mismatch"] = ldiff_any;
        emit(lp);
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "tile_bench: " << e.what() << "\n";
    return 1;
  }
}
