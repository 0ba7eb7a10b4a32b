#include "tracker/detail/frame_prep.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace trailscope::tracker::detail {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Median of 9 by the 19-exchange network of Paeth (Graphics Gems): most pixels have a full 3x3
// neighbourhood, and this is several times faster than nth_element.
inline void sort2(float& a, float& b) {
  const float lo = std::min(a, b), hi = std::max(a, b);
  a = lo;
  b = hi;
}
float median9(float* p) {
  sort2(p[1], p[2]);
  sort2(p[4], p[5]);
  sort2(p[7], p[8]);
  sort2(p[0], p[1]);
  sort2(p[3], p[4]);
  sort2(p[6], p[7]);
  sort2(p[1], p[2]);
  sort2(p[4], p[5]);
  sort2(p[7], p[8]);
  sort2(p[0], p[3]);
  sort2(p[5], p[8]);
  sort2(p[4], p[7]);
  sort2(p[3], p[6]);
  sort2(p[1], p[4]);
  sort2(p[2], p[5]);
  sort2(p[4], p[7]);
  sort2(p[4], p[2]);
  sort2(p[6], p[4]);
  sort2(p[4], p[2]);
  return p[4];
}

float median_of(float* v, int n) {
  if (n == 9) return median9(v);
  std::nth_element(v, v + n / 2, v + n);
  float m = v[n / 2];
  if (n % 2 == 0) m = 0.5f * (m + *std::max_element(v, v + n / 2));
  return m;
}

}  // namespace

void prepare_frame(const tof::DepthFrame& frame, int w, int h, const TrackerParams& p, PreparedFrame& out,
                   const std::vector<cv::Rect>* rois) {
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const bool gate_amp = frame.amplitude.size() == n;
  // The rows' spans to work on: the whole frame, or the union of the rectangles (merged per row).
  auto& spans = out.scratch.spans;
  spans.assign(h, {});
  if (!rois) {
    for (auto& row : spans) row.push_back({0, w});
  } else {
    for (const auto& r : *rois) {
      const int u0 = std::max(0, r.x), u1 = std::min(w, r.x + r.width);
      for (int v = std::max(0, r.y); v < std::min(h, r.y + r.height); ++v)
        if (u1 > u0) spans[v].push_back({u0, u1});
    }
    for (auto& row : spans) {
      std::sort(row.begin(), row.end());
      std::vector<std::pair<int, int>> merged;
      for (const auto& sp : row)
        if (!merged.empty() && sp.first <= merged.back().second)
          merged.back().second = std::max(merged.back().second, sp.second);
        else
          merged.push_back(sp);
      row.swap(merged);
    }
  }
  // Gates, into a scratch image.
  std::vector<float>& gated = out.scratch.gated;
  gated.assign(n, kNaN);
  const float zmin = static_cast<float>(p.z_min_mm), zmax = static_cast<float>(p.z_max_mm);
  const float amin = static_cast<float>(p.a_min);
  for (int v = 0; v < h; ++v)
    for (const auto& [u0, u1] : spans[v])
      for (int u = u0; u < u1; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * w + u;
        const float z = frame.depth_mm[i];
        const bool ok = z >= zmin && z <= zmax && (!gate_amp || frame.amplitude[i] >= amin);  // NaN fails
        if (ok) gated[i] = z;
      }
  out.width = w;
  out.height = h;
  out.z.assign(n, kNaN);
  out.valid = 0;
  out.flying = 0;
  const int r = p.median_k / 2;
  // Pass 1: each gated pixel's 3x3 median (NaN for isolated speckle with fewer than 3 valid neighbours).
  // Pixels with all 9 neighbours valid (most of them) take OpenCV's vectorised median; the others, at
  // holes and borders, the median of their valid neighbours.
  std::vector<float>& med = out.scratch.med;
  std::vector<float>& dev = out.scratch.dev;
  cv::Mat1f& filled = out.scratch.filled;
  cv::Mat1f& fast_med = out.scratch.fast_med;
  cv::Mat1b& mask = out.scratch.mask;
  cv::Mat1b& count = out.scratch.count;
  filled.create(h, w);
  mask.create(h, w);
  for (std::size_t i = 0; i < n; ++i) {
    const bool ok = !std::isnan(gated[i]);
    mask(static_cast<int>(i)) = ok;
    filled(static_cast<int>(i)) = ok ? gated[i] : 0.f;
  }
  cv::boxFilter(mask, count, -1, cv::Size(3, 3), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  cv::medianBlur(filled, fast_med, 3);
  med.assign(n, kNaN);
  dev.clear();
  std::array<float, 25> buf{};
  for (int v = 0; v < h; ++v)
    for (const auto& [u0, u1] : spans[v])
      for (int u = u0; u < u1; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * w + u;
        if (!mask(v, u)) continue;
        if (count(v, u) == 9) {
          med[i] = fast_med(v, u);
        } else {
          int k = 0;
          for (int dv = -1; dv <= 1; ++dv) {
            const int vv = v + dv;
            if (vv < 0 || vv >= h) continue;
            for (int du = -1; du <= 1; ++du) {
              const int uu = u + du;
              if (uu < 0 || uu >= w) continue;
              const float q = gated[static_cast<std::size_t>(vv) * w + uu];
              if (!std::isnan(q)) buf[k++] = q;
            }
          }
          if (k < 4) {
            ++out.flying;
            continue;
          }
          med[i] = median_of(buf.data(), k);
        }
        // Every other pixel is enough for the frame's noise level.
        if ((u + v) % 2 == 0) dev.push_back(std::fabs(gated[i] - med[i]));
      }
  // The flying-pixel threshold adapts to the frame's noise: 5 robust standard deviations of the
  // pixel-to-median differences (1.4826 MAD), never below flying_mm. A fixed threshold either keeps the
  // mixed pixels of a clean frame or throws away half of a noisy one.
  double threshold = p.flying_mm;
  out.noise_mm = 0.0;
  if (dev.size() > 16) {
    std::nth_element(dev.begin(), dev.begin() + dev.size() / 2, dev.end());
    out.noise_mm = 1.4826 * dev[dev.size() / 2];
    threshold = std::max(threshold, 5.0 * out.noise_mm);
  }
  out.flying_threshold_mm = threshold;
  // Pass 2: drop flying pixels, smooth the rest.
  for (int v = 0; v < h; ++v)
    for (const auto& [u0, u1] : spans[v])
      for (int u = u0; u < u1; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * w + u;
        const float z = gated[i];
        if (std::isnan(z) || std::isnan(med[i])) continue;
        if (std::fabs(z - med[i]) > threshold) {
          ++out.flying;
          continue;
        }
        float value = z;
        if (r == 1) {
          value = med[i];
        } else if (r == 2) {
          int k = 0;
          for (int dv = -2; dv <= 2; ++dv)
            for (int du = -2; du <= 2; ++du) {
              const int uu = u + du, vv = v + dv;
              if (uu < 0 || vv < 0 || uu >= w || vv >= h) continue;
              const float q = gated[static_cast<std::size_t>(vv) * w + uu];
              if (!std::isnan(q) && std::fabs(q - med[i]) <= threshold) buf[k++] = q;
            }
          value = median_of(buf.data(), k);
        }
        out.z[i] = value;
        ++out.valid;
      }
}

}  // namespace trailscope::tracker::detail
