#include "store/sector_store.hpp"

#include <fstream>
#include <sstream>

#include "limits.hpp"
#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
constexpr char kMagic[] = "TRAILSCOPE-SECTORS-1";
constexpr int kFormatVersion = 1;
constexpr char kGeoJsonFile[] = "sectors.geojson";
}  // namespace

SectorStore::SectorStore(fs::path root)
    : folders_(std::move(root), {"sectors", "sectors", 's', "manifest.json"},
               manifest_meta(kMagic, kFormatVersion)) {}

std::vector<nlohmann::json> SectorStore::list() const {
  return folders_.list();
}

nlohmann::json SectorStore::meta(const std::string& id) const {
  return folders_.meta(id);
}

std::string SectorStore::geojson(const std::string& id) const {
  std::lock_guard lock(mu_);
  folders_.check(id);
  // Read under the lock: a delete cannot move the folder away mid-read.
  const fs::path p = folders_.dir(id) / kGeoJsonFile;
  std::ifstream in(p, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw io_error(p, "read");
  return text.str();
}

nlohmann::json SectorStore::put(const std::string& name, const std::string& geojson, nlohmann::json figures,
                                const std::string& owner) {
  std::lock_guard lock(mu_);
  if (folders_.size() >= limits::kMaxStoredSectorSets)
    throw Error(Error::Kind::conflict, "sectors",
                "the server stores at most " + std::to_string(limits::kMaxStoredSectorSets) +
                    " sector sets (kMaxStoredSectorSets); delete one first");
  const std::string id = folders_.next_id();
  nlohmann::json meta = figures.is_object() ? std::move(figures) : nlohmann::json::object();
  meta["id"] = id;
  meta["name"] = name.empty() ? id : name;
  meta["created"] = utc_now_iso();
  meta["bytes"] = geojson.size();
  meta["owner"] = owner;
  const fs::path tmp = folders_.stage(id);
  try {
    write_file_atomic(tmp / kGeoJsonFile, geojson);
    nlohmann::json m = meta;
    m["magic"] = kMagic, m["version"] = kFormatVersion;
    write_manifest(tmp, m);
    folders_.publish(id, tmp, meta);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
  return meta;
}

void SectorStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  folders_.remove(id);
}

}  // namespace trailscope::server
