#pragma once
// Stage 2 of the tracker: teat-tip candidates by normalised cross-correlation (NCC) of the depth image
// with a bank of rounded-tip templates. Internal.
#include <vector>

#include <opencv2/core.hpp>

#include "tracker/detail/frame_prep.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::tracker::detail {

/// One template: a hemispherical bump of radius `radius_px` (as "height" = -depth, so a tip pointing at
/// the camera is a positive bump) on a flat surround. Large radii are matched on a downscaled image
/// (`scale` 1, 2 or 4) so that every correlation uses a small kernel: NCC is scale-free, and a 12 px tip
/// seen at 1/4 resolution is a 3 px tip.
struct TipTemplate {
  double radius_px = 0;  ///< at full resolution
  int scale = 1;         ///< image downscale the template runs at
  cv::Mat1f kernel;      ///< at its scale, odd square size
  /// The kernel's non-zero entries (the bump; a quarter of the kernel): offset from its top-left corner.
  struct Tap {
    int dx = 0, dy = 0;
    float weight = 0;
  };
  std::vector<Tap> taps;
  double mean = 0;  ///< mean of the kernel
  double norm = 0;  ///< sqrt of the sum of (kernel - mean)^2
};

/// radii geometric from template_min_px to template_max_px, `templates` of them.
std::vector<TipTemplate> make_template_bank(const TrackerParams& p);

struct Match {
  double u = 0, v = 0;  ///< full-resolution pixel
  double score = 0;     ///< NCC
  int template_index = 0;
};

/// Region of interest in full-resolution pixels, [u0, u1) x [v0, v1), and the templates to try there.
struct SearchWindow {
  int u0 = 0, v0 = 0, u1 = 0, v1 = 0;
  std::vector<int> templates;
  double min_score = 0;  ///< NCC a match here needs besides ncc_min (the larger of the two applies)
};

/// Correlates every window with its templates; returns local NCC maxima >= ncc_min (and the window's
/// min_score), strongest first,
/// merged across templates and windows (a weaker peak within 0.8 template radii of a stronger one is the
/// same tip), at most max_candidates.
class NccDetector {
 public:
  explicit NccDetector(const TrackerParams& p);
  const std::vector<TipTemplate>& bank() const { return bank_; }
  /// Builds the "height" images (filled holes, one per scale) of a new frame, over its prepared regions.
  void set_frame(const PreparedFrame& f);
  std::vector<Match> detect(const std::vector<SearchWindow>& windows) const;
  /// NCC of template `ti` centred at full-resolution pixel (u, v) (the kernel clipped to the image).
  double score_at(double u, double v, int ti) const;
  /// The template whose radius is nearest (in ratio) to `radius_px` (a tracked teat's expected size).
  std::vector<int> templates_near(double radius_px) const;
  /// NCC (as cv::TM_CCOEFF_NORMED) of template t at every position where it lies inside img: out is
  /// (img.rows - k + 1) x (img.cols - k + 1) for a k x k kernel. Public for the tests that hold it to
  /// OpenCV's.
  void correlate(const cv::Mat1f& img, const TipTemplate& t, cv::Mat1f& out) const;
  /// dst over r (dst pixels) as the 2x2 means of src (cv::resize INTER_AREA at exactly 1/2).
  static void halve(const cv::Mat1f& src, cv::Mat1f& dst, const cv::Rect& r);

 private:
  /// The full-resolution height image (-depth, holes filled) over region r of f.
  void fill_height(const PreparedFrame& f, const cv::Rect& r);

  TrackerParams p_;
  std::vector<TipTemplate> bank_;
  cv::Mat1f height_[3];                       ///< scales 1, 2, 4; valid over the frame's prepared regions
  std::vector<float> rowmax_, padded_, far_;  ///< scratch of fill_height
  /// Scratch of correlate (detect is logically const).
  mutable cv::Mat1f shifted_;
  mutable std::vector<double> col1_, col2_;
  mutable std::vector<float> cross_;
};

}  // namespace trailscope::tracker::detail
