// GET /api/v1/datasets/{dataset}/flights sorted on the server: every column in both orders on the real
// Europe day, paged through, against rows computed here by a plain scan and ordered by a comparator written
// here (a tuple key with the id as the last element); "in window" and "whole flight" columns against their
// definitions; the refusals with their exact messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <variant>

#include "europe_dataset.hpp"
#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT0 = 1514764800.0;  // 2018-01-01T00:00:00Z

struct Row {
  std::uint32_t id;
  double t_start = 0, t_end = 0, alt_max = NAN;
  std::uint64_t points = 0;
};

class FlightsSort : public test_routes::RouteFixture {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(test_routes::europe_so6())) GTEST_SKIP() << "the Europe SO6 day is absent";
    open(test_routes::europe_dataset("eu"));
  }
  void expect_detail(const Response& r, const std::string& param, const std::string& detail) {
    expect_error(r, 400, "invalid_argument", param);
    EXPECT_EQ(body(r)["detail"], detail) << r.body;
  }
};

TEST_F(FlightsSort, EveryColumnBothOrdersPagedAgainstAPlainSort) {
  const TrailSet& set = *test_routes::europe_trails();
  const auto& p = set.points();
  // The window 06:00-12:00 above FL100 (3048 m): many flights are only partly inside, so "in window" and
  // "whole flight" columns differ.
  const double t0 = kT0 + 6 * 3600, t1 = kT0 + 12 * 3600, alt_min = 10000 * 0.3048;
  std::vector<Row> rows;
  for (std::uint32_t fi = 0; fi < set.num_flights(); ++fi) {
    const Flight& f = set.flights()[fi];
    Row r{fi};
    for (std::size_t i = f.begin; i < f.end; ++i) {
      if (!(p.t[i] >= t0 && p.t[i] < t1 && p.alt[i] >= alt_min)) continue;
      if (r.points++ == 0) r.t_start = p.t[i];
      r.t_end = p.t[i];
      if (std::isnan(r.alt_max) || p.alt[i] > r.alt_max) r.alt_max = p.alt[i];
    }
    if (r.points) rows.push_back(r);
  }
  ASSERT_GT(rows.size(), 2000u);
  std::size_t partial = 0;
  for (const Row& r : rows) partial += r.points < set.flights()[r.id].size();
  EXPECT_GT(partial, rows.size() / 2);

  using Key = std::variant<double, std::string>;
  const auto key_of = [&](const Row& r, const std::string& col) -> Key {
    const Flight& f = set.flights()[r.id];
    if (col == "id") return double(r.id);
    if (col == "icao24") return f.icao24;
    if (col == "callsign") return f.callsign;
    if (col == "t_start") return r.t_start;
    if (col == "t_end") return r.t_end;
    if (col == "duration_s") return r.t_end - r.t_start;
    if (col == "points") return double(r.points);
    if (col == "alt_max_m") return r.alt_max;
    if (col == "flight_t_start") return f.t_min;
    if (col == "flight_t_end") return f.t_max;
    if (col == "flight_duration_s") return f.t_max - f.t_min;
    return double(f.size());  // flight_points
  };
  const std::vector<std::string> cols = {"id",
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
  for (const auto& col : cols)
    for (const std::string order : {"asc", "desc"}) {
      std::vector<std::pair<Key, std::uint32_t>> expect;
      for (const Row& r : rows) expect.emplace_back(key_of(r, col), r.id);
      // Descending: negate numbers; strings sort descending by a reversed comparison. The id stays ascending.
      std::sort(expect.begin(), expect.end(), [&](const auto& a, const auto& b) {
        if (a.first != b.first) return order == "asc" ? a.first < b.first : b.first < a.first;
        return a.second < b.second;
      });
      std::vector<std::uint32_t> got;
      for (int page = 0;; ++page) {
        const Response r = get("/api/v1/datasets/eu/flights", {{"t0", std::to_string(t0)},
                                                               {"t1", std::to_string(t1)},
                                                               {"alt_min", "10000"},
                                                               {"sort", col},
                                                               {"order", order},
                                                               {"page", std::to_string(page)},
                                                               {"page_size", "1000"}});
        ASSERT_EQ(r.status, 200) << r.body;
        const auto j = body(r);
        EXPECT_EQ(j["total"], rows.size());
        EXPECT_EQ(j["sort"], col);
        EXPECT_EQ(j["order"], order);
        if (j["flights"].empty()) break;
        for (const auto& f : j["flights"]) got.push_back(f["id"].get<std::uint32_t>());
      }
      ASSERT_EQ(got.size(), expect.size()) << col << " " << order;
      for (std::size_t k = 0; k < got.size(); ++k)
        ASSERT_EQ(got[k], expect[k].second) << col << " " << order << " at " << k;
    }
  // No altitude is unknown here (SO6 has flight levels), so check the NaN rule on alt_max_m elsewhere.
}

TEST_F(FlightsSort, InWindowAndWholeFlightColumns) {
  const TrailSet& set = *test_routes::europe_trails();
  const auto& p = set.points();
  const double t0 = kT0 + 8 * 3600, t1 = kT0 + 9 * 3600;
  const auto j = body(get("/api/v1/datasets/eu/flights",
                          {{"t0", std::to_string(t0)}, {"t1", std::to_string(t1)}, {"page_size", "1000"}}));
  ASSERT_EQ(j["flights"].size(), 1000u);
  for (const auto& row : j["flights"]) {
    const Flight& f = set.flights()[row["id"].get<std::uint32_t>()];
    double first = NAN, last = NAN;
    std::uint64_t n = 0;
    for (std::size_t i = f.begin; i < f.end; ++i)
      if (p.t[i] >= t0 && p.t[i] < t1) {
        if (!n++) first = p.t[i];
        last = p.t[i];
      }
    EXPECT_EQ(row["t_start"].get<double>(), first);
    EXPECT_EQ(row["t_end"].get<double>(), last);
    EXPECT_EQ(row["duration_s"].get<double>(), last - first);
    EXPECT_EQ(row["points"].get<std::uint64_t>(), n);
    EXPECT_EQ(row["flight_t_start"].get<double>(), p.t[f.begin]);
    EXPECT_EQ(row["flight_t_end"].get<double>(), p.t[f.end - 1]);
    EXPECT_EQ(row["flight_duration_s"].get<double>(), p.t[f.end - 1] - p.t[f.begin]);
    EXPECT_EQ(row["flight_points"].get<std::uint64_t>(), f.size());
  }
}

TEST_F(FlightsSort, Refusals) {
  expect_detail(get("/api/v1/datasets/eu/flights", {{"sort", "speed"}}), "sort",
                "sort must be one of id, icao24, callsign, t_start, t_end, duration_s, points, alt_max_m, "
                "flight_t_start, flight_t_end, flight_duration_s, flight_points, got 'speed'");
  expect_detail(get("/api/v1/datasets/eu/flights", {{"order", "up"}}), "order",
                "order must be 'asc' or 'desc', got 'up'");
}

// An unknown highest altitude sorts last in both orders; ties by ascending id in both orders.
class FlightsSortHand : public test_routes::RouteFixture {
 protected:
  FlightsSortHand() {
    TrailSetBuilder b;
    Sample s;
    const std::vector<std::pair<std::string, float>> flights = {
        {"AAA", 100.f}, {"BBB", Sample::kUnknown}, {"CCC", 200.f}, {"DDD", 100.f}};
    for (std::size_t k = 0; k < flights.size(); ++k) {
      s.lat = 50, s.lon = 8, s.alt = flights[k].second;
      s.t = kT0;
      b.add("bbbbb" + std::to_string(k), flights[k].first, s);
      s.t = kT0 + 60;
      b.add("bbbbb" + std::to_string(k), flights[k].first, s);
    }
    auto ds = std::make_shared<Dataset>();
    ds->id = "hand", ds->name = "hand", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
    ds->trails = std::make_shared<const TrailSet>(b.build());
    open(ds);
  }
  std::vector<std::string> callsigns(const std::string& order) {
    std::vector<std::string> out;
    const Response r = get("/api/v1/datasets/hand/flights", {{"sort", "alt_max_m"}, {"order", order}});
    EXPECT_EQ(r.status, 200) << r.body;
    const auto j = body(r);  // named: a range-for over a temporary's member would read freed memory
    for (const auto& f : j["flights"]) out.push_back(f["callsign"]);
    return out;
  }
};

TEST_F(FlightsSortHand, UnknownAltitudeLastInBothOrders) {
  EXPECT_EQ(callsigns("asc"), (std::vector<std::string>{"AAA", "DDD", "CCC", "BBB"}));
  EXPECT_EQ(callsigns("desc"), (std::vector<std::string>{"CCC", "AAA", "DDD", "BBB"}));
}

}  // namespace
}  // namespace trailscope::server
