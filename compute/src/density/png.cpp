#include "trailscope/density/png.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "trailscope/core/error.hpp"

namespace trailscope::density {
namespace OIIO = OIIO_NAMESPACE;

std::string encode_png(const Image& img) {
  if (img.width < 1 || img.height < 1 ||
      img.rgba.size() != static_cast<std::size_t>(img.width) * img.height * 4)
    throw Error(Error::Kind::internal, "", "encode_png: malformed image");
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput proxy(buffer);
  // The name only selects the PNG writer; the bytes go to `proxy`.
  auto out = OIIO::ImageOutput::create("tile.png", &proxy);
  if (!out)
    throw Error(Error::Kind::internal, "", "encode_png: OpenImageIO has no PNG writer: " + OIIO::geterror());
  OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  // Measured on the Europe day's z=4 tiles: libpng's adaptive filtering (the default) makes colormapped
  // density images both slower to deflate and larger — their runs of identical RGBA pixels are what
  // LZ77 finds; per-row filters turn them into noise. PNG_FILTER_NONE (8) at zlib level 2 took about
  // 2 ms for a 65–70 KB busy 256² tile, against 10 ms / 112 KB at level 3 with filtering and ~40 ms /
  // 105 KB at the default level 6.
  spec.attribute("png:compressionLevel", 2);
  spec.attribute("png:filter", 8);
  if (!out->open("tile.png", spec) || !out->write_image(OIIO::TypeDesc::UINT8, img.rgba.data()) ||
      !out->close())
    throw Error(Error::Kind::internal, "", "encode_png: " + out->geterror());
  return std::string(buffer.begin(), buffer.end());
}

namespace {
Image decode(OIIO::ImageInput::unique_ptr in, const std::string& what) {
  if (!in)
    throw Error(Error::Kind::unsupported_format, "png", what + " is not a readable PNG: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.nchannels > 4)
    throw Error(Error::Kind::unsupported_format, "png", what + " has an unsupported layout");
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, raw.data()))
    throw Error(Error::Kind::unsupported_format, "png", what + ": " + in->geterror());
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.rgba.resize(static_cast<std::size_t>(img.width) * img.height * 4);
  const int c = spec.nchannels;
  for (std::size_t p = 0; p < static_cast<std::size_t>(img.width) * img.height; ++p) {
    const std::uint8_t* s = &raw[p * c];
    std::uint8_t* d = &img.rgba[p * 4];
    const bool grey = c <= 2;
    d[0] = s[0];
    d[1] = grey ? s[0] : s[1];
    d[2] = grey ? s[0] : s[2];
    d[3] = c == 2 ? s[1] : (c == 4 ? s[3] : 255);
  }
  return img;
}
}  // namespace

Image decode_png(const std::string& bytes) {
  // Check the signature ourselves and ask for the PNG reader only: given other bytes, OpenImageIO 2.4
  // tries its other readers on the memory proxy, and its GIF reader crashes on that.
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0)
    throw Error(Error::Kind::unsupported_format, "png", "data is not a PNG (bad signature)");
  OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::Filesystem::IOProxy* proxy_ptr = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  auto in = OIIO::ImageInput::create("png", false, &config, &proxy);
  OIIO::ImageSpec spec;
  if (in) in->set_ioproxy(&proxy);
  if (!in || !in->open("tile.png", spec, config))
    throw Error(Error::Kind::unsupported_format, "png",
                "data is not a readable PNG: " + (in ? in->geterror() : OIIO::geterror()));
  return decode(std::move(in), "data");
}

void write_png(const Image& img, const std::filesystem::path& path) {
  const std::string bytes = encode_png(img);
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f) throw Error(Error::Kind::internal, "", "cannot write " + path.string());
}

Image read_png(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(Error::Kind::not_found, "path", "cannot open " + path.string());
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return decode_png(bytes);
}

}  // namespace trailscope::density
