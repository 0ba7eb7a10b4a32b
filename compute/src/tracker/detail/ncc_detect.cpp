#include "tracker/detail/ncc_detect.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace trailscope::tracker::detail {
namespace {

int scale_index(int scale) {
  return scale == 1 ? 0 : scale == 2 ? 1 : 2;
}

// sum over the taps of weight * a(y + dy, x + dx), for x in [0, cols): the cross term of the NCC at row
// y. A row at a time, vectorised along it, four taps per pass so that the row is loaded and stored a
// quarter as often.
void cross_row(const cv::Mat1f& a, int y, const std::vector<TipTemplate::Tap>& taps, float* __restrict cross,
               int cols) {
  std::fill(cross, cross + cols, 0.f);
  std::size_t i = 0;
  for (; i + 4 <= taps.size(); i += 4) {
    const float* __restrict s0 = a[y + taps[i].dy] + taps[i].dx;
    const float* __restrict s1 = a[y + taps[i + 1].dy] + taps[i + 1].dx;
    const float* __restrict s2 = a[y + taps[i + 2].dy] + taps[i + 2].dx;
    const float* __restrict s3 = a[y + taps[i + 3].dy] + taps[i + 3].dx;
    const float w0 = taps[i].weight, w1 = taps[i + 1].weight, w2 = taps[i + 2].weight,
                w3 = taps[i + 3].weight;
    for (int x = 0; x < cols; ++x) cross[x] += (w0 * s0[x] + w1 * s1[x]) + (w2 * s2[x] + w3 * s3[x]);
  }
  for (; i < taps.size(); ++i) {
    const float* __restrict src = a[y + taps[i].dy] + taps[i].dx;
    const float w = taps[i].weight;
    for (int x = 0; x < cols; ++x) cross[x] += w * src[x];
  }
}

// The NCC of a window from its zero-mean cross term num, its sum of squared deviations var, its raw sum of
// squares raw2 and the kernel's norm, finished as OpenCV finishes TM_CCOEFF_NORMED: a window flat to
// rounding correlates 0, and rounding just past +-1 is clamped.
double normalise(double num, double var, double raw2, double norm) {
  if (var <= std::min(0.5, 10 * FLT_EPSILON * raw2)) return 0.0;
  const double den = std::sqrt(var) * norm;
  if (std::fabs(num) < den) return num / den;
  if (std::fabs(num) < 1.125 * den) return num > 0 ? 1.0 : -1.0;
  return 0.0;
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
    const int k = tt.kernel.rows;
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x)
        if (tt.kernel(y, x) != 0.f) tt.taps.push_back({x, y, tt.kernel(y, x)});
    tt.mean = cv::mean(tt.kernel)[0];
    for (const float q : tt.kernel) tt.norm += (q - tt.mean) * (q - tt.mean);
    tt.norm = std::sqrt(tt.norm);
    bank.push_back(std::move(tt));
  }
  return bank;
}

NccDetector::NccDetector(const TrackerParams& p) : p_(p), bank_(make_template_bank(p)) {}

void NccDetector::set_frame(const PreparedFrame& f) {
  const int w = f.width, h = f.height;
  height_[0].create(h, w);
  bool need[3] = {true, false, false};
  for (const auto& t : bank_) need[scale_index(t.scale)] = true;
  need[1] = need[1] || need[2];
  const int align = need[2] ? 4 : need[1] ? 2 : 1;
  if (w % align || h % align) {
    // The pyramids' last pixels are partial: built whole, as cv::resize builds them.
    fill_height(f, {0, 0, w, h});
    if (need[1]) cv::resize(height_[0], height_[1], cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    if (need[2]) cv::resize(height_[1], height_[2], cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    return;
  }
  if (need[1]) height_[1].create(h / 2, w / 2);
  if (need[2]) height_[2].create(h / 4, w / 4);
  // Only the prepared regions are read (the windows and their kernels' reach); each is widened to whole
  // pixels of the coarsest scale so that its pyramid pixels are complete.
  for (const cv::Rect& r : f.regions) {
    const int x0 = r.x / align * align, y0 = r.y / align * align;
    const int x1 = std::min(w, (r.x + r.width + align - 1) / align * align);
    const int y1 = std::min(h, (r.y + r.height + align - 1) / align * align);
    fill_height(f, {x0, y0, x1 - x0, y1 - y0});
    if (need[1]) halve(height_[0], height_[1], {x0 / 2, y0 / 2, (x1 - x0) / 2, (y1 - y0) / 2});
    if (need[2]) halve(height_[1], height_[2], {x0 / 4, y0 / 4, (x1 - x0) / 4, (y1 - y0) / 4});
  }
}

void NccDetector::fill_height(const PreparedFrame& f, const cv::Rect& r) {
  // Holes become background: the largest valid depth in the 7x7 neighbourhood (or the far gate), so a
  // hole next to a teat reads as "behind it", never as a protrusion. The 7x7 maximum is separable: row
  // maxima over the region's rows and kReach more each side, then their column maxima. Invalid and
  // off-image pixels count as 0, below every depth.
  constexpr int kReach = 3;
  const int w = f.width, h = f.height, rw = r.width;
  const int y0 = std::max(0, r.y - kReach), y1 = std::min(h, r.y + r.height + kReach);
  rowmax_.resize(static_cast<std::size_t>(y1 - y0) * rw);
  padded_.assign(rw + 2 * kReach, 0.f);
  for (int y = y0; y < y1; ++y) {
    const float* z = f.z.data() + static_cast<std::size_t>(y) * w;
    for (int x = std::max(0, r.x - kReach); x < std::min(w, r.x + rw + kReach); ++x)
      padded_[x - r.x + kReach] = z[x] > 0.f ? z[x] : 0.f;  // NaN is not > 0
    float* out = rowmax_.data() + static_cast<std::size_t>(y - y0) * rw;
    const float* in = padded_.data();
    for (int i = 0; i < rw; ++i)
      out[i] = std::max({in[i], in[i + 1], in[i + 2], in[i + 3], in[i + 4], in[i + 5], in[i + 6]});
  }
  far_.resize(rw);
  const float zfar = static_cast<float>(p_.z_max_mm);
  for (int v = r.y; v < r.y + r.height; ++v) {
    std::fill(far_.begin(), far_.end(), 0.f);
    for (int y = std::max(y0, v - kReach); y <= std::min(y1 - 1, v + kReach); ++y) {
      const float* m = rowmax_.data() + static_cast<std::size_t>(y - y0) * rw;
      for (int i = 0; i < rw; ++i) far_[i] = std::max(far_[i], m[i]);
    }
    const float* z = f.z.data() + static_cast<std::size_t>(v) * w + r.x;
    float* out = height_[0][v] + r.x;
    for (int i = 0; i < rw; ++i) {
      const float hole = far_[i] > 0.f ? far_[i] : zfar;
      out[i] = -(z[i] > 0.f ? z[i] : hole);
    }
  }
}

void NccDetector::halve(const cv::Mat1f& src, cv::Mat1f& dst, const cv::Rect& r) {
  // INTER_AREA at exactly 1/2: the mean of each 2x2 block, summed as OpenCV's vectorised path sums it.
  for (int y = r.y; y < r.y + r.height; ++y) {
    const float* a = src[2 * y];
    const float* b = src[2 * y + 1];
    float* out = dst[y];
    for (int x = r.x; x < r.x + r.width; ++x)
      out[x] = ((a[2 * x] + a[2 * x + 1]) + (b[2 * x] + b[2 * x + 1])) * 0.25f;
  }
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

void NccDetector::correlate(const cv::Mat1f& img, const TipTemplate& t, cv::Mat1f& out) const {
  const int k = t.kernel.rows, rows = img.rows - k + 1, cols = img.cols - k + 1;
  if (rows < 1 || cols < 1) {
    out.release();
    return;
  }
  out.create(rows, cols);
  const double n = double(k) * k;
  // Heights relative to the image's mean: NCC ignores an offset, and the sums keep their precision.
  const double c = cv::mean(img)[0];
  cv::subtract(img, cv::Scalar(c), shifted_);
  const cv::Mat1f& a = shifted_;
  // Window sums of a and a^2 (double): column sums over the window's rows, slid down row by row.
  col1_.assign(img.cols, 0.0);
  col2_.assign(img.cols, 0.0);
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < img.cols; ++x) col1_[x] += a(y, x), col2_[x] += double(a(y, x)) * a(y, x);
  cross_.resize(cols);
  for (int y = 0; y < rows; ++y) {
    if (y > 0)
      for (int x = 0; x < img.cols; ++x) {
        const double in = a(y + k - 1, x), gone = a(y - 1, x);
        col1_[x] += in - gone;
        col2_[x] += in * in - gone * gone;
      }
    float* cross = cross_.data();
    cross_row(a, y, t.taps, cross, cols);
    double s1 = 0, s2 = 0;
    for (int x = 0; x < k; ++x) s1 += col1_[x], s2 += col2_[x];
    float* o = out[y];
    for (int x = 0; x < cols; ++x) {
      if (x > 0) s1 += col1_[x + k - 1] - col1_[x - 1], s2 += col2_[x + k - 1] - col2_[x - 1];
      // sum((a - mean a) * (kernel - mean kernel)) = sum(a * kernel) - mean kernel * sum(a).
      const double num = cross[x] - t.mean * s1;
      const double var = std::max(s2 - s1 * s1 / n, 0.0);
      const double raw2 = s2 + 2 * c * s1 + n * c * c;
      o[x] = static_cast<float>(normalise(num, var, raw2, t.norm));
    }
  }
}

std::vector<Match> NccDetector::detect(const std::vector<SearchWindow>& windows) const {
  std::vector<Match> peaks;
  for (const auto& w : windows) {
    const double min_score = std::max(p_.ncc_min, w.min_score);
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
      correlate(roi, t, ncc);  // (v1-v0) x (u1-u0)
      for (int y = 0; y < ncc.rows; ++y)
        for (int x = 0; x < ncc.cols; ++x) {
          const float c = ncc(y, x);
          if (!(c >= min_score) || c > 1.0001f) continue;
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
