#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>

#include "trailscope/core/json_text.hpp"
#include "trailscope/core/text.hpp"
#include "cli/commands.hpp"
#include "store/dataset_ingest.hpp"
#include "store/embedded_store.hpp"
#include "limits.hpp"
#include "formats/animation_chunk.hpp"
#include "trailscope/trails/animation_chunk.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/summary.hpp"

namespace trailscope::cli {

namespace {
using server::iso_utc;

void print_summary(const Summary& s) {
  std::printf("flights  %llu\npoints   %llu\n", static_cast<unsigned long long>(s.flights),
              static_cast<unsigned long long>(s.points));
  if (s.points) std::printf("window   %s .. %s\n", iso_utc(s.t_min).c_str(), iso_utc(s.t_max).c_str());
  if (s.speed.count)
    std::printf("speed    mean %.1f m/s, p50 %.1f, p95 %.1f, max %.1f\n", s.speed.mean, s.speed.p50,
                s.speed.p95, s.speed.max);
  if (!s.top_callsigns.empty()) {
    std::printf("top callsigns (points, flights):\n");
    for (const auto& c : s.top_callsigns)
      std::printf("  %-10s %10llu %6llu\n", c.callsign.c_str(), static_cast<unsigned long long>(c.points),
                  static_cast<unsigned long long>(c.flights));
  }
}

// One line per flight; unknown values print as "-".
void print_positions(const Positions& at) {
  std::printf("%zu flights at %s (t = %.3f)\n", at.positions.size(), iso_utc(at.t).c_str(), at.t);
  if (at.positions.empty()) return;
  std::printf("%8s %-6s %-9s %10s %11s %8s %8s %6s %8s %s\n", "id", "icao24", "callsign", "lat", "lon",
              "alt_m", "speed_ms", "track", "vrate_ms", "ground");
  const auto cell = [](double v, int width, int decimals) {
    char buf[32];
    if (v != v)
      std::snprintf(buf, sizeof buf, "%*s", width, "-");
    else
      std::snprintf(buf, sizeof buf, "%*.*f", width, decimals, v);
    return std::string(buf);
  };
  for (const Position& p : at.positions)
    std::printf("%8u %-6s %-9s %s %s %s %s %s %s %s\n", p.flight_id, p.icao24.c_str(), p.callsign.c_str(),
                cell(p.lat, 10, 5).c_str(), cell(p.lon, 11, 5).c_str(), cell(p.alt_m, 8, 0).c_str(),
                cell(p.speed_ms, 8, 1).c_str(), cell(p.track_deg, 6, 1).c_str(),
                cell(p.vrate_ms, 8, 1).c_str(), p.on_ground ? "yes" : "no");
}
}  // namespace

void add_query(CLI::App& app) {
  auto* cmd = app.add_subcommand("query", "Query an airspace time window of a dataset");
  cmd->require_subcommand(1);
  struct Opts {
    std::string data_dir = default_data_dir(), dataset;
    bool json = false;
    int bins = limits::kDefaultHistogramBins, top = 10;
    std::size_t page = 0, page_size = limits::kDefaultPageSize, flight_id = 0;
    std::string t;
    bool geojson = false;
    std::int64_t duration = limits::kDefaultAnimationChunkSeconds;
    std::string origin, out;
    std::string sort = "t_start", order = "asc";
    bool csv = false;
    std::string table = "totals";
    QueryFlags flags;
  };
  auto o = std::make_shared<Opts>();
  const auto common = [o](CLI::App* sub) {
    sub->add_option("DATASET", o->dataset, "dataset id")->required();
    sub->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
    sub->add_flag("--json", o->json, "print JSON (the REST API's body)");
    o->flags.add_to(*sub);
  };
  auto* summary = cmd->add_subcommand("summary", "Counts, histograms, speed statistics and top callsigns");
  common(summary);
  summary->add_option("--bins", o->bins, "time-histogram bins")->capture_default_str();
  summary->add_option("--top", o->top, "top callsigns listed")->capture_default_str();
  summary->add_flag("--csv", o->csv, "print one table as CSV (the API's format=csv)");
  summary
      ->add_option("--table", o->table,
                   "with --csv: totals, time_histogram, altitude_histogram or top_callsigns")
      ->capture_default_str();
  summary->callback([o] {
    if (o->csv && o->json) throw invalid_argument("csv", "--csv and --json exclude each other");
    if (o->csv) (void)Summary{}.to_csv(o->table);  // an unknown table is refused before the work
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    SummaryOptions opts;
    opts.bins = o->bins, opts.top_callsigns = o->top;
    if (o->flags.params.count("alt_unit") && o->flags.params["alt_unit"] == "m") opts.alt_unit = AltUnit::m;
    const Summary s = summarize(*ds->trails, parse_query(o->flags.params), opts);
    if (o->csv)
      std::cout << s.to_csv(o->table);
    else if (o->json)
      std::cout << json_text(s.to_json(), 2) << std::endl;
    else
      print_summary(s);
  });
  auto* flights = cmd->add_subcommand("flights", "The flights in the window, a page at a time");
  common(flights);
  flights->add_option("--page", o->page, "page, from 0")->capture_default_str();
  flights->add_option("--page-size", o->page_size, "flights per page")->capture_default_str();
  flights
      ->add_option("--sort", o->sort,
                   "column: id, icao24, callsign, in window t_start, t_end, duration_s, points, alt_max_m, "
                   "whole flight flight_t_start, flight_t_end, flight_duration_s, flight_points")
      ->capture_default_str();
  flights->add_option("--order", o->order, "asc or desc (ties by ascending id)")->capture_default_str();
  flights->callback([o] {
    const FlightSort sort = parse_flight_sort(o->sort, o->order);
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    const FlightPage p = list_flights(*ds->trails, parse_query(o->flags.params), o->page, o->page_size, sort);
    if (o->json) {
      std::cout << json_text(p.to_json(), 2) << std::endl;
      return;
    }
    std::printf("%llu flights; page %zu, by %s %s; in window | whole flight:\n",
                static_cast<unsigned long long>(p.total), p.page, o->sort.c_str(), o->order.c_str());
    for (const auto& f : p.flights)
      std::printf("%8u %-6s %-9s %s .. %s %7llu pts | %s .. %s %7llu pts\n", f.id, f.icao24.c_str(),
                  f.callsign.c_str(), iso_utc(f.t_start).c_str(), iso_utc(f.t_end).c_str(),
                  static_cast<unsigned long long>(f.points), iso_utc(f.flight_t_start).c_str(),
                  iso_utc(f.flight_t_end).c_str(), static_cast<unsigned long long>(f.flight_points));
  });
  auto* positions = cmd->add_subcommand(
      "positions",
      "Every flight at one instant: position, altitude, speed, track and vertical rate interpolated "
      "linearly between the samples around it (filters apply to the interpolated position; --t0/--t1 "
      "are refused)");
  common(positions);
  positions->add_option("--t", o->t, "the instant: Unix seconds or ISO 8601 (2018-01-01T08:00:00Z)")
      ->required();
  positions->add_flag("--geojson", o->geojson, "print a GeoJSON FeatureCollection of Points");
  positions->callback([o] {
    const double t = parse_time(o->t, "t");
    const Query q = parse_query(o->flags.params);
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    const Positions at = positions_at(*ds->trails, t, q, limits::kMaxPositionsPerResponse);
    if (!o->geojson && !o->json) return print_positions(at);
    nlohmann::json j = o->geojson ? at.to_geojson() : at.to_json();
    j["dataset"] = ds->id;  // as the REST API's body
    std::cout << json_text(j, 2) << std::endl;
  });
  auto* animation = cmd->add_subcommand(
      "animation",
      "One animation chunk [t, t+duration): the flights present and their samples, with the samples "
      "around the chunk, as TSAN (proto/animation_chunks.md) or JSON (only --callsign and --icao24 apply)");
  common(animation);
  animation->add_option("--t", o->t, "the chunk start: Unix seconds or ISO 8601, a multiple of --duration")
      ->required();
  animation->add_option("--duration", o->duration, "the chunk length, seconds")->capture_default_str();
  animation->add_option("--origin", o->origin,
                        "lon,lat of the projected origin (default: the dataset's centre)");
  animation->add_option("--out", o->out, "write the TSAN bytes to this file");
  animation->callback([o] {
    const double t = parse_time(o->t, "t");
    if (o->duration < limits::kMinAnimationChunkSeconds || o->duration > limits::kMaxAnimationChunkSeconds)
      throw invalid_argument("duration", "duration must be in [" +
                                             std::to_string(limits::kMinAnimationChunkSeconds) + ", " +
                                             std::to_string(limits::kMaxAnimationChunkSeconds) + "] seconds");
    server::check_animation_chunk_start(t, o->duration);
    if (o->flags.params.count("alt_unit"))
      throw invalid_argument("alt_unit",
                             "alt_unit does not apply to animation chunks: the player filters "
                             "positions during playback, and the chunk is the time window");
    const Query q = parse_query(o->flags.params);
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    const auto origin = o->origin.empty() ? server::default_animation_origin(*ds->trails)
                                          : server::parse_animation_origin(o->origin, "origin");
    const AnimationChunk chunk = animation_chunk(*ds->trails, t, static_cast<double>(o->duration), q,
                                                 limits::kMaxAnimationChunkSamples);
    if (!o->out.empty()) {
      const std::string bytes = server::encode_animation_chunk(*ds->trails, chunk, origin);
      std::ofstream f(o->out, std::ios::binary);
      f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      if (!f.flush()) throw invalid_argument("out", "out: cannot write '" + o->out + "'");
    }
    if (o->json) {
      nlohmann::json j = server::animation_chunk_json(*ds->trails, chunk, origin);
      j["dataset"] = ds->id;
      std::cout << json_text(j, 2) << std::endl;
    } else {
      std::printf("%zu flights, %zu samples in %s .. %s (t = %s, duration %lld s)\n", chunk.flights.size(),
                  chunk.samples, iso_utc(t).c_str(), iso_utc(t + static_cast<double>(o->duration)).c_str(),
                  format_double(t).c_str(), static_cast<long long>(o->duration));
    }
  });
  auto* flight = cmd->add_subcommand("flight", "One flight as GeoJSON");
  common(flight);
  flight->add_option("FLIGHT_ID", o->flight_id, "flight id (from `query flights`)")->required();
  flight->callback([o] {
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    const bool clip = !o->flags.params.empty();
    std::cout << json_text(flight_geojson(*ds->trails, o->flight_id, parse_query(o->flags.params), clip,
                                          limits::kMaxPointsPerResponse),
                           o->json ? 2 : -1)
              << std::endl;
  });
}

}  // namespace trailscope::cli
