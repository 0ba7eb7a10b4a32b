#include "store/gaze_store.hpp"

#include <sodium.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <iostream>
#include <sstream>

#include "limits.hpp"
#include "params/upload_body.hpp"
#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "store/dataset_store.hpp"
#include "store/failpoint.hpp"
#include "store/gaze_file.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using column_io::io_error;

namespace {
constexpr char kMagic[] = "TRAILSCOPE-GAZE-1";
constexpr int kFormatVersion = 1;
constexpr char kFile[] = "recordings.tsgz";
/// Datasets whose recordings stay in memory after use (one may hold tens of millions of samples).
constexpr std::size_t kLoadedDatasets = 4;

nlohmann::json positive_or_null(double v) {
  return number_or_null(v > 0 ? v : std::numeric_limits<double>::quiet_NaN());
}

nlohmann::json recording_json(const gaze::Recording& r, std::size_t index) {
  nlohmann::json annotations = nlohmann::json::array();
  for (const auto& a : r.annotations) annotations.push_back(a.first);
  const auto& g = r.geometry;
  return {{"index", index},
          {"participant", r.participant},
          {"stimulus", r.stimulus},
          {"trial", r.trial},
          {"format", r.format},
          {"units", gaze::to_string(r.units)},
          {"rate_hz", positive_or_null(r.rate_hz)},
          {"samples", r.size()},
          {"valid_samples", r.valid_count()},
          {"t0_ms", number_or_null(r.size() ? r.t_ms.front() : std::numeric_limits<double>::quiet_NaN())},
          {"t1_ms", number_or_null(r.size() ? r.t_ms.back() : std::numeric_limits<double>::quiet_NaN())},
          {"tracker_events", r.tracker_events.size()},
          {"annotations", annotations},
          {"geometry",
           {{"width_px", positive_or_null(g.width_px)},
            {"height_px", positive_or_null(g.height_px)},
            {"width_cm", positive_or_null(g.width_cm)},
            {"height_cm", positive_or_null(g.height_cm)},
            {"distance_cm", positive_or_null(g.distance_cm)}}}};
}

std::string stimulus_key(const std::string& stimulus) {
  unsigned char h[16];
  crypto_generichash(h, sizeof h, reinterpret_cast<const unsigned char*>(stimulus.data()), stimulus.size(),
                     nullptr, 0);
  char hex[2 * sizeof h + 1];
  sodium_bin2hex(hex, sizeof hex, h, sizeof h);
  return hex;
}

std::string manifest_text(nlohmann::json m) {
  m["magic"] = kMagic, m["version"] = kFormatVersion;
  return json_text(m);
}

Error missing(const std::string& id) {
  return not_found("gaze", "gaze dataset '" + id + "' does not exist");
}
}  // namespace

nlohmann::json gaze_summary(const nlohmann::json& m) {
  nlohmann::json s = m;
  s.erase("recording_list");
  s.erase("stimulus_images");
  return s;
}

GazeStore::GazeStore(fs::path root, Leftovers leftovers) : root_(std::move(root)), loaded_(kLoadedDatasets) {
  std::error_code ec;
  for (const char* sub : {"gaze", "tmp"}) {
    fs::create_directories(root_ / sub, ec);
    if (ec) throw io_error(root_ / sub, "create");
  }
  if (leftovers == Leftovers::remove)
    for (const auto& e : fs::directory_iterator(root_ / "tmp"))
      if (e.path().filename().string().rfind("gaze.", 0) == 0) fs::remove_all(e.path(), ec);
  for (const auto& e : fs::directory_iterator(root_ / "gaze")) {
    const std::string id = e.path().filename().string();
    if (!e.is_directory() || !fs::exists(e.path() / "manifest.json", ec)) continue;
    try {
      nlohmann::json m = column_io::read_manifest(e.path());
      if (m.value("magic", "") != kMagic || m.value("version", 0) != kFormatVersion ||
          m.value("id", "") != id)
        throw io_error(e.path(), "recognise the format of");
      m.erase("magic"), m.erase("version");
      manifests_[id] = std::move(m);
    } catch (const std::exception& ex) {
      std::cerr << "store: skipping gaze dataset '" << id << "': " << ex.what() << "\n";
    }
  }
}

std::uint64_t GazeStore::bytes_estimate(const gaze::GazeDataset& ds) {
  return gaze_file_size(ds) + (64u << 10);
}

const nlohmann::json& GazeStore::manifest_locked(const std::string& id) const {
  auto it = manifests_.find(id);
  if (it == manifests_.end()) throw missing(id);
  return it->second;
}

std::vector<nlohmann::json> GazeStore::list() const {
  std::lock_guard lock(mu_);
  std::vector<nlohmann::json> out;
  for (const auto& [id, m] : manifests_) out.push_back(gaze_summary(m));
  return out;
}

nlohmann::json GazeStore::meta(const std::string& id) const {
  std::lock_guard lock(mu_);
  return manifest_locked(id);
}

bool GazeStore::contains(const std::string& id) const {
  std::lock_guard lock(mu_);
  return manifests_.count(id) > 0;
}

std::size_t GazeStore::size() const {
  std::lock_guard lock(mu_);
  return manifests_.size();
}

std::string GazeStore::owner(const std::string& id) const {
  std::lock_guard lock(mu_);
  return manifest_locked(id).value("owner", "");
}

std::shared_ptr<const gaze::GazeDataset> GazeStore::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  const nlohmann::json& m = manifest_locked(id);
  // Read under the lock: a delete cannot move the folder away mid-read.
  return loaded_.get(id, [&] {
    const fs::path p = dir(id) / kFile;
    const std::string bytes = read_whole_file(p);
    if (bytes.size() != m.value("bytes", std::uint64_t{0})) throw io_error(p, "read (size mismatch)");
    try {
      return std::make_shared<const gaze::GazeDataset>(decode_gaze_file(bytes));
    } catch (const Error& e) {
      throw Error(Error::Kind::internal, "", "store: cannot read " + p.string() + ": " + e.what());
    }
  });
}

void GazeStore::check_new(const std::string& id) const {
  validate_dataset_id(id, "name");
  std::lock_guard lock(mu_);
  if (manifests_.count(id))
    throw Error(Error::Kind::conflict, "name", "gaze dataset '" + id + "' already exists");
  if (manifests_.size() >= limits::kMaxStoredGazeDatasets)
    throw Error(Error::Kind::conflict, "name",
                "the server stores at most " + std::to_string(limits::kMaxStoredGazeDatasets) +
                    " gaze datasets (kMaxStoredGazeDatasets); delete one first");
}

nlohmann::json GazeStore::put(const std::string& id, const std::string& owner, const std::string& format,
                              std::shared_ptr<const gaze::GazeDataset> ds) {
  check_new(id);
  nlohmann::json recs = nlohmann::json::array();
  for (std::size_t i = 0; i < ds->recordings.size(); ++i)
    recs.push_back(recording_json(ds->recordings[i], i));
  const std::string bytes = encode_gaze_file(*ds);
  nlohmann::json m = {{"id", id},
                      {"name", id},
                      {"format", format},
                      {"created", utc_now_iso()},
                      {"owner", owner},
                      {"recordings", ds->recordings.size()},
                      {"samples", ds->total_samples()},
                      {"participants", ds->participants()},
                      {"stimuli", ds->stimuli()},
                      {"bytes", bytes.size()},
                      {"recording_list", std::move(recs)},
                      {"stimulus_images", nlohmann::json::array()}};
  const fs::path tmp = stage_folder(root_ / "tmp", "gaze." + id);
  try {
    {
      const fs::path p = tmp / kFile;
      std::ofstream out(p, std::ios::binary | std::ios::trunc);
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      out.close();
      if (!out) throw io_error(p, "write");
      column_io::fsync_path(p);
      failpoint("store.write.column");
    }
    nlohmann::json written = m;
    written["magic"] = kMagic, written["version"] = kFormatVersion;
    column_io::write_manifest(tmp, written);
    std::lock_guard lock(mu_);
    if (manifests_.count(id))
      throw Error(Error::Kind::conflict, "name", "gaze dataset '" + id + "' already exists");
    publish_folder(tmp, dir(id));
    manifests_[id] = m;
    loaded_.put(id, std::move(ds));
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
  return m;
}

void GazeStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  manifest_locked(id);
  remove_folder(dir(id), root_ / "tmp" / ("gaze." + id + ".deleted." + column_io::random_suffix()));
  manifests_.erase(id);
  loaded_.erase(id);
}

nlohmann::json GazeStore::put_stimulus(const std::string& id, const std::string& stimulus,
                                       const std::string& bytes, const gaze::StimulusImage& image) {
  std::lock_guard lock(mu_);
  nlohmann::json m = manifest_locked(id);
  const auto& stimuli = m.at("stimuli");
  if (std::find(stimuli.begin(), stimuli.end(), stimulus) == stimuli.end()) {
    std::string names;
    for (const auto& s : stimuli) names += (names.empty() ? "'" : ", '") + s.get<std::string>() + "'";
    throw invalid_argument("stimulus", "stimulus '" + stimulus + "' is not in gaze dataset '" + id +
                                           "' (its stimuli: " + (names.empty() ? "none" : names) + ")");
  }
  const fs::path folder = dir(id) / "stimuli";
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw io_error(folder, "create");
  const std::string file = stimulus_key(stimulus) + (image.type == "png" ? ".png" : ".jpg");
  // The image first, then the manifest that names it: a crash between leaves an image nobody names.
  column_io::write_file_atomic(folder / file, bytes);
  nlohmann::json entry = {{"stimulus", stimulus},
                          {"file", file},
                          {"content_type", image.content_type},
                          {"width_px", image.width_px},
                          {"height_px", image.height_px},
                          {"bytes", bytes.size()}};
  nlohmann::json images = nlohmann::json::array();
  std::string replaced;
  for (const auto& e : m.at("stimulus_images"))
    if (e.at("stimulus") != stimulus)
      images.push_back(e);
    else if (e.at("file") != file)
      replaced = e.at("file").get<std::string>();
  images.push_back(entry);
  m["stimulus_images"] = std::move(images);
  column_io::write_file_atomic(dir(id) / "manifest.json", manifest_text(m));
  if (!replaced.empty()) fs::remove(folder / replaced, ec);  // a PNG replaced by a JPEG
  manifests_[id] = std::move(m);
  return entry;
}

GazeStore::Image GazeStore::stimulus(const std::string& id, const std::string& stimulus) const {
  std::lock_guard lock(mu_);
  const nlohmann::json& m = manifest_locked(id);
  for (const auto& e : m.at("stimulus_images"))
    if (e.at("stimulus") == stimulus)
      return {read_whole_file(dir(id) / "stimuli" / e.at("file").get<std::string>()),
              e.at("content_type").get<std::string>()};
  throw not_found("stimulus", "gaze dataset '" + id + "' has no image of stimulus '" + stimulus + "'");
}

}  // namespace trailscope::server
