#pragma once
// The CLI verbs of `trailscope`. Each add_* registers one subcommand with its options and --help text;
// the callback does the work and throws trailscope::Error on bad input (main prints it, exits 2).
#include <map>
#include <string>

#include <CLI/CLI.hpp>

namespace trailscope::cli {

void add_serve(CLI::App& app);
void add_ingest(CLI::App& app);
void add_query(CLI::App& app);
void add_tile(CLI::App& app);
void add_demo(CLI::App& app);
void add_bundle(CLI::App& app);
void add_metrics(CLI::App& app);
void add_synth(CLI::App& app);
void add_video(CLI::App& app);
void add_dmd(CLI::App& app);
void add_project(CLI::App& app);
void add_track(CLI::App& app);
void add_compare(CLI::App& app);
void add_congestion(CLI::App& app);
/// `trailscope token create|list|revoke` (cli/token.cpp).
void add_token(CLI::App& app);
/// `trailscope gaze ingest|events|tile|aoi|bundle` (cli/gaze.cpp).
void add_gaze(CLI::App& app);
/// `trailscope flow` (cli/flow.cpp): the flow map of a dataset's traffic or of an uploaded field.
void add_flow(CLI::App& app);
/// `trailscope export`: the window's flights as GeoJSON or CSV (cli/export.cpp).
void add_export(CLI::App& app);

/// The airspace-window filters shared by `query` and `tile` (--bbox --t0 --t1 --alt-min --alt-max
/// --alt-unit --icao24 --callsign --on-ground), collected as the REST API's parameter map so that
/// both go through the same parse_query().
struct QueryFlags {
  std::map<std::string, std::string> params;
  void add_to(CLI::App& cmd);
};

/// Default data folder: $TRAILSCOPE_DATA_DIR, else ./data.
std::string default_data_dir();

}  // namespace trailscope::cli
