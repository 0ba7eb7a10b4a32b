#include "trailscope/density/span.hpp"

#include <algorithm>
#include <cmath>

#include "trailscope/core/error.hpp"

namespace trailscope::density {

How parse_how(std::string_view text, const std::string& param) {
  if (text == "linear") return How::linear;
  if (text == "log") return How::log;
  if (text == "eq_hist") return How::eq_hist;
  throw invalid_argument(param,
                         "unknown shading '" + std::string(text) + "' (expected linear, log or eq_hist)");
}

const char* to_string(How h) noexcept {
  switch (h) {
    case How::linear:
      return "linear";
    case How::log:
      return "log";
    case How::eq_hist:
      return "eq_hist";
  }
  return "eq_hist";
}

double SpanStats::normalize(double v, How how) const {
  if (std::isnan(v)) return v;
  if (empty) return 0.0;
  if (v <= lo) return 0.0;
  if (v >= hi) return 1.0;  // also covers hi == lo
  switch (how) {
    case How::linear:
      return (v - lo) / (hi - lo);
    case How::log: {
      const double o = std::min(lo, 0.0);
      const double a = std::log1p(lo - o), b = std::log1p(hi - o);
      return (std::log1p(v - o) - a) / (b - a);
    }
    case How::eq_hist: {
      // lo < v < hi, so v lies strictly inside the table: cdf_values.front() = lo, back() = hi.
      const auto it = std::upper_bound(cdf_values.begin(), cdf_values.end(), v);
      const std::size_t k = static_cast<std::size_t>(it - cdf_values.begin()) - 1;
      const double f = (v - cdf_values[k]) / (cdf_values[k + 1] - cdf_values[k]);
      const double c = cdf[k] + f * (cdf[k + 1] - cdf[k]);
      const double c0 = cdf.front();
      return c0 >= 1.0 ? 1.0 : std::clamp((c - c0) / (1.0 - c0), 0.0, 1.0);
    }
  }
  return 0.0;
}

SpanStats compute_span(const Raster& r, double scale, double floor) {
  // The distinct values with their multiplicities, ascending: by counting when all values are small
  // non-negative integers (plain counts: O(n) where sorting a 1024² coarse raster took most of a span's
  // time), else by sorting.
  constexpr float kMaxCounted = 1 << 16;
  std::size_t n = 0;
  bool integral = true;
  float top = 0.0f;
  for (float v : r.values) {
    if (std::isnan(v)) continue;
    ++n;
    top = std::max(top, v);
    if (integral && !(v >= 0.0f && v <= kMaxCounted && v == std::floor(v))) integral = false;
  }
  SpanStats s;
  s.samples = n;
  if (n == 0) return s;
  std::vector<std::pair<double, std::uint64_t>> distinct;
  if (integral) {
    std::vector<std::uint64_t> hist(static_cast<std::size_t>(top) + 1, 0);
    for (float v : r.values)
      if (!std::isnan(v)) ++hist[static_cast<std::size_t>(v)];
    for (std::size_t k = 0; k < hist.size(); ++k)
      if (hist[k]) distinct.emplace_back(static_cast<double>(k), hist[k]);
  } else {
    std::vector<float> v;
    v.reserve(n);
    for (float x : r.values)
      if (!std::isnan(x)) v.push_back(x);
    std::sort(v.begin(), v.end());
    for (float x : v) {
      if (!distinct.empty() && distinct.back().first == x)
        ++distinct.back().second;
      else
        distinct.emplace_back(x, 1);
    }
  }
  // Scale and floor (monotone, so the order stays; values the floor merges are summed).
  std::vector<std::pair<double, std::uint64_t>> values;
  values.reserve(distinct.size());
  for (const auto& [v, m] : distinct) {
    const double x = std::max(v * scale, floor);
    if (!values.empty() && values.back().first == x)
      values.back().second += m;
    else
      values.emplace_back(x, m);
  }
  s.empty = false;
  s.lo = values.front().first;
  s.hi = values.back().first;
  const double total = static_cast<double>(n);
  if (values.size() <= kMaxCdfPoints) {
    std::uint64_t upto = 0;
    for (const auto& [x, m] : values) {
      upto += m;
      s.cdf_values.push_back(x);
      s.cdf.push_back(static_cast<double>(upto) / total);
    }
    return s;
  }
  // More distinct values than kept: the values at kMaxCdfPoints evenly spaced ranks (0 .. n−1), each
  // with the fraction of samples <= it, plus the maximum.
  std::size_t k = 0;
  std::uint64_t upto = values[0].second;  // samples <= values[k]
  for (std::size_t q = 0; q < kMaxCdfPoints; ++q) {
    const auto rank = static_cast<std::uint64_t>(static_cast<double>(q) * (total - 1) / (kMaxCdfPoints - 1));
    while (upto <= rank) upto += values[++k].second;
    if (s.cdf_values.empty() || s.cdf_values.back() != values[k].first) {
      s.cdf_values.push_back(values[k].first);
      s.cdf.push_back(static_cast<double>(upto) / total);
    }
  }
  if (s.cdf_values.back() != s.hi) {
    s.cdf_values.push_back(s.hi);
    s.cdf.push_back(1.0);
  }
  return s;
}

SpanStats rescale_span(const SpanStats& s, double scale, double floor) {
  SpanStats out;
  out.samples = s.samples;
  if (s.empty) return out;
  for (std::size_t k = 0; k < s.cdf_values.size(); ++k) {
    const double x = std::max(s.cdf_values[k] * scale, floor);
    if (!out.cdf_values.empty() && out.cdf_values.back() == x) {
      out.cdf.back() = s.cdf[k];
    } else {
      out.cdf_values.push_back(x);
      out.cdf.push_back(s.cdf[k]);
    }
  }
  out.empty = false;
  out.lo = out.cdf_values.front();
  out.hi = out.cdf_values.back();
  return out;
}

}  // namespace trailscope::density
