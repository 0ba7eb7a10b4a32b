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

// The generator's options for `flights` flights on one day, or (fleet.aircraft > 0) a fleet over days.
struct Fleet {
  std::size_t aircraft = 0;
  int days = 7;
  double sample_min_s = 120, sample_max_s = 180;
};

static TrailSet generate(std::size_t flights, std::uint64_t seed, const std::string& source,
                         const Fleet& fleet = {}) {
  ingest::DemoOptions opts;
  const std::string dir = demo_source_dir(source);
  opts.airports_csv = dir + "/airports.csv";
  opts.routes_csv = dir + "/flights-airport.csv";
  opts.flights = flights;
  opts.seed = seed;
  if (fleet.aircraft > 0) {
    opts.aircraft = fleet.aircraft, opts.days = fleet.days;
    opts.sample_min_s = fleet.sample_min_s, opts.sample_max_s = fleet.sample_max_s;
  }
  ProgressBar bar(fleet.aircraft ? "generating a fleet's traffic" : "generating demo traffic");
  return ingest::generate_demo_traffic(opts, bar.fn());
}

static void store_demo(server::DatasetStore& store, const std::string& id, std::size_t flights,
                       std::uint64_t seed, const std::string& source, const Fleet& fleet) {
  auto ds = std::make_shared<server::Dataset>();
  ds->id = id;
  ds->name = id;
  ds->format = "demo";
  ds->created = server::utc_now_iso();
  ds->trails = std::make_shared<const TrailSet>(generate(flights, seed, source, fleet));
  ds->ingest = {{"generator", "demo_traffic"}, {"seed", seed}};
  if (fleet.aircraft)
    ds->ingest.update({{"aircraft", fleet.aircraft},
                       {"days", fleet.days},
                       {"sample_min_s", fleet.sample_min_s},
                       {"sample_max_s", fleet.sample_max_s}});
  else
    ds->ingest["flights"] = flights;
  store.put(ds);
  std::cerr << "stored dataset '" << id << "': " << ds->trails->num_flights() << " flights, "
            << ds->trails->num_points() << " points\n";
}

void create_demo_dataset(server::DatasetStore& store, const std::string& id, std::size_t flights,
                         std::uint64_t seed, const std::string& source) {
  store_demo(store, id, flights, seed, source, {});
}

void add_demo(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "demo", "Generate a day of US airline traffic (vega-datasets routes, GeographicLib great circles)");
  struct Opts {
    std::string data_dir = default_data_dir(), name = "demo", source, csv;
    std::size_t flights = 20000;
    std::uint64_t seed = 42;
    Fleet fleet;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
  cmd->add_option("--name", o->name, "dataset id")->capture_default_str();
  cmd->add_option("--flights", o->flights, "number of flights")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--seed", o->seed, "random seed (same seed, same data)")->capture_default_str();
  cmd->add_option("--aircraft", o->fleet.aircraft,
                  "fleet mode: this many aircraft fly leg after leg for --days days (instead of --flights "
                  "flights on one day); 25,000 in the air at once is ~32,000 aircraft")
      ->check(CLI::Range(std::size_t{1}, ingest::kMaxDemoAircraft));
  cmd->add_option("--days", o->fleet.days, "fleet mode: days to generate")
      ->capture_default_str()
      ->check(CLI::Range(1, ingest::kMaxDemoDays));
  cmd->add_option("--sample-min", o->fleet.sample_min_s, "fleet mode: shortest time between samples, s")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 600.0));
  cmd->add_option("--sample-max", o->fleet.sample_max_s, "fleet mode: longest time between samples, s")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 600.0));
  cmd->add_option("--demo-source", o->source, "folder with airports.csv and flights-airport.csv");
  cmd->add_option("--csv", o->csv, "write an OpenSky state-vector CSV (.csv or .csv.gz) instead of storing");
  cmd->callback([o] {
    if (!o->csv.empty()) {
      const TrailSet t = generate(o->flights, o->seed, o->source, o->fleet);
      const bool gz = o->csv.size() > 3 && o->csv.compare(o->csv.size() - 3, 3, ".gz") == 0;
      ingest::write_opensky_csv(t, o->csv, gz);
      std::cerr << "wrote " << t.num_points() << " rows to " << o->csv << "\n";
      return;
    }
    server::EmbeddedStore store(o->data_dir);
    store_demo(store, o->name, o->flights, o->seed, o->source, o->fleet);
  });
}

}  // namespace trailscope::cli
