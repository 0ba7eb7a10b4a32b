// DepthVideoWriter: streams frames into a temporary folder (or pack file) next to the target and renames
// it into place in finish(), so the target is either absent, the old video, or the complete new one.
#include <tbb/parallel_for.h>

#include <cstdio>
#include <fstream>
#include <random>

#include "manifest.hpp"
#include "pixels.hpp"
#include "png16.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::tof {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {
std::string frame_file(const char* folder, std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "%s/%06zu.png", folder, index);
  return name;
}

void put_u64(std::string& s, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

// The temporary name is hidden (leading dot) and random, so concurrent writers of one target never share
// it and listings of the parent folder skip it.
fs::path temp_path_for(const fs::path& target) {
  std::random_device rd;
  char suffix[24];
  std::snprintf(suffix, sizeof suffix, ".tmp-%08x", static_cast<unsigned>(rd()));
  std::string name = ".";  // appended, not "." + ...: GCC 12 warns falsely (-Wrestrict) on the operator+ form
  name += target.filename().string();
  name += suffix;
  return target.parent_path() / name;
}
}  // namespace

struct DepthVideoWriter::Impl {
  fs::path target, temp;
  VideoInfo info;
  WriteOptions options;
  std::vector<detail::FrameEntry> entries;
  std::ofstream pack;
  std::uint64_t pack_bytes = 0;
  bool finished = false;

  void write_file(const std::string& relative, const std::string& bytes) {
    std::ofstream f(temp / relative, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw Error(Error::Kind::internal, "output", "cannot write " + (temp / relative).string());
  }
  json append_pack(const std::string& bytes) {
    if (pack_bytes + bytes.size() > limits::kMaxVideoUploadBytes)
      throw Error(Error::Kind::payload_too_large, "frames",
                  "the pack would exceed the limit of " + std::to_string(limits::kMaxVideoUploadBytes) +
                      " bytes (kMaxVideoUploadBytes) at frame " + std::to_string(entries.size()));
    pack.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!pack) throw Error(Error::Kind::internal, "output", "cannot write " + temp.string());
    json ref = {{"offset", pack_bytes}, {"bytes", bytes.size()}};
    pack_bytes += bytes.size();
    return ref;
  }
  std::string encode(const std::vector<std::uint16_t>& counts) const {
    return detail::encode_png16(counts.data(), info.intrinsics.width, info.intrinsics.height,
                                options.png_compression);
  }
  json store(const char* folder, const std::string& png) {
    if (options.layout == VideoLayout::pack) return append_pack(png);
    const std::string name = frame_file(folder, entries.size());
    write_file(name, png);
    return name;
  }

  // The checks of write(), for the frame that would get index `index` after `previous_t`.
  void check(const DepthFrame& frame, std::size_t index, const double* previous_t) const {
    if (finished) throw Error(Error::Kind::internal, "frame", "write() after finish()");
    if (index >= limits::kMaxVideoFrames)
      throw Error(
          Error::Kind::payload_too_large, "frames",
          "a video holds at most " + std::to_string(limits::kMaxVideoFrames) + " frames (kMaxVideoFrames)");
    validate_frame(info, frame, index);
    if (previous_t && frame.timestamp_s < *previous_t)
      throw invalid_argument("frame", "frame " + std::to_string(index) + ": timestamp_s " +
                                          std::to_string(frame.timestamp_s) +
                                          " is earlier than the previous frame's");
  }

  // Encoded images of one frame: the part worth running in parallel.
  struct Encoded {
    std::string depth, amplitude;
  };
  Encoded encode_frame(const DepthFrame& frame, std::size_t index) const {
    Encoded e;
    e.depth = encode(detail::depth_to_counts(frame.depth_mm, index));
    if (info.has_amplitude)
      e.amplitude = encode(detail::amplitude_to_counts(frame.amplitude, info.amplitude_scale));
    return e;
  }
  void append(const DepthFrame& frame, const Encoded& png) {
    detail::FrameEntry e;
    e.timestamp_s = frame.timestamp_s;
    e.truth = frame.truth;
    e.depth = store("depth", png.depth);
    if (info.has_amplitude) e.amplitude = store("amplitude", png.amplitude);
    entries.push_back(std::move(e));
  }
};

DepthVideoWriter::DepthVideoWriter(const fs::path& target, VideoInfo info, const WriteOptions& options)
    : impl_(std::make_unique<Impl>()) {
  info.frame_count = 0;
  validate_info(info);
  if (options.png_compression < 0 || options.png_compression > 9)
    throw invalid_argument("png_compression", "png_compression must be 0..9");
  if (target.empty() || target.filename().empty())
    throw invalid_argument("output", "output path '" + target.string() + "' has no file or folder name");
  if (fs::exists(target) && !options.overwrite)
    throw Error(Error::Kind::conflict, "output",
                target.string() + " exists (replace it with overwrite, CLI --force)");
  impl_->target = target;
  impl_->info = std::move(info);
  impl_->options = options;
  impl_->temp = temp_path_for(target);
  std::error_code ec;
  if (!target.parent_path().empty()) fs::create_directories(target.parent_path(), ec);
  if (options.layout == VideoLayout::folder) {
    if (!fs::create_directory(impl_->temp, ec) || !fs::create_directory(impl_->temp / "depth", ec) ||
        (impl_->info.has_amplitude && !fs::create_directory(impl_->temp / "amplitude", ec)))
      throw Error(Error::Kind::internal, "output",
                  "cannot create " + impl_->temp.string() + ": " + ec.message());
  } else {
    impl_->pack.open(impl_->temp, std::ios::binary | std::ios::trunc);
    if (!impl_->pack) throw Error(Error::Kind::internal, "output", "cannot create " + impl_->temp.string());
  }
}

DepthVideoWriter::~DepthVideoWriter() {
  if (!impl_ || impl_->finished) return;
  impl_->pack.close();
  std::error_code ec;
  fs::remove_all(impl_->temp, ec);
}

std::size_t DepthVideoWriter::frames_written() const {
  return impl_->entries.size();
}

void DepthVideoWriter::write(const DepthFrame& frame) {
  Impl& w = *impl_;
  const std::size_t index = w.entries.size();
  w.check(frame, index, index > 0 ? &w.entries.back().timestamp_s : nullptr);
  w.append(frame, w.encode_frame(frame, index));
}

void DepthVideoWriter::write(const std::vector<DepthFrame>& frames) {
  Impl& w = *impl_;
  const std::size_t first = w.entries.size();
  for (std::size_t j = 0; j < frames.size(); ++j) {
    const double* previous =
        j > 0 ? &frames[j - 1].timestamp_s : (first > 0 ? &w.entries.back().timestamp_s : nullptr);
    w.check(frames[j], first + j, previous);
  }
  // PNG encoding is most of the cost of writing; the files are then written in order.
  std::vector<Impl::Encoded> encoded(frames.size());
  tbb::parallel_for(std::size_t{0}, frames.size(),
                    [&](std::size_t j) { encoded[j] = w.encode_frame(frames[j], first + j); });
  for (std::size_t j = 0; j < frames.size(); ++j) w.append(frames[j], encoded[j]);
}

void DepthVideoWriter::finish() {
  Impl& w = *impl_;
  if (w.finished) return;
  if (w.entries.empty())
    throw Error(Error::Kind::unprocessable, "frames", "a video needs at least one frame");
  VideoInfo info = w.info;
  info.frame_count = w.entries.size();
  // The header indented, then one compact line per frame: readable and diffable, and a third of the
  // size of indenting everything.
  std::string text = json_text(detail::header_to_json(info), 1);
  text.resize(text.size() - 2);  // drop the closing "\n}"
  text += ",\n \"frames\": [\n";
  for (std::size_t i = 0; i < w.entries.size(); ++i)
    text += "  " + json_text(detail::entry_to_json(w.entries[i])) + (i + 1 < w.entries.size() ? ",\n" : "\n");
  text += " ]\n}\n";
  if (text.size() > limits::kMaxVideoManifestBytes)
    throw Error(Error::Kind::payload_too_large, "frames",
                "the manifest would be " + std::to_string(text.size()) + " bytes, over the limit of " +
                    std::to_string(limits::kMaxVideoManifestBytes) + " bytes (kMaxVideoManifestBytes)");
  if (w.options.layout == VideoLayout::folder) {
    w.write_file("manifest.json", text);
  } else {
    std::string tail = std::move(text);
    const std::uint64_t offset = w.pack_bytes, length = tail.size();
    put_u64(tail, offset);
    put_u64(tail, length);
    tail += detail::kPackMagic;
    w.pack.write(tail.data(), static_cast<std::streamsize>(tail.size()));
    w.pack.close();
    if (!w.pack) throw Error(Error::Kind::internal, "output", "cannot write " + w.temp.string());
  }
  // Move into place. Replacing an existing target takes two renames; the old one is parked under a
  // temporary name first so that the target name is never half-written.
  std::error_code ec;
  fs::path parked;
  if (fs::exists(w.target)) {
    if (!w.options.overwrite)
      throw Error(Error::Kind::conflict, "output",
                  w.target.string() + " exists (replace it with overwrite, CLI --force)");
    parked = temp_path_for(w.target);
    fs::rename(w.target, parked, ec);
    if (ec)
      throw Error(Error::Kind::internal, "output", "cannot move " + w.target.string() + ": " + ec.message());
  }
  fs::rename(w.temp, w.target, ec);
  if (ec) {
    if (!parked.empty()) fs::rename(parked, w.target);
    throw Error(Error::Kind::internal, "output",
                "cannot rename into " + w.target.string() + ": " + ec.message());
  }
  w.finished = true;
  if (!parked.empty()) fs::remove_all(parked, ec);
}

void write_depth_video(const DepthVideo& video, const fs::path& target, const WriteOptions& options,
                       const ProgressFn& progress) {
  DepthVideoWriter writer(target, video.info, options);
  constexpr std::size_t kBatch = 64;
  for (std::size_t begin = 0; begin < video.frames.size(); begin += kBatch) {
    const std::size_t end = std::min(video.frames.size(), begin + kBatch);
    writer.write(std::vector<DepthFrame>(video.frames.begin() + begin, video.frames.begin() + end));
    if (progress) progress(static_cast<double>(end) / video.frames.size(), "write");
  }
  writer.finish();
}

}  // namespace trailscope::tof
