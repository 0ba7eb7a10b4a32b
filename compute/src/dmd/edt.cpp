#include "dmd/edt.hpp"

#include <algorithm>
#include <cstdlib>

namespace trailscope::dmd::detail {
namespace {

constexpr std::int64_t kAbsent = std::numeric_limits<std::int64_t>::max();

// Lower envelope of the parabolas (x - q)^2 + f[q] over the q with f[q] != kAbsent, evaluated at
// x = 0 .. n-1: out[x] = min_q ((x - q)^2 + f[q]) (kAbsent if no parabola), arg[x] = its q (-1).
// f may be negative (the reverse transform). The scratch vectors are the envelope's parabola
// positions v and the boundaries z between them, reused across rows to avoid allocations.
struct Envelope {
  std::vector<int> v;
  std::vector<double> g;  // f[v[k]] + v[k]^2: the parabola's value terms, computed once
  std::vector<double> z;

  void run(const std::int64_t* f, int n, std::int64_t* out, int* arg) {
    v.resize(n);
    g.resize(n);
    z.resize(n + 1);
    int k = -1;
    for (int q = 0; q < n; ++q) {
      if (f[q] == kAbsent) continue;
      const double gq = static_cast<double>(f[q]) + static_cast<double>(q) * q;
      double s = 0;
      while (k >= 0) {
        s = (gq - g[k]) / (2.0 * (q - v[k]));  // where parabola q starts to undercut parabola v[k]
        if (s > z[k]) break;
        --k;  // parabola v[k] is nowhere lowest any more
      }
      ++k;
      v[k] = q;
      g[k] = gq;
      z[k] = k == 0 ? -std::numeric_limits<double>::infinity() : s;
      z[k + 1] = std::numeric_limits<double>::infinity();
    }
    if (k < 0) {
      std::fill(out, out + n, kAbsent);
      if (arg) std::fill(arg, arg + n, -1);
      return;
    }
    int j = 0;
    for (int x = 0; x < n; ++x) {
      while (z[j + 1] < x) ++j;
      const std::int64_t d = x - v[j];
      out[x] = d * d + f[v[j]];  // exact: the envelope only picks the parabola, integers give the value
      if (arg) arg[x] = v[j];
    }
  }
};

}  // namespace

void distance_transform(const std::uint8_t* site, int w, int h, std::vector<std::int32_t>& squared,
                        std::vector<std::int32_t>* nearest) {
  const std::size_t n = static_cast<std::size_t>(w) * h;
  // Column pass: the distance to the nearest site in the same column, and that site's row for the
  // feature transform. Swept a row at a time (the last site above, then the next below, per column)
  // so that memory is read in order: column-at-a-time sweeps miss the cache on every pixel.
  // Scratch reused across calls on a thread: fresh multi-100-kB buffers per layer cost page faults.
  thread_local std::vector<std::int32_t> col_dist, col_row;
  col_dist.resize(n);
  col_row.resize(n);
  constexpr std::int32_t kNone = -1;
  std::vector<std::int32_t> last(w, kNone);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* s = site + static_cast<std::size_t>(y) * w;
    std::int32_t* row = &col_row[static_cast<std::size_t>(y) * w];
    for (int x = 0; x < w; ++x) {
      if (s[x]) last[x] = y;
      row[x] = last[x];
    }
  }
  std::fill(last.begin(), last.end(), kNone);  // now: the next site below
  for (int y = h - 1; y >= 0; --y) {
    const std::uint8_t* s = site + static_cast<std::size_t>(y) * w;
    std::int32_t* row = &col_row[static_cast<std::size_t>(y) * w];
    std::int32_t* dist = &col_dist[static_cast<std::size_t>(y) * w];
    for (int x = 0; x < w; ++x) {
      if (s[x]) last[x] = y;
      const std::int32_t up = row[x], down = last[x];
      const std::int32_t best = (down != kNone && (up == kNone || down - y < y - up)) ? down : up;
      row[x] = best;
      dist[x] = best == kNone ? kNone : std::abs(y - best);
    }
  }
  // Row pass: min over columns q of (x - q)^2 + col_dist(q)^2.
  squared.resize(n);
  if (nearest) nearest->resize(n);
  thread_local std::vector<std::int64_t> f, out;
  thread_local std::vector<int> arg;
  thread_local Envelope env;
  f.resize(w);
  out.resize(w);
  arg.resize(w);
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      const std::int32_t d = col_dist[row + x];
      f[x] = d == kNone ? kAbsent : static_cast<std::int64_t>(d) * d;
    }
    env.run(f.data(), w, out.data(), arg.data());
    for (int x = 0; x < w; ++x) {
      if (out[x] == kAbsent) {
        squared[row + x] = kNoSite;
        if (nearest) (*nearest)[row + x] = -1;
        continue;
      }
      squared[row + x] = static_cast<std::int32_t>(out[x]);
      if (nearest) {
        const int q = arg[x];
        (*nearest)[row + x] = col_row[row + q] * w + q;
      }
    }
  }
}

void union_of_disks(const std::int32_t* radius2, int w, int h, std::vector<std::uint8_t>& covered) {
  const std::size_t n = static_cast<std::size_t>(w) * h;
  // max_c (r2(c) - |i - c|^2) = -min_c (|i - c|^2 - r2(c)): a lower envelope with f = -r2, first
  // down each column (c in that column), then along each row over the column results.
  thread_local std::vector<std::int64_t> col, f, out;
  thread_local Envelope env;
  col.resize(n);
  f.resize(std::max(w, h));
  out.resize(std::max(w, h));
  for (int x = 0; x < w; ++x) {
    for (int y = 0; y < h; ++y) {
      const std::int32_t r2 = radius2[static_cast<std::size_t>(y) * w + x];
      f[y] = r2 > 0 ? -static_cast<std::int64_t>(r2) : kAbsent;
    }
    env.run(f.data(), h, out.data(), nullptr);
    for (int y = 0; y < h; ++y) col[static_cast<std::size_t>(y) * w + x] = out[y];
  }
  covered.resize(n);
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * w;
    env.run(&col[row], w, out.data(), nullptr);
    for (int x = 0; x < w; ++x) covered[row + x] = out[x] != kAbsent && out[x] < 0;
  }
}

}  // namespace trailscope::dmd::detail
