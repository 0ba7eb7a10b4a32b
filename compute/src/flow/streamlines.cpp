// Evenly spaced streamlines after Jobard and Lefer (EG Workshop on Visualization in Scientific Computing,
// 1997); see streamlines.hpp for exactly what is traced.
#include "trailscope/flow/streamlines.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <deque>
#include <numeric>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::flow {
namespace {

struct Vec {
  double x = 0, y = 0;
};

/// The field at a point: bilinear (sx, sy, w) from the cell centres, indices clamped to the grid.
struct Sampler {
  const SectorField& f;
  int nx, ny;
  struct Value {
    double sx, sy, w;
  };
  Value at(double x, double y) const {
    const double fx = std::clamp(x - 0.5, 0.0, nx - 1.0), fy = std::clamp(y - 0.5, 0.0, ny - 1.0);
    const int i0 = std::min(static_cast<int>(fx), nx - 2 < 0 ? 0 : nx - 2);
    const int j0 = std::min(static_cast<int>(fy), ny - 2 < 0 ? 0 : ny - 2);
    const int i1 = std::min(i0 + 1, nx - 1), j1 = std::min(j0 + 1, ny - 1);
    const double ax = fx - i0, ay = fy - j0;
    const auto v = [&](const std::vector<float>& a) {
      const double c00 = a[static_cast<std::size_t>(j0) * nx + i0],
                   c10 = a[static_cast<std::size_t>(j0) * nx + i1];
      const double c01 = a[static_cast<std::size_t>(j1) * nx + i0],
                   c11 = a[static_cast<std::size_t>(j1) * nx + i1];
      return (1 - ay) * ((1 - ax) * c00 + ax * c10) + ay * ((1 - ax) * c01 + ax * c11);
    };
    return {v(f.sx), v(f.sy), v(f.w)};
  }
};

/// Points of accepted lines in buckets of d_sep cells, for the distance tests.
class PointGrid {
 public:
  PointGrid(int nx, int ny, double cell) : cell_(cell) {
    bx_ = std::max(1, static_cast<int>(std::ceil(nx / cell)) + 1);
    by_ = std::max(1, static_cast<int>(std::ceil(ny / cell)) + 1);
    buckets_.resize(static_cast<std::size_t>(bx_) * by_);
  }
  void add(Vec p) { buckets_[bucket(p)].push_back(p); }
  /// Some stored point is closer than r (r <= cell).
  bool any_within(Vec p, double r) const {
    const int bi = std::clamp(static_cast<int>(p.x / cell_), 0, bx_ - 1);
    const int bj = std::clamp(static_cast<int>(p.y / cell_), 0, by_ - 1);
    const double r2 = r * r;
    for (int j = std::max(0, bj - 1); j <= std::min(by_ - 1, bj + 1); ++j)
      for (int i = std::max(0, bi - 1); i <= std::min(bx_ - 1, bi + 1); ++i)
        for (const Vec& q : buckets_[static_cast<std::size_t>(j) * bx_ + i]) {
          const double dx = q.x - p.x, dy = q.y - p.y;
          if (dx * dx + dy * dy < r2) return true;
        }
    return false;
  }

 private:
  std::size_t bucket(Vec p) const {
    const int i = std::clamp(static_cast<int>(p.x / cell_), 0, bx_ - 1);
    const int j = std::clamp(static_cast<int>(p.y / cell_), 0, by_ - 1);
    return static_cast<std::size_t>(j) * bx_ + i;
  }
  double cell_;
  int bx_, by_;
  std::vector<std::vector<Vec>> buckets_;
};

class Tracer {
 public:
  Tracer(const SectorField& f, int nx, int ny, const StreamlineParams& p)
      : s_{f, nx, ny}, p_(p), nx_(nx), ny_(ny), d_test_(p.d_test * p.d_sep), grid_(nx, ny, p.d_sep) {}

  /// The flow is defined at p: inside the domain, traffic and coherence above their thresholds.
  bool flows(Vec p) const {
    if (!(p.x >= 0.5 && p.x <= nx_ - 0.5 && p.y >= 0.5 && p.y <= ny_ - 0.5)) return false;
    const auto v = s_.at(p.x, p.y);
    if (!(v.w >= p_.min_traffic) || !(v.w > 0)) return false;
    return std::hypot(v.sx, v.sy) >= p_.min_coherence * v.w && (v.sx != 0 || v.sy != 0);
  }
  bool seed_ok(Vec p) const { return flows(p) && !grid_.any_within(p, p_.d_sep); }

  /// Unit direction at p (false where there is none).
  bool dir(Vec p, Vec& d) const {
    const auto v = s_.at(p.x, p.y);
    const double m = std::hypot(v.sx, v.sy);
    if (!(m > 0)) return false;
    d = {v.sx / m, v.sy / m};
    return true;
  }

  /// One Runge–Kutta step of length h (signed) from p.
  bool step(Vec p, double h, Vec& out) const {
    Vec k1, k2, k3, k4;
    if (!dir(p, k1)) return false;
    if (p_.integrator == Integrator::rk2) {
      if (!dir({p.x + 0.5 * h * k1.x, p.y + 0.5 * h * k1.y}, k2)) return false;
      out = {p.x + h * k2.x, p.y + h * k2.y};
      return true;
    }
    if (!dir({p.x + 0.5 * h * k1.x, p.y + 0.5 * h * k1.y}, k2)) return false;
    if (!dir({p.x + 0.5 * h * k2.x, p.y + 0.5 * h * k2.y}, k3)) return false;
    if (!dir({p.x + h * k3.x, p.y + h * k3.y}, k4)) return false;
    out = {p.x + h / 6 * (k1.x + 2 * k2.x + 2 * k3.x + k4.x),
           p.y + h / 6 * (k1.y + 2 * k2.y + 2 * k3.y + k4.y)};
    return true;
  }

  /// One half of a line from the seed (excluded) with step h; `own` holds the other half's points.
  void half(Vec seed, double h, const std::vector<Vec>& own, std::vector<Vec>& pts) const {
    Vec p = seed, prev_d{0, 0};
    const double back = 3 * d_test_;
    const double r2 = d_test_ * d_test_;
    // The line so far: `own` (reached from the seed the other way, so far back in arc length only beyond
    // the seed) and `pts`. Arc length of pts[k] from the seed is (k+1)·step; of own[k], (k+1)·step too.
    while (pts.size() + own.size() + 1 < static_cast<std::size_t>(p_.max_line_points)) {
      Vec q;
      if (!step(p, h, q) || !flows(q)) break;
      const Vec d{q.x - p.x, q.y - p.y};
      if (d.x * prev_d.x + d.y * prev_d.y < 0) break;
      if (grid_.any_within(q, d_test_)) break;
      // Own line: points more than 3·d_test of arc length back.
      const double arc = (pts.size() + 1) * std::abs(h);
      bool closes = false;
      const std::size_t skip = static_cast<std::size_t>(std::ceil(back / std::abs(h)));
      for (std::size_t k = 0; k + skip < pts.size() && !closes; ++k) {
        const double dx = pts[k].x - q.x, dy = pts[k].y - q.y;
        closes = dx * dx + dy * dy < r2;
      }
      if (arc > back) {  // the seed and the other half are all at least `arc` back
        const double dx = seed.x - q.x, dy = seed.y - q.y;
        closes = closes || dx * dx + dy * dy < r2;
      }
      for (std::size_t k = 0; k < own.size() && !closes; ++k) {
        const double dx = own[k].x - q.x, dy = own[k].y - q.y;
        closes = dx * dx + dy * dy < r2 && arc + (k + 1) * std::abs(h) > back;
      }
      if (closes) break;
      pts.push_back(q);
      prev_d = d;
      p = q;
    }
  }

  /// The line through `seed`, in flow order (empty when too short).
  std::vector<Vec> line(Vec seed) const {
    std::vector<Vec> fwd, bwd;
    half(seed, p_.step, {}, fwd);
    half(seed, -p_.step, fwd, bwd);
    std::vector<Vec> out;
    out.reserve(fwd.size() + bwd.size() + 1);
    out.insert(out.end(), bwd.rbegin(), bwd.rend());
    out.push_back(seed);
    out.insert(out.end(), fwd.begin(), fwd.end());
    if ((out.size() - 1) * p_.step < p_.min_length || out.size() < 2) out.clear();
    return out;
  }

  void accept(const std::vector<Vec>& l) {
    for (const Vec& p : l) grid_.add(p);
  }
  double traffic(Vec p) const { return s_.at(p.x, p.y).w; }

 private:
  Sampler s_;
  const StreamlineParams& p_;
  int nx_, ny_;
  double d_test_;
  PointGrid grid_;
};

double number(std::string_view name, std::string_view text) {
  double v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc{} || r.ptr != text.data() + text.size() || !std::isfinite(v))
    throw invalid_argument(std::string(name),
                           std::string(name) + " must be a number, got '" + std::string(text) + "'");
  return v;
}

}  // namespace

void StreamlineParams::validate() const {
  const auto range = [](const char* name, double v, double lo, double hi, const std::string& unit) {
    if (!(v >= lo && v <= hi))
      throw invalid_argument(name, std::string(name) + " must be in [" + format_double(lo) + ", " +
                                       format_double(hi) + "]" + unit);
  };
  range("d_sep", d_sep, 0.5, 64, " cells");
  range("d_test", d_test, 0.1, 1, " (fraction of d_sep)");
  if (!(step >= 0.05 && step <= d_sep)) throw invalid_argument("step", "step must be in [0.05, d_sep] cells");
  range("min_length", min_length, 0, 1000, " cells");
  if (!(min_traffic >= 0) || !std::isfinite(min_traffic))
    throw invalid_argument("min_traffic", "min_traffic must be a finite number >= 0");
  range("min_coherence", min_coherence, 0, 1, "");
  if (max_line_points < 2 || max_line_points > 100000)
    throw invalid_argument("max_line_points", "max_line_points must be 2..100000");
}

void StreamlineParams::set(std::string_view name, std::string_view value) {
  StreamlineParams p = *this;
  if (name == "d_sep")
    p.d_sep = number(name, value);
  else if (name == "d_test")
    p.d_test = number(name, value);
  else if (name == "step")
    p.step = number(name, value);
  else if (name == "integrator")
    p.integrator = parse_integrator(value);
  else if (name == "min_length")
    p.min_length = number(name, value);
  else if (name == "min_traffic")
    p.min_traffic = number(name, value);
  else if (name == "min_coherence")
    p.min_coherence = number(name, value);
  else if (name == "max_line_points") {
    const double v = number(name, value);
    if (v != std::floor(v)) throw invalid_argument("max_line_points", "max_line_points must be an integer");
    p.max_line_points = static_cast<int>(std::clamp(v, -1.0, 1e9));
  } else
    throw invalid_argument(std::string(name), "unknown streamline parameter '" + std::string(name) + "'");
  p.validate();
  *this = p;
}

double StreamlineParams::max_points(int nx, int ny) const {
  const double dt = d_test * d_sep;
  // Disjoint strips of width d_test around the lines, one point per `step` along each, doubled for the
  // strips' ends and the lines' curvature; plus a line along each border cell.
  return 2.0 * nx * ny / (dt * step) + 2.0 * (nx + ny) / step;
}

const std::vector<ParamInfo>& streamline_parameter_infos() {
  static const std::vector<ParamInfo> infos = [] {
    const StreamlineParams d;
    auto num = [](std::string name, double def, double lo, double hi, std::string unit, std::string help) {
      ParamInfo i =
          describe_param(name, "number", format_double(def),
                         "[" + format_double(lo) + ", " + format_double(hi) + "] " + unit, std::move(help));
      i.unit = std::move(unit), i.default_number = def, i.min = lo, i.max = hi;
      return i;
    };
    std::vector<ParamInfo> v;
    v.push_back(num("d_sep", d.d_sep, 0.5, 64, "cells",
                    "distance between neighbouring streamlines (seed separation)"));
    v.push_back(num("d_test", d.d_test, 0.1, 1, "", "a line stops this fraction of d_sep from another"));
    v.push_back(num("step", d.step, 0.05, 64, "cells", "Runge-Kutta step (arc length); at most d_sep"));
    v.push_back(describe_param("integrator", "enum", "rk4", "rk2, rk4", "Runge-Kutta order"));
    v.push_back(num("min_length", d.min_length, 0, 1000, "cells", "shorter lines are dropped"));
    v.push_back(num("min_traffic", d.min_traffic, 0, 1e9, "flights/cell", "no flow where less traffic"));
    v.push_back(num("min_coherence", d.min_coherence, 0, 1, "", "no flow where directions cancel more"));
    ParamInfo m = num("max_line_points", d.max_line_points, 2, 100000, "points", "longest line");
    m.type = "integer", m.integer = true;
    v.push_back(m);
    return v;
  }();
  return infos;
}

Integrator parse_integrator(std::string_view text, const std::string& param) {
  if (text == "rk2") return Integrator::rk2;
  if (text == "rk4") return Integrator::rk4;
  throw invalid_argument(param, param + " must be rk2 or rk4");
}

const char* to_string(Integrator i) noexcept {
  return i == Integrator::rk2 ? "rk2" : "rk4";
}

Streamlines evenly_spaced_streamlines(const SectorField& field, int nx, int ny,
                                      const StreamlineParams& params, std::size_t max_points,
                                      const CancelToken* cancel) {
  params.validate();
  const std::size_t cells = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  if (nx < 2 || ny < 2 || field.sx.size() != cells || field.sy.size() != cells || field.w.size() != cells)
    throw invalid_argument("field", "a field needs at least 2 × 2 cells and nx · ny values per array");
  Streamlines out;
  Tracer tr(field, nx, ny, params);
  std::deque<std::vector<Vec>> queue;
  std::size_t total = 0;
  const auto add = [&](std::vector<Vec> l) {
    if (l.empty()) return;
    total += l.size();
    if (total > max_points)
      throw Error(Error::Kind::payload_too_large, "d_sep",
                  "the streamlines would have more than " + std::to_string(max_points) +
                      " points (limits::kMaxFlowLinePoints); raise d_sep or step, or use a coarser grid");
    tr.accept(l);
    std::vector<double> xs(l.size()), ys(l.size());
    for (std::size_t k = 0; k < l.size(); ++k) {
      xs[k] = l[k].x, ys[k] = l[k].y;
      out.traffic.push_back(static_cast<float>(tr.traffic(l[k])));
    }
    out.lines.add(xs, ys);
    queue.push_back(std::move(l));
  };
  // Cell centres by decreasing traffic: the first seed, then the seeds of disconnected parts.
  std::vector<std::uint32_t> order(cells);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return field.w[a] > field.w[b]; });
  std::size_t next_cell = 0;
  for (;;) {
    while (!queue.empty()) {
      if (cancel) cancel->throw_if_cancelled();
      const std::vector<Vec> l = std::move(queue.front());
      queue.pop_front();
      for (std::size_t k = 0; k < l.size(); ++k) {
        const Vec a = l[k > 0 ? k - 1 : k], b = l[k + 1 < l.size() ? k + 1 : k];
        double tx = b.x - a.x, ty = b.y - a.y;
        const double m = std::hypot(tx, ty);
        if (!(m > 0)) continue;
        tx /= m, ty /= m;
        for (const double side : {1.0, -1.0}) {
          const Vec c{l[k].x - side * ty * params.d_sep, l[k].y + side * tx * params.d_sep};
          if (tr.seed_ok(c)) add(tr.line(c));
        }
      }
    }
    bool seeded = false;
    while (next_cell < cells && !seeded) {
      const std::uint32_t c = order[next_cell++];
      if (!(field.w[c] >= params.min_traffic) || !(field.w[c] > 0)) {
        next_cell = cells;  // sorted: nothing further has the traffic
        break;
      }
      const Vec p{c % nx + 0.5, c / nx + 0.5};
      if (!tr.seed_ok(p)) continue;
      std::vector<Vec> l = tr.line(p);
      if (l.empty()) continue;
      add(std::move(l));
      seeded = true;
    }
    if (!seeded) break;
  }
  return out;
}

}  // namespace trailscope::flow
