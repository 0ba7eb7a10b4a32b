// `trailscope congestion DATASET`: occupancy and entry counts, hotspots, complexity and losses of
// separation of a dataset window, on the grid or on sectors from a GeoJSON file. The flags build the body
// of POST /api/v1/congestion and go through its parser (params/congestion_body.hpp), and the work is the
// job's (jobs/congestion_job.hpp), so the CLI and the API take the same input, refuse the same mistakes
// with the same messages, and print the same JSON and CSV.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "jobs/congestion_job.hpp"
#include "params/congestion_body.hpp"
#include "store/dataset_ingest.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::cli {

namespace {
using server::iso_utc;

/// The GeoJSON text of a sector file. Throws invalid_argument("sectors") when it cannot be read or is
/// not JSON.
nlohmann::json read_sector_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw invalid_argument("sectors", "--sectors: cannot read " + path);
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
  if (j.is_discarded())
    throw invalid_argument("sectors", "--sectors: " + path + " is not JSON (GeoJSON expected)");
  return j;
}

std::string hhmm(double seconds) {
  char buf[32];
  const long s = static_cast<long>(seconds + 0.5);
  std::snprintf(buf, sizeof buf, "%ldh%02ldm%02lds", s / 3600, s / 60 % 60, s % 60);
  return buf;
}

void print_counts(const congestion::CountsResult& c, const server::CongestionOutput& out, std::size_t top) {
  std::printf("%s .. %s: %u periods of %g s every %g s (%s), %u entry windows of %g s every %g s\n",
              iso_utc(c.t0).c_str(), iso_utc(c.t1).c_str(), c.steps, c.duration_s, c.step_s,
              congestion::to_string(c.method), c.entry_windows, c.entry_window_s, c.entry_step_s);
  std::printf("flights  %u\nvolumes  %zu %s\n", c.flights, c.volumes.size(),
              c.grid ? "grid cells with traffic" : "sectors");
  const auto has = [&](const char* part) {
    return std::find(out.compute.begin(), out.compute.end(), part) != out.compute.end();
  };
  if (has("occupancy") || has("entries")) {
    // The busiest volumes: by their largest occupancy, then entries.
    std::vector<std::size_t> order(c.volumes.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const auto& va = c.volumes[a];
      const auto& vb = c.volumes[b];
      if (va.occupancy.max() != vb.occupancy.max()) return va.occupancy.max() > vb.occupancy.max();
      return va.entries.max() > vb.entries.max();
    });
    order.resize(std::min(order.size(), top));
    if (!order.empty()) {
      std::printf("\nbusiest volumes:\n%-16s %13s %-20s %13s %8s %9s\n", "volume", "max occupancy", "at",
                  "max entries", "peak", "sustained");
      for (std::size_t i : order) {
        const auto& v = c.volumes[i];
        std::string at = "-";
        const std::uint32_t m = v.occupancy.max();
        for (std::size_t k = 0; m && k < v.occupancy.index.size(); ++k)
          if (v.occupancy.value[k] == m) {
            at = iso_utc(c.step_start(v.occupancy.index[k]));
            break;
          }
        const auto threshold = [](const std::optional<double>& t) {
          char buf[32];
          if (t)
            std::snprintf(buf, sizeof buf, "%g", *t);
          else
            std::snprintf(buf, sizeof buf, "-");
          return std::string(buf);
        };
        std::printf("%-16s %13u %-20s %13u %8s %9s\n", v.id.c_str(), m, at.c_str(), v.entries.max(),
                    threshold(v.peak).c_str(), threshold(v.sustained).c_str());
      }
    }
  }
  if (has("hotspots")) {
    std::printf("\nhotspots  %llu", static_cast<unsigned long long>(c.hotspots_total));
    if (c.hotspots.size() > top) std::printf(" (the %zu largest excesses)", top);
    std::printf("\n");
    if (!c.hotspots.empty())
      std::printf("%-16s %-9s %-20s %-9s %5s %9s %6s %7s\n", "volume", "kind", "start", "length", "peak",
                  "threshold", "excess", "flights");
    for (std::size_t i = 0; i < std::min(c.hotspots.size(), top); ++i) {
      const auto& h = c.hotspots[i];
      std::printf("%-16s %-9s %-20s %-9s %5u %9g %6g %7zu\n", c.volumes[h.volume].id.c_str(),
                  congestion::to_string(h.kind), iso_utc(h.start).c_str(), hhmm(h.end - h.start).c_str(),
                  h.peak, h.threshold, h.excess, h.flights.size());
    }
  }
  if (c.has_complexity) {
    const auto& t = c.complexity_total;
    std::printf(
        "\ncomplexity  %zu volume-hours: flight hours %.1f, interaction hours %.2f, adjusted density "
        "%.2f min/h, structural index %.3f, score %.3f\n",
        c.complexity.size(), t.flight_hours, t.interaction_hours, t.adjusted_density(), t.structural_index(),
        t.score());
    std::vector<const congestion::ComplexityCell*> cells;
    for (const auto& cell : c.complexity) cells.push_back(&cell);
    std::stable_sort(cells.begin(), cells.end(), [](auto* a, auto* b) { return a->score() > b->score(); });
    cells.resize(std::min(cells.size(), top));
    if (!cells.empty())
      std::printf("%-16s %-20s %12s %13s %9s %10s %8s\n", "volume", "hour", "flight h", "interaction h",
                  "density", "structural", "score");
    for (const auto* cell : cells)
      std::printf("%-16s %-20s %12.2f %13.3f %9.2f %10.3f %8.3f\n", c.volumes[cell->volume].id.c_str(),
                  iso_utc(c.t0 + 3600.0 * cell->hour).c_str(), cell->flight_hours, cell->interaction_hours,
                  cell->adjusted_density(), cell->structural_index(), cell->score());
  }
}

void print_separation(const congestion::SeparationResult& s, std::size_t top) {
  std::printf("\nlosses of separation  %zu among %zu flights (%zu pairs tested)\n", s.events.size(),
              s.flights, s.pairs_tested);
  if (s.events.empty()) return;
  std::printf("%-20s %9s %-9s %-9s %-20s %8s %10s\n", "start", "length", "flight a", "flight b", "closest at",
              "cpa NM", "cpa ft");
  for (std::size_t i = 0; i < std::min(s.events.size(), top); ++i) {
    const auto& e = s.events[i];
    std::printf("%-20s %9s %-9s %-9s %-20s %8.2f %10.0f\n", iso_utc(e.t_start).c_str(),
                hhmm(e.t_end - e.t_start).c_str(),
                e.callsign_a.empty() ? e.icao24_a.c_str() : e.callsign_a.c_str(),
                e.callsign_b.empty() ? e.icao24_b.c_str() : e.callsign_b.c_str(), iso_utc(e.cpa_t).c_str(),
                e.cpa_horizontal_m / congestion::kMetresPerNm, e.cpa_vertical_m / congestion::kMetresPerFoot);
  }
  if (s.events.size() > top)
    std::printf("... %zu more (--json or --csv --table separation lists all)\n", s.events.size() - top);
}
}  // namespace

void add_congestion(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "congestion",
      "Congestion of a dataset window: occupancy and entry counts per volume (grid cells of 20 NM x 20 NM x "
      "3,000 ft over --bbox and the altitude band, or the sectors of a GeoJSON file), hotspots against "
      "peak and sustained thresholds, the PRU complexity score, and (--separation) losses of separation "
      "(5 NM, 1,000 ft)");
  struct Opts {
    std::string data_dir = default_data_dir(), dataset, sectors, table = "series", compute;
    std::map<std::string, std::string> query, grid, body;
    bool separation = false, json = false, csv = false, quiet = false;
    std::size_t top = 10;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("DATASET", o->dataset, "dataset id")->required();
  cmd->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
  // Each flag writes the body field of POST /api/v1/congestion it stands for.
  const auto into = [&](std::map<std::string, std::string>& m, const std::string& name,
                        const std::string& key, const std::string& help) {
    cmd->add_option_function<std::string>(
        name, [&m, key](const std::string& v) { m[key] = v; }, help);
  };
  into(o->query, "--t0", "t0", "window start (Unix seconds or ISO 8601), inclusive; required");
  into(o->query, "--t1", "t1", "window end (Unix seconds or ISO 8601), exclusive; required");
  into(o->query, "--callsign", "callsign", "callsign prefix, or a pattern with * and ?");
  into(o->query, "--icao24", "icao24", "comma-separated 24-bit addresses (hex)");
  into(o->grid, "--bbox", "bbox", "grid extent: west,south,east,north in degrees (default: the world)");
  into(o->grid, "--alt-min", "alt_min", "grid extent: lowest altitude, in --alt-unit (default 0)");
  into(o->grid, "--alt-max", "alt_max", "grid extent: highest altitude, in --alt-unit (default 60,000 ft)");
  into(o->grid, "--alt-unit", "alt_unit", "ft (default) or m");
  cmd->add_option(
      "--sectors", o->sectors,
      "count in the sectors of this GeoJSON FeatureCollection (Polygons with name, lower_fl, upper_fl, "
      "optional peak and sustained) instead of the grid");
  into(o->body, "--step", "step", "seconds between counting periods, 1..3600 (default 60)");
  into(o->body, "--duration", "duration", "length of a counting period, seconds, 60..3600 (default 60)");
  into(o->body, "--method", "method", "interpolated (default: the trajectory between samples) or samples");
  into(o->body, "--entry-window", "entry_window", "entry-count window, seconds (default 3600)");
  into(o->body, "--entry-step", "entry_step", "seconds between entry windows (default 1200)");
  into(o->body, "--peak", "peak",
       "hotspot when the occupancy exceeds this (grid cells; sectors without their own)");
  into(o->body, "--sustained", "sustained",
       "hotspot when the occupancy exceeds this for --sustained-steps periods");
  into(o->body, "--sustained-steps", "sustained_steps",
       "consecutive periods of a sustained hotspot (default 3)");
  cmd->add_option(
      "--compute", o->compute,
      "comma-separated parts: occupancy, entries, hotspots, complexity, separation (default: all but "
      "separation)");
  cmd->add_flag("--separation", o->separation,
                "also find losses of separation (5 NM and 1,000 ft; 2,000 ft above FL410)");
  cmd->add_flag("--json", o->json, "print the result as JSON (the body of GET /api/v1/congestion/{job})");
  cmd->add_flag("--csv", o->csv, "print one table as CSV (as GET /api/v1/congestion/{job}?format=csv)");
  cmd->add_option("--table", o->table, "the --csv table: series, hotspots, complexity or separation")
      ->capture_default_str();
  cmd->add_option("--top", o->top, "rows of each list in the table output")->capture_default_str();
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  cmd->callback([o] {
    if (o->json && o->csv) throw invalid_argument("csv", "--json and --csv: give one of them");
    if (!o->csv && o->table != "series") throw invalid_argument("table", "--table: applies to --csv");
    // The body of POST /api/v1/congestion, with the sector file standing for a stored set.
    nlohmann::json body = {{"dataset", o->dataset}};
    body["query"] = o->query;
    if (!o->sectors.empty()) {
      if (!o->grid.empty())
        throw invalid_argument(
            o->grid.begin()->first,
            "--bbox, --alt-min, --alt-max and --alt-unit set the extent of the grid; sectors "
            "have their own");
      body["volumes"] = {{"sectors", o->sectors}};
    } else {
      body["volumes"] = {{"grid", o->grid}};
    }
    nlohmann::json compute = nlohmann::json::array();
    if (!o->compute.empty()) {
      std::stringstream parts(o->compute);
      for (std::string part; std::getline(parts, part, ',');) compute.push_back(part);
    } else {
      compute = {"occupancy", "entries", "hotspots", "complexity"};
    }
    if (o->separation) compute.push_back("separation");
    body["compute"] = compute;
    nlohmann::json thresholds = nlohmann::json::object();
    for (const auto& [k, v] : o->body)
      (k == "peak" || k == "sustained" || k == "sustained_steps" ? thresholds[k] : body[k]) = v;
    if (!thresholds.empty()) body["thresholds"] = thresholds;
    server::CongestionRequest r = server::parse_congestion_request(body);
    if (!r.sectors.empty()) {
      r.counts.sectors = congestion::parse_sectors(read_sector_file(r.sectors));
      congestion::validate(r.counts);
    }
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    std::shared_ptr<server::CongestionOutput> out;
    {
      ProgressBar bar("congestion", !o->quiet);
      out = server::run_congestion(*ds->trails, r, bar.fn(), nullptr);
    }
    if (o->json) {
      std::cout << json_text(out->to_json(), 2) << std::endl;
    } else if (o->csv) {
      std::cout << out->csv(o->table);
    } else {
      std::printf("congestion of %s\n", ds->id.c_str());
      if (out->counts) print_counts(*out->counts, *out, o->top);
      if (out->separation) print_separation(*out->separation, o->top);
    }
  });
}

}  // namespace trailscope::cli
