#pragma once
// Golden-image comparison shared by every test area that renders images (density tiles, bundles): the
// image must match tests/golden/<name> on all but 0.1 % of its pixels within 2/255 per channel. Rendering
// is deterministic, so the images match exactly on the machine that wrote them; the tolerance absorbs
// libm and floating-point shading differences between platforms. TRAILSCOPE_UPDATE_GOLDEN=1 rewrites the
// golden file instead of comparing (see tests/golden/README.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "test_support.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::test {

inline void compare_with_golden(const density::Image& img, const std::string& name) {
  const auto path = source_dir() / "tests" / "golden" / name;
  if (const char* u = std::getenv("TRAILSCOPE_UPDATE_GOLDEN"); u && std::string(u) == "1") {
    density::write_png(img, path);
    std::printf("wrote %s\n", path.c_str());
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing (TRAILSCOPE_UPDATE_GOLDEN=1 writes it)";
  const density::Image golden = density::read_png(path);
  ASSERT_EQ(golden.width, img.width);
  ASSERT_EQ(golden.height, img.height);
  std::size_t off = 0;
  int worst = 0;
  for (std::size_t p = 0; p < img.rgba.size() / 4; ++p) {
    int d = 0;
    for (int c = 0; c < 4; ++c)
      d = std::max(d, std::abs(int{img.rgba[4 * p + c]} - int{golden.rgba[4 * p + c]}));
    worst = std::max(worst, d);
    off += d > 2;
  }
  EXPECT_LE(off, img.rgba.size() / 4 / 1000)
      << name << ": " << off << " pixels differ by more than 2 (worst " << worst << ")";
}

}  // namespace trailscope::test
