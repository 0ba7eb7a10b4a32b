#pragma once
// PNG encoding and decoding of RGBA images through OpenImageIO, in memory (Filesystem::IOVecOutput /
// IOMemReader), so a tile never touches the disk. Alpha is written and read unassociated (straight), as
// PNG defines it: OpenImageIO would otherwise un-premultiply on write and premultiply on read.
#include <filesystem>
#include <string>

#include "trailscope/density/shade.hpp"

namespace trailscope::density {

/// PNG bytes of `img` (8-bit RGBA), unfiltered rows at zlib level 2 (on density tiles both faster and
/// smaller than libpng's defaults; see png.cpp). Throws Error(Kind::internal) if encoding fails.
std::string encode_png(const Image& img);
/// Decodes PNG bytes to 8-bit RGBA (grey, grey+alpha and RGB are expanded; 16-bit is reduced).
/// Throws Error(Kind::unsupported_format, `png`) for data that is not a readable PNG.
Image decode_png(const std::string& bytes);
/// Writes encode_png(img) to `path`. Throws Error(Kind::internal) on an I/O failure.
void write_png(const Image& img, const std::filesystem::path& path);
/// Reads a PNG file. Throws Error(Kind::not_found, `path`) when it cannot be opened, else as decode_png.
Image read_png(const std::filesystem::path& path);

}  // namespace trailscope::density
