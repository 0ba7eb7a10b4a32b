#pragma once
// Stimulus images (what a participant looked at) uploaded beside a gaze dataset: only PNG and JPEG are
// accepted, recognised by their magic bytes (never a name or a declared type) and decoded whole through
// OpenImageIO, so that what is stored is an image every browser and the gaze views can draw.
#include <cstdint>
#include <string>
#include <string_view>

namespace trailscope::gaze {

struct StimulusImage {
  std::string type;          ///< "png" | "jpeg"
  std::string content_type;  ///< "image/png" | "image/jpeg"
  int width_px = 0, height_px = 0;
  int channels = 0;
};

/// Checks `bytes`: the PNG signature (89 50 4E 47 0D 0A 1A 0A) or the JPEG SOI marker (FF D8 FF) first,
/// then the header's size (1 pixel at least, at most `max_pixels` pixels, checked before decoding: the
/// caller's limit, e.g. the server's kMaxGazeStimulusPixels), then the whole image decodes. Throws
/// Error(unsupported_format, "image", ...) when the magic is neither ("not a PNG or JPEG image"),
/// Error(unprocessable, "image", ...) with the decoder's message when it does not decode,
/// Error(payload_too_large, "image", ...) over the pixel limit.
StimulusImage inspect_stimulus_image(std::string_view bytes, std::uint64_t max_pixels);

}  // namespace trailscope::gaze
