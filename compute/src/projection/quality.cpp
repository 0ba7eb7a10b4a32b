// Projection quality metrics. The O(queries·N) distance rows in data and layout space are the device's
// part; ranking them is shared host code, so both paths differ only by float-versus-double distances.
#include "trailscope/projection/quality.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "ocl/dispatch.hpp"
#include "projection/projection_ocl.hpp"
#include "projection/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::projection {
namespace {

constexpr std::size_t kChunk = 64;  // query rows whose distance rows are held at once

void check(const Table& t, const std::vector<double>& xy, const QualityOptions& o) {
  validate_table(t);
  if (xy.size() != 2 * t.rows)
    throw invalid_argument("xy", "the layout holds " + std::to_string(xy.size()) +
                                     " values, not rows × 2 = " + std::to_string(2 * t.rows));
  for (double v : xy)
    if (!std::isfinite(v)) throw invalid_argument("xy", "the layout has a NaN or infinite coordinate");
  if (o.k < 1 || o.k > limits::kMaxQualityK || 2 * static_cast<std::size_t>(o.k) >= t.rows)
    throw invalid_argument("k", "k must be in [1, " + std::to_string(limits::kMaxQualityK) +
                                    "] and below rows / 2 (" + std::to_string(t.rows) + " rows), not " +
                                    std::to_string(o.k));
}

std::vector<std::size_t> query_rows(const Table& t, const QualityOptions& o, bool& sampled) {
  const std::size_t cap = o.sample ? o.sample : limits::kMaxQualitySample;
  sampled = t.rows > cap;
  if (!sampled) {
    std::vector<std::size_t> all(t.rows);
    std::iota(all.begin(), all.end(), std::size_t{0});
    return all;
  }
  return detail::sample_indices(t.rows, cap, o.seed);
}

// Indices of the k nearest (by (distance, index)) of row q, itself excluded.
template <class T>
std::vector<std::int32_t> nearest(const T* d, std::size_t n, std::size_t q, int k) {
  std::vector<std::int32_t> idx;
  idx.reserve(n - 1);
  for (std::size_t j = 0; j < n; ++j)
    if (j != q) idx.push_back(static_cast<std::int32_t>(j));
  const auto less = [d](std::int32_t a, std::int32_t b) { return d[a] < d[b] || (d[a] == d[b] && a < b); };
  std::partial_sort(idx.begin(), idx.begin() + k, idx.end(), less);
  idx.resize(k);
  return idx;
}

// Rank (1-based) of j among all rows but q by (distance, index).
template <class T>
std::size_t rank_of(const T* d, std::size_t n, std::size_t q, std::size_t j) {
  const T dj = d[j];
  std::size_t r = 1;
  for (std::size_t l = 0; l < n; ++l) r += (l != q) & ((d[l] < dj) | ((d[l] == dj) & (l < j)));
  return r;
}

std::vector<double> average_ranks(const std::vector<double>& v) {
  std::vector<std::size_t> order(v.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t a = 0; a < order.size();) {
    std::size_t b = a;
    while (b + 1 < order.size() && v[order[b + 1]] == v[order[a]]) ++b;
    const double avg = 0.5 * static_cast<double>(a + b) + 1.0;
    for (std::size_t c = a; c <= b; ++c) r[order[c]] = avg;
    a = b + 1;
  }
  return r;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= n, mb /= n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb), saa += (a[i] - ma) * (a[i] - ma), sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

// The metrics from distance rows that `fill(q0, q1, dd, pd)` writes: squared data and layout distances
// of query rows queries[q0..q1) to all n rows, (q1 − q0) × n each.
template <class T, class Fill>
Quality evaluate(const Table& t, const QualityOptions& o, const std::vector<std::size_t>& queries,
                 bool sampled, Fill&& fill) {
  const std::size_t n = t.rows, s = queries.size();
  const int k = o.k;
  std::vector<double> tsum(s, 0), csum(s, 0), npsum(s, 0);
  std::vector<double> qd(s * s), qp(s * s);  // distances among the queries
  std::vector<T> dd, pd;
  for (std::size_t q0 = 0; q0 < s; q0 += kChunk) {
    const std::size_t q1 = std::min(s, q0 + kChunk);
    fill(q0, q1, dd, pd);
    tbb::parallel_for(q0, q1, [&](std::size_t a) {
      const std::size_t q = queries[a];
      const T* d = dd.data() + (a - q0) * n;
      const T* p = pd.data() + (a - q0) * n;
      std::vector<std::int32_t> nk = nearest(d, n, q, k), vk = nearest(p, n, q, k);
      std::vector<std::int32_t> ns = nk, vs = vk;
      std::sort(ns.begin(), ns.end()), std::sort(vs.begin(), vs.end());
      std::vector<std::int32_t> both;
      std::set_intersection(ns.begin(), ns.end(), vs.begin(), vs.end(), std::back_inserter(both));
      npsum[a] = static_cast<double>(both.size()) / k;
      // A layout neighbour that is also a data neighbour has r ≤ k and costs nothing; the others need
      // their data rank (and vice versa for continuity).
      double tr = 0, co = 0;
      for (std::int32_t j : vs)
        if (!std::binary_search(ns.begin(), ns.end(), j))
          tr += static_cast<double>(rank_of(d, n, q, static_cast<std::size_t>(j))) - k;
      for (std::int32_t j : ns)
        if (!std::binary_search(vs.begin(), vs.end(), j))
          co += static_cast<double>(rank_of(p, n, q, static_cast<std::size_t>(j))) - k;
      tsum[a] = tr, csum[a] = co;
      for (std::size_t b = 0; b < s; ++b) {
        qd[a * s + b] = std::sqrt(static_cast<double>(d[queries[b]]));
        qp[a * s + b] = std::sqrt(static_cast<double>(p[queries[b]]));
      }
    });
  }
  Quality r;
  r.k = k, r.queries = s, r.sampled = sampled;
  const double nn = static_cast<double>(n), kk = k;
  const double norm = 2.0 / (nn * kk * (2.0 * nn - 3.0 * kk - 1.0)) * (nn / static_cast<double>(s));
  r.trustworthiness = 1.0 - norm * std::accumulate(tsum.begin(), tsum.end(), 0.0);
  r.continuity = 1.0 - norm * std::accumulate(csum.begin(), csum.end(), 0.0);
  r.neighborhood_preservation = std::accumulate(npsum.begin(), npsum.end(), 0.0) / static_cast<double>(s);
  // Pairs a < b of the queries: symmetrised (the float rows of a and b may differ in the last bit).
  std::vector<double> pd_, pp_;
  pd_.reserve(s * (s - 1) / 2), pp_.reserve(s * (s - 1) / 2);
  double sdd = 0, sdp = 0, spp = 0;
  for (std::size_t a = 0; a < s; ++a)
    for (std::size_t b = a + 1; b < s; ++b) {
      const double x = 0.5 * (qd[a * s + b] + qd[b * s + a]), y = 0.5 * (qp[a * s + b] + qp[b * s + a]);
      pd_.push_back(x), pp_.push_back(y);
      sdd += x * x, sdp += x * y, spp += y * y;
    }
  // Optimal scale α = Σd·d̂ / Σd̂²: stress after it is Σd² − (Σd·d̂)²/Σd̂², over Σd².
  if (sdd <= 0)
    r.stress = 0;
  else if (spp <= 0)
    r.stress = 1;
  else {
    double num = 0;
    const double alpha = sdp / spp;
    for (std::size_t e = 0; e < pd_.size(); ++e) num += (pd_[e] - alpha * pp_[e]) * (pd_[e] - alpha * pp_[e]);
    r.stress = num / sdd;
  }
  r.shepard = pd_.empty() ? 0.0 : pearson(average_ranks(pd_), average_ranks(pp_));
  return r;
}

}  // namespace

Quality quality_ref(const Table& t, const std::vector<double>& xy, const QualityOptions& o) {
  check(t, xy, o);
  bool sampled = false;
  const std::vector<std::size_t> queries = query_rows(t, o, sampled);
  const std::size_t n = t.rows;
  Quality r =
      evaluate<double>(t, o, queries, sampled,
                       [&](std::size_t q0, std::size_t q1, std::vector<double>& dd, std::vector<double>& pd) {
                         dd.resize((q1 - q0) * n), pd.resize((q1 - q0) * n);
                         tbb::parallel_for(q0, q1, [&](std::size_t a) {
                           const float* x = t.row(queries[a]);
                           const double qx = xy[2 * queries[a]], qy = xy[2 * queries[a] + 1];
                           for (std::size_t j = 0; j < n; ++j) {
                             const float* y = t.row(j);
                             double s = 0;
                             for (std::size_t c = 0; c < t.cols; ++c) {
                               const double v = static_cast<double>(x[c]) - y[c];
                               s += v * v;
                             }
                             dd[(a - q0) * n + j] = s;
                             const double ex = qx - xy[2 * j], ey = qy - xy[2 * j + 1];
                             pd[(a - q0) * n + j] = ex * ex + ey * ey;
                           }
                         });
                       });
  r.path = "cpu";
  return r;
}

Quality quality(const Table& t, const std::vector<double>& xy, const QualityOptions& o) {
  check(t, xy, o);
  Quality r;
  ocl::dispatch(
      "projection_quality", o.backend, ocl::device_is_gpu() && t.rows >= 2000,
      [&]() -> std::string {
        bool sampled = false;
        const std::vector<std::size_t> queries = query_rows(t, o, sampled);
        const std::size_t n = t.rows, d = t.cols;
        std::vector<float> yf(xy.begin(), xy.end()), qx, qy;
        std::string why;
        Quality q = evaluate<float>(
            t, o, queries, sampled,
            [&](std::size_t q0, std::size_t q1, std::vector<float>& dd, std::vector<float>& pd) {
              const std::size_t m = q1 - q0;
              dd.resize(m * n), pd.resize(m * n);
              qx.resize(m * d), qy.resize(m * 2);
              for (std::size_t a = q0; a < q1; ++a) {
                std::copy_n(t.row(queries[a]), d, qx.data() + (a - q0) * d);
                std::copy_n(yf.data() + 2 * queries[a], 2, qy.data() + (a - q0) * 2);
              }
              if (why.empty())
                why = ocl::projection_sqdist_ocl(qx.data(), m, t.values.data(), n, d, false, dd.data());
              if (why.empty())
                why = ocl::projection_sqdist_ocl(qy.data(), m, yf.data(), n, 2, false, pd.data());
            });
        if (!why.empty()) return why;
        q.path = "opencl";
        r = q;
        return {};
      },
      [&] { r = quality_ref(t, xy, o); });
  return r;
}

}  // namespace trailscope::projection
