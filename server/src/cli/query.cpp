#include <cstdio>
#include <ctime>
#include <iostream>

#include "trailscope/core/json_text.hpp"
#include "cli/commands.hpp"
#include "store/dataset_ingest.hpp"
#include "store/embedded_store.hpp"
#include "limits.hpp"
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
}  // namespace

void add_query(CLI::App& app) {
  auto* cmd = app.add_subcommand("query", "Query an airspace time window of a dataset");
  cmd->require_subcommand(1);
  struct Opts {
    std::string data_dir = default_data_dir(), dataset;
    bool json = false;
    int bins = limits::kDefaultHistogramBins, top = 10;
    std::size_t page = 0, page_size = limits::kDefaultPageSize, flight_id = 0;
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
  summary->callback([o] {
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    SummaryOptions opts;
    opts.bins = o->bins, opts.top_callsigns = o->top;
    if (o->flags.params.count("alt_unit") && o->flags.params["alt_unit"] == "m") opts.alt_unit = AltUnit::m;
    const Summary s = summarize(*ds->trails, parse_query(o->flags.params), opts);
    if (o->json)
      std::cout << json_text(s.to_json(), 2) << std::endl;
    else
      print_summary(s);
  });
  auto* flights = cmd->add_subcommand("flights", "The flights in the window, a page at a time");
  common(flights);
  flights->add_option("--page", o->page, "page, from 0")->capture_default_str();
  flights->add_option("--page-size", o->page_size, "flights per page")->capture_default_str();
  flights->callback([o] {
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    const FlightPage p = list_flights(*ds->trails, parse_query(o->flags.params), o->page, o->page_size);
    if (o->json) {
      std::cout << json_text(p.to_json(), 2) << std::endl;
      return;
    }
    std::printf("%llu flights; page %zu:\n", static_cast<unsigned long long>(p.total), p.page);
    for (const auto& f : p.flights)
      std::printf("%8u %-6s %-9s %s .. %s %7llu pts\n", f.id, f.icao24.c_str(), f.callsign.c_str(),
                  iso_utc(f.t_start).c_str(), iso_utc(f.t_end).c_str(),
                  static_cast<unsigned long long>(f.points));
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
