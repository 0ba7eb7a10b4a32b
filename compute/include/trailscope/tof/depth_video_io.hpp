#pragma once
// Reading and writing depth videos (depth_video.hpp). Full specification: proto/depth_video.md.
//
// A video FOLDER (format "trailscope-depth-video", version 1):
//   VIDEO/manifest.json          format, version, intrinsics, fps, amplitude_scale, frame_count, source,
//                                and per frame: timestamp_s, file names, ground truth
//   VIDEO/depth/000000.png ...   16-bit grey PNG, depth in whole mm, 0 = no return
//   VIDEO/amplitude/000000.png   16-bit grey PNG, round(amplitude / amplitude_scale) clamped to 65535
// The writer builds the folder under a temporary name next to the target and renames it into place only
// after manifest.json is written, so a reader never sees a half-written video.
//
// A PACK (one file, for uploads; by convention VIDEO.tsdv): the same PNGs back to back, then the manifest
// (file names replaced by byte ranges), then a 24-byte trailer: the manifest's offset and length
// (little-endian u64 each) and the magic "TSDVPK01". See proto/depth_video.md.
//
// Also read, without a manifest: a single 16-bit grey depth PNG, or a folder of them (frames in file-name
// order). Their intrinsics are default_intrinsics() (flagged `defaulted`), timestamps i / fps (flagged),
// no amplitude, no ground truth.
//
// Every failure throws trailscope::Error naming the parameter ("video", "manifest", "frames", "depth",
// ...) and, in the message, the file and frame at fault: not_found (no such path / a listed file is
// missing), unsupported_format (not a depth video, wrong format name or version, not a 16-bit PNG, a
// damaged PNG), unprocessable (well-formed but inconsistent: sizes, counts, timestamps),
// payload_too_large (limits::kMaxVideoFrames, kMaxVideoPixels, kMaxVideoManifestBytes,
// kMaxVideoUploadBytes, kMaxVideoLoadBytes), conflict (the target exists), internal (I/O failure).
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include "trailscope/core/progress.hpp"
#include "trailscope/tof/depth_video.hpp"

namespace trailscope::tof {

/// Format name and version written to and required from manifest.json and packs.
inline constexpr std::string_view kDepthVideoFormat = "trailscope-depth-video";
inline constexpr int kDepthVideoVersion = 1;
/// Frame rate assumed for imported PNGs without timestamps (Hz): the Redwood/PrimeSense rate.
inline constexpr double kDefaultImportFps = 30.0;

/// How to interpret manifest-less PNG frames.
struct ImportOptions {
  /// Millimetres per stored count (1 for Redwood/Open3D and Kinect; 0.2 for TUM RGB-D, 5000 per metre).
  double depth_unit_mm = 1.0;
  double fps = kDefaultImportFps;  ///< Hz, for timestamps i / fps
};

/// Random access to the frames of a video on disk without loading it whole (what trackers and the DMD
/// consume). Opening reads only the manifest (or lists the PNG folder); each read_frame() decodes one
/// frame's PNGs. Not thread-safe; open one reader per thread.
class DepthVideoReader {
 public:
  /// Opens a video folder, a pack file, a folder of 16-bit PNGs or one 16-bit PNG (told apart by content:
  /// manifest.json present, pack trailer, PNG signature). Validates the whole manifest. Throws as above.
  explicit DepthVideoReader(const std::filesystem::path& path, const ImportOptions& options = {});
  ~DepthVideoReader();
  DepthVideoReader(DepthVideoReader&&) noexcept;
  DepthVideoReader& operator=(DepthVideoReader&&) noexcept;

  const VideoInfo& info() const;
  std::size_t size() const { return info().frame_count; }
  /// Frame `index` (0-based). Throws Error(invalid_argument, "frame") for index >= size(), otherwise as
  /// above for a missing or damaged file.
  DepthFrame read_frame(std::size_t index) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Loads a whole video. Throws Error(payload_too_large, "video") when frames * pixels * 8 bytes exceed
/// limits::kMaxVideoLoadBytes (use DepthVideoReader for such videos); otherwise as DepthVideoReader.
DepthVideo read_depth_video(const std::filesystem::path& path, const ImportOptions& options = {},
                            const ProgressFn& progress = {});

/// On-disk form written by DepthVideoWriter.
enum class VideoLayout { folder, pack };

struct WriteOptions {
  VideoLayout layout = VideoLayout::folder;
  bool overwrite = false;  ///< replace an existing target (otherwise Error(conflict, "output"))
  /// zlib level of the PNGs, 0..9. 1 is the measured sweet spot for noisy depth (png16.cpp).
  int png_compression = 1;
};

/// Streams frames to disk. Frames are validated against `info` (validate_frame) and written in order;
/// finish() writes the manifest and moves the result to `target` atomically (rename). A writer destroyed
/// without finish() removes its temporary files, leaving `target` untouched. info.frame_count is ignored:
/// the count is the number of frames written.
class DepthVideoWriter {
 public:
  /// Throws Error(invalid_argument) for bad `info` (validate_info), Error(conflict, "output") when
  /// `target` exists and !overwrite, Error(internal) when the temporary folder cannot be created.
  DepthVideoWriter(const std::filesystem::path& target, VideoInfo info, const WriteOptions& options = {});
  ~DepthVideoWriter();
  DepthVideoWriter(const DepthVideoWriter&) = delete;
  DepthVideoWriter& operator=(const DepthVideoWriter&) = delete;

  /// Appends one frame. Throws Error(invalid_argument, "frame") for a frame that does not fit info, or a
  /// timestamp earlier than the previous frame's; Error(payload_too_large, "frames") beyond
  /// limits::kMaxVideoFrames (or, for a pack, beyond limits::kMaxVideoUploadBytes).
  void write(const DepthFrame& frame);
  /// Appends several frames, PNG-encoding them in parallel (oneTBB). All are checked before any is
  /// written, so on an error none of them is.
  void write(const std::vector<DepthFrame>& frames);
  std::size_t frames_written() const;
  /// Completes the video. Throws Error(unprocessable, "frames") when no frame was written.
  void finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes a whole video (DepthVideoWriter over video.frames).
void write_depth_video(const DepthVideo& video, const std::filesystem::path& target,
                       const WriteOptions& options = {}, const ProgressFn& progress = {});

/// The video-level part of a reader's manifest (everything but "frames") as JSON in the manifest.json
/// schema; for `trailscope video info --json` and the server.
nlohmann::json describe_video(const DepthVideoReader& reader);

}  // namespace trailscope::tof
