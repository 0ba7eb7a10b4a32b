#include "store/sweep_store.hpp"

#include <fstream>
#include <iostream>

#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

SweepStore::SweepStore(fs::path root)
    : root_(std::move(root)), sweeps_('s', "sweep", root_ / "sweeps" / kIdCounterFile) {
  std::error_code ec;
  fs::create_directories(root_ / "sweeps", ec);
  if (ec) throw io_error(root_ / "sweeps", "create");
  std::vector<fs::path> orphans;
  for (const auto& e : fs::directory_iterator(root_ / "sweeps")) {
    const fs::path p = e.path();
    if (p.filename().string().find(".tmp.") != std::string::npos) {
      orphans.push_back(p);
      continue;
    }
    if (p.extension() != ".json" || sweeps_.number(p.stem().string()) == 0) continue;
    try {
      std::ifstream in(p);
      nlohmann::json m = nlohmann::json::parse(in);
      if (m.value("state", "") == "running") {
        m["state"] = "interrupted";
        save_locked(m);
      }
      sweeps_.add(p.stem().string(), std::move(m));
    } catch (const std::exception& ex) {
      std::cerr << "store: skipping sweep '" << p.stem().string() << "': " << ex.what() << "\n";
    }
  }
  for (const auto& p : orphans) fs::remove(p, ec);
}

void SweepStore::save_locked(const nlohmann::json& record) const {
  write_file_atomic(root_ / "sweeps" / (record.at("id").get<std::string>() + ".json"), json_text(record));
}

std::string SweepStore::create(nlohmann::json spec, nlohmann::json videos, nlohmann::json frames,
                               std::size_t total, const std::string& owner) {
  std::lock_guard lock(mu_);
  const std::string id = sweeps_.next_id();
  nlohmann::json record = {{"id", id},
                           {"spec", std::move(spec)},
                           {"videos", std::move(videos)},
                           {"frames", std::move(frames)},
                           {"total", total},
                           {"runs", nlohmann::json::array()},
                           {"state", "running"},
                           {"done", false},
                           {"job", nullptr},
                           {"created", utc_now_iso()},
                           {"owner", owner}};
  save_locked(record);
  sweeps_.add(id, std::move(record));
  return id;
}

void SweepStore::set_job(const std::string& id, const std::string& job) {
  std::lock_guard lock(mu_);
  nlohmann::json& r = sweeps_.at(id, "sweep");
  r["job"] = job;
  save_locked(r);
}

void SweepStore::add_run(const std::string& id, const std::string& run) {
  std::lock_guard lock(mu_);
  nlohmann::json& r = sweeps_.at(id, "sweep");
  r["runs"].push_back(run);
  save_locked(r);
}

void SweepStore::finish(const std::string& id, const std::string& state) {
  std::lock_guard lock(mu_);
  nlohmann::json& r = sweeps_.at(id, "sweep");
  r["state"] = state;
  r["done"] = state == "done";
  save_locked(r);
}

nlohmann::json SweepStore::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  return sweeps_.at(id, "sweep");
}

std::vector<nlohmann::json> SweepStore::list() const {
  std::lock_guard lock(mu_);
  return sweeps_.list();
}

}  // namespace trailscope::server
