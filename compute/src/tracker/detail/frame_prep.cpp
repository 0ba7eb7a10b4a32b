#include "tracker/detail/frame_prep.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace trailscope::tracker::detail {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
// NaN border of the gated image: the 5x5 median reaches 2 pixels out.
constexpr int kPad = 2;

inline void sort2(float& a, float& b) {
  const float lo = std::min(a, b), hi = std::max(a, b);
  a = lo;
  b = hi;
}

// The median of the valid (non-NaN) values of each 3x3 neighbourhood along a row: out[i] and count[i] (the
// valid values) for the neighbourhood whose rows start at up + i, mid + i, down + i; meaningful with at
// least 4 valid values (even counts take the mean of the middle two). Most of a frame's pixels pass
// through here, so it is written for the compiler to vectorise: no branches (invalid values sort last as
// +inf through a full 9-input sorting network, 25 exchanges, and the count picks the middle by
// independent selects), an integer count and no conditional float arithmetic (either would stop GCC's
// if-conversion under the default -ftrapping-math).
void median3x3_row(const float* __restrict up, const float* __restrict mid, const float* __restrict down,
                   float* __restrict out, int* __restrict count, int n) {
  for (int i = 0; i < n; ++i) {
    float s[9] = {up[i],      up[i + 1], up[i + 2],   mid[i],     mid[i + 1],
                  mid[i + 2], down[i],   down[i + 1], down[i + 2]};
    int c = 0;
    for (float& x : s) {
      const bool ok = x == x;
      c += ok;
      x = ok ? x : kInf;
    }
    sort2(s[0], s[1]), sort2(s[3], s[4]), sort2(s[6], s[7]), sort2(s[1], s[2]), sort2(s[4], s[5]);
    sort2(s[7], s[8]), sort2(s[0], s[1]), sort2(s[3], s[4]), sort2(s[6], s[7]), sort2(s[0], s[3]);
    sort2(s[3], s[6]), sort2(s[0], s[3]), sort2(s[1], s[4]), sort2(s[4], s[7]), sort2(s[1], s[4]);
    sort2(s[2], s[5]), sort2(s[5], s[8]), sort2(s[2], s[5]), sort2(s[1], s[3]), sort2(s[5], s[7]);
    sort2(s[2], s[6]), sort2(s[4], s[6]), sort2(s[2], s[4]), sort2(s[2], s[3]), sort2(s[5], s[6]);
    // Sorted ascending: the lower middle s[(c - 1) / 2] and the upper s[c / 2], for c = 4..9.
    const float lo = std::max({c >= 5 ? s[2] : s[1], c >= 7 ? s[3] : s[1], c >= 9 ? s[4] : s[1]});
    const float hi = std::max(c >= 6 ? s[3] : s[2], c >= 8 ? s[4] : s[2]);
    out[i] = 0.5f * (lo + hi);
    count[i] = c;
  }
}

// Median of n values (n <= 25; even counts take the mean of the middle two).
float median_of(float* v, int n) {
  std::nth_element(v, v + n / 2, v + n);
  float m = v[n / 2];
  if (n % 2 == 0) m = 0.5f * (m + *std::max_element(v, v + n / 2));
  return m;
}

// The value std::nth_element would put at rank k of v (non-negative floats, reordered). Their bit patterns
// order as the values do, so a histogram of the top bits (exponent and 3 mantissa bits) finds the bucket
// holding rank k, and only that bucket is partially sorted: a few times faster than nth_element over the
// frame's thousands of samples.
float select_nonnegative(std::vector<float>& v, std::size_t k, std::vector<float>& bucket) {
  constexpr int kShift = 20;
  std::array<std::uint32_t, (1u << (32 - kShift)) / 2> hist{};  // the sign bit is clear
  for (const float x : v) ++hist[std::bit_cast<std::uint32_t>(x) >> kShift];
  std::size_t below = 0, b = 0;
  while (below + hist[b] <= k) below += hist[b++];
  bucket.clear();
  for (const float x : v)
    if ((std::bit_cast<std::uint32_t>(x) >> kShift) == b) bucket.push_back(x);
  std::nth_element(bucket.begin(), bucket.begin() + static_cast<std::ptrdiff_t>(k - below), bucket.end());
  return bucket[k - below];
}

// The largest float f with f <= t: for every float d, d > t exactly when d > f (a float threshold that
// compares like the double one, so that the comparisons vectorise in single precision).
float float_below(double t) {
  float f = static_cast<float>(t);
  if (static_cast<double>(f) > t) f = std::nextafter(f, -kInf);
  return f;
}

using Spans = std::vector<std::vector<std::pair<int, int>>>;

// The rows' spans to work on: the whole frame, or the union of the rectangles (merged per row).
void make_spans(int w, int h, const std::vector<cv::Rect>* rois, std::vector<cv::Rect>& regions,
                Spans& spans) {
  regions.clear();
  if (!rois) {
    regions.push_back({0, 0, w, h});
  } else {
    for (const auto& r : *rois) {
      const cv::Rect c = r & cv::Rect(0, 0, w, h);
      if (!c.empty()) regions.push_back(c);
    }
  }
  spans.resize(h);
  for (auto& row : spans) row.clear();
  for (const auto& r : regions)
    for (int v = r.y; v < r.y + r.height; ++v) spans[v].push_back({r.x, r.x + r.width});
  for (auto& row : spans) {
    if (row.size() < 2) continue;
    std::sort(row.begin(), row.end());
    std::size_t k = 0;
    for (std::size_t i = 1; i < row.size(); ++i)
      if (row[i].first <= row[k].second)
        row[k].second = std::max(row[k].second, row[i].second);
      else
        row[++k] = row[i];
    row.resize(k + 1);
  }
}

// The gated depth inside its NaN border of kPad pixels (PreparedFrame::Scratch::gated).
struct Padded {
  float* data;
  int pitch;
  float* row(int v) const { return data + static_cast<std::ptrdiff_t>(v + kPad) * pitch + kPad; }
};

// Puts the previous frame's spans (the only pixels holding values) back to NaN in z and the gated image,
// rather than clearing whole images; allocates them for a new frame size.
void clear_previous(PreparedFrame& out, int w, int h) {
  const std::size_t n = static_cast<std::size_t>(w) * h;
  auto& gated = out.scratch.gated;
  if (out.width != w || out.height != h || out.z.size() != n) {
    out.z.assign(n, kNaN);
    gated.assign(static_cast<std::size_t>(h + 2 * kPad) * (w + 2 * kPad), kNaN);
    out.scratch.med.assign(n, kNaN);
    out.spans.assign(h, {});
    return;
  }
  const Padded g{gated.data(), w + 2 * kPad};
  for (int v = 0; v < h; ++v)
    for (const auto& [u0, u1] : out.spans[v]) {
      std::fill(out.z.data() + static_cast<std::size_t>(v) * w + u0,
                out.z.data() + static_cast<std::size_t>(v) * w + u1, kNaN);
      std::fill(g.row(v) + u0, g.row(v) + u1, kNaN);
    }
}

// Amplitude gate (when the frame has amplitudes) and depth gate over the spans; a NaN depth fails them.
void gate(const tof::DepthFrame& frame, const TrackerParams& p, const Spans& spans, int w, const Padded& g) {
  const bool gate_amp = frame.amplitude.size() == frame.depth_mm.size();
  const float zmin = static_cast<float>(p.z_min_mm), zmax = static_cast<float>(p.z_max_mm);
  const float amin = static_cast<float>(p.a_min);
  for (int v = 0; v < static_cast<int>(spans.size()); ++v)
    for (const auto& [u0, u1] : spans[v]) {
      const float* z = frame.depth_mm.data() + static_cast<std::size_t>(v) * w;
      const float* a = gate_amp ? frame.amplitude.data() + static_cast<std::size_t>(v) * w : z;
      float* out = g.row(v);
      for (int u = u0; u < u1; ++u)
        out[u] = z[u] >= zmin && z[u] <= zmax && (!gate_amp || a[u] >= amin) ? z[u] : kNaN;
    }
}

// Pass 1: each pixel's 3x3 median of valid neighbours into scratch.med (NaN for isolated speckle with
// fewer than 4 valid values, itself included, which counts as flying), and the pixel-to-median differences
// of every other pixel into scratch.dev for the noise level.
void median_pass(PreparedFrame& out, const Padded& g) {
  auto& dev = out.scratch.dev;
  auto& count = out.scratch.count;
  count.resize(out.width);
  dev.clear();
  for (int v = 0; v < out.height; ++v)
    for (const auto& [u0, u1] : out.spans[v]) {
      float* m = out.scratch.med.data() + static_cast<std::size_t>(v) * out.width;
      median3x3_row(g.row(v - 1) + u0 - 1, g.row(v) + u0 - 1, g.row(v + 1) + u0 - 1, m + u0, count.data(),
                    u1 - u0);
      const float* gv = g.row(v);
      for (int u = u0; u < u1; ++u) {
        if (std::isnan(gv[u])) continue;
        if (count[u - u0] < 4) {
          m[u] = kNaN;
          ++out.flying;
          continue;
        }
        if ((u + v) % 2 == 0) dev.push_back(std::fabs(gv[u] - m[u]));
      }
    }
}

// The flying-pixel threshold adapts to the frame's noise: 5 robust standard deviations of the
// pixel-to-median differences (1.4826 MAD), never below flying_mm. A fixed threshold either keeps the
// mixed pixels of a clean frame or throws away half of a noisy one. Sets noise_mm and flying_threshold_mm.
void noise_threshold(PreparedFrame& out, const TrackerParams& p) {
  auto& dev = out.scratch.dev;
  double threshold = p.flying_mm;
  out.noise_mm = 0.0;
  if (dev.size() > 16) {
    out.noise_mm = 1.4826 * select_nonnegative(dev, dev.size() / 2, out.scratch.bucket);
    threshold = std::max(threshold, 5.0 * out.noise_mm);
  }
  out.flying_threshold_mm = threshold;
}

// Pass 2: drop flying pixels (farther than the threshold from their median), smooth the rest with the
// median of radius r (0: none, 1: the 3x3 median, 2: the 5x5 median of the non-flying neighbours).
void smooth_pass(PreparedFrame& out, const Padded& g, int r) {
  const float limit = float_below(out.flying_threshold_mm);
  std::array<float, 25> buf{};
  for (int v = 0; v < out.height; ++v)
    for (const auto& [u0, u1] : out.spans[v]) {
      const float* gv = g.row(v);
      const float* m = out.scratch.med.data() + static_cast<std::size_t>(v) * out.width;
      float* z = out.z.data() + static_cast<std::size_t>(v) * out.width;
      int valid = 0, flying = 0;
      for (int u = u0; u < u1; ++u) {
        const float d = std::fabs(gv[u] - m[u]);  // NaN when either is
        const bool keep = d <= limit;
        valid += keep;
        flying += d > limit;
        z[u] = keep ? (r == 1 ? m[u] : gv[u]) : kNaN;
      }
      out.valid += valid;
      out.flying += flying;
      if (r != 2) continue;
      for (int u = u0; u < u1; ++u) {
        if (std::isnan(z[u])) continue;
        int k = 0;
        for (int dv = -2; dv <= 2; ++dv)
          for (int du = -2; du <= 2; ++du) {
            const float q = g.row(v + dv)[u + du];
            if (!std::isnan(q) && std::fabs(q - m[u]) <= limit) buf[k++] = q;
          }
        z[u] = median_of(buf.data(), k);
      }
    }
}

}  // namespace

void prepare_frame(const tof::DepthFrame& frame, int w, int h, const TrackerParams& p, PreparedFrame& out,
                   const std::vector<cv::Rect>* rois) {
  clear_previous(out, w, h);
  out.width = w;
  out.height = h;
  out.valid = 0;
  out.flying = 0;
  make_spans(w, h, rois, out.regions, out.spans);
  const Padded g{out.scratch.gated.data(), w + 2 * kPad};
  gate(frame, p, out.spans, w, g);
  median_pass(out, g);
  noise_threshold(out, p);
  smooth_pass(out, g, p.median_k / 2);
}

}  // namespace trailscope::tracker::detail
