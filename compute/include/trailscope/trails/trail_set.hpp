#pragma once
// A set of flight trails in a columnar layout: one array per variable over all points, flights stored
// as contiguous, time-sorted point ranges. Units are SI throughout (seconds, degrees, metres, m/s).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace trailscope {

/// One flight: a contiguous range [begin, end) of points in a TrailSet, sorted by time, with the
/// extents the query engine uses as its zone map (a flight disjoint from a window is skipped whole).
struct Flight {
  std::string icao24;    ///< 24-bit ICAO address, lower-case hex (6 chars); may be empty for SO6 data
  std::string callsign;  ///< trimmed, upper-case; may be empty
  std::uint32_t begin = 0, end = 0;                          ///< point range
  double t_min = 0, t_max = 0;                               ///< Unix seconds
  float lat_min = 0, lat_max = 0, lon_min = 0, lon_max = 0;  ///< degrees; lon extent may cross 180
  float alt_min = 0, alt_max = 0;     ///< metres over the known altitudes; NaN when no point has one
  bool crosses_antimeridian = false;  ///< some consecutive pair has |Δlon| > 180°
  std::uint32_t size() const { return end - begin; }
};

struct PointColumns;
class TimeIndex;
/// Recomputes a flight's extents (time, position, altitude, antimeridian flag) from its points.
void compute_extents(Flight& f, const PointColumns& points);

/// Columns of all points. Every vector has the same length. NaN marks an unknown value.
struct PointColumns {
  std::vector<double> t;                ///< Unix seconds (UTC)
  std::vector<float> lat;               ///< degrees, [-90, 90]
  std::vector<float> lon;               ///< degrees, [-180, 180)
  std::vector<float> alt;               ///< barometric altitude, metres (NaN unknown)
  std::vector<float> speed;             ///< ground speed, m/s (NaN unknown)
  std::vector<float> track;             ///< true track, degrees clockwise from north, [0, 360) (NaN unknown)
  std::vector<float> vrate;             ///< vertical rate, m/s, positive up (NaN unknown)
  std::vector<std::uint8_t> on_ground;  ///< 1 on the ground, 0 airborne
  std::size_t size() const { return t.size(); }
  void reserve(std::size_t n);
  void resize(std::size_t n);
};

/// Immutable after construction (TrailSetBuilder::build or the store's loader); safe to read from many
/// threads. Web Mercator coordinates and the time index (time_index.hpp) are derived on construction, not
/// stored; copies share the index.
class TrailSet {
 public:
  TrailSet() = default;
  TrailSet(PointColumns points, std::vector<Flight> flights);

  const PointColumns& points() const { return points_; }
  const std::vector<Flight>& flights() const { return flights_; }
  std::size_t num_points() const { return points_.size(); }
  std::size_t num_flights() const { return flights_.size(); }

  /// Web Mercator position of each point as unsigned 32-bit fixed point over the whole world
  /// (x = 2^32·(lon+180)/360, y = 0 at the north edge, latitude clamped to ±85.0511°), as adsb.exposed
  /// stores it: enough for pixel-exact tiles up to zoom 24.
  const std::vector<std::uint32_t>& merc_x() const { return merc_x_; }
  const std::vector<std::uint32_t>& merc_y() const { return merc_y_; }

  /// The time index of the points and flights (trails/time_index.hpp); an invalid (empty) index for a
  /// default-constructed set or flights not in start order.
  const TimeIndex& time_index() const;

  /// Overall extents (Unix seconds, degrees); zero for an empty set.
  double t_min() const { return t_min_; }
  double t_max() const { return t_max_; }
  float lat_min() const { return lat_min_; }
  float lat_max() const { return lat_max_; }
  float lon_min() const { return lon_min_; }
  float lon_max() const { return lon_max_; }

 private:
  PointColumns points_;
  std::vector<Flight> flights_;
  std::vector<std::uint32_t> merc_x_, merc_y_;
  std::shared_ptr<const TimeIndex> time_index_;
  double t_min_ = 0, t_max_ = 0;
  float lat_min_ = 0, lat_max_ = 0, lon_min_ = 0, lon_max_ = 0;
};

}  // namespace trailscope
