#include "trailscope/trails/trail_set_builder.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <tuple>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/trails/quality.hpp"

namespace trailscope {

std::size_t TrailSetBuilder::KeyHash::operator()(const KeyView& k) const noexcept {
  return std::hash<std::string_view>()(k.icao24) * 31u ^ std::hash<std::string_view>()(k.callsign);
}

namespace {
// Trims ASCII blanks and folds ASCII case into `out` (identifiers are ASCII; no locale involved).
void normalise(std::string_view s, bool upper, std::string& out) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r' || s[b] == '\n')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r' || s[e - 1] == '\n')) --e;
  out.assign(s.data() + b, e - b);
  for (char& c : out) {
    if (upper && c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    if (!upper && c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
}

// Appends one flight made of samples[b, e) (time-sorted) to the columns and the flight list.
void append_flight(const std::string& icao24, const std::string& callsign, const std::vector<Sample>& s,
                   std::size_t b, std::size_t e, PointColumns& cols, std::vector<Flight>& flights) {
  Flight f;
  f.icao24 = icao24;
  f.callsign = callsign;
  f.begin = static_cast<std::uint32_t>(cols.size());
  for (std::size_t i = b; i < e; ++i) {
    const Sample& p = s[i];
    cols.t.push_back(p.t), cols.lat.push_back(p.lat), cols.lon.push_back(p.lon);
    cols.alt.push_back(p.alt), cols.speed.push_back(p.speed), cols.track.push_back(p.track);
    cols.vrate.push_back(p.vrate), cols.on_ground.push_back(p.on_ground ? 1 : 0);
  }
  f.end = static_cast<std::uint32_t>(cols.size());
  compute_extents(f, cols);
  flights.push_back(std::move(f));
}
}  // namespace

void TrailSetBuilder::add(std::string_view icao24, std::string_view callsign, const Sample& s) {
  if (!std::isfinite(s.t) || !std::isfinite(s.lat) || !std::isfinite(s.lon))
    throw Error(Error::Kind::internal, "", "TrailSetBuilder::add: non-finite time or position");
  normalise(icao24, false, icao_buf_);
  normalise(callsign, true, callsign_buf_);
  auto it = groups_.find(KeyView{icao_buf_, callsign_buf_});
  if (it == groups_.end()) it = groups_.emplace(Key{icao_buf_, callsign_buf_}, std::vector<Sample>{}).first;
  it->second.push_back(s);
  ++samples_;
}

TrailSet TrailSetBuilder::build(Stats* stats, double gap_seconds, bool split_jumps) {
  if (gap_seconds <= 0) gap_seconds = limits::kFlightGapSeconds;
  if (samples_ > std::numeric_limits<std::uint32_t>::max())
    throw Error(Error::Kind::payload_too_large, "", "a dataset holds at most 2^32-1 points");
  Stats local;
  // Flights are emitted in start-time order, so gather (start, key, range) first.
  struct Piece {
    double t0;
    const Key* key;
    std::vector<Sample>* samples;
    std::size_t b, e;
  };
  std::vector<Piece> pieces;
  std::vector<double> since;
  pieces.reserve(groups_.size());
  for (auto& [key, samples] : groups_) {
    // Stable sort keeps the first of equal-time samples, which is the one kept below.
    std::stable_sort(samples.begin(), samples.end(),
                     [](const Sample& a, const Sample& b) { return a.t < b.t; });
    std::size_t w = 0;
    for (std::size_t r = 0; r < samples.size(); ++r) {
      if (w > 0 && samples[r].t == samples[w - 1].t) {
        ++local.duplicates;
        continue;
      }
      samples[w++] = samples[r];
    }
    samples.resize(w);
    std::size_t b = 0;
    // since[i]: the first report of samples[i]'s position (a stale repeat counts from there).
    since.resize(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i)
      since[i] = i > 0 && samples[i].lat == samples[i - 1].lat && samples[i].lon == samples[i - 1].lon
                     ? since[i - 1]
                     : samples[i].t;
    // A step x→y (x < y) no aircraft flies, by the splitting thresholds (trails/quality.hpp).
    // `pts`, not the structured binding `samples`: clang before 16 cannot capture a binding in a lambda.
    auto impossible = [&, &pts = samples](std::size_t x, std::size_t y) {
      const Sample &p = pts[x], &q = pts[y];
      const double d = great_circle_m(p.lat, p.lon, q.lat, q.lon);
      return d >= kJumpSplitMinDistanceM && d / std::max(q.t - since[x], kMinJumpSeconds) > kJumpSplitSpeedMs;
    };
    for (std::size_t i = 1; i <= samples.size(); ++i) {
      const std::size_t n = samples.size();
      bool split = i == n || samples[i].t - samples[i - 1].t > gap_seconds, counted = false;
      if (!split && split_jumps) {
        if (samples[i].t - samples[i - 1].t > kLegGapSeconds) {
          // A leg is at least two samples: a lone sample beyond the gap (an SO6 segment whose clock
          // wrapped at midnight) is not a leg and stays.
          if (i - b >= 2 && i + 1 < n && samples[i + 1].t - samples[i].t <= kLegGapSeconds) {
            split = counted = true;
            local.legs.push_back({key.icao24, key.callsign, samples[i].t, samples[i].t - samples[i - 1].t});
          }
        } else if (i >= 2 && i + 1 < n && impossible(i - 1, i) && impossible(i - 1, i + 1) &&
                   impossible(i - 2, i) && !impossible(i, i + 1) && !impossible(i - 2, i - 1)) {
          split = counted = true;
          const Sample &a = samples[i - 1], &c = samples[i];
          local.jumps.push_back({key.icao24, key.callsign, c.t,
                                 implied_speed_ms(since[i - 1], a.lat, a.lon, c.t, c.lat, c.lon)});
        }
      }
      if (split) {
        pieces.push_back({samples[b].t, &key, &samples, b, i});
        if (i != n && !counted) ++local.splits;
        b = i;
      }
    }
  }
  local.jump_splits = local.jumps.size();
  local.leg_splits = local.legs.size();
  std::sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) {
    return std::tie(a.t0, a.key->icao24, a.key->callsign, a.b) <
           std::tie(b.t0, b.key->icao24, b.key->callsign, b.b);
  });
  PointColumns cols;
  cols.reserve(samples_ - local.duplicates);
  std::vector<Flight> flights;
  flights.reserve(pieces.size());
  for (const Piece& p : pieces)
    append_flight(p.key->icao24, p.key->callsign, *p.samples, p.b, p.e, cols, flights);
  groups_.clear();
  samples_ = 0;
  if (stats) *stats = local;
  return TrailSet(std::move(cols), std::move(flights));
}

}  // namespace trailscope
