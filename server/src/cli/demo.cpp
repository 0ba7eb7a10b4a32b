#include <filesystem>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/demo_dataset.hpp"
#include "cli/progress_bar.hpp"
#include "store/dataset_ingest.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ingest/demo_traffic.hpp"
#include "trailscope/ingest/opensky_csv_writer.hpp"

namespace trailscope::cli {
namespace fs = std::filesystem;

std::string demo_source_dir(const std::string& source) {
  const fs::path dir = source.empty() ? fs::path("web/node_modules/vega-datasets/data") : fs::path(source);
  for (const char* f : {"airports.csv", "flights-airport.csv"})
    if (!fs::exists(dir / f))
      throw not_found("demo-source", "demo source: " + (dir / f).string() +
                                         " is missing (run `npm ci` in web/, or pass --demo-source)");
  return dir.string();
}

static TrailSet generate(std::size_t flights, std::uint64_t seed, const std::string& source) {
  ingest::DemoOptions opts;
  const std::string dir = demo_source_dir(source);
  opts.airports_csv = dir + "/airports.csv";
  opts.routes_csv = dir + "/flights-airport.csv";
  opts.flights = flights;
  opts.seed = seed;
  ProgressBar bar("generating demo traffic");
  return ingest::generate_demo_traffic(opts, bar.fn());
}

void create_demo_dataset(server::DatasetStore& store, const std::string& id, std::size_t flights,
                         std::uint64_t seed, const std::string& source) {
  auto ds = std::make_shared<server::Dataset>();
  ds->id = id;
  ds->name = id;
  ds->format = "demo";
  ds->created = server::utc_now_iso();
  ds->trails = std::make_shared<const TrailSet>(generate(flights, seed, source));
  ds->ingest = {{"generator", "demo_traffic"}, {"seed", seed}, {"flights", flights}};
  store.put(ds);
  std::cerr << "stored dataset '" << id << "': " << ds->trails->num_flights() << " flights, "
            << ds->trails->num_points() << " points\n";
}

void add_demo(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "demo", "Generate a day of US airline traffic (vega-datasets routes, GeographicLib great circles)");
  struct Opts {
    std::string data_dir = default_data_dir(), name = "demo", source, csv;
    std::size_t flights = 20000;
    std::uint64_t seed = 42;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
  cmd->add_option("--name", o->name, "dataset id")->capture_default_str();
  cmd->add_option("--flights", o->flights, "number of flights")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--seed", o->seed, "random seed (same seed, same data)")->capture_default_str();
  cmd->add_option("--demo-source", o->source, "folder with airports.csv and flights-airport.csv");
  cmd->add_option("--csv", o->csv, "write an OpenSky state-vector CSV (.csv or .csv.gz) instead of storing");
  cmd->callback([o] {
    if (!o->csv.empty()) {
      const TrailSet t = generate(o->flights, o->seed, o->source);
      const bool gz = o->csv.size() > 3 && o->csv.compare(o->csv.size() - 3, 3, ".gz") == 0;
      ingest::write_opensky_csv(t, o->csv, gz);
      std::cerr << "wrote " << t.num_points() << " rows to " << o->csv << "\n";
      return;
    }
    server::EmbeddedStore store(o->data_dir);
    create_demo_dataset(store, o->name, o->flights, o->seed, o->source);
  });
}

}  // namespace trailscope::cli
