#pragma once
// The binary file of a stored gaze dataset (proto/gaze_store.md, "TSGZ"): every recording of one ingested
// upload — its tags, units, geometry, rate, samples (time, x, y, validity), the tracker's own events and
// the per-sample label columns — in one file, so that a stored dataset reads back exactly what was
// ingested (doubles as doubles: the detectors give the same events on the stored copy as on the file).
// Little-endian; the encoder and decoder refuse to build on a big-endian machine.
#include <cstdint>
#include <string>
#include <string_view>

#include "trailscope/gaze/gaze.hpp"

namespace trailscope::server {

/// The first four bytes of the file and its version.
inline constexpr char kGazeFileMagic[] = "TSGZ";
inline constexpr std::uint32_t kGazeFileVersion = 1;
/// Longest tag text (participant, stimulus, trial, format, annotation name) the format holds (bytes).
inline constexpr std::uint32_t kGazeFileMaxText = 4096;
/// Most annotation columns of one recording.
inline constexpr std::uint32_t kGazeFileMaxAnnotations = 64;

/// The encoded size of `ds` (bytes), without encoding it: what a disk budget grants the write.
std::uint64_t gaze_file_size(const gaze::GazeDataset& ds);

/// Encodes `ds`. Throws invalid_argument("file") when a text is longer than kGazeFileMaxText, a recording
/// has more than kGazeFileMaxAnnotations annotation columns, or its columns differ in length.
std::string encode_gaze_file(const gaze::GazeDataset& ds);

/// Decodes a whole file. Throws Error(unprocessable, "gaze_file", "gaze file: byte N: <what>") on
/// anything but a complete file of this format: a wrong magic or version, a count or length running past
/// the end (checked before anything is allocated), more than limits::kMaxGazeRecordings recordings or
/// limits::kMaxGazeSamples samples in all, an unknown units, validity, event type or eye code, a text
/// or annotation count over the limits above, or bytes after the last recording.
gaze::GazeDataset decode_gaze_file(std::string_view bytes);

}  // namespace trailscope::server
