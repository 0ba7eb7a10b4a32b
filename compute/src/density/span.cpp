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
  std::vector<double> v;
  v.reserve(r.values.size() / 4);
  for (float x : r.values)
    if (!std::isnan(x)) v.push_back(std::max(static_cast<double>(x) * scale, floor));
  SpanStats s;
  s.samples = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.empty = false;
  s.lo = v.front();
  s.hi = v.back();
  const double n = static_cast<double>(v.size());
  // Distinct values with the fraction of samples <= each; past kMaxCdfPoints distinct values, evenly
  // spaced order statistics instead (plus the maximum).
  auto push = [&](double value) {
    if (!s.cdf_values.empty() && s.cdf_values.back() == value) return;
    const auto upto = std::upper_bound(v.begin(), v.end(), value) - v.begin();
    s.cdf_values.push_back(value);
    s.cdf.push_back(static_cast<double>(upto) / n);
  };
  std::size_t count_distinct = 1;
  for (std::size_t i = 1; i < v.size() && count_distinct <= kMaxCdfPoints; ++i)
    count_distinct += v[i] != v[i - 1];
  if (count_distinct <= kMaxCdfPoints) {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (i + 1 == v.size() || v[i + 1] != v[i]) push(v[i]);
  } else {
    for (std::size_t q = 0; q < kMaxCdfPoints; ++q)
      push(v[static_cast<std::size_t>(static_cast<double>(q) * (n - 1) /
                                      static_cast<double>(kMaxCdfPoints - 1))]);
    push(v.back());
  }
  return s;
}

}  // namespace trailscope::density
