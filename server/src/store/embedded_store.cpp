#include "store/embedded_store.hpp"
#include "store/column_io.hpp"
#include "store/folder_store.hpp"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>

#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

namespace {
constexpr char kMagic[] = "TRAILSCOPE-COLUMNS-1";
constexpr int kFormatVersion = 1;

// The column files, fsync and temporary names are shared with the graph and bundle stores.
using column_io::fsync_path;
using column_io::io_error;
using column_io::random_suffix;
using column_io::read_column;
using column_io::write_column;
}  // namespace

EmbeddedStore::EmbeddedStore(fs::path root, Leftovers leftovers) : root_(std::move(root)) {
  std::error_code ec;
  for (const char* sub : {"datasets", "tmp", "uploads"}) {
    fs::create_directories(root_ / sub, ec);
    if (ec) throw io_error(root_ / sub, "create");
  }
  // Leftovers of interrupted writes and uploads are never part of a dataset; only the server removes
  // them, since a CLI verb run beside a live server would otherwise delete its writes in flight.
  if (leftovers == Leftovers::remove)
    for (const char* sub : {"tmp", "uploads"})
      for (const auto& e : fs::directory_iterator(root_ / sub)) fs::remove_all(e.path(), ec);
  // Only complete datasets (their manifest is written last) are known; their columns are read when
  // first asked for, so a CLI query of one dataset does not read every other one.
  for (const auto& e : fs::directory_iterator(root_ / "datasets"))
    if (e.is_directory() && fs::exists(e.path() / "manifest.json", ec))
      datasets_[e.path().filename().string()] = nullptr;
}

std::shared_ptr<const Dataset> EmbeddedStore::load_locked(const std::string& id) const {
  auto it = datasets_.find(id);
  if (it == datasets_.end()) return nullptr;
  if (it->second) return it->second;
  try {
    it->second = read_dataset(root_ / "datasets" / id);
    return it->second;
  } catch (const std::exception& ex) {
    // Unreadable on disk: reported and forgotten for this run, never deleted.
    std::cerr << "store: skipping dataset '" << id << "': " << ex.what() << "\n";
    datasets_.erase(it);
    return nullptr;
  }
}

std::uint64_t EmbeddedStore::bytes_estimate(const Dataset& ds) {
  return ds.trails->num_points() * kBytesPerPoint + ds.trails->num_flights() * kBytesPerFlight + (64u << 10);
}

void EmbeddedStore::write_dataset(const Dataset& ds, const fs::path& dir) {
  const TrailSet& t = *ds.trails;
  const PointColumns& p = t.points();
  write_column(dir, "t", p.t);
  write_column(dir, "lat", p.lat);
  write_column(dir, "lon", p.lon);
  write_column(dir, "alt", p.alt);
  write_column(dir, "speed", p.speed);
  write_column(dir, "track", p.track);
  write_column(dir, "vrate", p.vrate);
  write_column(dir, "on_ground", p.on_ground);
  // Flights: ranges as a column pair, identifiers in the manifest (short strings, at most millions).
  std::vector<std::uint32_t> ranges;
  nlohmann::json icao = nlohmann::json::array(), callsign = nlohmann::json::array();
  for (const Flight& f : t.flights()) {
    ranges.push_back(f.begin), ranges.push_back(f.end);
    icao.push_back(f.icao24), callsign.push_back(f.callsign);
  }
  write_column(dir, "flight_ranges", ranges);
  const nlohmann::json manifest = {{"magic", kMagic},
                                   {"version", kFormatVersion},
                                   {"id", ds.id},
                                   {"name", ds.name},
                                   {"format", ds.format},
                                   {"created", ds.created},
                                   {"ingest", ds.ingest},
                                   {"points", p.size()},
                                   {"flights", t.num_flights()},
                                   {"owner", ds.owner},
                                   {"icao24", icao},
                                   {"callsign", callsign}};
  // The manifest is written last: a folder without it is incomplete by definition.
  column_io::write_manifest(dir, manifest);
}

std::shared_ptr<Dataset> EmbeddedStore::read_dataset(const fs::path& dir) {
  std::ifstream in(dir / "manifest.json");
  if (!in) throw io_error(dir / "manifest.json", "open");
  const nlohmann::json m = nlohmann::json::parse(in);
  if (m.value("magic", "") != kMagic || m.value("version", 0) != kFormatVersion)
    throw io_error(dir, "recognise the format of");
  const std::size_t n = m.at("points").get<std::size_t>(), nf = m.at("flights").get<std::size_t>();
  PointColumns p;
  read_column(dir, "t", p.t, n);
  read_column(dir, "lat", p.lat, n);
  read_column(dir, "lon", p.lon, n);
  read_column(dir, "alt", p.alt, n);
  read_column(dir, "speed", p.speed, n);
  read_column(dir, "track", p.track, n);
  read_column(dir, "vrate", p.vrate, n);
  read_column(dir, "on_ground", p.on_ground, n);
  std::vector<std::uint32_t> ranges;
  read_column(dir, "flight_ranges", ranges, 2 * nf);
  const auto& icao = m.at("icao24");
  const auto& cs = m.at("callsign");
  if (icao.size() != nf || cs.size() != nf) throw io_error(dir, "read flights of");
  std::vector<Flight> flights(nf);
  for (std::size_t i = 0; i < nf; ++i) {
    Flight& f = flights[i];
    f.begin = ranges[2 * i], f.end = ranges[2 * i + 1];
    if (f.begin > f.end || f.end > n) throw io_error(dir, "validate flight ranges of");
    f.icao24 = icao[i].get<std::string>(), f.callsign = cs[i].get<std::string>();
    compute_extents(f, p);
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = m.at("id").get<std::string>();
  ds->name = m.value("name", ds->id);
  ds->format = m.value("format", "");
  ds->created = m.value("created", "");
  ds->ingest = m.value("ingest", nlohmann::json::object());
  ds->owner = m.value("owner", "");
  ds->trails = std::make_shared<const TrailSet>(std::move(p), std::move(flights));
  return ds;
}

std::vector<std::shared_ptr<const Dataset>> EmbeddedStore::list() const {
  std::lock_guard lock(mu_);
  std::vector<std::string> ids;
  for (const auto& [id, ds] : datasets_) ids.push_back(id);
  std::vector<std::shared_ptr<const Dataset>> out;
  for (const auto& id : ids)
    if (auto ds = load_locked(id)) out.push_back(std::move(ds));
  return out;
}

std::shared_ptr<const Dataset> EmbeddedStore::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  if (auto ds = load_locked(id)) return ds;
  throw not_found("dataset", "dataset '" + id + "' does not exist");
}

bool EmbeddedStore::contains(const std::string& id) const {
  std::lock_guard lock(mu_);
  return datasets_.count(id) > 0;
}

void EmbeddedStore::put(std::shared_ptr<const Dataset> ds, const ProgressFn&) {
  validate_dataset_id(ds->id);
  if (contains(ds->id)) throw Error(Error::Kind::conflict, "name", "dataset '" + ds->id + "' already exists");
  const fs::path tmp = stage_folder(root_ / "tmp", ds->id);
  try {
    write_dataset(*ds, tmp);
    std::lock_guard lock(mu_);
    if (datasets_.count(ds->id))
      throw Error(Error::Kind::conflict, "name", "dataset '" + ds->id + "' already exists");
    // Readers after a crash see the old state or the whole dataset.
    publish_folder(tmp, root_ / "datasets" / ds->id);
    datasets_[ds->id] = std::move(ds);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
}

void EmbeddedStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  auto it = datasets_.find(id);
  if (it == datasets_.end()) throw not_found("dataset", "dataset '" + id + "' does not exist");
  // Out of datasets/ first (atomic), then deleted: a crash mid-delete leaves only tmp/.
  remove_folder(root_ / "datasets" / id, root_ / "tmp" / (id + ".deleted." + random_suffix()));
  datasets_.erase(it);
}

}  // namespace trailscope::server
