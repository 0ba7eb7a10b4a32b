// The detector's own correlation and 2x2 downscale against OpenCV's: they replaced cv::matchTemplate
// (TM_CCOEFF_NORMED) and cv::resize (INTER_AREA at 1/2) with code that touches only a template's non-zero
// taps and the prepared regions, and must still give OpenCV's numbers.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tracker/detail/frame_prep.hpp"
#include "tracker/detail/ncc_detect.hpp"

namespace trailscope::tracker::detail {
namespace {

/// A height image like the detector's (-depth, mm): a smooth surface with bumps and noise, and (`flat`) a
/// flat patch where every window's variance is zero.
cv::Mat1f height_image(int width, int height, std::uint64_t seed, bool flat = true) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.f, 1.5f);
  cv::Mat1f img(height, width);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      img(y, x) = -600.f + 30.f * std::sin(0.2f * x) * std::cos(0.15f * y) + noise(rng);
  if (flat) img(cv::Rect(width - 30, height - 28, 26, 24)).setTo(-580.f);
  return img;
}

TEST(NccDetect, CorrelationIsOpenCvsNormalisedTemplateMatching) {
  const NccDetector detector{TrackerParams{}};
  const cv::Mat1f img = height_image(96, 72, 3);
  ASSERT_FALSE(detector.bank().empty());
  for (const TipTemplate& t : detector.bank()) {
    cv::Mat1f ours;
    detector.correlate(img, t, ours);
    cv::Mat ref;
    cv::matchTemplate(img, t.kernel, ref, cv::TM_CCOEFF_NORMED);
    ASSERT_EQ(ours.size(), ref.size()) << "template of radius " << t.radius_px;
    // OpenCV correlates in float through the DFT; ours sums in double: equal to float rounding.
    EXPECT_LT(cv::norm(ours, ref, cv::NORM_INF), 1e-3) << "template of radius " << t.radius_px;
    // The flat patch: OpenCV's convention for a window without variance holds too.
    const int k = t.kernel.rows;
    EXPECT_NEAR(ours(img.rows - 28 + 2, img.cols - 30 + 2),
                ref.at<float>(img.rows - 28 + 2, img.cols - 30 + 2), 1e-3)
        << "k " << k;
  }
}

TEST(NccDetect, HalvingIsOpenCvsAreaDownscale) {
  const cv::Mat1f src = height_image(64, 48, 5);
  cv::Mat1f ours(24, 32, 0.f), ref;
  NccDetector::halve(src, ours, {0, 0, 32, 24});
  cv::resize(src, ref, cv::Size(32, 24), 0, 0, cv::INTER_AREA);
  EXPECT_EQ(cv::norm(ours, ref, cv::NORM_INF), 0.0);
  // Over a sub-rectangle only: the rest of dst is left as it was.
  cv::Mat1f part(24, 32, 7.f);
  NccDetector::halve(src, part, {4, 2, 10, 6});
  EXPECT_EQ(cv::norm(part(cv::Rect(4, 2, 10, 6)), ref(cv::Rect(4, 2, 10, 6)), cv::NORM_INF), 0.0);
  EXPECT_EQ(part(0, 0), 7.f);
  EXPECT_EQ(part(23, 31), 7.f);
}

TEST(FramePrep, MedianOfAFullyValidFrameIsOpenCvsMedianBlur) {
  // A smooth surface with mild noise: no pixel is gated or flying, so inside a 1-pixel border every
  // prepared value is the plain 3x3 median (the border takes the median of its valid neighbours only).
  const cv::Mat1f height = height_image(64, 48, 9, false);
  tof::DepthFrame frame;
  for (int y = 0; y < height.rows; ++y)
    for (int x = 0; x < height.cols; ++x) frame.depth_mm.push_back(-height(y, x));
  PreparedFrame prepared;
  prepare_frame(frame, height.cols, height.rows, TrackerParams{}, prepared);
  ASSERT_EQ(prepared.flying, 0);
  ASSERT_EQ(prepared.valid, height.cols * height.rows);
  const cv::Mat1f depth(height.rows, height.cols, frame.depth_mm.data());
  cv::Mat1f ref;
  cv::medianBlur(depth, ref, 3);
  double worst = 0;
  for (int y = 1; y < height.rows - 1; ++y)
    for (int x = 1; x < height.cols - 1; ++x)
      worst = std::max(worst, double(std::fabs(prepared.at(x, y) - ref(y, x))));
  EXPECT_EQ(worst, 0.0);
}

}  // namespace
}  // namespace trailscope::tracker::detail
