// DepthVideoReader: one interface over the four on-disk forms (video folder, pack, PNG folder, one PNG).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <variant>

#include "manifest.hpp"
#include "pixels.hpp"
#include "png16.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::tof {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {
// One PNG frame file is far smaller than this; the bound only stops a hostile manifest or folder from
// making us read a huge file into memory.
constexpr std::uint64_t kMaxFrameFileBytes = 256ull << 20;

std::uint64_t get_u64(const char* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}

// File names in a manifest must stay inside the video folder: relative, [A-Za-z0-9_.-] components that
// do not start with a dot (so no "..", no hidden files).
bool safe_relative_name(const std::string& s) {
  if (s.empty() || s.size() > 255) return false;
  bool at_component_start = true;
  for (char c : s) {
    if (c == '/') {
      if (at_component_start) return false;
      at_component_start = true;
      continue;
    }
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok || (at_component_start && c == '.')) return false;
    at_component_start = false;
  }
  return !at_component_start;
}

bool is_png_name(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png";
}

std::string frame_label(const std::string& file, std::size_t index) {
  return file + " (frame " + std::to_string(index) + ")";
}
}  // namespace

struct DepthVideoReader::Impl {
  enum class Mode { folder, pack, pngs } mode = Mode::folder;
  fs::path path;
  VideoInfo info;
  std::vector<detail::FrameEntry> entries;  // folder and pack
  std::vector<fs::path> pngs;               // pngs: the frame files in order
  std::uint64_t pack_data_end = 0;          // pack: where the images end (the manifest's offset)
  double depth_unit_mm = 1.0;

  // The PNG bytes an entry's reference points at.
  std::string fetch(const json& ref, std::size_t index, const char* param) const {
    if (mode == Mode::folder) {
      if (!ref.is_string() || !safe_relative_name(ref.get<std::string>()))
        throw Error(Error::Kind::unsupported_format, "manifest",
                    (path / "manifest.json").string() + " frame " + std::to_string(index) + ": " + param +
                        " must be a relative file name inside the video folder, not " + ref.dump());
      const fs::path file = path / ref.get<std::string>();
      if (!fs::exists(file))
        throw not_found(param, frame_label(file.string(), index) + ": listed in manifest.json but missing");
      return detail::read_file_bytes(file, kMaxFrameFileBytes, param);
    }
    const std::string where = path.string() + " frame " + std::to_string(index);
    if (!ref.is_object() || !ref.contains("offset") || !ref.contains("bytes") ||
        !ref["offset"].is_number_unsigned() || !ref["bytes"].is_number_unsigned())
      throw Error(Error::Kind::unsupported_format, "manifest",
                  where + ": " + param + " must be {\"offset\": N, \"bytes\": N}");
    const std::uint64_t offset = ref["offset"].get<std::uint64_t>(),
                        bytes = ref["bytes"].get<std::uint64_t>();
    if (offset > pack_data_end || bytes > pack_data_end - offset || bytes > kMaxFrameFileBytes)
      throw Error(Error::Kind::unprocessable, param,
                  where + ": " + param + " bytes [" + std::to_string(offset) + ", +" + std::to_string(bytes) +
                      ") lie outside the pack's image data (" + std::to_string(pack_data_end) + " bytes)");
    std::ifstream f(path, std::ios::binary);
    std::string data(bytes, '\0');
    if (!f.seekg(static_cast<std::streamoff>(offset)) ||
        !f.read(data.data(), static_cast<std::streamsize>(bytes)))
      throw Error(Error::Kind::internal, param, where + ": read failed");
    return data;
  }

  detail::Png16 decode(const std::string& bytes, const std::string& label, const char* param) const {
    detail::Png16 img = detail::decode_png16(bytes, label, param);
    if (img.width != info.intrinsics.width || img.height != info.intrinsics.height)
      throw Error(Error::Kind::unprocessable, param,
                  label + ": image is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                      " px, the video is " + std::to_string(info.intrinsics.width) + "x" +
                      std::to_string(info.intrinsics.height));
    return img;
  }

  std::string label_of(const json& ref, std::size_t index, const char* what) const {
    if (mode == Mode::folder && ref.is_string()) return frame_label(ref.get<std::string>(), index);
    return frame_label(path.filename().string() + " " + what, index);
  }

  void open_manifest_folder() {
    mode = Mode::folder;
    const fs::path mpath = path / "manifest.json";
    const std::string text = detail::read_file_bytes(mpath, limits::kMaxVideoManifestBytes, "manifest");
    detail::Manifest m = detail::manifest_from_text(text, mpath.string());
    info = std::move(m.info);
    entries = std::move(m.frames);
  }

  void open_pack(std::uint64_t size) {
    mode = Mode::pack;
    if (size > limits::kMaxVideoUploadBytes)
      throw Error(Error::Kind::payload_too_large, "video",
                  path.string() + ": " + std::to_string(size) + " bytes exceeds the limit of " +
                      std::to_string(limits::kMaxVideoUploadBytes) + " bytes (kMaxVideoUploadBytes)");
    std::ifstream f(path, std::ios::binary);
    char trailer[detail::kPackTrailerBytes];
    f.seekg(static_cast<std::streamoff>(size - detail::kPackTrailerBytes));
    if (!f.read(trailer, sizeof trailer))
      throw Error(Error::Kind::internal, "video", path.string() + ": read failed");
    const std::uint64_t offset = get_u64(trailer), length = get_u64(trailer + 8);
    if (offset > size - detail::kPackTrailerBytes || length != size - detail::kPackTrailerBytes - offset)
      throw Error(Error::Kind::unsupported_format, "video",
                  path.string() + ": damaged pack (the trailer's manifest range does not fit the file)");
    if (length > limits::kMaxVideoManifestBytes)
      throw Error(Error::Kind::payload_too_large, "manifest",
                  path.string() + ": manifest of " + std::to_string(length) + " bytes exceeds the limit of " +
                      std::to_string(limits::kMaxVideoManifestBytes) + " bytes (kMaxVideoManifestBytes)");
    std::string text(length, '\0');
    f.seekg(static_cast<std::streamoff>(offset));
    if (!f.read(text.data(), static_cast<std::streamsize>(length)))
      throw Error(Error::Kind::internal, "video", path.string() + ": read failed");
    detail::Manifest m = detail::manifest_from_text(text, path.string());
    info = std::move(m.info);
    entries = std::move(m.frames);
    pack_data_end = offset;
  }

  void open_pngs(std::vector<fs::path> files, double fps) {
    mode = Mode::pngs;
    if (files.size() > limits::kMaxVideoFrames)
      throw Error(Error::Kind::payload_too_large, "frames",
                  path.string() + ": " + std::to_string(files.size()) + " PNG frames exceed the limit of " +
                      std::to_string(limits::kMaxVideoFrames) + " frames (kMaxVideoFrames)");
    // The first frame fixes the size; every later one must match (checked when it is read).
    const std::string first = detail::read_file_bytes(files[0], kMaxFrameFileBytes, "depth");
    const detail::Png16 img = detail::decode_png16(first, frame_label(files[0].string(), 0), "depth");
    if (static_cast<std::size_t>(img.width) * img.height > limits::kMaxVideoPixels)
      throw Error(Error::Kind::payload_too_large, "depth",
                  files[0].string() + ": " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                      " px exceeds the limit of " + std::to_string(limits::kMaxVideoPixels) +
                      " pixels per frame (kMaxVideoPixels)");
    info.intrinsics = default_intrinsics(img.width, img.height);
    info.fps = fps;
    info.frame_count = files.size();
    info.has_amplitude = false;
    info.has_truth = false;
    info.timestamps_defaulted = true;
    json names = json::array();
    for (const auto& f : files) names.push_back(f.filename().string());
    info.source = {{"import", "png"}, {"depth_unit_mm", depth_unit_mm}, {"files", names}};
    pngs = std::move(files);
  }
};

DepthVideoReader::DepthVideoReader(const fs::path& path, const ImportOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!(std::isfinite(options.depth_unit_mm) && options.depth_unit_mm > 0))
    throw invalid_argument("depth_unit_mm", "depth_unit_mm must be finite and > 0");
  if (!(std::isfinite(options.fps) && options.fps > 0))
    throw invalid_argument("fps", "fps must be finite and > 0 Hz");
  Impl& r = *impl_;
  r.path = path;
  r.depth_unit_mm = options.depth_unit_mm;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw not_found("video", path.string() + ": no such file or folder");
  if (fs::is_directory(st)) {
    if (fs::exists(path / "manifest.json")) {
      r.open_manifest_folder();
      return;
    }
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(path, ec))
      if (e.is_regular_file() && is_png_name(e.path()) && e.path().filename().string()[0] != '.')
        files.push_back(e.path());
    if (files.empty())
      throw Error(Error::Kind::unsupported_format, "video",
                  path.string() + ": not a depth video (no manifest.json and no .png frames)");
    std::sort(files.begin(), files.end());
    r.open_pngs(std::move(files), options.fps);
    return;
  }
  const std::uint64_t size = fs::file_size(path, ec);
  if (ec) throw not_found("video", path.string() + ": cannot read");
  std::string head(std::min<std::uint64_t>(size, 8), '\0');
  {
    std::ifstream f(path, std::ios::binary);
    f.read(head.data(), static_cast<std::streamsize>(head.size()));
  }
  // The trailer first: a pack begins with its first frame's PNG.
  if (size >= detail::kPackTrailerBytes) {
    std::ifstream f(path, std::ios::binary);
    std::string magic(detail::kPackMagic.size(), '\0');
    f.seekg(static_cast<std::streamoff>(size - magic.size()));
    if (f.read(magic.data(), static_cast<std::streamsize>(magic.size())) && magic == detail::kPackMagic) {
      r.open_pack(size);
      return;
    }
  }
  if (detail::has_png_signature(head)) {
    r.open_pngs({path}, options.fps);
    return;
  }
  throw Error(Error::Kind::unsupported_format, "video",
              path.string() + ": not a depth video (neither a 16-bit PNG nor a depth-video pack)");
}

DepthVideoReader::~DepthVideoReader() = default;
DepthVideoReader::DepthVideoReader(DepthVideoReader&&) noexcept = default;
DepthVideoReader& DepthVideoReader::operator=(DepthVideoReader&&) noexcept = default;

const VideoInfo& DepthVideoReader::info() const {
  return impl_->info;
}

DepthFrame DepthVideoReader::read_frame(std::size_t index) const {
  const Impl& r = *impl_;
  if (index >= r.info.frame_count)
    throw invalid_argument("frame", "frame " + std::to_string(index) + " does not exist (the video has " +
                                        std::to_string(r.info.frame_count) + " frames)");
  DepthFrame frame;
  if (r.mode == Impl::Mode::pngs) {
    const fs::path& file = r.pngs[index];
    const std::string label = frame_label(file.string(), index);
    const detail::Png16 img =
        r.decode(detail::read_file_bytes(file, kMaxFrameFileBytes, "depth"), label, "depth");
    frame.timestamp_s = static_cast<double>(index) / r.info.fps;
    frame.depth_mm = detail::counts_to_depth(img.data, r.depth_unit_mm);
    return frame;
  }
  const detail::FrameEntry& e = r.entries[index];
  frame.timestamp_s = e.timestamp_s;
  frame.truth = e.truth;
  const detail::Png16 depth =
      r.decode(r.fetch(e.depth, index, "depth"), r.label_of(e.depth, index, "depth"), "depth");
  frame.depth_mm = detail::counts_to_depth(depth.data, 1.0);
  if (r.info.has_amplitude) {
    const detail::Png16 amp = r.decode(r.fetch(e.amplitude, index, "amplitude"),
                                       r.label_of(e.amplitude, index, "amplitude"), "amplitude");
    frame.amplitude = detail::counts_to_amplitude(amp.data, r.info.amplitude_scale);
  }
  return frame;
}

DepthVideo read_depth_video(const fs::path& path, const ImportOptions& options, const ProgressFn& progress) {
  DepthVideoReader reader(path, options);
  const VideoInfo& info = reader.info();
  const std::uint64_t bytes = static_cast<std::uint64_t>(info.frame_count) * info.intrinsics.width *
                              info.intrinsics.height * (info.has_amplitude ? 8u : 4u);
  if (bytes > limits::kMaxVideoLoadBytes)
    throw Error(Error::Kind::payload_too_large, "video",
                path.string() + ": loading " + std::to_string(bytes) + " bytes exceeds the limit of " +
                    std::to_string(limits::kMaxVideoLoadBytes) +
                    " bytes (kMaxVideoLoadBytes); read it frame by frame (DepthVideoReader)");
  DepthVideo video;
  video.info = info;
  video.frames.reserve(info.frame_count);
  for (std::size_t i = 0; i < info.frame_count; ++i) {
    video.frames.push_back(reader.read_frame(i));
    if (progress && (i % 16 == 0 || i + 1 == info.frame_count))
      progress(static_cast<double>(i + 1) / info.frame_count, "read");
  }
  return video;
}

json describe_video(const DepthVideoReader& reader) {
  return detail::header_to_json(reader.info());
}

}  // namespace trailscope::tof
