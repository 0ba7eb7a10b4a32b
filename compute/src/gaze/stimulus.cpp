// Stimulus image checks (stimulus.hpp) through OpenImageIO, from memory.
#include "trailscope/gaze/stimulus.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <vector>

#include "trailscope/core/error.hpp"
#include <algorithm>

namespace trailscope::gaze {

StimulusImage inspect_stimulus_image(std::string_view bytes, std::uint64_t max_pixels) {
  StimulusImage out;
  constexpr std::string_view kPng("\x89PNG\r\n\x1a\n", 8), kJpeg("\xff\xd8\xff", 3);
  if (bytes.substr(0, kPng.size()) == kPng)
    out.type = "png", out.content_type = "image/png";
  else if (bytes.substr(0, kJpeg.size()) == kJpeg)
    out.type = "jpeg", out.content_type = "image/jpeg";
  else
    throw Error(
        Error::Kind::unsupported_format, "image",
        "not a PNG or JPEG image (the first bytes are neither the PNG signature nor a JPEG SOI marker)");
  // The plugin is chosen by the extension of this name; the bytes come from the proxy.
  OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
  auto in = OIIO::ImageInput::open(out.type == "png" ? "stimulus.png" : "stimulus.jpg", nullptr, &proxy);
  if (!in)
    throw Error(Error::Kind::unprocessable, "image",
                "the " + out.type + " image does not decode: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  const std::uint64_t pixels =
      std::uint64_t(std::max(spec.width, 0)) * std::uint64_t(std::max(spec.height, 0));
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw Error(Error::Kind::unprocessable, "image", "the " + out.type + " image has no pixels");
  if (pixels > max_pixels)
    throw Error(Error::Kind::payload_too_large, "image",
                "the image is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                    " px, more than the limit of " + std::to_string(max_pixels) + " pixels");
  std::vector<unsigned char> pixels_buf(pixels * std::uint64_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels_buf.data()))
    throw Error(Error::Kind::unprocessable, "image",
                "the " + out.type + " image does not decode: " + in->geterror());
  out.width_px = spec.width, out.height_px = spec.height, out.channels = spec.nchannels;
  return out;
}

}  // namespace trailscope::gaze
