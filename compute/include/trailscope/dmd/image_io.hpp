#pragma once
// PNG input and output of the DMD verb, through OpenImageIO (kept out of this header).
#include <cstdint>
#include <filesystem>
#include <vector>

#include "trailscope/dmd/image.hpp"

namespace trailscope::dmd {

/// A single-channel PNG as read: 8-bit files are grey images, 16-bit files depth in mm (0 = hole),
/// the convention of Kinect/Redwood/TUM-style depth PNGs (TUM's 5000-per-metre frames must be scaled
/// by the caller). For multi-channel files the first channel is read.
struct PngInput {
  int bits = 8;      ///< 8 or 16
  GreyImage grey;    ///< when bits == 8
  DepthImage depth;  ///< when bits == 16
};

/// Throws Error(not_found, "image") when the file cannot be opened, Error(unsupported_format, "image")
/// when it is not a readable 8- or 16-bit PNG.
PngInput read_png_input(const std::filesystem::path& path);

/// Writes an 8-bit grey PNG. Throws Error(internal, "output") on failure.
void write_grey_png(const GreyImage& image, const std::filesystem::path& path);

/// Writes a label image as a 16-bit grey PNG whose values are the labels. Throws
/// invalid_argument("labels") for a label outside [0, 65535] or a size mismatch, Error(internal,
/// "output") on failure.
void write_label_png(const std::vector<std::int32_t>& labels, int width, int height,
                     const std::filesystem::path& path);

}  // namespace trailscope::dmd
