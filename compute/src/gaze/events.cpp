// Fixation / saccade / glissade detection (events.hpp): I-VT, I-DT, and the adaptive velocity threshold.
#include "trailscope/gaze/events.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::gaze {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void in_range(double v, double lo, double hi, bool lo_open, const char* name) {
  if (!std::isfinite(v) || v > hi || (lo_open ? v <= lo : v < lo))
    throw invalid_argument(name, std::string(name) + " must be in " + (lo_open ? "(" : "[") +
                                     format_double(lo) + ", " + format_double(hi) + "], not " +
                                     format_double(v));
}

double median_step(const std::vector<double>& t) {
  std::vector<double> d;
  d.reserve(t.size());
  for (std::size_t i = 1; i < t.size(); ++i)
    if (t[i] > t[i - 1]) d.push_back(t[i] - t[i - 1]);
  if (d.empty()) return 1;
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2];
}

/// Fixation runs shorter than `min_ms` -> none.
void drop_short(std::vector<EventType>& l, const std::vector<double>& t, EventType type, double min_ms) {
  if (min_ms <= 0) return;
  const double step = median_step(t);
  for (std::size_t i = 0; i < l.size();) {
    if (l[i] != type) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < l.size() && l[j + 1] == type) ++j;
    // A run's duration includes its last sample's own period (n samples last n steps).
    if (t[j] - t[i] + step < min_ms - 1e-9)
      for (std::size_t k = i; k <= j; ++k) l[k] = EventType::none;
    i = j + 1;
  }
}

// --- I-VT ---------------------------------------------------------------------------------------------

std::vector<EventType> ivt(const Recording& r, const std::vector<double>& x, const std::vector<double>& y,
                           const IvtParams& p, const std::vector<double>& v) {
  std::vector<EventType> l(r.size(), EventType::none);
  for (std::size_t i = 0; i < l.size(); ++i)
    l[i] = !r.valid[i] || !std::isfinite(v[i]) ? EventType::blink
           : v[i] > p.velocity_threshold_deg_s ? EventType::saccade
                                               : EventType::fixation;
  (void)x, (void)y;
  drop_short(l, r.t_ms, EventType::fixation, p.min_fixation_ms);
  return l;
}

// --- I-DT ---------------------------------------------------------------------------------------------

std::vector<EventType> idt(const Recording& r, const std::vector<double>& x, const std::vector<double>& y,
                           const IdtParams& p) {
  const std::size_t n = r.size();
  std::vector<EventType> l(n, EventType::saccade);
  for (std::size_t i = 0; i < n; ++i)
    if (!r.valid[i]) l[i] = EventType::blink;
  const double step = median_step(r.t_ms);
  if (p.min_duration_ms / step > double(limits::kMaxGazeWindowSamples))
    throw invalid_argument("min_duration_ms", "an I-DT window of " + format_double(p.min_duration_ms) +
                                                  " ms holds more than limits::kMaxGazeWindowSamples (" +
                                                  std::to_string(limits::kMaxGazeWindowSamples) +
                                                  ") samples");
  // Salvucci and Goldberg's loop in O(n): times do not decrease (detect_events checks), so the end of the
  // initial window only moves forward, and the window's x/y extremes come from monotonic deques of indices
  // (front = extreme of [lo, hi)), whose two ends only move forward too.
  std::vector<std::size_t> next_invalid(n + 1, n);
  for (std::size_t k = n; k-- > 0;) next_invalid[k] = r.valid[k] ? next_invalid[k + 1] : k;
  std::deque<std::size_t> xmax, xmin, ymax, ymin;
  std::size_t hi = 0, lo = 0;  // samples [lo, hi) are in the deques
  const auto push = [&](std::size_t k) {
    const auto put = [&](std::deque<std::size_t>& d, const std::vector<double>& v, bool greater) {
      while (!d.empty() && (greater ? v[d.back()] <= v[k] : v[d.back()] >= v[k])) d.pop_back();
      d.push_back(k);
    };
    put(xmax, x, true), put(xmin, x, false), put(ymax, y, true), put(ymin, y, false);
  };
  const auto move_lo = [&](std::size_t to) {
    lo = to;
    for (auto* d : {&xmax, &xmin, &ymax, &ymin})
      while (!d->empty() && d->front() < lo) d->pop_front();
    if (hi < lo) hi = lo;
  };
  const auto dispersion = [&](std::size_t extra) {  // of [lo, hi) plus sample `extra` (n: none)
    double a0 = x[xmin.front()], a1 = x[xmax.front()], b0 = y[ymin.front()], b1 = y[ymax.front()];
    if (extra < n)
      a0 = std::min(a0, x[extra]), a1 = std::max(a1, x[extra]), b0 = std::min(b0, y[extra]),
      b1 = std::max(b1, y[extra]);
    return (a1 - a0) + (b1 - b0);
  };
  std::size_t i = 0, end = 0;  // end: first sample that closes the initial window of i
  while (i < n) {
    if (!r.valid[i]) {
      ++i;
      continue;
    }
    end = std::max(end, i);
    while (end < n && r.t_ms[end] - r.t_ms[i] + step < p.min_duration_ms - 1e-9) ++end;
    if (end >= n) break;           // no full window left: the rest stays saccade
    if (next_invalid[i] <= end) {  // every window starting before the gap contains it
      i = next_invalid[i];
      continue;
    }
    move_lo(i);
    while (hi <= end) push(hi++);
    if (dispersion(n) > p.dispersion_threshold_deg) {
      ++i;  // i stays a saccade sample
      continue;
    }
    std::size_t j = end;
    while (j + 1 < n && r.valid[j + 1] && dispersion(j + 1) <= p.dispersion_threshold_deg) push(hi++), ++j;
    for (std::size_t k = i; k <= j; ++k) l[k] = EventType::fixation;
    i = j + 1;
  }
  return l;
}

// --- adaptive (Nystrom and Holmqvist 2010) ------------------------------------------------------------

/// Savitzky-Golay first derivative: the slope of a least-squares line through the valid samples within
/// m samples of i (a quadratic fit's derivative at the centre of a symmetric window equals this slope, so
/// inside a recording this is the order-2 filter of Nystrom and Holmqvist); at the ends and next to
/// invalid samples the window is the one-sided part that exists. Speed = |(vx, vy)|; NaN when i has no
/// valid neighbour.
std::vector<double> sg_velocity(const Recording& r, const std::vector<double>& x,
                                const std::vector<double>& y, std::size_t m, double dt_ms) {
  const std::size_t n = r.size();
  std::vector<double> v(n, kNaN);
  for (std::size_t i = 0; i < n; ++i) {
    if (!r.valid[i]) continue;
    std::size_t a = i, b = i;
    while (a > 0 && i - a < m && r.valid[a - 1]) --a;
    while (b + 1 < n && b - i < m && r.valid[b + 1]) ++b;
    if (a == b) continue;
    const double kc = (double(a) + double(b)) / 2;
    double sx = 0, sy = 0, kk = 0;
    for (std::size_t k = a; k <= b; ++k) {
      const double d = double(k) - kc;
      sx += d * x[k], sy += d * y[k], kk += d * d;
    }
    v[i] = std::hypot(sx, sy) / kk / (dt_ms / 1000.0);
  }
  return v;
}

std::vector<EventType> adaptive(const Recording& r, const std::vector<double>& x,
                                const std::vector<double>& y, const AdaptiveParams& p, double& pt_out,
                                double& onset_out) {
  const std::size_t n = r.size();
  const double dt = median_step(r.t_ms);
  // Both windows in samples are bounded: a recording with a tiny time step must not make them huge.
  for (const auto& [ms, name] : {std::pair{p.filter_window_ms, "filter_window_ms"},
                                 std::pair{p.glissade_window_ms, "glissade_window_ms"}})
    if (ms / dt > double(limits::kMaxGazeWindowSamples))
      throw invalid_argument(name, std::string(name) + " of " + format_double(ms) + " ms holds more than " +
                                       "limits::kMaxGazeWindowSamples (" +
                                       std::to_string(limits::kMaxGazeWindowSamples) + ") samples");
  const std::size_t m = std::max<std::size_t>(1, std::size_t(std::lround(p.filter_window_ms / dt / 2)));
  std::vector<double> v = sg_velocity(r, x, y, m, dt);
  std::vector<EventType> l(n, EventType::none);
  // Noise (Nystrom and Holmqvist: beyond what an eye can do): speed over max_velocity, or an acceleration
  // (central difference of the speed) over max_acceleration; such samples are left out like lost ones.
  std::vector<bool> noise(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    if (!r.valid[i] || !(v[i] <= p.max_velocity_deg_s)) {
      noise[i] = true;
      continue;
    }
    const std::size_t a = i > 0 && std::isfinite(v[i - 1]) ? i - 1 : i;
    const std::size_t b = i + 1 < n && std::isfinite(v[i + 1]) ? i + 1 : i;
    if (a != b && std::abs(v[b] - v[a]) / (double(b - a) * dt / 1000.0) > p.max_acceleration_deg_s2)
      noise[i] = true;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (noise[i]) l[i] = EventType::blink, v[i] = kNaN;
  // Peak threshold: PT <- mean + 6 sd of the velocities below PT, until it moves < 1 deg/s.
  double pt = p.initial_peak_threshold_deg_s, mean = 0, sd = 0;
  for (int it = 0; it < 100; ++it) {
    double s = 0, s2 = 0;
    std::size_t c = 0;
    for (double vi : v)
      if (vi < pt) s += vi, s2 += vi * vi, ++c;
    if (c < 2) break;
    mean = s / double(c);
    sd = std::sqrt(std::max(0.0, s2 / double(c) - mean * mean));
    const double next = mean + 6 * sd;
    const bool done = std::abs(next - pt) < 1;
    pt = next;
    if (done) break;
  }
  const double onset = mean + 3 * sd;
  pt_out = pt, onset_out = onset;
  const auto ok = [&](std::size_t i) { return std::isfinite(v[i]); };
  // Prefix sums of the speeds (and squares, counts) for the local noise before each saccade in O(1).
  std::vector<double> cs(n + 1, 0), cs2(n + 1, 0), cc(n + 1, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const bool f = ok(k);
    cs[k + 1] = cs[k] + (f ? v[k] : 0), cs2[k + 1] = cs2[k] + (f ? v[k] * v[k] : 0), cc[k + 1] = cc[k] + f;
  }
  const std::size_t win = std::max<std::size_t>(1, std::size_t(std::lround(p.glissade_window_ms / dt)));
  std::size_t i = 0;
  while (i < n) {
    if (!ok(i) || v[i] <= pt || l[i] != EventType::none) {
      ++i;
      continue;
    }
    // Onset: walk back while above the onset threshold or still falling backwards.
    std::size_t s = i;
    while (s > 0 && ok(s - 1) && l[s - 1] == EventType::none && (v[s] > onset || v[s - 1] < v[s])) --s;
    // Local noise before the onset (the glissade window's length): the offset threshold.
    const std::size_t w0 = s >= win ? s - win : 0;
    const double ls = cs[s] - cs[w0], ls2 = cs2[s] - cs2[w0], lc = cc[s] - cc[w0];
    const double local =
        lc >= 2 ? ls / lc + 3 * std::sqrt(std::max(0.0, ls2 / lc - (ls / lc) * (ls / lc))) : onset;
    const double off_thr = 0.7 * onset + 0.3 * local;
    std::size_t e = i;
    while (e + 1 < n && ok(e + 1) && (v[e] > off_thr || v[e + 1] < v[e])) ++e;
    const bool long_enough = r.t_ms[e] - r.t_ms[s] + dt >= p.min_saccade_ms - 1e-9;
    if (long_enough)
      for (std::size_t k = s; k <= e; ++k) l[k] = EventType::saccade;
    // Glissade: samples above the offset threshold within the window after the offset, up to the last
    // such sample and then down to the next local velocity minimum.
    std::size_t g_end = e;
    if (long_enough) {
      for (std::size_t k = e + 1; k < n && k <= e + win && ok(k); ++k)
        if (v[k] > off_thr) g_end = k;
      if (g_end > e) {
        while (g_end + 1 < n && ok(g_end + 1) && v[g_end + 1] < v[g_end]) ++g_end;
        for (std::size_t k = e + 1; k <= g_end; ++k)
          if (l[k] == EventType::none) l[k] = EventType::pso;
      }
    }
    i = g_end + 1;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (l[k] == EventType::none && ok(k)) l[k] = EventType::fixation;
  drop_short(l, r.t_ms, EventType::fixation, p.min_fixation_ms);
  return l;
}

}  // namespace

const char* to_string(Method m) noexcept {
  return m == Method::idt ? "idt" : m == Method::adaptive ? "adaptive" : "ivt";
}

Method parse_method(std::string_view text, const std::string& param) {
  if (text == "ivt") return Method::ivt;
  if (text == "idt") return Method::idt;
  if (text == "adaptive") return Method::adaptive;
  throw invalid_argument(param, "method must be ivt, idt or adaptive, not \"" + std::string(text) + "\"");
}

void validate(const EventParams& p) {
  in_range(p.ivt.velocity_threshold_deg_s, 0, 5000, true, "velocity_threshold_deg_s");
  in_range(p.ivt.min_fixation_ms, 0, 10000, false, "min_fixation_ms");
  in_range(p.idt.dispersion_threshold_deg, 0, 100, true, "dispersion_threshold_deg");
  in_range(p.idt.min_duration_ms, 0, 10000, true, "min_duration_ms");
  in_range(p.adaptive.initial_peak_threshold_deg_s, 0, 1000, true, "initial_peak_threshold_deg_s");
  in_range(p.adaptive.filter_window_ms, 0, 1000, true, "filter_window_ms");
  in_range(p.adaptive.min_saccade_ms, 0, 1000, false, "min_saccade_ms");
  in_range(p.adaptive.min_fixation_ms, 0, 10000, false, "min_fixation_ms");
  in_range(p.adaptive.glissade_window_ms, 0, 1000, false, "glissade_window_ms");
  in_range(p.adaptive.max_velocity_deg_s, 0, 10000, true, "max_velocity_deg_s");
  in_range(p.adaptive.max_acceleration_deg_s2, 0, 10000000, true, "max_acceleration_deg_s2");
}

std::vector<double> point_velocity(const std::vector<double>& t, const std::vector<double>& x,
                                   const std::vector<double>& y, const std::vector<std::uint8_t>& valid) {
  const std::size_t n = t.size();
  std::vector<double> v(n, kNaN);
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    const std::size_t a = i > 0 && valid[i - 1] ? i - 1 : i;
    const std::size_t b = i + 1 < n && valid[i + 1] ? i + 1 : i;
    if (a == b || !(t[b] > t[a])) continue;
    v[i] = std::hypot(x[b] - x[a], y[b] - y[a]) / ((t[b] - t[a]) / 1000.0);
  }
  return v;
}

Detection detect_events(const Recording& r, const EventParams& p) {
  validate(p);
  for (std::size_t k = 0; k < r.size(); ++k)
    if (!std::isfinite(r.t_ms[k]) || (k > 0 && r.t_ms[k] < r.t_ms[k - 1]))
      throw Error(Error::Kind::unprocessable, "file",
                  "sample times must be finite and must not decrease; sample " + std::to_string(k) +
                      " is at " + format_double(r.t_ms[k]) + " ms after " +
                      format_double(k > 0 ? r.t_ms[k - 1] : 0) + " ms");
  std::vector<double> x, y;
  r.degrees(x, y);
  Detection d;
  switch (p.method) {
    case Method::ivt:
      d.labels = ivt(r, x, y, p.ivt, point_velocity(r.t_ms, x, y, r.valid));
      d.peak_threshold_deg_s = d.onset_threshold_deg_s = p.ivt.velocity_threshold_deg_s;
      break;
    case Method::idt:
      d.labels = idt(r, x, y, p.idt);
      d.peak_threshold_deg_s = d.onset_threshold_deg_s = kNaN;
      break;
    case Method::adaptive:
      d.labels = adaptive(r, x, y, p.adaptive, d.peak_threshold_deg_s, d.onset_threshold_deg_s);
      break;
  }
  d.events = label_runs(r.t_ms, d.labels);
  return d;
}

std::vector<GazeEvent> label_runs(const std::vector<double>& t, const std::vector<EventType>& l) {
  std::vector<GazeEvent> out;
  for (std::size_t i = 0; i < l.size();) {
    std::size_t j = i;
    while (j + 1 < l.size() && l[j + 1] == l[i]) ++j;
    if (l[i] != EventType::none) out.push_back({l[i], 0, t[i], t[j]});
    i = j + 1;
  }
  return out;
}

double cohen_kappa(const std::vector<EventType>& a, const std::vector<EventType>& b, EventType type) {
  if (a.size() != b.size() || a.empty()) return kNaN;
  double both = 0, only_a = 0, only_b = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const bool x = a[i] == type, y = b[i] == type;
    both += x && y, only_a += x && !y, only_b += !x && y;
  }
  const double n = double(a.size());
  const double neither = n - both - only_a - only_b;
  const double po = (both + neither) / n;
  const double pa = (both + only_a) / n, pb = (both + only_b) / n;
  const double pe = pa * pb + (1 - pa) * (1 - pb);
  if (pe >= 1) return kNaN;
  return (po - pe) / (1 - pe);
}

}  // namespace trailscope::gaze
