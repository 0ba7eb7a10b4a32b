// Depth video folders and packs: write -> read round trips, atomic writing, manifest-less PNG import.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_support.hpp"
#include "tof_test_util.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::tof {
namespace {
namespace fs = std::filesystem;
using test::TempDir;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// What a 16-bit depth PNG can hold of z: whole mm, at least 1 mm, NaN for a hole.
float stored_depth(float z) {
  if (std::isnan(z)) return kNaN;
  const double r = std::round(static_cast<double>(z));
  return static_cast<float>(r < 1 ? 1 : r);
}

// A hand-made 4x3 video: edge values of the encoding (sub-mm returns, 65535 mm, holes, amplitude that
// saturates 16 bits) and truth with absent optional fields.
DepthVideo small_video() {
  DepthVideo v;
  v.info.intrinsics = {100.0, 101.5, 1.5, 1.0, 4, 3, false};
  v.info.fps = 10;
  v.info.amplitude_scale = 0.25;
  v.info.has_truth = true;
  v.info.source = {{"made_by", "depth_video_io_test"}};
  for (int f = 0; f < 3; ++f) {
    DepthFrame fr;
    fr.timestamp_s = 0.1 * f + 1e-9 * f;  // not a multiple of 1/fps: timestamps are stored, not derived
    fr.depth_mm = {kNaN,     0.4f,     1.5f,       2.5f, 999.49f, 999.5f,
                   65535.0f, 65534.6f, 150.0f + f, kNaN, 7.0f,    12345.678f};
    fr.amplitude = {0.0f,     0.1f,     0.125f, 0.13f, 1000.0f, 16383.75f,
                    16383.9f, 20000.0f, 3.3f,   0.0f,  5.0f,    7.77f};
    FrameTruth t;
    for (int k = 0; k < kTeatCount; ++k) {
      t.teats[k].tip_mm = {-10.25 * k, 3.0 / 7.0, 400.0 + f};
      t.teats[k].visible = (k + f) % 2 == 0;
      t.teats[k].visible_fraction = 0.1 * k;
      t.teats[k].cup_attached = k == 3;
      if (k != 1) t.teats[k].tip_px = std::array<double, 2>{1.0 / 3.0, 2.5};
      if (k != 2) t.teats[k].box_px = BoxPx{0.5, -0.5, 2, 3};
    }
    fr.truth = t;
    v.frames.push_back(fr);
  }
  v.info.frame_count = v.frames.size();
  return v;
}

void expect_same_video(const DepthVideo& written, const DepthVideo& read) {
  const VideoInfo &a = written.info, &b = read.info;
  EXPECT_EQ(a.intrinsics.fx, b.intrinsics.fx);
  EXPECT_EQ(a.intrinsics.fy, b.intrinsics.fy);
  EXPECT_EQ(a.intrinsics.cx, b.intrinsics.cx);
  EXPECT_EQ(a.intrinsics.cy, b.intrinsics.cy);
  EXPECT_EQ(a.intrinsics.width, b.intrinsics.width);
  EXPECT_EQ(a.intrinsics.height, b.intrinsics.height);
  EXPECT_EQ(a.intrinsics.defaulted, b.intrinsics.defaulted);
  EXPECT_EQ(a.fps, b.fps);
  EXPECT_EQ(a.amplitude_scale, b.amplitude_scale);
  EXPECT_EQ(a.has_amplitude, b.has_amplitude);
  EXPECT_EQ(a.has_truth, b.has_truth);
  EXPECT_EQ(a.source, b.source);
  ASSERT_EQ(b.frame_count, written.frames.size());
  ASSERT_EQ(read.frames.size(), written.frames.size());
  const double q = a.amplitude_scale;
  for (std::size_t f = 0; f < written.frames.size(); ++f) {
    const DepthFrame &w = written.frames[f], &r = read.frames[f];
    EXPECT_EQ(w.timestamp_s, r.timestamp_s) << "frame " << f;
    ASSERT_EQ(r.depth_mm.size(), w.depth_mm.size());
    std::vector<float> expected(w.depth_mm.size());
    for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = stored_depth(w.depth_mm[i]);
    EXPECT_TRUE(test::same_bits(expected, r.depth_mm)) << "frame " << f;
    ASSERT_EQ(r.amplitude.size(), w.amplitude.size());
    for (std::size_t i = 0; i < w.amplitude.size(); ++i) {
      const double a_w = std::min<double>(w.amplitude[i], 65535 * q);  // 16 bits saturate
      EXPECT_LE(std::abs(r.amplitude[i] - a_w), q / 2 + 1e-6) << "frame " << f << " pixel " << i;
    }
    EXPECT_EQ(w.truth, r.truth) << "frame " << f;
  }
}

TEST(DepthVideoIo, HandMadeVideoRoundTripsThroughFolderAndPack) {
  TempDir dir;
  const DepthVideo v = small_video();
  for (VideoLayout layout : {VideoLayout::folder, VideoLayout::pack}) {
    const fs::path target = dir.path() / (layout == VideoLayout::folder ? "v" : "v.tsdv");
    WriteOptions o;
    o.layout = layout;
    write_depth_video(v, target, o);
    const DepthVideo r = read_depth_video(target);
    expect_same_video(v, r);
    // The encoding's edge cases, spelled out: 0.4 mm is a return (1 mm), 65534.6 rounds to 65535,
    // 16383.9 amplitude clips at 65535 counts of 0.25.
    EXPECT_EQ(r.frames[0].depth_mm[1], 1.0f);
    EXPECT_EQ(r.frames[0].depth_mm[7], 65535.0f);
    EXPECT_EQ(r.frames[0].amplitude[6], 16383.75f);
    EXPECT_FALSE(r.frames[0].truth->teats[1].tip_px.has_value());
    EXPECT_FALSE(r.frames[0].truth->teats[2].box_px.has_value());
  }
}

TEST(DepthVideoIo, SyntheticVideoRoundTripsBitExact) {
  TempDir dir;
  SynthOptions o;
  o.frames = 12;
  o.seed = 3;
  const DepthVideo v = synthesize(o);
  write_depth_video(v, dir.path() / "synth");
  expect_same_video(v, read_depth_video(dir.path() / "synth"));
  WriteOptions pack;
  pack.layout = VideoLayout::pack;
  write_depth_video(v, dir.path() / "synth.tsdv", pack);
  const DepthVideo from_pack = read_depth_video(dir.path() / "synth.tsdv");
  expect_same_video(v, from_pack);
  // Random access gives the same frame as the sequential load.
  const DepthVideoReader reader(dir.path() / "synth.tsdv");
  EXPECT_TRUE(test::same_bits(reader.read_frame(7).depth_mm, from_pack.frames[7].depth_mm));
  EXPECT_EQ(describe_video(reader)["frame_count"], 12);
  EXPECT_EQ(describe_video(reader)["source"]["scenario"], "standard");
}

TEST(DepthVideoIo, FolderLayoutIsAsDocumented) {
  TempDir dir;
  write_depth_video(small_video(), dir.path() / "v");
  for (const char* f : {"manifest.json", "depth/000000.png", "depth/000002.png", "amplitude/000002.png"})
    EXPECT_TRUE(fs::exists(dir.path() / "v" / f)) << f;
  const auto m = nlohmann::json::parse(test::slurp(dir.path() / "v/manifest.json"));
  EXPECT_EQ(m["format"], "trailscope-depth-video");
  EXPECT_EQ(m["version"], 1);
  EXPECT_EQ(m["depth_unit"], "mm");
  EXPECT_EQ(m["frame_count"], 3);
  EXPECT_EQ(m["frames"][1]["depth"], "depth/000001.png");
  EXPECT_EQ(m["frames"][1]["truth"]["teats"][3]["name"], "RR");
}

TEST(DepthVideoIo, WriterIsAtomic) {
  TempDir dir;
  const DepthVideo v = small_video();
  const fs::path target = dir.path() / "v";
  {
    DepthVideoWriter w(target, v.info);
    w.write(v.frames[0]);
    w.write(v.frames[1]);
    EXPECT_FALSE(fs::exists(target));  // nothing visible until finish()
  }                                    // abandoned: the temporary folder goes too
  EXPECT_TRUE(fs::is_empty(dir.path()));
  write_depth_video(v, target);
  test::expect_error([&] { DepthVideoWriter w(target, v.info); }, Error::Kind::conflict, "output",
                     target.string() + " exists (replace it with overwrite, CLI --force)");
  DepthVideo shorter = v;
  shorter.frames.resize(1);
  WriteOptions o;
  o.overwrite = true;
  write_depth_video(shorter, target, o);
  EXPECT_EQ(DepthVideoReader(target).size(), 1u);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(DepthVideoIo, WriterRejectsFramesThatDoNotFit) {
  TempDir dir;
  const DepthVideo v = small_video();
  DepthVideoWriter w(dir.path() / "v", v.info);
  DepthFrame bad = v.frames[0];
  bad.depth_mm.pop_back();
  test::expect_error([&] { w.write(bad); }, Error::Kind::invalid_argument, "frame",
                     "frame 0: depth has 11 values, expected 12");
  bad = v.frames[0];
  bad.depth_mm[3] = -5;
  test::expect_error([&] { w.write(bad); }, Error::Kind::invalid_argument, "frame",
                     "frame 0: depth at pixel 3 is -5.000000 (must be > 0 mm, or NaN for no return)");
  bad = v.frames[0];
  bad.depth_mm[3] = 70000;
  test::expect_error([&] { w.write(bad); }, Error::Kind::invalid_argument, "frame",
                     "frame 0: depth at pixel 3 is 70000.000000 mm, beyond the 65535 mm a 16-bit PNG holds");
  w.write(v.frames[1]);
  test::expect_error([&] { w.write(v.frames[0]); }, Error::Kind::invalid_argument, "frame",
                     "frame 1: timestamp_s 0.000000 is earlier than the previous frame's");
  // A batch is checked whole before anything of it is written.
  std::vector<DepthFrame> batch = {v.frames[1], v.frames[2], v.frames[0]};
  batch[0].timestamp_s = 0.15;
  test::expect_error([&] { w.write(batch); }, Error::Kind::invalid_argument, "frame",
                     "frame 3: timestamp_s 0.000000 is earlier than the previous frame's");
  EXPECT_EQ(w.frames_written(), 1u);
  batch.pop_back();
  w.write(batch);
  EXPECT_EQ(w.frames_written(), 3u);
  DepthVideoWriter empty(dir.path() / "e", v.info);
  test::expect_error([&] { empty.finish(); }, Error::Kind::unprocessable, "frames",
                     "a video needs at least one frame");
}

TEST(DepthVideoIo, ReadsPngFramesWithoutManifest) {
  TempDir dir;
  SynthOptions o;
  o.frames = 3;
  const DepthVideo v = synthesize(o);
  write_depth_video(v, dir.path() / "v");
  fs::create_directory(dir.path() / "pngs");
  for (int f = 0; f < 3; ++f)
    fs::copy_file(dir.path() / "v/depth" / ("00000" + std::to_string(f) + ".png"),
                  dir.path() / "pngs" / ("frame_" + std::to_string(f) + ".png"));
  const DepthVideo r = read_depth_video(dir.path() / "pngs");
  ASSERT_EQ(r.frames.size(), 3u);
  EXPECT_TRUE(r.info.intrinsics.defaulted);
  EXPECT_DOUBLE_EQ(r.info.intrinsics.fx, 150.0);  // the synthetic camera's field of view at 176 px
  EXPECT_DOUBLE_EQ(r.info.intrinsics.cx, 87.5);
  EXPECT_TRUE(r.info.timestamps_defaulted);
  EXPECT_FALSE(r.info.has_amplitude);
  EXPECT_FALSE(r.info.has_truth);
  EXPECT_DOUBLE_EQ(r.frames[2].timestamp_s, 2.0 / kDefaultImportFps);
  EXPECT_TRUE(r.frames[2].amplitude.empty());
  std::vector<float> expected(v.frames[2].depth_mm.size());
  for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = stored_depth(v.frames[2].depth_mm[i]);
  EXPECT_TRUE(test::same_bits(expected, r.frames[2].depth_mm));
  // One PNG alone is a one-frame video; a depth unit scales the counts.
  ImportOptions half;
  half.depth_unit_mm = 0.5;
  const DepthVideo one = read_depth_video(dir.path() / "pngs/frame_1.png", half);
  ASSERT_EQ(one.frames.size(), 1u);
  for (std::size_t i = 0; i < expected.size(); i += 97) {
    const float e = stored_depth(v.frames[1].depth_mm[i]);
    if (std::isnan(e))
      EXPECT_TRUE(std::isnan(one.frames[0].depth_mm[i]));
    else
      EXPECT_EQ(one.frames[0].depth_mm[i], e * 0.5f);
  }
}

}  // namespace
}  // namespace trailscope::tof
