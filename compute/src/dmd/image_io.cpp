#include "trailscope/dmd/image_io.hpp"

#include <OpenImageIO/imageio.h>

#include <string>

#include "trailscope/core/error.hpp"

namespace trailscope::dmd {
namespace OIIO = OIIO_NAMESPACE;

PngInput read_png_input(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw not_found("image", "cannot open " + path.string());
  // Ask for the PNG reader only: other readers must not guess at a file that is not a PNG.
  auto in = OIIO::ImageInput::create("png");
  OIIO::ImageSpec spec;
  if (!in || !in->open(path.string(), spec))
    throw Error(Error::Kind::unsupported_format, "image",
                path.string() + " is not a readable PNG: " + (in ? in->geterror() : OIIO::geterror()));
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1)
    throw Error(Error::Kind::unsupported_format, "image", path.string() + " has an unsupported layout");
  const bool sixteen = spec.format.basetype == OIIO::TypeDesc::UINT16;
  if (!sixteen && spec.format.basetype != OIIO::TypeDesc::UINT8)
    throw Error(Error::Kind::unsupported_format, "image", path.string() + " is neither 8- nor 16-bit");
  const std::size_t n = static_cast<std::size_t>(spec.width) * spec.height;
  PngInput out;
  out.bits = sixteen ? 16 : 8;
  if (sixteen) {
    std::vector<std::uint16_t> raw(n);
    if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT16, raw.data()))
      throw Error(Error::Kind::unsupported_format, "image", path.string() + ": " + in->geterror());
    out.depth.width = spec.width;
    out.depth.height = spec.height;
    out.depth.mm.assign(raw.begin(), raw.end());
  } else {
    out.grey.width = spec.width;
    out.grey.height = spec.height;
    out.grey.pixels.resize(n);
    if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT8, out.grey.pixels.data()))
      throw Error(Error::Kind::unsupported_format, "image", path.string() + ": " + in->geterror());
  }
  return out;
}

namespace {
void write_one_channel(const std::filesystem::path& path, int w, int h, OIIO::TypeDesc type,
                       const void* data) {
  auto out = OIIO::ImageOutput::create("png");
  const OIIO::ImageSpec spec(w, h, 1, type);
  if (!out || !out->open(path.string(), spec) || !out->write_image(type, data) || !out->close())
    throw Error(Error::Kind::internal, "output",
                "cannot write " + path.string() + ": " + (out ? out->geterror() : OIIO::geterror()));
}
}  // namespace

void write_grey_png(const GreyImage& image, const std::filesystem::path& path) {
  if (image.width < 1 || image.height < 1 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
    throw invalid_argument("image", "image must be non-empty with width * height pixels");
  write_one_channel(path, image.width, image.height, OIIO::TypeDesc::UINT8, image.pixels.data());
}

void write_label_png(const std::vector<std::int32_t>& labels, int width, int height,
                     const std::filesystem::path& path) {
  if (width < 1 || height < 1 || labels.size() != static_cast<std::size_t>(width) * height)
    throw invalid_argument("labels", "labels must be non-empty with width * height values");
  std::vector<std::uint16_t> raw(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 0 || labels[i] > 65535)
      throw invalid_argument("labels", "label " + std::to_string(labels[i]) + " does not fit a 16-bit PNG");
    raw[i] = static_cast<std::uint16_t>(labels[i]);
  }
  write_one_channel(path, width, height, OIIO::TypeDesc::UINT16, raw.data());
}

}  // namespace trailscope::dmd
