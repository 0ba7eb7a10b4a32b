// Deterministic one-day US traffic generator (see demo_traffic.hpp for the model).
// Each flight is simulated as a point moving along the WGS84 geodesic of its route with a speed and an
// altitude that follow simple airline procedures; the state is integrated in sub-steps of ≤ 5 s and
// sampled every 5–10 s. Flights are independent, each with its own RNG, so they run in parallel and the
// result is the same whatever the thread count.
#include "trailscope/ingest/demo_traffic.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/GeodesicLine.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "core/rng.hpp"
#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::ingest {
namespace {

/// The flights' point ranges laid end to end: flight k (named by `name(k, flight)`, which returns its point
/// count) takes the next points. Throws payload_too_large(param) past 2^32-1 points in all (a TrailSet's
/// ranges are 32-bit). `total` is the points in all.
template <typename Name>
std::vector<Flight> lay_out_flights(std::size_t n, const char* param, std::uint64_t& total, Name name) {
  std::vector<Flight> flights(n);
  total = 0;
  for (std::size_t k = 0; k < n; ++k) {
    flights[k].begin = static_cast<std::uint32_t>(total);
    total += name(k, flights[k]);
    if (total > std::numeric_limits<std::uint32_t>::max())
      throw Error(Error::Kind::payload_too_large, param, "a dataset holds at most 2^32-1 points");
    flights[k].end = static_cast<std::uint32_t>(total);
  }
  return flights;
}

using detail::kFeet;
using detail::kFeetPerMinute;
using detail::kKnot;

// --- deterministic random numbers (own algorithms: std:: distributions differ between libraries) ----------

// xoshiro256** seeded through splitmix64 (core/rng.hpp).
class Rng : public rng::Xoshiro256ss {
 public:
  using Xoshiro256ss::Xoshiro256ss;
  /// Uniform integer in [a, b].
  int integer(int a, int b) { return a + static_cast<int>(uniform() * (b - a + 1)); }
};

// Index into a cumulative weight table for a uniform u in [0, 1).
std::size_t pick(const std::vector<double>& cumulative, double u) {
  const double x = u * cumulative.back();
  const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), x);
  return std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()), cumulative.size() - 1);
}

// --- inputs
// ---------------------------------------------------------------------------------------------------

struct Airport {
  double lat, lon;
};
struct Route {
  std::uint32_t origin, destination;
  double count;
};

std::string read_text(const std::string& path, const std::string& param) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw not_found(param, "no such file: '" + path + "'");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (!in) throw Error(Error::Kind::internal, param, "cannot read '" + path + "'");
  return ss.str();
}

// Reads a small CSV with a header; calls row(fields) for each data row. Returns the column indexes of
// `wanted` (throws unprocessable naming the missing ones).
template <std::size_t N, class F>
void read_csv(const std::string& path, const std::string& param, const std::array<const char*, N>& wanted,
              F&& row) {
  const std::string text = read_text(path, param);
  std::string_view rest = text;
  const std::string_view header = detail::first_line(rest);
  const auto names = detail::csv_header_names(header);
  std::array<std::size_t, N> col{};
  for (std::size_t k = 0; k < N; ++k) {
    const auto it = std::find(names.begin(), names.end(), wanted[k]);
    if (it == names.end())
      throw Error(Error::Kind::unprocessable, param, "'" + path + "' has no column '" + wanted[k] + "'");
    col[k] = static_cast<std::size_t>(it - names.begin());
  }
  std::vector<std::string_view> fields;
  std::array<std::string_view, N> picked;
  std::size_t pos = std::min(rest.size(), rest.find('\n') + 1);
  while (pos < rest.size()) {
    std::size_t nl = rest.find('\n', pos);
    if (nl == std::string_view::npos) nl = rest.size();
    std::string_view line = rest.substr(pos, nl - pos);
    pos = nl + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    detail::split_csv(line, fields);
    bool ok = true;
    for (std::size_t k = 0; k < N && ok; ++k) {
      if (col[k] >= fields.size())
        ok = false;
      else
        picked[k] = detail::trim(fields[col[k]]);
    }
    if (ok) row(picked);
  }
}

// --- the flight model
// -------------------------------------------------------------------------------------------

constexpr double kTan3Deg = 0.052407779283041196;  // tan(3°): the standard approach/descent path
constexpr double kFL100 = 10000 * kFeet;
constexpr double kMaxAccel = 0.8;  // m/s², speed changes in flight (≈ 1.5 kt/s)

// Local-time departure weights per hour 00..23: near-empty nights, a morning bank, a steady day, an evening
// bank and a red-eye tail (shape of US domestic schedules).
constexpr std::array<double, 24> kHourWeights = {0.3, 0.15, 0.1, 0.1, 0.2, 2.0, 5.5, 6.5, 6.5, 6.0, 6.0, 6.0,
                                                 6.0, 6.0,  6.0, 6.0, 6.5, 6.5, 6.0, 5.5, 4.0, 3.0, 1.8, 1.0};

struct Airline {
  const char* icao;
  double share;
  int number_min, number_max;  // regional carriers fly the 3000–6999 numbers
};
constexpr std::array<Airline, 12> kAirlines = {{
    {"SWA", 0.20, 1, 2999},
    {"AAL", 0.17, 1, 2999},
    {"DAL", 0.17, 1, 2999},
    {"UAL", 0.14, 1, 2999},
    {"SKW", 0.09, 3000, 6999},
    {"ASA", 0.05, 1, 1999},
    {"JBU", 0.05, 1, 2999},
    {"ENY", 0.03, 3000, 4999},
    {"RPA", 0.03, 3000, 5999},
    {"NKS", 0.03, 100, 999},
    {"FFT", 0.02, 1000, 2999},
    {"EDV", 0.02, 4000, 5999},
}};

// US civil aircraft addresses: a00001 .. adf7c7.
constexpr std::uint32_t kIcaoFirst = 0xa00001, kIcaoCount = 0xadf7c7 - 0xa00001 + 1;
// A prime, hence coprime with kIcaoCount: i ↦ first + (i·P + o) mod N is a bijection on [0, N), so flights
// get distinct, scattered-looking addresses.
constexpr std::uint64_t kIcaoStride = 1000003;

double lerp(double a, double b, double f) {
  return a + (b - a) * std::clamp(f, 0.0, 1.0);
}

class FlightModel {
 public:
  FlightModel(double distance, Rng& rng, double cruise_alt) : distance_(distance), h_cruise_(cruise_alt) {
    cruise_gs_ = rng.uniform(440, 480) * kKnot;
    climb_factor_ = rng.uniform(0.85, 1.15);
    taxi_speed_ = rng.uniform(6, 9);
    taxi_out_ = rng.uniform(1500, 3500);
    hold_ = rng.uniform(0, 180);
    taxi_in_ = rng.uniform(1000, 3000);
    roll_ = rng.uniform(1500, 2200);
    s_ = -(roll_ + taxi_out_);
    v_ = taxi_speed_;
  }

  bool finished() const { return phase_ == Phase::done; }

  /// Advances the state by dt seconds in sub-steps of at most 5 s. The profile is smooth (speed changes
  /// ≤ 0.8 m/s², climb ≤ 15 m/s), so finer steps move samples by metres only, and this loop is the
  /// generator's hot spot.
  void advance(double dt) {
    const int n = std::max(1, static_cast<int>(std::ceil(dt / 5.0)));
    const double h = dt / n;
    for (int i = 0; i < n && phase_ != Phase::done; ++i) step(h);
  }

  double s() const { return s_; }
  double speed() const { return v_; }
  double vrate() const { return vrate_; }
  bool on_ground() const { return phase_ != Phase::airborne; }
  double altitude() const {
    return phase_ == Phase::airborne ? std::min({hc_, h_cruise_, descent_path(s_)}) : 0.0;
  }

 private:
  enum class Phase { taxi_out, hold, roll, airborne, rollout, taxi_in, done };

  double descent_path(double s) const { return std::max(0.0, distance_ - s) * kTan3Deg; }

  double climb_rate(double h) const {
    const double fpm = h < kFL100 ? 2800 : h < 25000 * kFeet ? 2000 : 1400;
    return fpm * kFeetPerMinute * climb_factor_;
  }

  // Target speed of the current flight phase at altitude h (m).
  double target_speed(double h, bool climbing, bool cruising) const {
    const double kt = kKnot;
    if (cruising) return cruise_gs_;
    const double upper = std::max(h_cruise_ - kFL100, 1.0);
    if (climbing) {
      if (h < 3000 * kFeet) return lerp(160 * kt, 250 * kt, h / (3000 * kFeet));
      if (h < kFL100) return 250 * kt;
      return lerp(290 * kt, cruise_gs_, (h - kFL100) / upper);
    }
    if (h > kFL100) return lerp(280 * kt, cruise_gs_, (h - kFL100) / upper);
    if (h > 3000 * kFeet) return lerp(180 * kt, 250 * kt, (h - 3000 * kFeet) / (kFL100 - 3000 * kFeet));
    return lerp(140 * kt, 180 * kt, h / (3000 * kFeet));
  }

  void approach(double target, double max_change) { v_ += std::clamp(target - v_, -max_change, max_change); }

  void step(double dt) {
    switch (phase_) {
      case Phase::taxi_out:
        v_ = taxi_speed_;
        s_ += v_ * dt;
        if (s_ >= -roll_) s_ = -roll_, phase_ = Phase::hold, v_ = 0, held_ = 0;
        break;
      case Phase::hold:
        v_ = 0;
        held_ += dt;
        if (held_ >= hold_) phase_ = Phase::roll;
        break;
      case Phase::roll: {
        // Constant acceleration that reaches rotation speed (~150 kt) at the airport reference point.
        const double v_rot = 150 * kKnot;
        const double a = v_rot * v_rot / (2 * roll_);
        v_ += a * dt;
        s_ += v_ * dt;
        if (v_ >= v_rot || s_ >= 0) phase_ = Phase::airborne, hc_ = 0, v_ = std::min(v_, v_rot);
        break;
      }
      case Phase::airborne: {
        const double h = altitude();
        const bool climbing = hc_ < h_cruise_ && hc_ <= descent_path(s_);
        const bool cruising = !climbing && h_cruise_ <= descent_path(s_);
        approach(target_speed(h, climbing, cruising), kMaxAccel * dt);
        s_ += v_ * dt;
        if (climbing) hc_ += climb_rate(hc_) * dt;
        vrate_ = climbing ? climb_rate(hc_) : cruising ? 0.0 : -v_ * kTan3Deg;
        if (s_ >= distance_) phase_ = Phase::rollout, vrate_ = 0;
        break;
      }
      case Phase::rollout:
        approach(taxi_speed_, 1.8 * dt);  // braking and reversers, ~1.8 m/s²
        s_ += v_ * dt;
        if (v_ <= taxi_speed_ + 1e-9) phase_ = Phase::taxi_in, rolled_to_ = s_;
        break;
      case Phase::taxi_in:
        v_ = taxi_speed_;
        s_ += v_ * dt;
        if (s_ >= rolled_to_ + taxi_in_) s_ = rolled_to_ + taxi_in_, phase_ = Phase::done, v_ = 0;
        break;
      case Phase::done:
        break;
    }
  }

  const double distance_, h_cruise_;
  double cruise_gs_, climb_factor_, taxi_speed_, taxi_out_, hold_, taxi_in_, roll_;
  Phase phase_ = Phase::taxi_out;
  double s_ = 0, v_ = 0, hc_ = 0, vrate_ = 0, held_ = 0, rolled_to_ = 0;
};

// Positions along a geodesic for a non-decreasing path coordinate: exact GeodesicLine positions at knots
// every 10 km, linear in between. On a 10 km chord the geodesic departs from the straight lat/lon line by
// about Δ²/8R ≈ 2 m, far below what a demo shows, and a sample then costs a few flops instead of a
// GeodesicLine::Position (~150 ns, which dominated the generator).
class PathInterpolator {
 public:
  static constexpr double kStep = 10000.0;
  PathInterpolator(const GeographicLib::GeodesicLine& line, double s0) : line_(line), origin_(s0) { load(0); }

  void at(double s, double& lat, double& lon, double& azi) {
    const auto k = static_cast<std::int64_t>(std::floor((s - origin_) / kStep));
    if (k != k_) load(k);
    const double f = (s - origin_) / kStep - static_cast<double>(k_);
    lat = a_[0] + (b_[0] - a_[0]) * f;
    lon = a_[1] + (b_[1] - a_[1]) * f;
    azi = a_[2] + (b_[2] - a_[2]) * f;
    if (lon >= 180) lon -= 360;
    if (lon < -180) lon += 360;
    if (azi < 0) azi += 360;
    if (azi >= 360) azi -= 360;
  }

 private:
  void knot(std::int64_t k, double* out) const {
    line_.Position(origin_ + static_cast<double>(k) * kStep, out[0], out[1], out[2]);
  }
  void load(std::int64_t k) {
    if (k == k_ + 1)
      std::copy(b_, b_ + 3, a_);
    else
      knot(k, a_);
    knot(k + 1, b_);
    // Unwrap b against a so that interpolation never runs the long way round.
    if (b_[1] - a_[1] > 180) b_[1] -= 360;
    if (b_[1] - a_[1] < -180) b_[1] += 360;
    if (b_[2] - a_[2] > 180) b_[2] -= 360;
    if (b_[2] - a_[2] < -180) b_[2] += 360;
    k_ = k;
  }
  const GeographicLib::GeodesicLine& line_;
  const double origin_;
  std::int64_t k_ = -2;
  double a_[3] = {}, b_[3] = {};
};

// Cruise level for a route: longer routes fly higher; odd thousands of feet eastbound, even westbound.
double cruise_altitude(double distance_m, double azimuth, Rng& rng) {
  const double km = distance_m / 1000;
  int lo, hi;  // thousands of feet
  if (km < 150)
    lo = 10, hi = 16;
  else if (km < 350)
    lo = 20, hi = 28;
  else if (km < 700)
    lo = 28, hi = 34;
  else if (km < 1500)
    lo = 30, hi = 38;
  else
    lo = 33, hi = 39;
  int kft = rng.integer(lo, hi);
  const bool eastbound = azimuth >= 0 && azimuth < 180;
  if ((kft % 2 == 1) != eastbound) kft = kft + 1 <= hi ? kft + 1 : kft - 1;
  return kft * 1000 * kFeet;
}

// --- fleet mode: aircraft flying leg after leg over several days
// ---------------------------------------------

// Flight extents exactly as TrailSetBuilder computes them.
void flight_extents(Flight& fl, const PointColumns& cols) {
  fl.t_min = cols.t[fl.begin], fl.t_max = cols.t[fl.end - 1];
  fl.lat_min = fl.lon_min = fl.alt_min = std::numeric_limits<float>::infinity();
  fl.lat_max = fl.lon_max = fl.alt_max = -std::numeric_limits<float>::infinity();
  for (std::uint32_t j = fl.begin; j < fl.end; ++j) {
    fl.lat_min = std::min(fl.lat_min, cols.lat[j]), fl.lat_max = std::max(fl.lat_max, cols.lat[j]);
    fl.lon_min = std::min(fl.lon_min, cols.lon[j]), fl.lon_max = std::max(fl.lon_max, cols.lon[j]);
    fl.alt_min = std::min(fl.alt_min, cols.alt[j]), fl.alt_max = std::max(fl.alt_max, cols.alt[j]);
    if (j > fl.begin && std::fabs(cols.lon[j] - cols.lon[j - 1]) > 180.0f) fl.crosses_antimeridian = true;
  }
}

// One sample into row i of the columns.
void write_sample(PointColumns& cols, std::uint32_t i, double t, double lat, double lon, double azi,
                  double alt, double speed, double vrate, bool on_ground) {
  cols.t[i] = t;
  cols.lat[i] = static_cast<float>(lat);
  cols.lon[i] = static_cast<float>(lon);
  if (cols.lon[i] >= 180.0f) cols.lon[i] = -180.0f;
  cols.alt[i] = static_cast<float>(alt);
  cols.speed[i] = static_cast<float>(speed);
  cols.track[i] = static_cast<float>(azi);
  if (cols.track[i] >= 360.0f) cols.track[i] = 0.0f;
  cols.vrate[i] = static_cast<float>(vrate);
  cols.on_ground[i] = on_ground ? 1 : 0;
}

struct FleetInputs {
  const std::vector<Airport>& airports;
  const std::vector<Route>& routes;
  const std::vector<double>& cumulative;  // of route counts, for the first leg and dead ends
  std::uint64_t icao_offset;
};

// The fleet: aircraft a (0 ≤ a < opts.aircraft) has the address kIcaoFirst + (a·P + o) mod N (distinct
// aircraft, distinct addresses), one airline (by market share) and flight numbers that count up from a
// random one, leg after leg, so (icao24, callsign) never repeats and every leg is one Flight. Its first
// off-block time lies up to 6 h before the first day, so that the fleet is already airborne at its start;
// each next leg leaves from where the last one landed (a route out of that airport, ∝ count; any route
// when none leaves it) after a turnaround of opts.turnaround_min_s..max_s at the gate, where the aircraft
// does not report. Samples outside [day_start, day_start + days) are dropped (a leg with fewer than two
// left is dropped whole). Two RNG streams per aircraft keep legs independent: the aircraft's own (airline,
// routes, turnarounds) and one per leg (cruise level, the flight model, the sampling), so pass 2 can
// regenerate any leg from its header alone.
TrailSet generate_fleet(const DemoOptions& opts, const FleetInputs& in, ProgressFn progress) {
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  const auto& airports = in.airports;
  const auto& routes = in.routes;
  // Routes by origin, with cumulative counts, for the next leg out of an airport.
  std::vector<std::vector<std::uint32_t>> out_routes(airports.size());
  std::vector<std::vector<double>> out_cumulative(airports.size());
  for (std::uint32_t r = 0; r < routes.size(); ++r) {
    out_routes[routes[r].origin].push_back(r);
    auto& c = out_cumulative[routes[r].origin];
    c.push_back((c.empty() ? 0.0 : c.back()) + routes[r].count);
  }
  std::vector<double> airline_cumulative;
  for (const Airline& a : kAirlines)
    airline_cumulative.push_back((airline_cumulative.empty() ? 0 : airline_cumulative.back()) + a.share);

  const double start = opts.day_start, end = opts.day_start + 86400.0 * opts.days;
  struct Leg {
    double off_block = 0, first = 0;  // first: time of the first sample kept
    std::uint32_t count = 0, route = 0;
    std::uint64_t seed = 0;
    char icao24[8], callsign[12];
  };
  auto leg_geodesic = [&](const Route& r) {
    const Airport &o = airports[r.origin], &d = airports[r.destination];
    return geod.InverseLine(o.lat, o.lon, d.lat, d.lon,
                            GeographicLib::Geodesic::LATITUDE | GeographicLib::Geodesic::LONGITUDE |
                                GeographicLib::Geodesic::AZIMUTH | GeographicLib::Geodesic::DISTANCE_IN);
  };
  // Runs leg `g` from off-block to on-block, calling emit(t, model) for every sample inside [start, end).
  // Returns the on-block time.
  auto simulate = [&](const Leg& g, const GeographicLib::GeodesicLine& line, auto&& emit) {
    Rng rng(g.seed);
    const double cruise = cruise_altitude(line.Distance(), line.Azimuth(), rng);
    FlightModel model(line.Distance(), rng, cruise);
    double t = g.off_block;
    if (t >= start && t < end) emit(t, model);
    while (!model.finished()) {
      const double dt = rng.uniform(opts.sample_min_s, opts.sample_max_s);
      model.advance(dt);
      t += dt;
      if (t >= start && t < end) emit(t, model);
    }
    return t;
  };

  // Pass 1: every aircraft's legs, in sequence (a leg starts where and after the last one ended).
  const std::size_t n = opts.aircraft;
  std::vector<std::vector<Leg>> legs_of(n);
  std::atomic<std::size_t> done{0};
  constexpr std::size_t kChunk = 1024;
  for (std::size_t first = 0; first < n; first += kChunk) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(first, std::min(n, first + kChunk), 4), [&](const auto& r) {
          for (std::size_t a = r.begin(); a != r.end(); ++a) {
            Rng arng(opts.seed ^ (0x9e3779b97f4a7c15ull * (a + 1)) ^ 0xf1ee7f1ee7ull);
            const Airline& al = kAirlines[pick(airline_cumulative, arng.uniform())];
            const int numbers = al.number_max - al.number_min + 1;
            const int base = arng.integer(0, numbers - 1);
            char icao24[8];
            std::snprintf(
                icao24, sizeof icao24, "%06x",
                kIcaoFirst + static_cast<std::uint32_t>((a * kIcaoStride + in.icao_offset) % kIcaoCount));
            std::uint32_t route = static_cast<std::uint32_t>(pick(in.cumulative, arng.uniform()));
            double off_block = start - arng.uniform(0, 6 * 3600.0);
            auto& legs = legs_of[a];
            for (std::uint32_t k = 0; off_block < end; ++k) {
              Leg g;
              g.off_block = off_block, g.route = route;
              g.seed = arng.next();
              std::memcpy(g.icao24, icao24, sizeof icao24);
              std::snprintf(
                  g.callsign, sizeof g.callsign, "%s%d", al.icao,
                  al.number_min + static_cast<int>((base + k) % static_cast<std::uint32_t>(numbers)));
              const auto line = leg_geodesic(routes[route]);
              bool any = false;
              const double on_block = simulate(g, line, [&](double t, const FlightModel&) {
                if (!any) g.first = t, any = true;
                ++g.count;
              });
              if (g.count >= 2) legs.push_back(g);
              off_block = on_block + arng.uniform(opts.turnaround_min_s, opts.turnaround_max_s);
              const std::uint32_t at = routes[route].destination;
              route = out_routes[at].empty() ? static_cast<std::uint32_t>(pick(in.cumulative, arng.uniform()))
                                             : out_routes[at][pick(out_cumulative[at], arng.uniform())];
            }
          }
          done += r.size();
        });
    if (progress) progress(0.5 * static_cast<double>(done.load()) / static_cast<double>(n), "generate");
  }

  // Legs in the order TrailSetBuilder::build() gives flights: first sample, then icao24, then callsign.
  std::vector<Leg> legs;
  {
    std::size_t total_legs = 0;
    for (const auto& l : legs_of) total_legs += l.size();
    legs.reserve(total_legs);
    for (auto& l : legs_of) {
      legs.insert(legs.end(), l.begin(), l.end());
      std::vector<Leg>().swap(l);
    }
  }
  std::sort(legs.begin(), legs.end(), [](const Leg& x, const Leg& y) {
    if (x.first != y.first) return x.first < y.first;
    if (const int c = std::strcmp(x.icao24, y.icao24)) return c < 0;
    return std::strcmp(x.callsign, y.callsign) < 0;
  });
  std::uint64_t total = 0;
  std::vector<Flight> flights =
      lay_out_flights(legs.size(), "aircraft", total, [&](std::size_t k, Flight& f) -> std::uint64_t {
        f.icao24 = legs[k].icao24;
        f.callsign = legs[k].callsign;
        return legs[k].count;
      });

  // Pass 2: each leg again from its header, written straight into the columns (the store's own memory:
  // no other copy of the points is ever made).
  PointColumns cols;
  cols.resize(total);
  done = 0;
  const std::size_t m = legs.size();
  constexpr std::size_t kLegChunk = 16384;
  for (std::size_t first = 0; first < m; first += kLegChunk) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, std::min(m, first + kLegChunk), 16),
                      [&](const auto& r) {
                        for (std::size_t k = r.begin(); k != r.end(); ++k) {
                          Flight& fl = flights[k];
                          const Leg& g = legs[k];
                          const auto line = leg_geodesic(routes[g.route]);
                          PathInterpolator path(line, 0.0);
                          std::uint32_t i = fl.begin;
                          simulate(g, line, [&](double t, const FlightModel& md) {
                            double lat, lon, azi;
                            path.at(md.s(), lat, lon, azi);
                            write_sample(cols, i++, t, lat, lon, azi, md.altitude(), md.speed(), md.vrate(),
                                         md.on_ground());
                          });
                          flight_extents(fl, cols);
                        }
                        done += r.size();
                      });
    if (progress) progress(0.5 + 0.5 * static_cast<double>(done.load()) / static_cast<double>(m), "generate");
  }
  std::vector<Leg>().swap(legs);
  if (progress) progress(0.0, "assemble");
  TrailSet set(std::move(cols), std::move(flights));
  if (progress) progress(1.0, "assemble");
  return set;
}

}  // namespace

TrailSet generate_demo_traffic(const DemoOptions& opts, ProgressFn progress) {
  if (opts.aircraft == 0 && (opts.flights < 1 || opts.flights > 1000000))
    throw invalid_argument("flights", "flights must be in 1..1000000, got " + std::to_string(opts.flights));
  if (opts.aircraft > kMaxDemoAircraft)
    throw invalid_argument("aircraft", "aircraft must be in 0..200000, got " + std::to_string(opts.aircraft));
  if (opts.aircraft > 0 && (opts.days < 1 || opts.days > kMaxDemoDays))
    throw invalid_argument("days", "days must be in 1..31, got " + std::to_string(opts.days));
  if (opts.aircraft > 0 && !(opts.turnaround_min_s >= 0 && opts.turnaround_min_s <= opts.turnaround_max_s &&
                             opts.turnaround_max_s <= 86400))
    throw invalid_argument("turnaround", "turnaround must satisfy 0 <= min <= max <= 86400 seconds");
  if (!(opts.sample_min_s > 0) || !(opts.sample_min_s <= 600))
    throw invalid_argument("sample_min_s", "sample_min_s must be in (0, 600] seconds");
  if (!(opts.sample_max_s >= opts.sample_min_s) || !(opts.sample_max_s <= 600))
    throw invalid_argument("sample_max_s", "sample_max_s must be in [sample_min_s, 600] seconds");
  if (!(opts.day_start >= 0 && opts.day_start < kMaxTime - (2 + kMaxDemoDays) * 86400.0))
    throw invalid_argument("day_start", "day_start must be Unix seconds between 1970 and 2100");

  // Airports and routes.
  std::unordered_map<std::string, std::uint32_t> by_iata;
  std::vector<Airport> airports;
  read_csv(opts.airports_csv, "airports_csv", std::array<const char*, 3>{"iata", "latitude", "longitude"},
           [&](const auto& f) {
             double lat, lon;
             if (detail::parse_number(f[1], lat) != detail::Num::ok ||
                 detail::parse_number(f[2], lon) != detail::Num::ok || std::fabs(lat) > 90 ||
                 std::fabs(lon) > 180)
               return;  // unusable row: skipped
             if (by_iata.try_emplace(std::string(f[0]), static_cast<std::uint32_t>(airports.size())).second)
               airports.push_back({lat, lon});
           });
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  std::vector<Route> routes;
  std::vector<double> cumulative;
  read_csv(opts.routes_csv, "routes_csv", std::array<const char*, 3>{"origin", "destination", "count"},
           [&](const auto& f) {
             const auto o = by_iata.find(std::string(f[0])), d = by_iata.find(std::string(f[1]));
             double count;
             if (o == by_iata.end() || d == by_iata.end() ||
                 detail::parse_number(f[2], count) != detail::Num::ok || !(count > 0))
               return;
             double dist;
             geod.Inverse(airports[o->second].lat, airports[o->second].lon, airports[d->second].lat,
                          airports[d->second].lon, dist);
             if (dist < 5000) return;  // same field or a data error: not a flight
             routes.push_back({o->second, d->second, count});
             cumulative.push_back((cumulative.empty() ? 0.0 : cumulative.back()) + count);
           });
  if (routes.empty())
    throw Error(Error::Kind::unprocessable, "routes_csv",
                "no usable route in '" + opts.routes_csv + "' (both airports in '" + opts.airports_csv +
                    "', at least 5 km apart, count > 0)");

  std::vector<double> hour_cumulative, airline_cumulative;
  for (double w : kHourWeights)
    hour_cumulative.push_back((hour_cumulative.empty() ? 0 : hour_cumulative.back()) + w);
  for (const Airline& a : kAirlines)
    airline_cumulative.push_back((airline_cumulative.empty() ? 0 : airline_cumulative.back()) + a.share);

  std::uint64_t icao_seed = opts.seed ^ 0x5bd1e9955bd1e995ull;
  const std::uint64_t icao_offset = rng::splitmix64(icao_seed) % kIcaoCount;
  if (opts.aircraft > 0) return generate_fleet(opts, {airports, routes, cumulative, icao_offset}, progress);

  // One flight, drawn from its own RNG: identity, route, schedule, and the model that produces its samples.
  // Constructing it twice for the same index gives the same flight (the two passes below rely on this).
  struct DemoFlight {
    Rng rng;
    const Airport *origin, *destination;
    GeographicLib::GeodesicLine line;
    double cruise = 0, t0 = 0;
    char icao24[8], callsign[12];
  };
  auto make_flight = [&](std::size_t i, DemoFlight& f) {
    f.rng = Rng(opts.seed ^ (0xd1b54a32d192ed03ull * (i + 1)));
    const Route& r = routes[pick(cumulative, f.rng.uniform())];
    f.origin = &airports[r.origin], f.destination = &airports[r.destination];
    f.line = geod.InverseLine(f.origin->lat, f.origin->lon, f.destination->lat, f.destination->lon,
                              GeographicLib::Geodesic::LATITUDE | GeographicLib::Geodesic::LONGITUDE |
                                  GeographicLib::Geodesic::AZIMUTH | GeographicLib::Geodesic::DISTANCE_IN);
    f.cruise = cruise_altitude(f.line.Distance(), f.line.Azimuth(), f.rng);
    // Off-block time: local hour from the diurnal profile, local ≈ UTC + round(lon / 15°) hours.
    const double local =
        (static_cast<double>(pick(hour_cumulative, f.rng.uniform())) + f.rng.uniform()) * 3600;
    const double utc_offset = std::round(f.origin->lon / 15.0) * 3600;
    f.t0 = opts.day_start + std::fmod(local - utc_offset + 2 * 86400.0, 86400.0);
    const Airline& al = kAirlines[pick(airline_cumulative, f.rng.uniform())];
    std::snprintf(f.callsign, sizeof f.callsign, "%s%d", al.icao,
                  f.rng.integer(al.number_min, al.number_max));
    std::snprintf(f.icao24, sizeof f.icao24, "%06x",
                  kIcaoFirst + static_cast<std::uint32_t>((i * kIcaoStride + icao_offset) % kIcaoCount));
  };
  // Runs the model from off-block to on-block, calling emit(t, model) at every sample.
  auto run = [&](DemoFlight& f, auto&& emit) {
    FlightModel model(f.line.Distance(), f.rng, f.cruise);
    double t = f.t0;
    emit(t, model);
    while (!model.finished()) {
      const double dt = f.rng.uniform(opts.sample_min_s, opts.sample_max_s);
      model.advance(dt);
      t += dt;
      emit(t, model);
    }
  };

  // Pass 1: identity, start time and sample count of every flight (no positions: cheap).
  struct Header {
    double t0;
    std::uint32_t count;
    char icao24[8], callsign[12];
  };
  const std::size_t n = opts.flights;
  std::vector<Header> headers(n);
  std::atomic<std::size_t> done{0};
  const auto report = [&](double base, double span) {
    if (progress)
      progress(base + span * static_cast<double>(done.load()) / static_cast<double>(n), "generate");
  };
  constexpr std::size_t kChunk = 4096;  // progress is reported between chunks, from the caller's thread only
  for (std::size_t first = 0; first < n; first += kChunk) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, std::min(n, first + kChunk), 16),
                      [&](const auto& r) {
                        DemoFlight f;
                        for (std::size_t i = r.begin(); i != r.end(); ++i) {
                          make_flight(i, f);
                          Header& h = headers[i];
                          h.t0 = f.t0, h.count = 0;
                          std::memcpy(h.icao24, f.icao24, sizeof h.icao24);
                          std::memcpy(h.callsign, f.callsign, sizeof h.callsign);
                          run(f, [&](double, const FlightModel&) { ++h.count; });
                        }
                        done += r.size();
                      });
    report(0.0, 0.25);
  }

  // Flights in the order TrailSetBuilder::build() gives them: start time, then icao24, then callsign.
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const Header &x = headers[a], &y = headers[b];
    if (x.t0 != y.t0) return x.t0 < y.t0;
    if (const int c = std::strcmp(x.icao24, y.icao24)) return c < 0;
    return std::strcmp(x.callsign, y.callsign) < 0;
  });
  std::uint64_t total = 0;
  std::vector<Flight> flights =
      lay_out_flights(n, "flights", total, [&](std::size_t k, Flight& f) -> std::uint64_t {
        const Header& h = headers[order[k]];
        f.icao24 = h.icao24;
        f.callsign = h.callsign;
        return h.count;
      });

  // Pass 2: the same flights again, now writing their samples straight into the columns. Building the
  // TrailSet directly (rather than through TrailSetBuilder) avoids a serial hash-map insert and a copy of
  // every sample; the result is identical because generated flights are time-sorted, have no duplicate
  // times or long gaps, and have distinct (icao24, callsign) keys — the test suite checks the equivalence.
  PointColumns cols;
  cols.resize(total);
  done = 0;
  for (std::size_t first = 0; first < n; first += kChunk) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, std::min(n, first + kChunk), 16),
                      [&](const auto& r) {
                        DemoFlight f;
                        for (std::size_t k = r.begin(); k != r.end(); ++k) {
                          Flight& fl = flights[k];
                          make_flight(order[k], f);
                          PathInterpolator path(f.line, 0.0);
                          std::uint32_t i = fl.begin;
                          run(f, [&](double t, const FlightModel& m) {
                            double lat, lon, azi;
                            path.at(m.s(), lat, lon, azi);
                            cols.t[i] = t;
                            cols.lat[i] = static_cast<float>(lat);
                            cols.lon[i] = static_cast<float>(lon);
                            if (cols.lon[i] >= 180.0f) cols.lon[i] = -180.0f;
                            cols.alt[i] = static_cast<float>(m.altitude());
                            cols.speed[i] = static_cast<float>(m.speed());
                            cols.track[i] = static_cast<float>(azi);
                            if (cols.track[i] >= 360.0f) cols.track[i] = 0.0f;
                            cols.vrate[i] = static_cast<float>(m.vrate());
                            cols.on_ground[i] = m.on_ground() ? 1 : 0;
                            ++i;
                          });
                          flight_extents(fl, cols);
                        }
                        done += r.size();
                      });
    report(0.25, 0.75);
  }
  if (progress) progress(0.0, "assemble");
  TrailSet set(std::move(cols), std::move(flights));
  if (progress) progress(1.0, "assemble");
  return set;
}

}  // namespace trailscope::ingest
