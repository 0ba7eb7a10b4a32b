#include "tracker/detail/ncc_detect.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace trailscope::tracker::detail {
namespace {

int scale_index(int scale) {
  return scale == 1 ? 0 : scale == 2 ? 1 : 2;
}

}  // namespace

std::vector<TipTemplate> make_template_bank(const TrackerParams& p) {
  std::vector<TipTemplate> bank;
  const int n = p.templates;
  for (int i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.0 : double(i) / (n - 1);
    const double r = p.template_min_px * std::pow(p.template_max_px / p.template_min_px, t);
    TipTemplate tt;
    tt.radius_px = r;
    tt.scale = r <= 5.0 ? 1 : r <= 10.0 ? 2 : 4;
    const double rs = r / tt.scale;
    // The surround (out to 1.7 radii) is what makes a bump a tip: NCC needs the fall-off around it.
    const int half = std::max(2, static_cast<int>(std::ceil(1.7 * rs)));
    tt.kernel.create(2 * half + 1, 2 * half + 1);
    for (int y = -half; y <= half; ++y)
      for (int x = -half; x <= half; ++x) {
        const double d2 = double(x) * x + double(y) * y;
        tt.kernel(y + half, x + half) = static_cast<float>(d2 < rs * rs ? std::sqrt(rs * rs - d2) : 0.0);
      }
    bank.push_back(std::move(tt));
  }
  return bank;
}

NccDetector::NccDetector(const TrackerParams& p) : p_(p), bank_(make_template_bank(p)) {}

void NccDetector::set_frame(const PreparedFrame& f) {
  // Holes become background: the largest valid depth in the 7x7 neighbourhood (or the far gate), so a
  // hole next to a teat reads as "behind it", never as a protrusion.
  cv::Mat1f z(f.height, f.width);
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) {
      const float d = f.at(u, v);
      z(v, u) = std::isnan(d) ? 0.f : d;
    }
  cv::Mat1f far;
  cv::dilate(z, far, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(7, 7)));
  cv::Mat1f& h = height_[0];
  h.create(f.height, f.width);
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) {
      float d = z(v, u);
      if (d == 0.f) d = far(v, u) > 0.f ? far(v, u) : static_cast<float>(p_.z_max_mm);
      h(v, u) = -d;
    }
  bool need[3] = {true, false, false};
  for (const auto& t : bank_) need[scale_index(t.scale)] = true;
  if (need[1] || need[2]) cv::resize(h, height_[1], cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  if (need[2]) cv::resize(height_[1], height_[2], cv::Size(), 0.5, 0.5, cv::INTER_AREA);
}

std::vector<int> NccDetector::templates_near(double radius_px) const {
  std::vector<std::pair<double, int>> by;
  for (int i = 0; i < static_cast<int>(bank_.size()); ++i)
    by.push_back({std::fabs(std::log(bank_[i].radius_px / std::max(radius_px, 0.5))), i});
  std::sort(by.begin(), by.end());
  std::vector<int> out;
  if (!by.empty()) out.push_back(by[0].second);
  return out;
}

double NccDetector::score_at(double u, double v, int ti) const {
  const TipTemplate& t = bank_[ti];
  const cv::Mat1f& img = height_[scale_index(t.scale)];
  const int s = t.scale, half = t.kernel.rows / 2;
  const int cu = static_cast<int>(std::lround((u - 0.5 * (s - 1)) / s));
  const int cv_ = static_cast<int>(std::lround((v - 0.5 * (s - 1)) / s));
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  int n = 0;
  for (int y = -half; y <= half; ++y)
    for (int x = -half; x <= half; ++x) {
      const int yy = cv_ + y, xx = cu + x;
      if (yy < 0 || xx < 0 || yy >= img.rows || xx >= img.cols) continue;
      const double a = img(yy, xx), b = t.kernel(y + half, x + half);
      sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b, ++n;
    }
  if (n < 4) return 0.0;
  const double cov = sab - sa * sb / n, va = saa - sa * sa / n, vb = sbb - sb * sb / n;
  return va > 1e-9 && vb > 1e-9 ? cov / std::sqrt(va * vb) : 0.0;
}

std::vector<Match> NccDetector::detect(const std::vector<SearchWindow>& windows) const {
  std::vector<Match> peaks;
  for (const auto& w : windows) {
    for (int ti : w.templates) {
      const TipTemplate& t = bank_[ti];
      const cv::Mat1f& img = height_[scale_index(t.scale)];
      const int s = t.scale, half = t.kernel.rows / 2;
      // The window at this scale, widened by the kernel so peaks at its edge are correlated in full.
      const int u0 = std::max(0, w.u0 / s), v0 = std::max(0, w.v0 / s);
      const int u1 = std::min(img.cols, (w.u1 + s - 1) / s), v1 = std::min(img.rows, (w.v1 + s - 1) / s);
      if (u1 - u0 < 1 || v1 - v0 < 1) continue;
      const int pu0 = std::max(0, u0 - half), pv0 = std::max(0, v0 - half);
      const int pu1 = std::min(img.cols, u1 + half), pv1 = std::min(img.rows, v1 + half);
      // Replicate beyond the image so teats at the border are still found.
      const int pad_l = half - (u0 - pu0), pad_t = half - (v0 - pv0);
      const int pad_r = half - (pu1 - u1), pad_b = half - (pv1 - v1);
      cv::Mat1f roi;
      cv::copyMakeBorder(img(cv::Rect(pu0, pv0, pu1 - pu0, pv1 - pv0)), roi, pad_t, pad_b, pad_l, pad_r,
                         cv::BORDER_REPLICATE);
      cv::Mat1f ncc;
      cv::matchTemplate(roi, t.kernel, ncc, cv::TM_CCOEFF_NORMED);  // (v1-v0) x (u1-u0)
      for (int y = 0; y < ncc.rows; ++y)
        for (int x = 0; x < ncc.cols; ++x) {
          const float c = ncc(y, x);
          if (!(c >= p_.ncc_min) || c > 1.0001f) continue;
          bool is_max = true;
          for (int dy = -1; dy <= 1 && is_max; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int yy = y + dy, xx = x + dx;
              if ((dy || dx) && yy >= 0 && xx >= 0 && yy < ncc.rows && xx < ncc.cols &&
                  (ncc(yy, xx) > c || (ncc(yy, xx) == c && (dy < 0 || (dy == 0 && dx < 0))))) {
                is_max = false;
                break;
              }
            }
          if (!is_max) continue;
          // Centre of the downscaled pixel in full-resolution pixel coordinates.
          peaks.push_back({(x + u0) * s + 0.5 * (s - 1), (y + v0) * s + 0.5 * (s - 1), c, ti});
        }
    }
  }
  std::sort(peaks.begin(), peaks.end(), [](const Match& a, const Match& b) {
    return a.score != b.score ? a.score > b.score : (a.v != b.v ? a.v < b.v : a.u < b.u);
  });
  std::vector<Match> kept;
  for (const auto& m : peaks) {
    bool dup = false;
    for (const auto& k : kept) {
      const double r = 0.8 * std::max(bank_[k.template_index].radius_px, bank_[m.template_index].radius_px);
      if ((k.u - m.u) * (k.u - m.u) + (k.v - m.v) * (k.v - m.v) < r * r) {
        dup = true;
        break;
      }
    }
    if (!dup) kept.push_back(m);
    if (static_cast<int>(kept.size()) >= p_.max_candidates) break;
  }
  return kept;
}

}  // namespace trailscope::tracker::detail
