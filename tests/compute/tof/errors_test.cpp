// Damaged and hostile videos: each failure is a trailscope::Error with the parameter and an exact message
// naming the file and frame.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <zlib.h>

#include "test_support.hpp"
#include "tof_test_util.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::tof {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using test::expect_error;
using test::TempDir;

fs::path small_synthetic(const TempDir& dir, const char* name = "v") {
  SynthOptions o;
  o.frames = 3;
  o.width = 32;
  o.height = 24;
  write_depth_video(synthesize(o), dir.path() / name);
  return dir.path() / name;
}

void edit_manifest(const fs::path& video, const std::function<void(json&)>& edit) {
  json m = json::parse(test::slurp(video / "manifest.json"));
  edit(m);
  test::spit(video / "manifest.json", m.dump());
}

TEST(DepthVideoErrors, NoSuchPath) {
  TempDir dir;
  const fs::path p = dir.path() / "nope";
  expect_error([&] { DepthVideoReader r(p); }, Error::Kind::not_found, "video",
               p.string() + ": no such file or folder");
}

TEST(DepthVideoErrors, FolderWithoutManifestOrFrames) {
  TempDir dir;
  test::spit(dir.path() / "notes.txt", "hello");
  expect_error([&] { DepthVideoReader r(dir.path()); }, Error::Kind::unsupported_format, "video",
               dir.path().string() + ": not a depth video (no manifest.json and no .png frames)");
}

TEST(DepthVideoErrors, BadVersionAndFormat) {
  TempDir dir;
  const fs::path v = small_synthetic(dir);
  const std::string where = (v / "manifest.json").string();
  edit_manifest(v, [](json& m) { m["version"] = 2; });
  expect_error([&] { DepthVideoReader r(v); }, Error::Kind::unsupported_format, "manifest",
               where + ": version 2 is not supported (this build reads version 1)");
  edit_manifest(v, [](json& m) {
    m["version"] = 1;
    m["format"] = "something-else";
  });
  expect_error([&] { DepthVideoReader r(v); }, Error::Kind::unsupported_format, "manifest",
               where + ": format is \"something-else\", expected \"trailscope-depth-video\"");
  edit_manifest(v, [](json& m) {
    m["format"] = "trailscope-depth-video";
    m.erase("fps");
  });
  expect_error([&] { DepthVideoReader r(v); }, Error::Kind::unsupported_format, "manifest",
               where + ": missing field \"fps\"");
  test::spit(v / "manifest.json", "{\"format\": ");
  try {
    DepthVideoReader r(v);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "manifest");
    EXPECT_EQ(std::string(e.what()).rfind(where + ": not valid JSON (", 0), 0u) << e.what();
  }
}

TEST(DepthVideoErrors, TooManyFrames) {
  TempDir dir;
  const fs::path v = small_synthetic(dir);
  edit_manifest(v, [](json& m) { m["frame_count"] = limits::kMaxVideoFrames + 1; });
  expect_error([&] { DepthVideoReader r(v); }, Error::Kind::payload_too_large, "frames",
               (v / "manifest.json").string() +
                   ": frame_count 100001 exceeds the limit of 100000 frames (kMaxVideoFrames)");
  SynthOptions o;
  o.frames = limits::kMaxVideoFrames + 1;
  expect_error([&] { ToFSynth s(o); }, Error::Kind::payload_too_large, "frames",
               "frames 100001 exceeds the limit of 100000 frames (kMaxVideoFrames)");
}

TEST(DepthVideoErrors, InconsistentManifest) {
  TempDir dir;
  const fs::path v = small_synthetic(dir);
  const std::string where = (v / "manifest.json").string();
  edit_manifest(v, [](json& m) { m["frame_count"] = 4; });
  expect_error([&] { DepthVideoReader r(v); }, Error::Kind::unprocessable, "frames",
               where + ": frame_count is 4 but \"frames\" has 3 entries");
  edit_manifest(v, [](json& m) {
    m["frame_count"] = 3;
    m["frames"][2]["timestamp_s"] = 0.01;
  });
  expect_error([&] { DepthVideoReader r(v); }, Error::Kind::unprocessable, "frames",
               where + ": frame 2 has timestamp_s 0.010000, earlier than frame 1's 0.040000");
  edit_manifest(v, [](json& m) {
    m["frames"][2]["timestamp_s"] = 0.08;
    m["frames"][1]["depth"] = "../../etc/passwd";
  });
  const DepthVideoReader r(v);
  expect_error(
      [&] { r.read_frame(1); }, Error::Kind::unsupported_format, "manifest",
      where +
          " frame 1: depth must be a relative file name inside the video folder, not \"../../etc/passwd\"");
  expect_error([&] { r.read_frame(3); }, Error::Kind::invalid_argument, "frame",
               "frame 3 does not exist (the video has 3 frames)");
}

TEST(DepthVideoErrors, MissingAndTruncatedFrameFiles) {
  TempDir dir;
  const fs::path v = small_synthetic(dir);
  fs::remove(v / "amplitude/000000.png");
  const DepthVideoReader r(v);
  expect_error([&] { r.read_frame(0); }, Error::Kind::not_found, "amplitude",
               (v / "amplitude/000000.png").string() + " (frame 0): listed in manifest.json but missing");

  // Cut depth/000001.png in half; find, independently, the chunk the cut falls in.
  const std::string png = test::slurp(v / "depth/000001.png");
  const std::size_t cut = png.size() / 2;
  std::size_t pos = 8, need = 0;
  while (true) {
    const auto* p = reinterpret_cast<const unsigned char*>(png.data() + pos);
    const std::size_t len = (std::size_t{p[0]} << 24) | (p[1] << 16) | (p[2] << 8) | p[3];
    if (pos + 12 + len > cut) {
      need = 12 + len;
      break;
    }
    pos += 12 + len;
  }
  test::spit(v / "depth/000001.png", png.substr(0, cut));
  expect_error([&] { r.read_frame(1); }, Error::Kind::unsupported_format, "depth",
               "depth/000001.png (frame 1): truncated PNG (chunk at byte " + std::to_string(pos) + " needs " +
                   std::to_string(need) + " bytes, the data has " + std::to_string(cut - pos) + ")");
  EXPECT_NO_THROW(r.read_frame(2));  // the other frames stay readable
}

TEST(DepthVideoErrors, WrongPngLayoutAndSize) {
  TempDir dir;
  const fs::path v = small_synthetic(dir);
  // An 8-bit PNG where a 16-bit one belongs.
  {
    auto out = OIIO::ImageOutput::create((v / "depth/000000.png").string());
    OIIO::ImageSpec spec(32, 24, 1, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> px(32 * 24, 7);
    ASSERT_TRUE(out->open((v / "depth/000000.png").string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
  }
  // A 16-bit PNG of the wrong size: another video's frame.
  const fs::path other = [&] {
    SynthOptions o;
    o.frames = 1;
    o.width = 16;
    o.height = 16;
    write_depth_video(synthesize(o), dir.path() / "other");
    return dir.path() / "other";
  }();
  fs::copy_file(other / "depth/000000.png", v / "depth/000001.png", fs::copy_options::overwrite_existing);
  const DepthVideoReader r(v);
  expect_error([&] { r.read_frame(0); }, Error::Kind::unsupported_format, "depth",
               "depth/000000.png (frame 0): must be a 16-bit grey PNG, not 8-bit with 1 channel(s)");
  expect_error([&] { r.read_frame(1); }, Error::Kind::unprocessable, "depth",
               "depth/000001.png (frame 1): image is 16x16 px, the video is 32x24");
}

// A PNG of 69 bytes whose header claims 100,000 x 100,000 px (valid CRCs, written here with zlib) is
// refused from its header: decoding it would first allocate a 20 GB pixel buffer.
TEST(DepthVideoErrors, PngClaimingHugeSizeIsRefusedBeforeDecoding) {
  const auto chunk = [](const std::string& type, const std::string& data) {
    const auto be32 = [](std::uint32_t v) {
      return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    const std::string body = type + data;
    return be32(static_cast<std::uint32_t>(data.size())) + body +
           be32(static_cast<std::uint32_t>(
               crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
  };
  std::string ihdr = std::string("\x00\x01\x86\xa0\x00\x01\x86\xa0", 8);  // 100000, 100000
  ihdr += std::string("\x10\x00\x00\x00\x00", 5);                         // 16-bit grey
  const std::string zeros(64, '\0');
  std::string idat(compressBound(zeros.size()), '\0');
  uLongf n = idat.size();
  ASSERT_EQ(compress(reinterpret_cast<Bytef*>(idat.data()), &n, reinterpret_cast<const Bytef*>(zeros.data()),
                     zeros.size()),
            Z_OK);
  idat.resize(n);
  const std::string png =
      std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", idat) + chunk("IEND", "");

  TempDir dir;
  const fs::path v = small_synthetic(dir);
  test::spit(v / "depth/000002.png", png);
  const DepthVideoReader r(v);
  expect_error([&] { r.read_frame(2); }, Error::Kind::payload_too_large, "depth",
               "depth/000002.png (frame 2): 100000x100000 px exceeds the limit of " +
                   std::to_string(limits::kMaxVideoPixels) + " pixels per frame (kMaxVideoPixels)");
}

TEST(DepthVideoErrors, DamagedPack) {
  TempDir dir;
  SynthOptions o;
  o.frames = 2;
  o.width = 32;
  o.height = 24;
  WriteOptions w;
  w.layout = VideoLayout::pack;
  const fs::path pack = dir.path() / "v.tsdv";
  write_depth_video(synthesize(o), pack, w);
  const std::string bytes = test::slurp(pack);
  // Cut off: the trailer is gone, so it is not recognisable as a pack; nor is it one PNG, although it
  // starts like its first frame (whose length the manifest gives).
  const auto manifest_at = bytes.find("{\n \"amplitude_scale\"");
  ASSERT_NE(manifest_at, std::string::npos);
  const auto m = nlohmann::json::parse(bytes.substr(manifest_at, bytes.size() - 24 - manifest_at));
  const std::size_t first_png = m["frames"][0]["depth"]["bytes"].get<std::size_t>();
  test::spit(pack, bytes.substr(0, bytes.size() - 5));
  expect_error([&] { DepthVideoReader r(pack); }, Error::Kind::unsupported_format, "depth",
               pack.string() + " (frame 0): " + std::to_string(bytes.size() - 5 - first_png) +
                   " bytes of trailing data after the PNG's IEND chunk (a damaged pack?)");
  test::spit(dir.path() / "junk.bin", "not a video at all, just some bytes of text");
  expect_error([&] { DepthVideoReader r(dir.path() / "junk.bin"); }, Error::Kind::unsupported_format, "video",
               (dir.path() / "junk.bin").string() +
                   ": not a depth video (neither a 16-bit PNG nor a depth-video pack)");
  // Trailer intact but the file shortened in front of it: the manifest range no longer fits.
  test::spit(pack, bytes.substr(100));
  expect_error([&] { DepthVideoReader r(pack); }, Error::Kind::unsupported_format, "video",
               pack.string() + ": damaged pack (the trailer's manifest range does not fit the file)");
}

}  // namespace
}  // namespace trailscope::tof
