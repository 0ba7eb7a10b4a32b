// Sectors (POST/GET/DELETE /api/v1/sectors) and congestion jobs (POST /api/v1/congestion, GET
// /api/v1/congestion/{job}) through the real router:
//   - a synthetic airspace whose counts are worked out by hand below (a sector crossed between two samples,
//     which `samples` misses and `interpolated` catches; a flight below the sector's floor; two flights 3 NM
//     apart at the same level, a known loss of separation);
//   - the job's JSON and CSV equal to calling congestion::count() and losses_of_separation() directly on the
//     same data, on the synthetic airspace and on the real Europe SO6 day;
//   - the job's events (queued, running with monotonic progress, done), the sector store across a restart,
//     the limits, and every refusal with its exact status, parameter and message.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <mutex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "jobs/congestion_job.hpp"
#include "route_fixture.hpp"
#include "store/sector_store.hpp"
#include "trailscope/congestion/counts.hpp"
#include "trailscope/congestion/separation.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT0 = 1514764800.0;  // 2018-01-01T00:00:00Z
constexpr double kFt = 0.3048;

// AAA1 flies east along 45°N from 0°E to 2°E in 20 min at FL350 (one degree of longitude per 10 min);
// BBB2 does the same at FL200; CCC3 flies along 45.05°N from 0.6°E (00:00) through 1.0°E (00:10) to 1.4°E
// (00:20) at FL350. By flight id (start time, then icao24): AAA1 0, BBB2 1, CCC3 2.
std::shared_ptr<Dataset> synthetic(const std::string& id) {
  TrailSetBuilder b;
  const auto add = [&](const char* icao, const char* cs, double t, double lat, double lon, double alt) {
    Sample s;
    s.t = kT0 + t, s.lat = lat, s.lon = lon, s.alt = alt, s.speed = 200, s.track = 90, s.vrate = 0;
    b.add(icao, cs, s);
  };
  add("aaaaa1", "AAA1", 0, 45.0, 0.0, 35000 * kFt);
  add("aaaaa1", "AAA1", 1200, 45.0, 2.0, 35000 * kFt);
  add("bbbbb2", "BBB2", 0, 45.0, 0.0, 20000 * kFt);
  add("bbbbb2", "BBB2", 1200, 45.0, 2.0, 20000 * kFt);
  add("ccccc3", "CCC3", 0, 45.05, 0.6, 35000 * kFt);
  add("ccccc3", "CCC3", 600, 45.05, 1.0, 35000 * kFt);
  add("ccccc3", "CCC3", 1200, 45.05, 1.4, 35000 * kFt);
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

// S1: 0.95°E..1.05°E x 44.9°N..45.1°N, FL300-FL400, peak 1. AAA1 is inside for t in [570, 630] s (no
// sample inside), CCC3 for [525, 675] (its 00:10 sample inside), BBB2 never (below the floor). S2: away
// from all traffic, no thresholds.
const std::string kSectors = R"({"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"name": "S1", "lower_fl": 300, "upper_fl": 400, "peak": 1},
   "geometry": {"type": "Polygon", "coordinates": [[[0.95, 44.9], [1.05, 44.9], [1.05, 45.1], [0.95, 45.1], [0.95, 44.9]]]}},
  {"type": "Feature", "properties": {"name": "S2", "lower_fl": 0, "upper_fl": 100},
   "geometry": {"type": "Polygon", "coordinates": [[[5, 44], [6, 44], [6, 45], [5, 45], [5, 44]]]}}]})";

/// Two windows of 1 h every 20 min over [00:00, 00:30): J = ceil(1800 / 1200) = 2.
nlohmann::json sectors_body(const std::string& sectors, const std::string& method = "interpolated") {
  return {{"dataset", "syn"},
          {"query", {{"t0", "2018-01-01T00:00:00Z"}, {"t1", kT0 + 1800}}},
          {"volumes", {{"sectors", sectors}}},
          {"compute", {"occupancy", "entries", "hotspots", "complexity", "separation"}},
          {"step", 60},
          {"duration", 60},
          {"method", method}};
}

/// The same request, written directly against the compute library.
congestion::CountsRequest direct_request(double t0, double t1, congestion::Method method) {
  congestion::CountsRequest r;
  r.query.t0 = t0, r.query.t1 = t1;
  r.method = method;
  return r;
}

std::string write_csv(const congestion::CountsResult& c, const char* table) {
  std::ostringstream out;
  if (std::string(table) == "series")
    c.write_csv(out);
  else if (std::string(table) == "hotspots")
    c.write_hotspots_csv(out);
  else
    c.write_complexity_csv(out);
  return out.str();
}

/// What a JSON value reads as after the server's serialisation.
nlohmann::json wire(const nlohmann::json& j) {
  return nlohmann::json::parse(json_text(j));
}

/// Whether `a` and `b` are equal, numbers as doubles (an integer and the same double are equal): the
/// complexity figures are sums that congestion::count() adds in a fixed order, so runs agree to the bit.
bool same_values(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_number() && b.is_number()) return a.get<double>() == b.get<double>();
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it)
      if (!b.contains(it.key()) || !same_values(it.value(), b[it.key()])) return false;
    return true;
  }
  if (a.is_array()) {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!same_values(a[i], b[i])) return false;
    return true;
  }
  return a == b;
}

/// The counts equal (everything, the complexity figures included, exactly), and on failure
/// the JSON patch from one to the other rather than both whole answers.
void expect_same(const nlohmann::json& a, const nlohmann::json& b) {
  nlohmann::json x = a, y = b;
  const nlohmann::json cx = x.contains("complexity") ? x["complexity"] : nlohmann::json();
  const nlohmann::json cy = y.contains("complexity") ? y["complexity"] : nlohmann::json();
  x.erase("complexity"), y.erase("complexity");
  EXPECT_TRUE(x == y) << nlohmann::json::diff(x, y).dump().substr(0, 4000);
  EXPECT_TRUE(same_values(cx, cy)) << nlohmann::json::diff(cx, cy).dump().substr(0, 4000);
}

/// CSV texts equal cell by cell, numbers exactly.
void expect_same_csv(const std::string& a, const std::string& b) {
  std::istringstream ia(a), ib(b);
  std::string la, lb;
  std::size_t line = 0;
  while (std::getline(ia, la)) {
    ++line;
    ASSERT_TRUE(std::getline(ib, lb)) << "line " << line << " missing: " << la;
    if (la == lb) continue;
    std::istringstream ca(la), cb(lb);
    std::string xa, xb;
    while (std::getline(ca, xa, ',')) {
      ASSERT_TRUE(std::getline(cb, xb, ',')) << la << " vs " << lb;
      char* ea = nullptr;
      char* eb = nullptr;
      const double va = std::strtod(xa.c_str(), &ea), vb = std::strtod(xb.c_str(), &eb);
      if (xa.empty() || *ea || *eb)
        EXPECT_EQ(xa, xb) << la << " vs " << lb;
      else
        EXPECT_TRUE(same_values(va, vb)) << la << " vs " << lb;
    }
  }
  EXPECT_FALSE(std::getline(ib, lb)) << "extra line: " << lb;
}

/// A dense series of `n` values from the result's sparse {"step"|"window": [...], "count": [...]}.
std::vector<int> dense(const nlohmann::json& series, const char* index, std::size_t n) {
  std::vector<int> v(n, 0);
  for (std::size_t i = 0; i < series.at(index).size(); ++i)
    v.at(series[index][i].get<std::size_t>()) = series["count"][i].get<int>();
  return v;
}

class CongestionRoute : public test_routes::RouteFixture {
 protected:
  CongestionRoute() { open(synthetic("syn")); }

  void expect_detail(const Response& r, int status, const std::string& param, const std::string& detail) {
    static const std::map<int, std::string> kinds = {{400, "invalid_argument"},
                                                     {404, "not_found"},
                                                     {409, "conflict"},
                                                     {413, "payload_too_large"},
                                                     {422, "unprocessable"}};
    expect_error(r, status, kinds.at(status), param);
    EXPECT_EQ(body(r)["detail"], detail);
  }
  std::string upload_sectors(const std::string& text = kSectors, std::map<std::string, std::string> q = {}) {
    const Response r = send("POST", "/api/v1/sectors", text, std::move(q));
    EXPECT_EQ(r.status, 201) << r.body;
    return body(r).at("id");
  }
  /// Submits `b`, waits for the job and answers its id (the job must end done).
  std::string run(const nlohmann::json& b) {
    const Response r = send("POST", "/api/v1/congestion", b.dump());
    EXPECT_EQ(r.status, 202) << r.body;
    const std::string job = body(r)["job"]["id"];
    EXPECT_EQ(header(r, "Location"), "/api/v1/jobs/" + job);
    EXPECT_EQ(body(r)["congestion"], "/api/v1/congestion/" + job);
    const JobState s = app->jobs.wait(job);
    EXPECT_EQ(s.state, "done") << s.to_json().dump();
    return job;
  }
  Response post(const nlohmann::json& b) { return send("POST", "/api/v1/congestion", b.dump()); }
};

TEST_F(CongestionRoute, SectorsAreStoredListedServedAndDeleted) {
  const Response created = send("POST", "/api/v1/sectors", kSectors, {{"name", "south-west"}});
  ASSERT_EQ(created.status, 201) << created.body;
  const auto meta = body(created);
  const std::string id = meta["id"];
  EXPECT_EQ(id, "s1");
  EXPECT_EQ(header(created, "Location"), "/api/v1/sectors/s1");
  EXPECT_EQ(meta["name"], "south-west");
  EXPECT_EQ(meta["sectors"], 2);
  EXPECT_EQ(meta["names"], nlohmann::json({"S1", "S2"}));
  EXPECT_EQ(meta["vertices"], 8);  // rings without their closing vertex
  EXPECT_EQ(meta["bbox"], nlohmann::json({0.95, 44.0, 6.0, 45.1}));
  EXPECT_EQ(meta["lower_fl"], 0);
  EXPECT_EQ(meta["upper_fl"], 400);
  EXPECT_EQ(meta["bytes"], kSectors.size());

  const auto list = body(get("/api/v1/sectors"));
  ASSERT_EQ(list["sectors"].size(), 1u);
  EXPECT_EQ(list["sectors"][0], meta);
  // The stored GeoJSON is the upload, byte for byte.
  const Response geo = get("/api/v1/sectors/s1");
  ASSERT_EQ(geo.status, 200);
  EXPECT_EQ(geo.content_type, "application/geo+json");
  EXPECT_EQ(geo.body, kSectors);
  // Unnamed: named by its id.
  EXPECT_EQ(body(send("POST", "/api/v1/sectors", kSectors))["name"], "s2");

  // A restart finds both whole, and no staging folder is left behind.
  {
    SectorStore reopened(tmp.path() / "store");
    ASSERT_EQ(reopened.list().size(), 2u);
    EXPECT_EQ(reopened.meta("s1"), meta);
    EXPECT_EQ(reopened.geojson("s1"), kSectors);
  }
  for (const auto& e : std::filesystem::directory_iterator(tmp.path() / "store" / "tmp"))
    EXPECT_EQ(e.path().filename().string().rfind("sectors.", 0), std::string::npos) << e.path();

  EXPECT_EQ(send("DELETE", "/api/v1/sectors/s1").status, 204);
  expect_detail(get("/api/v1/sectors/s1"), 404, "sectors", "sectors 's1' does not exist");
  expect_detail(send("DELETE", "/api/v1/sectors/s1"), 404, "sectors", "sectors 's1' does not exist");
  EXPECT_EQ(body(get("/api/v1/sectors"))["sectors"].size(), 1u);
  // Ids are not reused while the store is open.
  EXPECT_EQ(upload_sectors(), "s3");
}

TEST_F(CongestionRoute, SectorUploadsAreValidated) {
  expect_detail(send("POST", "/api/v1/sectors", "{\"type\": "), 400, "body",
                "body: not JSON (a GeoJSON FeatureCollection of Polygon features is expected)");
  expect_detail(send("POST", "/api/v1/sectors", ""), 400, "body", "body: the upload is empty");
  // The parser's own refusals: 422 naming "sectors", nothing stored.
  const Response not_fc = send("POST", "/api/v1/sectors", R"({"type": "Feature"})");
  expect_error(not_fc, 422, "unprocessable", "sectors");
  std::string bowtie = kSectors;
  bowtie.replace(bowtie.find("[1.05, 45.1], [0.95, 45.1]"), 26, "[0.95, 45.1], [1.05, 45.1]");
  const Response crossed = send("POST", "/api/v1/sectors", bowtie);
  expect_error(crossed, 422, "unprocessable", "sectors");
  EXPECT_NE(body(crossed)["detail"].get<std::string>().find("feature 0"), std::string::npos) << crossed.body;
  std::string floors = kSectors;
  floors.replace(floors.find("\"upper_fl\": 400"), 15, "\"upper_fl\": 250");
  expect_error(send("POST", "/api/v1/sectors", floors), 422, "unprocessable", "sectors");
  EXPECT_TRUE(body(get("/api/v1/sectors"))["sectors"].empty());

  expect_detail(send("POST", "/api/v1/sectors", kSectors, {{"name", ""}}), 400, "name",
                "name: 1 to 128 characters");
  expect_detail(send("POST", "/api/v1/sectors", kSectors, {{"nmae", "x"}}), 400, "nmae",
                "unknown query parameter 'nmae'");
  // Larger than the route's body limit (the network layer refuses it before reading; the handler too).
  expect_detail(send("POST", "/api/v1/sectors", std::string(limits::kMaxSectorUploadBytes + 1, ' ')), 413,
                "body", "sector upload exceeds the limit of 16 MiB");
  const BodyRule rule = router.body_rule("POST", "/api/v1/sectors");
  EXPECT_EQ(rule.limit, limits::kMaxSectorUploadBytes);
  EXPECT_EQ(rule.name, "sector upload");
}

// The counts of the synthetic airspace, worked out by hand (see synthetic() and kSectors), and the whole
// answer equal to the compute library's own on the same data.
TEST_F(CongestionRoute, SectorCountsKnownAnswersAndEqualToTheLibrary) {
  const std::string sectors = upload_sectors();
  const std::string job = run(sectors_body(sectors));
  const Response r = get("/api/v1/congestion/" + job);
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["job"], job);
  EXPECT_EQ(j["dataset"], "syn");
  EXPECT_EQ(j["volumes"], nlohmann::json({{"sectors", sectors}}));
  const auto& c = j["counts"];
  EXPECT_EQ(c["steps"], 30);
  EXPECT_EQ(c["entry_windows"], 2);
  EXPECT_EQ(c["flights"], 3);
  ASSERT_EQ(c["volumes"].size(), 2u);
  const auto& s1 = c["volumes"][0];
  EXPECT_EQ(s1["id"], "S1");
  // Interpolated: CCC3 in periods 8..11 (525..675 s), AAA1 in 9..10 (570..630 s); BBB2 never.
  std::vector<int> occupancy(30, 0);
  occupancy[8] = 1, occupancy[9] = 2, occupancy[10] = 2, occupancy[11] = 1;
  EXPECT_EQ(dense(s1["occupancy"], "step", 30), occupancy);
  EXPECT_EQ(dense(s1["entries"], "window", 2), std::vector<int>({2, 0}));
  EXPECT_EQ(s1["max_occupancy"], 2);
  EXPECT_TRUE(c["volumes"][1]["occupancy"]["step"].empty());
  // One peak hotspot: periods 9-10 above S1's peak of 1, both flights.
  ASSERT_EQ(c["hotspots"].size(), 1u);
  const auto& h = c["hotspots"][0];
  EXPECT_EQ(h["volume"], "S1");
  EXPECT_EQ(h["kind"], "peak");
  EXPECT_EQ(h["first_step"], 9);
  EXPECT_EQ(h["last_step"], 10);
  EXPECT_EQ(h["start"], kT0 + 540);
  EXPECT_EQ(h["end"], kT0 + 660);
  EXPECT_EQ(h["peak"], 2);
  EXPECT_EQ(h["excess"], 1);
  ASSERT_EQ(h["flights"].size(), 2u);
  EXPECT_EQ(h["flights"][0]["callsign"], "AAA1");
  EXPECT_EQ(h["flights"][1]["callsign"], "CCC3");
  // AAA1 and CCC3 are 0.05° of latitude (3.0 NM) apart at the same level, abeam at 00:10: one loss of
  // separation, closest at 00:10 at ~5,556 m (M(45°)·0.05° = 5,555.9 m on WGS84).
  const auto& sep = j["separation"];
  ASSERT_EQ(sep["events"].size(), 1u) << sep.dump();
  const auto& e = sep["events"][0];
  EXPECT_EQ(e["callsign_a"], "AAA1");
  EXPECT_EQ(e["callsign_b"], "CCC3");
  EXPECT_NEAR(e["cpa"]["t"].get<double>(), kT0 + 600, 1.0);
  EXPECT_NEAR(e["cpa"]["horizontal_m"].get<double>(), 5555.9, 5.0);
  // |Δlon| < 4 NM / (60 NM·cos 45°) = 0.0943° while abeam: t within (505.7, 694.3) s.
  EXPECT_NEAR(e["t_start"].get<double>(), kT0 + 505.7, 2.0);
  EXPECT_NEAR(e["t_end"].get<double>(), kT0 + 694.3, 2.0);

  // The same request made directly.
  const auto ds = store->get("syn");
  congestion::CountsRequest req = direct_request(kT0, kT0 + 1800, congestion::Method::interpolated);
  req.sectors = congestion::parse_sectors(nlohmann::json::parse(kSectors));
  const congestion::CountsResult counts = congestion::count(*ds->trails, req);
  Query window;
  window.t0 = kT0, window.t1 = kT0 + 1800;
  const congestion::SeparationResult separation = congestion::losses_of_separation(*ds->trails, window);
  expect_same(j["counts"], wire(counts.to_json()));
  expect_same(j["separation"], wire(separation.to_json()));
  for (const char* table : {"series", "hotspots", "complexity"}) {
    const Response csv = get("/api/v1/congestion/" + job, {{"format", "csv"}, {"table", table}});
    ASSERT_EQ(csv.status, 200) << csv.body;
    EXPECT_EQ(csv.content_type, "text/csv");
    expect_same_csv(csv.body, write_csv(counts, table));
  }
  EXPECT_EQ(get("/api/v1/congestion/" + job, {{"format", "csv"}}).body, write_csv(counts, "series"));
  EXPECT_EQ(get("/api/v1/congestion/" + job, {{"format", "csv"}, {"table", "separation"}}).body,
            separation.to_csv());

  // The job's own result is a summary pointing at the answer.
  const JobState s = app->jobs.get(job);
  EXPECT_EQ(s.kind, "congestion");
  EXPECT_EQ(s.dataset, "syn");
  EXPECT_EQ(s.result["congestion"], "/api/v1/congestion/" + job);
  EXPECT_EQ(s.result["volumes"], 2);
  EXPECT_EQ(s.result["hotspots"], 1);
  EXPECT_EQ(s.result["separation_events"], 1);
}

// method=samples counts only reported positions: AAA1 crosses S1 between two samples and is missed; CCC3's
// 00:10 sample is inside.
TEST_F(CongestionRoute, SamplesMethodMissesTheCrossingBetweenSamples) {
  const std::string sectors = upload_sectors();
  nlohmann::json b = sectors_body(sectors, "samples");
  b["compute"] = {"occupancy", "entries"};
  const auto j = body(get("/api/v1/congestion/" + run(b)));
  const auto& s1 = j["counts"]["volumes"][0];
  std::vector<int> occupancy(30, 0);
  occupancy[10] = 1;
  EXPECT_EQ(dense(s1["occupancy"], "step", 30), occupancy);
  EXPECT_EQ(dense(s1["entries"], "window", 2), std::vector<int>({1, 0}));
  // Parts not asked for are left out: no hotspots (S1 has a peak of its own), no complexity, no separation.
  EXPECT_TRUE(j["counts"]["hotspots"].empty());
  EXPECT_EQ(j["counts"]["hotspots_total"], 0);
  EXPECT_TRUE(j["counts"]["complexity"].is_null());
  EXPECT_TRUE(j["separation"].is_null());
  EXPECT_EQ(j["compute"], nlohmann::json({"occupancy", "entries"}));
  const std::string job = j["job"];
  expect_detail(get("/api/v1/congestion/" + job, {{"format", "csv"}, {"table", "hotspots"}}), 400, "table",
                "table hotspots: this result did not compute hotspots");
  expect_detail(get("/api/v1/congestion/" + job, {{"format", "csv"}, {"table", "separation"}}), 400, "table",
                "table separation: this result did not compute separation");
}

TEST_F(CongestionRoute, GridCountsEqualToTheLibrary) {
  const nlohmann::json b = {
      {"dataset", "syn"},
      {"query", {{"t0", kT0}, {"t1", kT0 + 1800}, {"callsign", "?CC3"}}},
      {"volumes", {{"grid", {{"bbox", {-1, 44, 3, 46}}, {"alt_min", 30000}, {"alt_max", 40000}}}}},
      {"step", 120},
      {"duration", 300},
      {"entry_window", 600},
      {"entry_step", 300},
      {"thresholds", {{"peak", 0}, {"sustained", 0}, {"sustained_steps", 2}}}};
  const std::string job = run(b);
  const auto j = body(get("/api/v1/congestion/" + job));
  congestion::CountsRequest req = direct_request(kT0, kT0 + 1800, congestion::Method::interpolated);
  req.query.callsign = "?CC3";
  req.query.bbox = BBox{-1, 44, 3, 46};
  req.query.alt_min = 30000 * kFt, req.query.alt_max = 40000 * kFt;
  req.step_s = 120, req.duration_s = 300, req.entry_window_s = 600, req.entry_step_s = 300;
  req.peak = 0, req.sustained = 0, req.sustained_steps = 2;
  const congestion::CountsResult counts = congestion::count(*store->get("syn")->trails, req);
  expect_same(j["counts"], wire(counts.to_json()));
  EXPECT_EQ(get("/api/v1/congestion/" + job, {{"format", "csv"}}).body, write_csv(counts, "series"));
  // Only CCC3 (callsign ?CC3): every cell it crosses at FL350 is layer 11 (FL330-FL360) of row 405
  // (45°N-45°20'N), and each counts it once at most per period.
  EXPECT_EQ(j["counts"]["flights"], 1);
  ASSERT_FALSE(j["counts"]["volumes"].empty());
  for (const auto& v : j["counts"]["volumes"]) {
    EXPECT_EQ(v["id"].get<std::string>().substr(0, 4), "r405") << v["id"];
    EXPECT_EQ(v["id"].get<std::string>().substr(v["id"].get<std::string>().size() - 3), "l11") << v["id"];
    EXPECT_EQ(v["max_occupancy"], 1);
  }
  EXPECT_FALSE(j["counts"]["hotspots"].empty());
}

TEST_F(CongestionRoute, RequestsAreCheckedBeforeAnyWork) {
  const std::string sectors = upload_sectors();
  const nlohmann::json good = sectors_body(sectors);
  const auto with = [&](const std::string& key, const nlohmann::json& v) {
    nlohmann::json b = good;
    b[key] = v;
    return post(b);
  };
  expect_detail(send("POST", "/api/v1/congestion", "[1]"), 400, "body", "body: must be a JSON object");
  expect_detail(with("colour", 1), 400, "colour", "unknown field 'colour' in the body");
  {
    nlohmann::json b = good;
    b.erase("dataset");
    expect_detail(post(b), 400, "dataset", "dataset: required");
  }
  expect_detail(with("dataset", "nope"), 404, "dataset", "dataset 'nope' does not exist");
  {
    nlohmann::json b = good;
    b["query"].erase("t0");
    expect_detail(post(b), 400, "t0", "t0 is required: congestion counts need a time window [t0, t1)");
  }
  {
    nlohmann::json b = good;
    b["query"]["t1"] = kT0 + 8 * 86400.0;  // more than kMaxCongestionSpanSeconds (7 days)
    expect_detail(post(b), 400, "t1", "t1 - t0 exceeds the longest congestion window of 7 days");
  }
  {
    nlohmann::json b = good;
    b["query"]["bbox"] = "0,44,2,46";
    expect_detail(post(b), 400, "bbox",
                  "bbox: the extent of the grid goes in volumes.grid, not in query (sectors have their own)");
    b["query"].erase("bbox");
    b["query"]["t_0"] = 1;
    expect_detail(post(b), 400, "t_0", "unknown query parameter 't_0'");
  }
  const std::string volumes_detail =
      "volumes: an object {\"grid\": {\"bbox\", \"alt_min\", \"alt_max\"}} or {\"sectors\": \"<id>\"} is "
      "required";
  expect_detail(with("volumes", nlohmann::json::object()), 400, "volumes", volumes_detail);
  expect_detail(with("volumes", {{"grid", nlohmann::json::object()}, {"sectors", sectors}}), 400, "volumes",
                volumes_detail);
  expect_detail(with("volumes", {{"sectors", "s99"}}), 404, "sectors", "sectors 's99' does not exist");
  expect_detail(with("volumes", {{"sectors", 3}}), 400, "sectors",
                "sectors: must be the id of a stored sector set (POST /api/v1/sectors)");
  expect_detail(with("volumes", {{"grid", {{"bbox", {0, 44, "x", 46}}}}}), 400, "bbox",
                "bbox: must be [west, south, east, north] in degrees");
  expect_detail(with("volumes", {{"grid", {{"height", 3}}}}), 400, "height",
                "unknown field 'height' in grid");
  expect_detail(with("compute", {"occupancy", "weather"}), 400, "compute",
                "compute: unknown part 'weather' (occupancy, entries, hotspots, complexity or separation)");
  expect_detail(with("compute", nlohmann::json::array()), 400, "compute",
                "compute: must be a non-empty array of occupancy, entries, hotspots, complexity, separation");
  {
    nlohmann::json b = good;
    b["compute"] = {"occupancy"};
    b["thresholds"] = {{"peak", 3}};
    expect_detail(post(b), 400, "thresholds", "thresholds: they make hotspots, which compute does not list");
  }
  expect_detail(with("thresholds", {{"peak", 3}, {"valley", 1}}), 400, "valley",
                "unknown field 'valley' in thresholds");
  expect_detail(with("thresholds", {{"peak", -1}}), 400, "peak",
                "peak must be a number of flights >= 0, got -1");
  expect_detail(with("method", "guess"), 400, "method",
                "method must be 'interpolated' or 'samples', got 'guess'");
  expect_detail(with("duration", 30), 400, "duration", "duration must lie in [60, 3600] seconds, got 30");
  expect_detail(with("step", "soon"), 400, "step", "step: 'soon' is not a number");
  // Cost bounds: more periods than kMaxCongestionSteps (a week at 1 s), more cells than kMaxGridCells.
  {
    nlohmann::json b = good;
    b["query"]["t1"] = kT0 + 2 * 86400.0;
    b["step"] = 1;
    expect_detail(
        post(b), 413, "step",
        "the window holds 172800 counting periods, more than the limit of 100000; use a longer step or a "
        "shorter window");
  }
  expect_error(with("volumes", {{"grid", {{"alt_min", 0}, {"alt_max", 80000}}}}), 413, "payload_too_large",
               "bbox");
  // Nothing was queued by any of these.
  EXPECT_TRUE(app->jobs.list().empty());
}

TEST_F(CongestionRoute, ResultsFollowTheJobAndAreKeptBounded) {
  expect_detail(get("/api/v1/congestion/j99"), 404, "job", "job 'j99' does not exist");
  // Jobs ahead of it hold every worker: the congestion job is queued and has no result yet.
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::vector<JobState> blockers;
  for (unsigned w = 0; w < limits::kJobWorkers; ++w)
    blockers.push_back(app->jobs.submit("test", "", [released](const ProgressFn&, const CancelToken&) {
      released.wait();
      return nlohmann::json::object();
    }));
  const JobState& blocker = blockers.front();
  const Response accepted = post(sectors_body(upload_sectors()));
  ASSERT_EQ(accepted.status, 202);
  const std::string queued = body(accepted)["job"]["id"];
  expect_detail(get("/api/v1/congestion/" + queued), 409, "job",
                "job '" + queued + "' is queued; its result is not ready (GET /api/v1/jobs/" + queued +
                    " or the WebSocket shows its progress)");
  expect_detail(get("/api/v1/congestion/" + blocker.id), 404, "job",
                "job '" + blocker.id + "' is a test job, not a congestion job");
  release.set_value();
  EXPECT_EQ(app->jobs.wait(queued).state, "done");
  ASSERT_EQ(get("/api/v1/congestion/" + queued).status, 200);
  expect_detail(get("/api/v1/congestion/" + queued, {{"format", "xml"}}), 400, "format",
                "format must be json or csv, got 'xml'");
  expect_detail(get("/api/v1/congestion/" + queued, {{"format", "csv"}, {"table", "rows"}}), 400, "table",
                "table must be series, hotspots, complexity or separation, got 'rows'");
  expect_detail(get("/api/v1/congestion/" + queued, {{"table", "series"}}), 400, "table",
                "table: applies to format=csv (the JSON holds every table)");

  // kMaxCongestionResults more: the first result is dropped (its job stays), the last ones are kept.
  nlohmann::json small = sectors_body("s1");
  small["compute"] = {"occupancy"};
  std::vector<std::string> jobs;
  for (std::size_t i = 0; i < limits::kMaxCongestionResults; ++i) jobs.push_back(run(small));
  expect_detail(get("/api/v1/congestion/" + queued), 404, "job",
                "the result of congestion job '" + queued +
                    "' is no longer kept (the server keeps the last " +
                    std::to_string(limits::kMaxCongestionResults) + ", kMaxCongestionResults)");
  EXPECT_EQ(app->jobs.get(queued).state, "done");
  for (const auto& id : jobs) EXPECT_EQ(get("/api/v1/congestion/" + id).status, 200) << id;
}

// The real Europe SO6 day (11,043 flights): a two-hour window over western Europe on the grid with
// separation, and on two sectors; the answers are the library's, and the job reports its progress.
class CongestionEurope : public test_routes::RouteFixture {
 protected:
  static std::filesystem::path so6() {
    return test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
  }
  static std::shared_ptr<const TrailSet> europe() {
    static const auto set = std::make_shared<const TrailSet>(ingest::ingest_file(so6().string()));
    return set;
  }
  void SetUp() override {
    if (!std::filesystem::exists(so6())) GTEST_SKIP() << so6() << " is absent";
    auto ds = std::make_shared<Dataset>();
    ds->id = "europe", ds->name = "europe", ds->format = "so6", ds->created = "2026-01-01T00:00:00Z";
    ds->trails = europe();
    open(ds);
  }
};

TEST_F(CongestionEurope, GridAndSeparationEqualToTheLibraryWithProgressEvents) {
  std::mutex mu;
  std::vector<JobState> events;
  app->jobs.add_listener([&](const JobState& s) {
    std::lock_guard lock(mu);
    if (s.kind == "congestion") events.push_back(s);
  });
  const double t0 = kT0 + 8 * 3600, t1 = kT0 + 10 * 3600;
  const nlohmann::json b = {
      {"dataset", "europe"},
      {"query", {{"t0", "2018-01-01T08:00:00Z"}, {"t1", "2018-01-01T10:00:00Z"}}},
      {"volumes", {{"grid", {{"bbox", "-5,45,10,55"}, {"alt_min", 20000}, {"alt_max", 45000}}}}},
      {"compute", {"occupancy", "entries", "hotspots", "complexity", "separation"}},
      {"thresholds", {{"peak", 6}, {"sustained", 4}}}};
  const Response accepted = send("POST", "/api/v1/congestion", b.dump());
  ASSERT_EQ(accepted.status, 202) << accepted.body;
  const std::string job = body(accepted)["job"]["id"];
  ASSERT_EQ(app->jobs.wait(job).state, "done");
  const Response r = get("/api/v1/congestion/" + job);
  ASSERT_EQ(r.status, 200);
  const auto j = body(r);

  congestion::CountsRequest req = direct_request(t0, t1, congestion::Method::interpolated);
  req.query.bbox = BBox{-5, 45, 10, 55};
  req.query.alt_min = 20000 * kFt, req.query.alt_max = 45000 * kFt;
  req.peak = 6, req.sustained = 4;
  const congestion::CountsResult counts = congestion::count(*europe(), req);
  const congestion::SeparationResult separation = congestion::losses_of_separation(*europe(), req.query);
  EXPECT_GT(counts.flights, 1000u);
  EXPECT_GT(counts.volumes.size(), 100u);
  expect_same(j["counts"], wire(counts.to_json()));
  expect_same(j["separation"], wire(separation.to_json()));
  for (const char* table : {"series", "hotspots", "complexity"})
    EXPECT_EQ(get("/api/v1/congestion/" + job, {{"format", "csv"}, {"table", table}}).body,
              write_csv(counts, table));
  EXPECT_EQ(get("/api/v1/congestion/" + job, {{"format", "csv"}, {"table", "separation"}}).body,
            separation.to_csv());

  // The events the WebSocket forwards: queued, running, progress that never goes back, done last with the
  // summary.
  std::lock_guard lock(mu);
  ASSERT_GE(events.size(), 3u);
  EXPECT_EQ(events.front().state, "queued");
  EXPECT_EQ(events[1].state, "running");
  EXPECT_EQ(events.back().state, "done");
  EXPECT_EQ(events.back().result["congestion"], "/api/v1/congestion/" + job);
  EXPECT_EQ(events.back().result["separation_events"], separation.events.size());
  // The Europe window takes long enough (about a second here) for progress to be reported in between.
  EXPECT_TRUE(std::any_of(events.begin(), events.end(), [](const JobState& e) {
    return e.state == "running" && e.progress > 0 && e.progress < 1 && !e.stage.empty();
  }));
  const std::set<std::string> stages = {"", "inside", "counts", "complexity", "separation"};
  for (std::size_t i = 1; i < events.size(); ++i) {
    EXPECT_GE(events[i].progress, events[i - 1].progress);
    EXPECT_TRUE(stages.count(events[i].stage)) << events[i].stage;
  }
}

TEST_F(CongestionEurope, SectorsEqualToTheLibrary) {
  // Two rectangles: around Paris (FL100-FL300, peak 10) and over the Channel (FL250-FL450).
  const std::string geo = R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "properties": {"name": "PARIS", "lower_fl": 100, "upper_fl": 300, "peak": 10, "sustained": 8},
     "geometry": {"type": "Polygon", "coordinates": [[[1.5, 48.3], [3.5, 48.3], [3.5, 49.4], [1.5, 49.4], [1.5, 48.3]]]}},
    {"type": "Feature", "properties": {"name": "CHANNEL", "lower_fl": 250, "upper_fl": 450},
     "geometry": {"type": "Polygon", "coordinates": [[[-2, 49.5], [2, 50.2], [1, 51], [-2.5, 50.5], [-2, 49.5]]]}}]})";
  const Response up = send("POST", "/api/v1/sectors", geo);
  ASSERT_EQ(up.status, 201) << up.body;
  const nlohmann::json b = {{"dataset", "europe"},
                            {"query", {{"t0", kT0 + 6 * 3600}, {"t1", kT0 + 12 * 3600}}},
                            {"volumes", {{"sectors", body(up)["id"]}}},
                            {"step", 300},
                            {"duration", 600},
                            {"method", "samples"},
                            {"thresholds", {{"sustained", 5}, {"sustained_steps", 2}}}};
  const Response accepted = send("POST", "/api/v1/congestion", b.dump());
  ASSERT_EQ(accepted.status, 202) << accepted.body;
  const std::string job = body(accepted)["job"]["id"];
  ASSERT_EQ(app->jobs.wait(job).state, "done");
  congestion::CountsRequest req =
      direct_request(kT0 + 6 * 3600, kT0 + 12 * 3600, congestion::Method::samples);
  req.sectors = congestion::parse_sectors(nlohmann::json::parse(geo));
  req.step_s = 300, req.duration_s = 600, req.sustained = 5, req.sustained_steps = 2;
  const congestion::CountsResult counts = congestion::count(*europe(), req);
  EXPECT_GT(counts.volumes[0].occupancy.max(), 0u);
  expect_same(body(get("/api/v1/congestion/" + job))["counts"], wire(counts.to_json()));
  EXPECT_EQ(get("/api/v1/congestion/" + job, {{"format", "csv"}}).body, write_csv(counts, "series"));
}

}  // namespace
}  // namespace trailscope::server
