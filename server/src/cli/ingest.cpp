#include <filesystem>
#include <iostream>
#include <optional>

#include "trailscope/core/json_text.hpp"
#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "store/dataset_ingest.hpp"
#include "store/clickhouse_store.hpp"

namespace trailscope::cli {

void add_ingest(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "ingest",
      "Ingest an ADS-B file (OpenSky CSV, traffic JSON, SO6, readsb trace; plain or gzip) as a dataset");
  struct Opts {
    std::string file, data_dir = default_data_dir(), name, format, store;
    bool json = false, quiet = false;
    std::optional<bool> split_jumps;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("FILE", o->file, "input file")->required();
  cmd->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
  cmd->add_option("--name", o->name, "dataset id (default: derived from the file name)");
  cmd->add_option("--format", o->format,
                  "opensky_csv | traffic_json | so6 | readsb_trace (default: detected)");
  cmd->add_option("--store", o->store,
                  "where the dataset goes: 'embedded' (the data folder, default) or "
                  "clickhouse://HOST:PORT[,HOST:PORT...]/DB?cluster=NAME");
  cmd->add_flag("--json", o->json, "print the dataset and its ingest report as JSON");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  cmd->add_option("--split-jumps", o->split_jumps,
                  "true | false: split flights that are two legs (a gap over 20 h) or teleport (a confirmed "
                  "jump of 50 km or "
                  "more beyond 1600 kt) (default true)");
  cmd->callback([o] {
    server::IngestRequest req;
    req.file = o->file;
    if (o->name.empty()) {
      std::string stem = std::filesystem::path(o->file).filename().string();
      stem = stem.substr(0, stem.find('.'));
      o->name = server::dataset_id_from_name(stem);
    }
    req.name = o->name;
    if (!o->format.empty()) req.format = o->format;
    req.split_jumps = o->split_jumps;
    const auto store =
        server::open_dataset_store(o->store, o->data_dir, server::EmbeddedStore::Leftovers::keep);
    std::shared_ptr<const server::Dataset> ds;
    {
      ProgressBar bar("ingest " + o->name, !o->quiet);
      ds = server::ingest_into_store(*store, req, bar.fn(), nullptr);
    }
    const auto j = ds->to_json();
    if (o->json) {
      std::cout << json_text(j, 2) << std::endl;
    } else {
      std::cout << "dataset " << ds->id << ": " << j["flights"] << " flights, " << j["points"] << " points, "
                << ds->ingest.value("rejected", 0) << " rows rejected (" << ds->format << ")" << std::endl;
      if (const auto q = ds->ingest.find("quality"); q != ds->ingest.end())
        std::cout << "implausible: " << (*q)["speed"]["count"] << " ground speeds over "
                  << (*q)["limits"]["speed_kt"] << " kt, " << (*q)["altitude"]["count"]
                  << " altitudes over FL" << (*q)["limits"]["altitude_fl"] << ", " << (*q)["jumps"]["count"]
                  << " position jumps; " << (*q)["jump_splits"]["count"] << " flights split at jumps, "
                  << (*q)["leg_splits"]["count"] << " between legs" << std::endl;
    }
  });
}

}  // namespace trailscope::cli
