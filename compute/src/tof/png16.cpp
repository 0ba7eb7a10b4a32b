#include "png16.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstring>
#include <fstream>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::tof::detail {
namespace OIIO = OIIO_NAMESPACE;

namespace {
constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};

std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

// Walks the chunk list (length, type, data, CRC) up to IEND. libpng reports a cut-off file only as a
// generic read error deep in IDAT decoding (and prints to stderr); checking the structure first gives a
// message that says what is wrong, and where.
void check_chunks(std::string_view bytes, const std::string& what, const std::string& param) {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t pos = 8;
  while (true) {
    if (pos + 12 > bytes.size())
      throw Error(Error::Kind::unsupported_format, param,
                  what + ": truncated PNG (chunk at byte " + std::to_string(pos) +
                      " needs 12 bytes, the data has " + std::to_string(bytes.size() - pos) + ")");
    const std::uint64_t len = be32(p + pos);
    const std::string type(bytes.substr(pos + 4, 4));
    if (len > 0x7fffffffu)
      throw Error(Error::Kind::unsupported_format, param,
                  what + ": corrupt PNG (chunk " + type + " at byte " + std::to_string(pos) + " claims " +
                      std::to_string(len) + " bytes)");
    if (pos + 12 + len > bytes.size())
      throw Error(Error::Kind::unsupported_format, param,
                  what + ": truncated PNG (chunk at byte " + std::to_string(pos) + " needs " +
                      std::to_string(12 + len) + " bytes, the data has " +
                      std::to_string(bytes.size() - pos) + ")");
    pos += 12 + len;
    if (type == "IEND") {
      // Decoders ignore what follows, but here it means the bytes are not what they claim (e.g. a pack
      // whose trailer was cut off, which would otherwise read as its first frame alone).
      if (pos != bytes.size())
        throw Error(Error::Kind::unsupported_format, param,
                    what + ": " + std::to_string(bytes.size() - pos) +
                        " bytes of trailing data after the PNG's IEND chunk (a damaged pack?)");
      return;
    }
  }
}
}  // namespace

bool has_png_signature(std::string_view bytes) {
  return bytes.size() >= 8 && std::memcmp(bytes.data(), kSignature, 8) == 0;
}

std::string encode_png16(const std::uint16_t* data, int width, int height, int compression) {
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput proxy(buffer);
  auto out = OIIO::ImageOutput::create("frame.png", &proxy);
  if (!out) throw Error(Error::Kind::internal, "", "OpenImageIO has no PNG writer: " + OIIO::geterror());
  OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::UINT16);
  // Measured on noisy synthetic 176x144 frames (depth + amplitude PNG per frame): zlib level 1 gives
  // 46 KB in 2.1 ms, level 3 45 KB in 3.5 ms, level 6 44 KB in 6.4 ms, level 0 102 KB in 1.1 ms: noise
  // does not compress, so level 1 (WriteOptions' default) takes nearly all there is to take.
  spec.attribute("png:compressionLevel", compression);
  if (!out->open("frame.png", spec) || !out->write_image(OIIO::TypeDesc::UINT16, data) || !out->close())
    throw Error(Error::Kind::internal, "", "cannot encode a 16-bit PNG: " + out->geterror());
  return std::string(buffer.begin(), buffer.end());
}

Png16 decode_png16(std::string_view bytes, const std::string& what, const std::string& param) {
  if (!has_png_signature(bytes))
    throw Error(Error::Kind::unsupported_format, param, what + ": not a PNG (bad signature)");
  check_chunks(bytes, what, param);
  // Ask for the PNG reader only: given other bytes, OpenImageIO 2.4 tries its other readers on a memory
  // proxy (see density/png.cpp).
  OIIO::Filesystem::IOMemReader proxy(const_cast<char*>(bytes.data()), bytes.size());
  OIIO::ImageSpec config;
  OIIO::Filesystem::IOProxy* proxy_ptr = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  auto in = OIIO::ImageInput::create("png", false, &config, &proxy);
  OIIO::ImageSpec spec;
  if (in) in->set_ioproxy(&proxy);
  if (!in || !in->open("frame.png", spec, config))
    throw Error(Error::Kind::unsupported_format, param,
                what + ": unreadable PNG: " + (in ? in->geterror() : OIIO::geterror()));
  if (spec.nchannels != 1 || spec.format != OIIO::TypeDesc::UINT16)
    throw Error(Error::Kind::unsupported_format, param,
                what + ": must be a 16-bit grey PNG, not " + std::to_string(spec.format.size() * 8) +
                    "-bit with " + std::to_string(spec.nchannels) + " channel(s)");
  if (spec.width < 1 || spec.height < 1)
    throw Error(Error::Kind::unsupported_format, param, what + ": empty image");
  // The size comes from the header, before a pixel is decoded: a PNG of a few dozen bytes may claim
  // 100,000 x 100,000 px, and the buffer below would then be 20 GB.
  const std::uint64_t pixels =
      static_cast<std::uint64_t>(spec.width) * static_cast<std::uint64_t>(spec.height);
  if (pixels > limits::kMaxVideoPixels)
    throw Error(Error::Kind::payload_too_large, param,
                what + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                    " px exceeds the limit of " + std::to_string(limits::kMaxVideoPixels) +
                    " pixels per frame (kMaxVideoPixels)");
  Png16 img;
  img.width = spec.width;
  img.height = spec.height;
  img.data.resize(static_cast<std::size_t>(spec.width) * spec.height);
  if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT16, img.data.data()))
    throw Error(Error::Kind::unsupported_format, param, what + ": corrupt PNG: " + in->geterror());
  return img;
}

std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes,
                            const std::string& param) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw not_found(param, path.string() + ": no such file");
  if (size > max_bytes)
    throw Error(Error::Kind::payload_too_large, param,
                path.string() + ": " + std::to_string(size) + " bytes exceeds the limit of " +
                    std::to_string(max_bytes) + " bytes");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw not_found(param, path.string() + ": cannot open");
  std::string bytes(size, '\0');
  if (!f.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw Error(Error::Kind::internal, param, path.string() + ": read failed");
  return bytes;
}

}  // namespace trailscope::tof::detail
