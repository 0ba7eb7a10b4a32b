#pragma once
// 16-bit single-channel PNGs in memory, through OpenImageIO: the pixel store of depth videos. Internal to
// compute/src/tof.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace trailscope::tof::detail {

struct Png16 {
  int width = 0, height = 0;
  std::vector<std::uint16_t> data;  ///< row-major
};

/// PNG bytes of a 16-bit grey image; `compression` is the zlib level 0..9. Throws Error(internal).
std::string encode_png16(const std::uint16_t* data, int width, int height, int compression);

/// Decodes a 16-bit grey PNG. `what` names the file and frame in messages ("depth/000003.png (frame 3)"),
/// `param` is the Error's parameter. Throws Error(unsupported_format, param) for a bad signature, a
/// truncated chunk structure (exact message: "<what>: truncated PNG (chunk at byte P needs N bytes, the
/// data has M)"), data after the IEND chunk, a decoder failure, or a layout other than one 16-bit channel;
/// Error(payload_too_large, param) when the header claims more than limits::kMaxVideoPixels pixels ("<what>:
/// WxH px exceeds the limit of N pixels per frame (kMaxVideoPixels)"), checked before any pixel buffer is
/// allocated.
Png16 decode_png16(std::string_view bytes, const std::string& what, const std::string& param);

/// Whole file as bytes, refusing files over `max_bytes`. Throws Error(not_found, param) when it cannot be
/// opened, Error(payload_too_large, param) when too big, Error(internal) on a read failure.
std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes,
                            const std::string& param);

/// True when `bytes` starts with the PNG signature.
bool has_png_signature(std::string_view bytes);

}  // namespace trailscope::tof::detail
