#include "trailscope/trails/export.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope {

ExportPlan plan_export(const TrailSet& set, const Query& q, std::uint64_t max_points) {
  const auto& pts = set.points();
  const auto& flights = set.flights();
  const PointFilter filter(q);
  std::vector<std::uint64_t> counts(flights.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, flights.size(), 16), [&](const auto& r) {
    for (std::size_t fi = r.begin(); fi != r.end(); ++fi) {
      const Flight& f = flights[fi];
      if (!q.may_match(f)) continue;
      if (filter.contains(f)) {
        counts[fi] = f.size();
        continue;
      }
      std::uint64_t n = 0;
      for (std::size_t i = f.begin; i < f.end; ++i) n += filter(pts, i);
      counts[fi] = n;
    }
  });
  ExportPlan plan;
  for (std::size_t fi = 0; fi < counts.size(); ++fi)
    if (counts[fi]) plan.flights.push_back(static_cast<std::uint32_t>(fi)), plan.points += counts[fi];
  if (plan.points > max_points)
    throw Error(Error::Kind::payload_too_large, "max_points",
                "the window holds " + std::to_string(plan.points) + " points, more than max_points=" +
                    std::to_string(max_points) + ": narrow the window or the filters");
  return plan;
}

const std::string& flights_csv_header() {
  static const std::string h =
      "flight_id,icao24,callsign,t,lat,lon,alt_m,speed_ms,track_deg,vrate_ms,on_ground\n";
  return h;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

void append_flight_csv(std::string& out, const TrailSet& set, const PointFilter& filter, std::uint32_t id) {
  const Flight& f = set.flights().at(id);
  const auto& p = set.points();
  const std::string prefix =
      std::to_string(id) + "," + csv_field(f.icao24) + "," + csv_field(f.callsign) + ",";
  const auto value = [&out](float v) {
    out += ',';
    if (v == v) append_shortest(out, v);
  };
  for (std::size_t i = f.begin; i < f.end; ++i) {
    if (!filter(p, i)) continue;
    out += prefix;
    append_shortest(out, p.t[i]);
    value(p.lat[i]);
    value(p.lon[i]);
    value(p.alt[i]);
    value(p.speed[i]);
    value(p.track[i]);
    value(p.vrate[i]);
    out += p.on_ground[i] ? ",1\n" : ",0\n";
  }
}

}  // namespace trailscope
