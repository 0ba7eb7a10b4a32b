#include "store/video_store.hpp"

#include <algorithm>
#include <fstream>
#include <iostream>

#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "store/graph_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tof/depth_render.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
constexpr char kPackFile[] = "video.tsdv";
constexpr char kMetaFile[] = "meta.json";
constexpr char kMagic[] = "TRAILSCOPE-VIDEO-1";

/// [min, max] mm of tof::video_depth_range: the colour range a viewer uses for every frame of the video.
nlohmann::json depth_range_json(const tof::DepthVideoReader& reader) {
  const tof::DepthRange r = tof::video_depth_range(reader);
  return {r.min_mm, r.max_mm};
}
constexpr std::string_view kPackMagic = "TSDVPK01";  // the last 8 bytes of a pack (proto/depth_video.md)

bool has_pack_trailer(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  in.seekg(-static_cast<std::streamoff>(kPackMagic.size()), std::ios::end);
  std::string tail(kPackMagic.size(), '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  return in && tail == kPackMagic;
}

/// The reader's error with the upload's temporary path replaced: the client never saw that name.
Error rename_upload(const Error& e, const fs::path& file) {
  std::string msg = e.what();
  const std::string p = file.string();
  for (auto at = msg.find(p); at != std::string::npos; at = msg.find(p))
    msg.replace(at, p.size(), "the upload");
  return Error(e.kind(), e.param(), msg);
}

void write_meta(const fs::path& dir, const nlohmann::json& meta) {
  nlohmann::json m = meta;
  m["magic"] = kMagic;
  const fs::path p = dir / kMetaFile;
  std::ofstream out(p, std::ios::trunc);
  out << json_text(m);
  out.close();
  if (!out) throw io_error(p, "write");
  fsync_path(p);
  fsync_path(dir);
}
}  // namespace

VideoStore::VideoStore(fs::path root) : root_(std::move(root)) {
  std::error_code ec;
  for (const char* sub : {"videos", "tmp"}) {
    fs::create_directories(root_ / sub, ec);
    if (ec) throw io_error(root_ / sub, "create");
  }
  for (const auto& e : fs::directory_iterator(root_ / "tmp"))
    if (e.path().filename().string().rfind("video.", 0) == 0) fs::remove_all(e.path(), ec);
  for (const auto& e : fs::directory_iterator(root_ / "videos")) {
    const std::string id = e.path().filename().string();
    const std::uint64_t n = store_id_number(id, 'v');
    if (!e.is_directory() || n == 0 || !fs::exists(e.path() / kMetaFile, ec)) continue;
    try {
      std::ifstream in(e.path() / kMetaFile);
      nlohmann::json m = nlohmann::json::parse(in);
      if (m.value("magic", "") != kMagic || !fs::exists(e.path() / kPackFile, ec))
        throw io_error(e.path(), "recognise the format of");
      m.erase("magic");
      meta_[id] = std::move(m);
      ids_[n] = id;
      next_ = std::max(next_, n + 1);
    } catch (const std::exception& ex) {
      std::cerr << "store: skipping video '" << id << "': " << ex.what() << "\n";
    }
  }
}

std::vector<nlohmann::json> VideoStore::list() const {
  std::lock_guard lock(mu_);
  std::vector<nlohmann::json> out;
  for (const auto& [n, id] : ids_) out.push_back(meta_.at(id));
  return out;
}

nlohmann::json VideoStore::meta(const std::string& id) const {
  std::lock_guard lock(mu_);
  auto it = meta_.find(id);
  if (it == meta_.end()) throw not_found("video", "video '" + id + "' does not exist");
  return it->second;
}

fs::path VideoStore::pack_path(const std::string& id) const {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("video", "video '" + id + "' does not exist");
  return root_ / "videos" / id / kPackFile;
}

std::string VideoStore::find_by_name(const std::string& name) const {
  std::lock_guard lock(mu_);
  for (const auto& [n, id] : ids_)
    if (meta_.at(id).value("name", "") == name) return id;
  return "";
}

std::string VideoStore::reserve() {
  std::lock_guard lock(mu_);
  if (ids_.size() + pending_.size() >= limits::kMaxStoredVideos)
    throw Error(Error::Kind::conflict, "video",
                "the server stores at most " + std::to_string(limits::kMaxStoredVideos) +
                    " videos (kMaxStoredVideos); delete one first");
  std::string id = store_id('v', next_++);
  pending_.insert(id);
  return id;
}

void VideoStore::release(const std::string& id) {
  std::lock_guard lock(mu_);
  pending_.erase(id);
}

nlohmann::json VideoStore::publish(const std::string& id, const fs::path& tmp, nlohmann::json meta) {
  std::error_code ec;
  const fs::path pack = tmp / kPackFile;
  meta["id"] = id;
  meta["created"] = utc_now_iso();
  meta["bytes"] = fs::file_size(pack, ec);
  fsync_path(pack);
  write_meta(tmp, meta);  // last: a folder without meta.json is incomplete
  const fs::path final_dir = root_ / "videos" / id;
  fs::rename(tmp, final_dir, ec);  // atomic: the video appears whole or not at all
  if (ec) throw io_error(final_dir, "rename into");
  fsync_path(root_ / "videos");
  std::lock_guard lock(mu_);
  pending_.erase(id);
  ids_[store_id_number(id, 'v')] = id;
  meta_[id] = meta;
  return meta;
}

nlohmann::json VideoStore::commit_pack(const std::string& id, const fs::path& file, std::string name) {
  const fs::path tmp = root_ / "tmp" / ("video." + id + "." + random_suffix());
  std::error_code ec;
  try {
    nlohmann::json meta;
    try {
      const tof::DepthVideoReader reader(file);
      if (!has_pack_trailer(file))
        throw Error(Error::Kind::unsupported_format, "body",
                    "body: a video upload must be a depth-video pack (.tsdv, proto/depth_video.md); pack a "
                    "video folder or PNG frames with `trailscope synth --pack` or DepthVideoWriter");
      if (reader.size() > 0) reader.read_frame(0);  // the manifest can be fine and the PNGs not
      meta = tof::describe_video(reader);
      meta["depth_range_mm"] = depth_range_json(reader);
    } catch (const Error& e) {
      throw rename_upload(e, file);
    }
    fs::create_directories(tmp, ec);
    if (ec) throw io_error(tmp, "create");
    fs::rename(file, tmp / kPackFile, ec);
    if (ec) {  // another file system: copy instead
      ec.clear();
      fs::copy_file(file, tmp / kPackFile, ec);
      if (ec) throw io_error(tmp / kPackFile, "write");
      fs::remove(file, ec);
    }
    meta["name"] = name.empty() ? id : std::move(name);
    meta["origin"] = "upload";
    return publish(id, tmp, std::move(meta));
  } catch (...) {
    fs::remove(file, ec);
    fs::remove_all(tmp, ec);
    release(id);
    throw;
  }
}

nlohmann::json VideoStore::commit_synthetic(const std::string& id, const tof::SynthOptions& options,
                                            std::string name, const ProgressFn& progress) {
  const fs::path tmp = root_ / "tmp" / ("video." + id + "." + random_suffix());
  std::error_code ec;
  try {
    fs::create_directories(tmp, ec);
    if (ec) throw io_error(tmp, "create");
    tof::WriteOptions wo;
    wo.layout = tof::VideoLayout::pack;
    tof::write_synthetic_video(options, tmp / kPackFile, wo, progress);
    const tof::DepthVideoReader reader(tmp / kPackFile);
    nlohmann::json meta = tof::describe_video(reader);
    meta["depth_range_mm"] = depth_range_json(reader);
    meta["name"] = name.empty() ? id : std::move(name);
    meta["origin"] = "synthetic";
    return publish(id, tmp, std::move(meta));
  } catch (...) {
    fs::remove_all(tmp, ec);
    release(id);
    throw;
  }
}

void VideoStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("video", "video '" + id + "' does not exist");
  const fs::path gone = root_ / "tmp" / ("video." + id + ".deleted." + random_suffix());
  std::error_code ec;
  fs::rename(root_ / "videos" / id, gone, ec);
  if (ec) throw io_error(root_ / "videos" / id, "remove");
  ids_.erase(store_id_number(id, 'v'));
  meta_.erase(id);
  // A replay or track job still reading the pack fails at its next frame (the reader reopens the file per
  // frame) and reports that as its error; nothing half-deleted stays behind.
  fs::remove_all(gone, ec);
}

std::size_t VideoStore::size() const {
  std::lock_guard lock(mu_);
  return ids_.size();
}

}  // namespace trailscope::server
