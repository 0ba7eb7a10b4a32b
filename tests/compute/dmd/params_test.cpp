// Parameter validation: each bad value names its parameter with an exact message.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/dmd/dmd.hpp"
#include "trailscope/dmd/image.hpp"

namespace trailscope::dmd {
namespace {

void expect_error(const std::function<void()>& f, const std::string& param, const std::string& message) {
  try {
    f();
    ADD_FAILURE() << "no error for " << param;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    EXPECT_EQ(e.param(), param);
    EXPECT_EQ(std::string(e.what()), message);
  }
}

DmdParams with(const std::function<void(DmdParams&)>& set) {
  DmdParams p;
  set(p);
  return p;
}

TEST(DmdParams, DefaultsAreValidAndDocumented) {
  EXPECT_NO_THROW(DmdParams{}.validate());
  const auto& infos = parameter_infos();
  ASSERT_EQ(infos.size(), 6u);
  EXPECT_EQ(infos[0].name, "layers");
  EXPECT_EQ(infos[0].default_value, "20");
  EXPECT_EQ(infos[0].range, "[2, 256]");
  EXPECT_EQ(infos[3].name, "island");
  EXPECT_EQ(infos[3].default_value, "0.001");
  EXPECT_EQ(infos[4].name, "saliency");
  EXPECT_EQ(infos[4].default_value, "0.5");
}

TEST(DmdParams, OutOfRangeValuesNameTheParameter) {
  expect_error([] { with([](DmdParams& p) { p.layers = 1; }).validate(); }, "layers",
               "layers must be in [2, 256] (got 1)");
  expect_error([] { with([](DmdParams& p) { p.layers = 257; }).validate(); }, "layers",
               "layers must be in [2, 256] (got 257)");
  expect_error([] { with([](DmdParams& p) { p.min_gap = 0; }).validate(); }, "min_gap",
               "min_gap must be in [1, 128] (got 0)");
  expect_error([] { with([](DmdParams& p) { p.island = 0.2; }).validate(); }, "island",
               "island must be in [0, 0.1] (got 0.2)");
  expect_error([] { with([](DmdParams& p) { p.island = -0.001; }).validate(); }, "island",
               "island must be in [0, 0.1] (got -0.001)");
  expect_error([] { with([](DmdParams& p) { p.saliency = 101; }).validate(); }, "saliency",
               "saliency must be in [0, 100] (got 101)");
  expect_error([] { with([](DmdParams& p) { p.saliency = std::nan(""); }).validate(); }, "saliency",
               "saliency must be in [0, 100] (got nan)");
  expect_error([] { with([](DmdParams& p) { p.selection = static_cast<LayerSelection>(7); }).validate(); },
               "selection", "selection must be cumulative or local_maxima");
  expect_error([] { parse_layer_selection("median"); }, "selection",
               "selection must be cumulative or local_maxima (got 'median')");
  EXPECT_EQ(parse_layer_selection("local_maxima"), LayerSelection::local_maxima);
}

TEST(DmdParams, RunRejectsBadImagesAndBadParameters) {
  expect_error([] { run_dmd(GreyImage{}); }, "image",
               "image must be non-empty, at most 32765 px a side, with width * height pixels");
  expect_error(
      [] {
        run_dmd(GreyImage{2, 2, {1, 2, 3}});
      },
      "image", "image must be non-empty, at most 32765 px a side, with width * height pixels");
  expect_error(
      [] {
        run_dmd(GreyImage{2, 2, {1, 2, 3, 4}}, with([](DmdParams& p) { p.layers = 0; }));
      },
      "layers", "layers must be in [2, 256] (got 0)");
}

TEST(DmdParams, DepthMappingRejectsBadRanges) {
  const DepthImage d{2, 1, {1000.f, 2000.f}};
  expect_error([&] { depth_to_grey(d, 0, 100); }, "near",
               "near must be a finite depth > 0 mm (got 0.000000)");
  expect_error([&] { depth_to_grey(d, 500, 500); }, "far",
               "far must be a finite depth > near (500.000000 mm) (got 500.000000)");
  expect_error(
      [&] {
        depth_to_grey(DepthImage{2, 2, {1.f}}, 500, 900);
      },
      "depth", "depth image must be non-empty with width * height values");
  expect_error(
      [&] {
        valid_depth_range(DepthImage{2, 1, {0.f, std::nanf("")}});
      },
      "depth", "depth image has no valid pixel (all holes)");
}

}  // namespace
}  // namespace trailscope::dmd
