// `trailscope export`: the window's flights as GeoJSON or CSV, the same bytes as GET .../export
// (formats/flight_export.hpp), written a piece at a time to a file or stdout.
#include <cstdio>
#include <fstream>
#include <iostream>

#include "cli/commands.hpp"
#include "formats/flight_export.hpp"
#include "limits.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::cli {

void add_export(CLI::App& app) {
  auto* cmd = app.add_subcommand("export",
                                 "Export the flights of a window as GeoJSON or CSV: every flight with a "
                                 "matching point, with its matching "
                                 "points only (the bytes of GET /api/v1/datasets/{id}/export)");
  struct Opts {
    std::string data_dir = default_data_dir(), dataset, format = "geojson", out;
    std::uint64_t max_points = limits::kMaxExportPoints;
    bool json = false;
    QueryFlags flags;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("DATASET", o->dataset, "dataset id")->required();
  cmd->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
  cmd->add_option("--format", o->format, "geojson or csv")->capture_default_str();
  cmd->add_option("-o,--out", o->out, "write to this file (default: stdout)");
  cmd->add_option("--max-points", o->max_points, "refuse an export of more matching points")
      ->capture_default_str();
  cmd->add_flag(
      "--json", o->json,
      "with --out: print what was written as JSON ({dataset, format, flights, points, bytes, out})");
  o->flags.add_to(*cmd);
  cmd->callback([o] {
    const server::FlightExportFormat format = server::parse_flight_export_format(o->format, "format");
    if (o->max_points < 1 || o->max_points > limits::kMaxExportPoints)
      throw invalid_argument("max_points", "max_points must lie in 1.." +
                                               std::to_string(limits::kMaxExportPoints) + ", got " +
                                               std::to_string(o->max_points));
    if (o->json && o->out.empty())
      throw invalid_argument("json",
                             "--json describes the file written with --out (without --out the export "
                             "itself goes to stdout)");
    const Query q = parse_query(o->flags.params);
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    ExportPlan plan = plan_export(*ds->trails, q, o->max_points);
    const std::size_t flights = plan.flights.size();
    const std::uint64_t points = plan.points;
    auto stream = server::flight_export_stream(ds, q, std::move(plan), format);
    std::ofstream file;
    if (!o->out.empty()) {
      file.open(o->out, std::ios::binary | std::ios::trunc);
      if (!file) throw invalid_argument("out", "out: cannot write '" + o->out + "'");
    }
    std::ostream& sink = o->out.empty() ? std::cout : file;
    std::uint64_t bytes = 0;
    std::string piece;
    for (bool more = true; more;) {
      piece.clear();
      more = stream(piece);
      sink.write(piece.data(), static_cast<std::streamsize>(piece.size()));
      bytes += piece.size();
    }
    if (!sink.flush()) throw invalid_argument("out", "out: cannot write '" + o->out + "'");
    if (o->out.empty()) return;
    if (o->json)
      std::cout << json_text(nlohmann::json{{"dataset", ds->id},
                                            {"format", o->format},
                                            {"flights", flights},
                                            {"points", points},
                                            {"bytes", bytes},
                                            {"out", o->out}},
                             2)
                << std::endl;
    else
      std::printf("%zu flights, %llu points, %llu bytes -> %s\n", flights,
                  static_cast<unsigned long long>(points), static_cast<unsigned long long>(bytes),
                  o->out.c_str());
  });
}

}  // namespace trailscope::cli
