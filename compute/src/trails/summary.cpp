#include "trailscope/trails/summary.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/blocked_range.h>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/trails/export.hpp"
#include "trailscope/trails/partial_reads.hpp"
#include "trailscope/trails/point_filter.hpp"
#include "trailscope/trails/time_index.hpp"

namespace trailscope {

namespace {
constexpr double kFeet = 0.3048;
constexpr double kSpeedBin = SummaryLayout::kSpeedBin;
constexpr int kSpeedBins = SummaryLayout::kSpeedBins;

// Smallest "nice" bin width (seconds) giving at most `bins` bins over `span`.
double nice_bin_seconds(double span, int bins) {
  static constexpr std::array<double, 22> steps = {
      1,    2,    5,    10,    15,    30,    60,    120,    300,    600,     900,
      1800, 3600, 7200, 10800, 21600, 43200, 86400, 172800, 604800, 1209600, 2592000};
  const double want = span / bins;
  for (double s : steps)
    if (s >= want) return s;
  return std::ceil(want / 86400.0) * 86400.0;
}

struct Acc {
  std::uint64_t points = 0;
  double t_min = std::numeric_limits<double>::infinity(), t_max = -std::numeric_limits<double>::infinity();
  std::vector<std::uint64_t> time, alt, speed;
  std::uint64_t speed_n = 0;
  double speed_sum = 0, speed_min = std::numeric_limits<double>::infinity(), speed_max = -speed_min;

  Acc(std::size_t time_bins, std::size_t alt_bins) : time(time_bins), alt(alt_bins), speed(kSpeedBins) {}
  void merge(const Acc& o) {
    points += o.points;
    t_min = std::min(t_min, o.t_min), t_max = std::max(t_max, o.t_max);
    for (std::size_t i = 0; i < time.size(); ++i) time[i] += o.time[i];
    for (std::size_t i = 0; i < alt.size(); ++i) alt[i] += o.alt[i];
    for (std::size_t i = 0; i < speed.size(); ++i) speed[i] += o.speed[i];
    speed_n += o.speed_n, speed_sum += o.speed_sum;
    speed_min = std::min(speed_min, o.speed_min), speed_max = std::max(speed_max, o.speed_max);
  }
};

double percentile(const std::vector<std::uint64_t>& h, std::uint64_t n, double q) {
  if (n == 0) return 0;
  const double target = q * static_cast<double>(n);
  double cum = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (cum + h[i] >= target && h[i] > 0) return (i + (target - cum) / h[i]) * kSpeedBin;
    cum += h[i];
  }
  return h.size() * kSpeedBin;
}

const char* unit_name(AltUnit u) {
  return u == AltUnit::ft ? "ft" : "m";
}
}  // namespace

SummaryLayout summary_layout(const Query& q, const SummaryOptions& opts, double data_t_min, double data_t_max,
                             double top_alt_m) {
  if (opts.bins < 1 || opts.bins > limits::kMaxHistogramBins)
    throw invalid_argument("bins", "bins must lie in 1..1000");
  if (opts.top_callsigns < 0 || opts.top_callsigns > limits::kMaxTopCallsigns)
    throw invalid_argument("top", "top must lie in 0..100");
  SummaryLayout l;
  // Time axis: the window when given, else the data extent.
  double lo = q.t0.value_or(data_t_min), hi = q.t1.value_or(std::nextafter(data_t_max, INFINITY));
  // A one-sided window that ends before the data starts (or starts after it ends) is empty; its
  // histogram is one bin at the edge the client gave.
  if (!(hi > lo)) {
    if (q.t0)
      hi = lo + 1;
    else
      lo = hi - 1;
  }
  l.bin_seconds = nice_bin_seconds(std::max(hi - lo, 1.0), opts.bins);
  l.t_origin = std::floor(lo / l.bin_seconds) * l.bin_seconds;
  // hi > lo >= t_origin, and nice_bin_seconds() keeps the count within opts.bins (+1 for alignment).
  l.time_bins = static_cast<std::size_t>(std::max(1.0, std::ceil((hi - l.t_origin) / l.bin_seconds)));
  const double alt_unit = opts.alt_unit == AltUnit::ft ? kFeet : 1.0;
  l.alt_bin_width = opts.alt_unit == AltUnit::ft ? 1000.0 : 300.0;
  // Altitude bins from 0 to the top of the data (at least one bin); negative altitudes go to bin 0.
  l.alt_bins = static_cast<std::size_t>(std::max(0.0, top_alt_m) / alt_unit / l.alt_bin_width) + 1;
  l.alt_scale = 1.0 / (alt_unit * l.alt_bin_width);
  return l;
}

SummaryCounts::SummaryCounts(const SummaryLayout& l, std::size_t flights)
    : time(l.time_bins), alt(l.alt_bins), speed(SummaryLayout::kSpeedBins), matched(flights, 0) {}

namespace {
// Everything of a summary but its flight count and busiest callsigns.
Summary finish_counts(const SummaryLayout& l, const SummaryOptions& opts, SummaryCounts& total,
                      QualityReport quality) {
  Summary s;
  s.points = total.points;
  if (total.points) s.t_min = total.t_min, s.t_max = total.t_max;
  s.time_histogram = {l.t_origin, l.bin_seconds, std::move(total.time)};
  s.altitude_histogram = {opts.alt_unit, l.alt_bin_width, 0.0, std::move(total.alt)};
  s.speed.count = total.speed_n;
  if (total.speed_n) {
    s.speed.min = total.speed_min, s.speed.max = total.speed_max;
    // Rounded to a micrometre per second (kSpeedMeanPerMs steps of 1 m/s): the sum's order moves only its
    // last bits (summary.hpp). Dividing the whole number of steps gives the double nearest the decimal.
    constexpr double kSpeedMeanPerMs = 1e6;
    s.speed.mean =
        std::round(total.speed_sum / static_cast<double>(total.speed_n) * kSpeedMeanPerMs) / kSpeedMeanPerMs;
    s.speed.p50 = std::clamp(percentile(total.speed, total.speed_n, 0.50), s.speed.min, s.speed.max);
    s.speed.p95 = std::clamp(percentile(total.speed, total.speed_n, 0.95), s.speed.min, s.speed.max);
  }
  s.quality = std::move(quality);
  return s;
}

// The `top` busiest of the callsigns counted, by points then callsign (empty ones left out).
std::vector<Summary::CallsignCount> busiest(std::vector<Summary::CallsignCount> all, int top) {
  const std::size_t k = std::min<std::size_t>(top, all.size());
  std::partial_sort(all.begin(), all.begin() + k, all.end(), [](const auto& a, const auto& b) {
    return a.points != b.points ? a.points > b.points : a.callsign < b.callsign;
  });
  all.resize(k);
  return all;
}
}  // namespace

Summary finish_summary(const SummaryLayout& l, const SummaryOptions& opts, SummaryCounts total,
                       const std::vector<Flight>& flights, QualityReport quality) {
  Summary s = finish_counts(l, opts, total, std::move(quality));
  std::unordered_map<std::string_view, Summary::CallsignCount> by_callsign;
  for (std::size_t fi = 0; fi < flights.size() && fi < total.matched.size(); ++fi) {
    if (!total.matched[fi]) continue;
    ++s.flights;
    auto& c = by_callsign[flights[fi].callsign];
    ++c.flights, c.points += total.matched[fi];
  }
  std::vector<Summary::CallsignCount> all;
  all.reserve(by_callsign.size());
  for (auto& [name, c] : by_callsign) {
    if (name.empty()) continue;
    c.callsign = std::string(name);
    all.push_back(std::move(c));
  }
  s.top_callsigns = busiest(std::move(all), opts.top_callsigns);
  return s;
}

namespace {
// The scan of summarize_scan(), or with `ix` the same answer from the time index (time_index.hpp): only
// the flights that may meet the window, and of each only its points in the partial buckets at the two
// ends of the window; the whole buckets in between come from the index's counts.
Summary summarize_impl(const TrailSet& set, const Query& q, const SummaryOptions& opts, const TimeIndex* ix) {
  const auto& pts = set.points();
  const auto& flights = set.flights();
  double top_alt = 0;
  if (ix)
    top_alt = ix->top_alt_m();
  else
    for (const Flight& f : flights)
      if (!std::isnan(f.alt_max)) top_alt = std::max<double>(top_alt, f.alt_max);
  const SummaryLayout l = summary_layout(q, opts, set.t_min(), set.t_max(), top_alt);
  const double t_origin = l.t_origin, bin = l.bin_seconds;
  const std::size_t time_bins = l.time_bins, alt_bins = l.alt_bins;
  const double alt_scale = l.alt_scale;
  const PointFilter filter(q);
  const double inv_bin = 1.0 / bin;

  // With the index: the window [t0, t1), its whole buckets [b0, b1) spanning [ta, tb), and the flights
  // that may meet it, [fb, fe). Whole buckets only serve when every time bin holds whole fine cells.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double t0 = q.t0.value_or(-kInf), t1 = q.t1.value_or(kInf);
  std::size_t b0 = 0, b1 = 0, fb = 0, fe = flights.size();
  double ta = t1, tb = t1;
  if (ix) {
    std::tie(fb, fe) = ix->flight_range(t0, t1);
    const double o = ix->origin(), w = ix->bucket_seconds();
    const std::size_t nb = ix->buckets().size();
    const bool alt_fits =
        (opts.alt_unit == AltUnit::ft ? ix->buckets()[0].alt_ft : ix->buckets()[0].alt_m).size() == alt_bins;
    if (std::fmod(bin, ix->fine_seconds()) == 0 && alt_fits) {
      const auto edge = [&](std::size_t k) { return o + static_cast<double>(k) * w; };
      if (t0 > o) b0 = std::min<double>(nb, std::max(0.0, std::floor((t0 - o) / w)));
      while (b0 > 0 && edge(b0 - 1) >= t0) --b0;
      while (b0 < nb && edge(b0) < t0) ++b0;
      b1 = t1 >= edge(nb) ? nb : static_cast<std::size_t>(std::max(0.0, std::floor((t1 - o) / w)));
      while (b1 < nb && edge(b1 + 1) <= t1) ++b1;
      while (b1 > 0 && edge(b1) > t1) --b1;
      if (b1 > b0)
        ta = edge(b0), tb = edge(b1);
      else
        b0 = b1 = 0;
    }
  }
  std::vector<std::uint32_t> matched(fe - fb, 0);
  // First point of flight f at or after t (f.end when none).
  const auto lower = [&](const Flight& f, double t) -> std::size_t {
    if (!(t > f.t_min)) return f.begin;
    if (t > f.t_max) return f.end;
    return static_cast<std::size_t>(std::lower_bound(pts.t.begin() + f.begin, pts.t.begin() + f.end, t) -
                                    pts.t.begin());
  };

  // One flight's points into an accumulator. Points are time-sorted, so the time bin only moves forward
  // and is advanced by comparison instead of a division per point. kAll: every point passes.
  const auto scan = [&]<bool kAll>(std::size_t begin, std::size_t end, Acc& acc) -> std::uint32_t {
    std::uint32_t n = 0;
    std::size_t tb = 0;
    double edge = -std::numeric_limits<double>::infinity();
    float vmin = std::numeric_limits<float>::infinity(), vmax = -vmin;
    double vsum = 0;
    std::uint64_t vn = 0;
    double first = 0, last = 0;
    for (std::size_t i = begin; i < end; ++i) {
      if constexpr (!kAll) {
        if (!filter(pts, i)) continue;
      }
      const double t = pts.t[i];
      if (n++ == 0) first = t;
      last = t;
      if (t >= edge) {
        tb = std::min(static_cast<std::size_t>(std::max(0.0, (t - t_origin) * inv_bin)), time_bins - 1);
        edge = tb + 1 == time_bins ? std::numeric_limits<double>::infinity() : t_origin + (tb + 1) * bin;
        while (t >= edge && tb + 1 < time_bins) edge = t_origin + (++tb + 1) * bin;
      }
      ++acc.time[tb];
      const float a = pts.alt[i];
      if (a == a) {
        // Altitudes are float metres; one converted from a round flight level (FL100 = 3048 m) must
        // land in the bin that starts at it, not a hair below, hence the nudge.
        const double ab = a * alt_scale + SummaryLayout::kAltEdgeNudge;
        ++acc.alt[ab <= 0 ? 0 : std::min(static_cast<std::size_t>(ab), alt_bins - 1)];
      }
      const float v = pts.speed[i];
      if (v == v) {
        ++vn, vsum += v;
        vmin = std::min(vmin, v), vmax = std::max(vmax, v);
        const float sb = v * static_cast<float>(1.0 / SummaryLayout::kSpeedBin);
        ++acc.speed[sb <= 0
                        ? 0
                        : std::min<std::size_t>(static_cast<std::size_t>(sb), SummaryLayout::kSpeedBins - 1)];
      }
    }
    if (n) {
      acc.t_min = std::min(acc.t_min, first), acc.t_max = std::max(acc.t_max, last);
      acc.speed_n += vn, acc.speed_sum += vsum;
      if (vn)
        acc.speed_min = std::min<double>(acc.speed_min, vmin),
        acc.speed_max = std::max<double>(acc.speed_max, vmax);
    }
    return n;
  };

  Acc total = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(fb, fe, 64), Acc(time_bins, alt_bins),
      [&](const tbb::blocked_range<std::size_t>& r, Acc acc) {
        for (std::size_t fi = r.begin(); fi != r.end(); ++fi) {
          const Flight& f = flights[fi];
          if (!q.may_match(f)) continue;
          if (ix) {
            // Time is the only filter: the window's points are one range, of which the parts outside
            // the whole buckets are scanned.
            const std::size_t i0 = lower(f, t0), i1 = lower(f, t1);
            const std::size_t ia = std::max(i0, lower(f, ta)), ib = std::min(i1, std::max(ia, lower(f, tb)));
            acc.points += scan.template operator()<true>(i0, ia, acc);
            acc.points += scan.template operator()<true>(ib, i1, acc);
            matched[fi - fb] = static_cast<std::uint32_t>(i1 - i0);
            continue;
          }
          const std::uint32_t n = filter.contains(f) ? scan.template operator()<true>(f.begin, f.end, acc)
                                                     : scan.template operator()<false>(f.begin, f.end, acc);
          matched[fi] = n;
          acc.points += n;
        }
        return acc;
      },
      [](Acc a, const Acc& b) {
        a.merge(b);
        return a;
      });
  if (ix) {
    // The whole buckets, from the index.
    const auto& buckets = ix->buckets();
    for (std::size_t j = b0; j < b1; ++j) {
      const TimeIndex::Bucket& k = buckets[j];
      if (!k.points) continue;
      total.points += k.points;
      total.t_min = std::min(total.t_min, k.t_first), total.t_max = std::max(total.t_max, k.t_last);
      total.speed_n += k.speed_n, total.speed_sum += k.speed_sum;
      total.speed_min = std::min(total.speed_min, k.speed_min);
      total.speed_max = std::max(total.speed_max, k.speed_max);
      const auto& alt = opts.alt_unit == AltUnit::ft ? k.alt_ft : k.alt_m;
      for (std::size_t i = 0; i < alt_bins; ++i) total.alt[i] += alt[i];
      for (std::size_t i = 0; i < total.speed.size(); ++i) total.speed[i] += k.speed[i];
    }
    // Fine cells into time bins: a cell [s, s + fine) lies in one bin, as bins are whole cells from a
    // multiple of their width.
    const auto& fine = ix->fine_counts();
    const double fw = ix->fine_seconds();
    const std::size_t per = fine.size() / buckets.size();
    for (std::size_t c = b0 * per; c < b1 * per; ++c) {
      if (!fine[c]) continue;
      const double start = ix->origin() + static_cast<double>(c) * fw;
      const double k = std::floor((start - t_origin) / bin);
      total.time[static_cast<std::size_t>(std::clamp(k, 0.0, static_cast<double>(time_bins - 1)))] += fine[c];
    }
    SummaryCounts c;
    c.points = total.points, c.t_min = total.t_min, c.t_max = total.t_max;
    c.time = std::move(total.time), c.alt = std::move(total.alt), c.speed = std::move(total.speed);
    c.speed_n = total.speed_n, c.speed_sum = total.speed_sum;
    c.speed_min = total.speed_min, c.speed_max = total.speed_max;
    Summary s = finish_counts(l, opts, c, window_quality(set, t0, t1));
    // Flights and busiest callsigns by the index's callsign ids instead of a map of names.
    const auto& ids = ix->callsign_ids();
    const auto& names = ix->callsign_names();
    std::vector<std::uint64_t> id_flights(names.size()), id_points(names.size());
    for (std::size_t fi = fb; fi < fe; ++fi) {
      const std::uint32_t n = matched[fi - fb];
      if (!n) continue;
      ++s.flights;
      ++id_flights[ids[fi]], id_points[ids[fi]] += n;
    }
    std::vector<Summary::CallsignCount> all;
    for (std::size_t i = 0; i < names.size(); ++i)
      if (id_flights[i] && !names[i].empty()) all.push_back({names[i], id_flights[i], id_points[i]});
    s.top_callsigns = busiest(std::move(all), opts.top_callsigns);
    return s;
  }
  SummaryCounts c;
  c.points = total.points, c.t_min = total.t_min, c.t_max = total.t_max;
  c.time = std::move(total.time), c.alt = std::move(total.alt), c.speed = std::move(total.speed);
  c.speed_n = total.speed_n, c.speed_sum = total.speed_sum;
  c.speed_min = total.speed_min, c.speed_max = total.speed_max;
  c.matched = std::move(matched);
  return finish_summary(l, opts, std::move(c), flights, check_quality(set, q));
}
}  // namespace

Summary summarize_scan(const TrailSet& set, const Query& q, const SummaryOptions& opts) {
  return summarize_impl(set, q, opts, nullptr);
}

Summary summarize(const TrailSet& set, const Query& q, const SummaryOptions& opts) {
  const TimeIndex& ix = set.time_index();
  // The index serves time windows only: any other filter takes the scan.
  const bool time_only =
      !q.bbox && !q.alt_min && !q.alt_max && q.icao24.empty() && q.callsign.empty() && !q.on_ground;
  return summarize_impl(set, q, opts, ix.valid() && time_only ? &ix : nullptr);
}

nlohmann::json Summary::to_json() const {
  nlohmann::json top = nlohmann::json::array();
  for (const auto& c : top_callsigns)
    top.push_back({{"callsign", c.callsign}, {"flights", c.flights}, {"points", c.points}});
  return {
      {"flights", flights},
      {"points", points},
      {"t_min", points ? nlohmann::json(t_min) : nlohmann::json()},
      {"t_max", points ? nlohmann::json(t_max) : nlohmann::json()},
      {"time_histogram",
       {{"t0", time_histogram.t0},
        {"bin_seconds", time_histogram.bin_seconds},
        {"counts", time_histogram.counts}}},
      {"altitude_histogram",
       {{"unit", unit_name(altitude_histogram.unit)},
        {"bin_width", altitude_histogram.bin_width},
        {"min", altitude_histogram.min},
        {"counts", altitude_histogram.counts}}},
      {"speed",
       {{"unit", "m/s"},
        {"count", speed.count},
        {"min", speed.min},
        {"max", speed.max},
        {"mean", speed.mean},
        {"p50", speed.p50},
        {"p95", speed.p95}}},
      {"top_callsigns", std::move(top)},
      {"quality", quality.to_json()},
  };
}

const std::vector<std::string>& Summary::csv_tables() {
  static const std::vector<std::string> tables = {"totals", "time_histogram", "altitude_histogram",
                                                  "top_callsigns", "quality"};
  return tables;
}

std::string Summary::to_csv(const std::string& table) const {
  std::string out;
  const auto num = [&out](double v) {
    if (std::isfinite(v)) append_shortest(out, v);
  };
  if (table == "totals") {
    out = "key,value\n";
    const auto row = [&](const char* key, double v, bool known = true) {
      out += key;
      out += ',';
      if (known) num(v);
      out += '\n';
    };
    row("flights", double(flights));
    row("points", double(points));
    row("t_min", t_min, points > 0);
    row("t_max", t_max, points > 0);
    row("speed_count", double(speed.count));
    row("speed_min_ms", speed.min);
    row("speed_max_ms", speed.max);
    row("speed_mean_ms", speed.mean);
    row("speed_p50_ms", speed.p50);
    row("speed_p95_ms", speed.p95);
    row("implausible_speeds", double(quality.speed.count));
    row("implausible_altitudes", double(quality.altitude.count));
    row("position_jumps", double(quality.jumps.count));
  } else if (table == "time_histogram") {
    out = "t0,t1,points\n";
    for (std::size_t i = 0; i < time_histogram.counts.size(); ++i) {
      num(time_histogram.t0 + double(i) * time_histogram.bin_seconds);
      out += ',';
      num(time_histogram.t0 + double(i + 1) * time_histogram.bin_seconds);
      out += ',' + std::to_string(time_histogram.counts[i]) + '\n';
    }
  } else if (table == "altitude_histogram") {
    out = "lower,upper,unit,points\n";
    const std::string unit = altitude_histogram.unit == AltUnit::m ? "m" : "ft";
    for (std::size_t i = 0; i < altitude_histogram.counts.size(); ++i) {
      num(altitude_histogram.min + double(i) * altitude_histogram.bin_width);
      out += ',';
      num(altitude_histogram.min + double(i + 1) * altitude_histogram.bin_width);
      out += ',' + unit + ',' + std::to_string(altitude_histogram.counts[i]) + '\n';
    }
  } else if (table == "top_callsigns") {
    out = "callsign,flights,points\n";
    for (const auto& c : top_callsigns)
      out += csv_field(c.callsign) + ',' + std::to_string(c.flights) + ',' + std::to_string(c.points) + '\n';
  } else if (table == "quality") {
    out = "kind,flight_id,callsign,t,value\n";
    const std::pair<const char*, const QualityCount*> kinds[] = {
        {"speed", &quality.speed}, {"altitude", &quality.altitude}, {"jump", &quality.jumps}};
    for (const auto& [kind, c] : kinds)
      for (const auto& e : c->examples) {
        out += std::string(kind) + ',' + std::to_string(e.flight_id) + ',' + csv_field(e.callsign) + ',';
        num(e.t);
        out += ',';
        num(e.value);
        out += '\n';
      }
  } else {
    std::string list;
    for (const auto& t : csv_tables()) list += (list.empty() ? "" : ", ") + t;
    throw invalid_argument("table", "table must be one of " + list + ", got '" + table + "'");
  }
  return out;
}

const std::vector<std::string>& flight_sort_keys() {
  static const std::vector<std::string> keys = {"id",
                                                "icao24",
                                                "callsign",
                                                "t_start",
                                                "t_end",
                                                "duration_s",
                                                "points",
                                                "alt_max_m",
                                                "flight_t_start",
                                                "flight_t_end",
                                                "flight_duration_s",
                                                "flight_points"};
  return keys;
}

FlightSort parse_flight_sort(const std::string& sort, const std::string& order, const std::string& sort_param,
                             const std::string& order_param) {
  FlightSort out;
  const auto& keys = flight_sort_keys();
  const auto it = std::find(keys.begin(), keys.end(), sort);
  if (it == keys.end()) {
    std::string list;
    for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
    throw invalid_argument(sort_param, sort_param + " must be one of " + list + ", got '" + sort + "'");
  }
  out.key = static_cast<FlightSortKey>(it - keys.begin());
  if (order != "asc" && order != "desc")
    throw invalid_argument(order_param, order_param + " must be 'asc' or 'desc', got '" + order + "'");
  out.descending = order == "desc";
  return out;
}

namespace {
// -1, 0, 1 as a < b, a == b, a > b on the sort column; an unknown altitude is "greatest" here and placed
// last by the caller in both directions.
int compare_rows(const FlightRow& a, const FlightRow& b, FlightSortKey key,
                 const std::vector<Flight>& flights) {
  const auto cmp = [](auto x, auto y) { return x < y ? -1 : (y < x ? 1 : 0); };
  switch (key) {
    case FlightSortKey::id:
      return cmp(a.id, b.id);
    case FlightSortKey::icao24:
      return cmp(flights[a.id].icao24.compare(flights[b.id].icao24), 0);
    case FlightSortKey::callsign:
      return cmp(flights[a.id].callsign.compare(flights[b.id].callsign), 0);
    case FlightSortKey::t_start:
      return cmp(a.t_start, b.t_start);
    case FlightSortKey::t_end:
      return cmp(a.t_end, b.t_end);
    case FlightSortKey::duration_s:
      return cmp(a.duration_s, b.duration_s);
    case FlightSortKey::points:
      return cmp(a.points, b.points);
    case FlightSortKey::alt_max_m:
      return cmp(a.alt_max_m, b.alt_max_m);  // NaN handled by the caller
    case FlightSortKey::flight_t_start:
      return cmp(a.flight_t_start, b.flight_t_start);
    case FlightSortKey::flight_t_end:
      return cmp(a.flight_t_end, b.flight_t_end);
    case FlightSortKey::flight_duration_s:
      return cmp(a.flight_duration_s, b.flight_duration_s);
    case FlightSortKey::flight_points:
      return cmp(a.flight_points, b.flight_points);
  }
  return 0;
}
}  // namespace

FlightPage list_flights(const TrailSet& set, const Query& q, std::size_t page, std::size_t page_size,
                        const FlightSort& sort) {
  if (page_size < 1 || page_size > limits::kMaxPageSize)
    throw invalid_argument("page_size", "page_size must lie in 1..1000");
  const auto& pts = set.points();
  const auto& flights = set.flights();
  const PointFilter filter(q);
  std::vector<FlightRow> rows(flights.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, flights.size(), 16), [&](const auto& r) {
    for (std::size_t fi = r.begin(); fi != r.end(); ++fi) {
      const Flight& f = flights[fi];
      if (!q.may_match(f)) continue;
      FlightRow& row = rows[fi];
      row.alt_max_m = std::numeric_limits<double>::quiet_NaN();
      for (std::size_t i = f.begin; i < f.end; ++i) {
        if (!filter(pts, i)) continue;
        if (!row.points++) row.t_start = pts.t[i];
        row.t_end = pts.t[i];
        const float a = pts.alt[i];
        if (a == a && !(a <= row.alt_max_m)) row.alt_max_m = a;
      }
      row.id = static_cast<std::uint32_t>(fi);
      row.duration_s = row.t_end - row.t_start;
      row.flight_t_start = f.t_min, row.flight_t_end = f.t_max;
      row.flight_duration_s = f.t_max - f.t_min;
      row.flight_points = f.size();
    }
  });
  std::vector<FlightRow> hits;
  for (auto& r : rows)
    if (r.points) hits.push_back(std::move(r));
  return page_flights(std::move(hits), flights, page, page_size, sort);
}

FlightPage page_flights(std::vector<FlightRow> hits, const std::vector<Flight>& flights, std::size_t page,
                        std::size_t page_size, const FlightSort& sort) {
  if (page_size < 1 || page_size > limits::kMaxPageSize)
    throw invalid_argument("page_size", "page_size must lie in 1..1000");
  const bool alt = sort.key == FlightSortKey::alt_max_m;
  std::sort(hits.begin(), hits.end(), [&](const FlightRow& a, const FlightRow& b) {
    if (alt && std::isnan(a.alt_max_m) != std::isnan(b.alt_max_m)) return std::isnan(b.alt_max_m);
    if (!(alt && std::isnan(a.alt_max_m))) {
      const int c = compare_rows(a, b, sort.key, flights);
      if (c != 0) return sort.descending ? c > 0 : c < 0;
    }
    return a.id < b.id;
  });
  FlightPage out;
  out.total = hits.size(), out.page = page, out.page_size = page_size, out.sort = sort;
  const std::size_t first = std::min(hits.size(), page * page_size);
  const std::size_t last = std::min(hits.size(), first + page_size);
  for (std::size_t i = first; i < last; ++i) {
    hits[i].icao24 = flights[hits[i].id].icao24;
    hits[i].callsign = flights[hits[i].id].callsign;
    out.flights.push_back(std::move(hits[i]));
  }
  return out;
}

nlohmann::json FlightPage::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& r : flights)
    list.push_back({{"id", r.id},
                    {"icao24", r.icao24},
                    {"callsign", r.callsign},
                    {"t_start", r.t_start},
                    {"t_end", r.t_end},
                    {"duration_s", r.duration_s},
                    {"points", r.points},
                    {"alt_max_m", std::isnan(r.alt_max_m) ? nlohmann::json() : nlohmann::json(r.alt_max_m)},
                    {"flight_t_start", r.flight_t_start},
                    {"flight_t_end", r.flight_t_end},
                    {"flight_duration_s", r.flight_duration_s},
                    {"flight_points", r.flight_points}});
  return {{"total", total},
          {"page", page},
          {"page_size", page_size},
          {"sort", flight_sort_keys()[static_cast<std::size_t>(sort.key)]},
          {"order", sort.descending ? "desc" : "asc"},
          {"flights", std::move(list)}};
}

nlohmann::json flight_geojson(const TrailSet& set, std::size_t flight_id, const Query& q, bool clip,
                              std::size_t max_points) {
  if (flight_id >= set.num_flights())
    throw not_found("flight_id", "flight " + std::to_string(flight_id) + " does not exist in this dataset");
  const Flight& f = set.flights()[flight_id];
  const auto& p = set.points();
  const PointFilter filter(q);
  std::vector<std::size_t> keep;
  for (std::size_t i = f.begin; i < f.end; ++i)
    if (!clip || filter(p, i)) keep.push_back(i);
  if (keep.size() > max_points)
    throw Error(Error::Kind::payload_too_large, "max_points",
                "flight has " + std::to_string(keep.size()) +
                    " points, more than max_points=" + std::to_string(max_points));
  const auto num = [](float v) { return v == v ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json coords = nlohmann::json::array(), times = nlohmann::json::array(),
                 alts = nlohmann::json::array(), speeds = nlohmann::json::array();
  for (std::size_t i : keep) {
    nlohmann::json c = {p.lon[i], p.lat[i]};
    if (p.alt[i] == p.alt[i]) c.push_back(p.alt[i]);
    coords.push_back(std::move(c));
    times.push_back(p.t[i]);
    alts.push_back(num(p.alt[i]));
    speeds.push_back(num(p.speed[i]));
  }
  return {{"type", "Feature"},
          {"geometry", {{"type", "LineString"}, {"coordinates", std::move(coords)}}},
          {"properties",
           {{"id", flight_id},
            {"icao24", f.icao24},
            {"callsign", f.callsign},
            {"times", std::move(times)},
            {"altitudes_m", std::move(alts)},
            {"speeds_ms", std::move(speeds)}}}};
}

}  // namespace trailscope
