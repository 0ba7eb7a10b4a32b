#include "store/video_store.hpp"

#include <fstream>

#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"
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

/// Bytes of the regular files under `dir` (a staging folder: a few files).
std::uint64_t folder_bytes(const fs::path& dir) {
  std::uint64_t total = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec))
    if (it->is_regular_file(ec)) total += it->file_size(ec);
  return total;
}

void write_meta(const fs::path& dir, const nlohmann::json& meta) {
  nlohmann::json m = meta;
  m["magic"] = kMagic;
  failpoint("store.write.before_manifest");
  const fs::path p = dir / kMetaFile;
  std::ofstream out(p, std::ios::trunc);
  out << json_text(m);
  out.close();
  if (!out) throw io_error(p, "write");
  fsync_path(p);
  fsync_path(dir);
}
}  // namespace

VideoStore::VideoStore(fs::path root)
    : folders_(std::move(root), {"video", "videos", 'v', kMetaFile}, [](const fs::path& dir) {
        std::ifstream in(dir / kMetaFile);
        nlohmann::json m = nlohmann::json::parse(in);
        std::error_code ec;
        if (m.value("magic", "") != kMagic || !fs::exists(dir / kPackFile, ec))
          throw io_error(dir, "recognise the format of");
        m.erase("magic");
        return m;
      }) {}

std::vector<nlohmann::json> VideoStore::list() const {
  return folders_.list();
}

nlohmann::json VideoStore::meta(const std::string& id) const {
  return folders_.meta(id);
}

fs::path VideoStore::pack_path(const std::string& id) const {
  folders_.check(id);
  return folders_.dir(id) / kPackFile;
}

std::string VideoStore::find_by_name(const std::string& name) const {
  for (const nlohmann::json& m : folders_.list())
    if (m.value("name", "") == name) return m.at("id").get<std::string>();
  return "";
}

std::string VideoStore::reserve() {
  std::lock_guard lock(mu_);
  if (folders_.size() + pending_.size() >= limits::kMaxStoredVideos)
    throw Error(Error::Kind::conflict, "video",
                "the server stores at most " + std::to_string(limits::kMaxStoredVideos) +
                    " videos (kMaxStoredVideos); delete one first");
  std::string id = folders_.next_id();
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
  std::lock_guard lock(mu_);
  folders_.publish(id, tmp, meta);  // atomic: the video appears whole or not at all
  pending_.erase(id);
  return meta;
}

nlohmann::json VideoStore::commit_pack(const std::string& id, const fs::path& file, std::string name,
                                       const std::string& owner) {
  fs::path tmp;
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
    tmp = folders_.stage(id);
    fs::rename(file, tmp / kPackFile, ec);
    if (ec) {  // another file system: copy instead
      ec.clear();
      fs::copy_file(file, tmp / kPackFile, ec);
      if (ec) throw io_error(tmp / kPackFile, "write");
      fs::remove(file, ec);
    }
    meta["name"] = name.empty() ? id : std::move(name);
    meta["origin"] = "upload";
    meta["owner"] = owner;
    return publish(id, tmp, std::move(meta));
  } catch (...) {
    fs::remove(file, ec);
    fs::remove_all(tmp, ec);
    release(id);
    throw;
  }
}

nlohmann::json VideoStore::commit_synthetic(const std::string& id, const tof::SynthOptions& options,
                                            std::string name, const ProgressFn& progress,
                                            const std::string& owner, const WriteCheck& check) {
  fs::path tmp;
  std::error_code ec;
  try {
    tmp = folders_.stage(id);
    tof::WriteOptions wo;
    wo.layout = tof::VideoLayout::pack;
    // The writer's temporary files lie inside the staging folder: its size is what has been written.
    const ProgressFn report = [&](double fraction, std::string_view stage) {
      if (progress) progress(fraction, stage);
      if (check) check(folder_bytes(tmp));
    };
    tof::write_synthetic_video(options, tmp / kPackFile, wo, report);
    if (check) check(folder_bytes(tmp));
    const tof::DepthVideoReader reader(tmp / kPackFile);
    nlohmann::json meta = tof::describe_video(reader);
    meta["depth_range_mm"] = depth_range_json(reader);
    meta["name"] = name.empty() ? id : std::move(name);
    meta["origin"] = "synthetic";
    meta["owner"] = owner;
    return publish(id, tmp, std::move(meta));
  } catch (...) {
    fs::remove_all(tmp, ec);
    release(id);
    throw;
  }
}

void VideoStore::remove(const std::string& id) {
  // A replay or track job still reading the pack fails at its next frame (the reader reopens the file per
  // frame) and reports that as its error; nothing half-deleted stays behind.
  folders_.remove(id);
}

std::size_t VideoStore::size() const {
  return folders_.size();
}

}  // namespace trailscope::server
