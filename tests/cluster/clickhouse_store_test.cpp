// The ClickHouse store against a real local cluster (tests/cluster/cluster.sh, started by the ctest fixture
// `cluster_up`, stopped by `cluster_down`): rows round-trip bit for bit, every read route answers the same
// bytes as over the embedded store on the Europe SO6 day and the demo day, an ingest killed midway leaves
// nothing visible, a delete is whole, and the URL parser refuses what it must.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <csignal>
#include <random>
#include <sys/wait.h>
#include <thread>

#include "route_fixture.hpp"
#include "store/clickhouse_store.hpp"
#include "test_support.hpp"
#include "trailscope/ingest/demo_traffic.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {
namespace fs = std::filesystem;

// ---- without a cluster --------------------------------------------------------------------------------

TEST(ClickHouseUrl, ParsesHostsDatabaseAndCluster) {
  const auto u = ClickHouseUrl::parse("clickhouse://127.0.0.1:29110,ch-2.example:8123/trail_db?cluster=c1");
  ASSERT_EQ(u.hosts.size(), 2u);
  EXPECT_EQ(u.hosts[0].host, "127.0.0.1");
  EXPECT_EQ(u.hosts[0].port, 29110);
  EXPECT_EQ(u.hosts[1].host, "ch-2.example");
  EXPECT_EQ(u.hosts[1].port, 8123);
  EXPECT_EQ(u.database, "trail_db");
  EXPECT_EQ(u.cluster, "c1");
}

TEST(ClickHouseUrl, RefusesWhatIsWrongNamingTheOption) {
  for (const char* bad :
       {"http://h:1/db?cluster=c", "clickhouse://h:1", "clickhouse://h/db?cluster=c",
        "clickhouse://h:0/db?cluster=c", "clickhouse://h:70000/db?cluster=c",
        "clickhouse://h:1,/db?cluster=c", "clickhouse://h:1/db", "clickhouse://h:1/d-b?cluster=c",
        "clickhouse://h:1/db?cluster=c;drop", "clickhouse://h:1/db?cluster=c&user=x",
        "clickhouse://h'x:1/db?cluster=c", "clickhouse://:1/db?cluster=c"}) {
    try {
      ClickHouseUrl::parse(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument) << bad;
      EXPECT_EQ(e.param(), "--store") << bad;
    }
  }
}

TEST(ClickHouseStoreMorton, InterleavesBitByBit) {
  // A second implementation: one bit at a time.
  auto slow = [](std::uint32_t x, std::uint32_t y) {
    std::uint64_t m = 0;
    for (int i = 0; i < 32; ++i)
      m |= std::uint64_t((x >> i) & 1) << (2 * i) | std::uint64_t((y >> i) & 1) << (2 * i + 1);
    return m;
  };
  std::mt19937 rng(7);
  for (int k = 0; k < 10000; ++k) {
    const std::uint32_t x = rng(), y = rng();
    ASSERT_EQ(ClickHouseStore::morton(x, y), slow(x, y)) << x << " " << y;
  }
  EXPECT_EQ(ClickHouseStore::morton(0xffffffffu, 0), 0x5555555555555555ull);
  EXPECT_EQ(ClickHouseStore::morton(0, 0xffffffffu), 0xaaaaaaaaaaaaaaaaull);
  // The aligned z5 tile x16 y10 (256 px) is one Morton range starting at 392 << 54.
  EXPECT_EQ(ClickHouseStore::morton(16u << 27, 10u << 27), 392ull << 54);
}

// ---- on the local cluster ------------------------------------------------------------------------------

/// The URL of the cluster the ctest fixture `cluster_up` starts ($TRAILSCOPE_CLUSTER_URL overrides it).
std::string cluster_url() {
  const char* url = std::getenv("TRAILSCOPE_CLUSTER_URL");
  return url ? url : TRAILSCOPE_CLUSTER_URL_DEFAULT;
}

#define REQUIRE_CLUSTER()                                                                        \
  do {                                                                                           \
    if (!fs::exists("/usr/sbin/clickhouse-server") && !fs::exists("/usr/bin/clickhouse-server")) \
      GTEST_SKIP() << "clickhouse-server is not installed (make deps-test installs it)";         \
  } while (0)

std::shared_ptr<ClickHouseStore> open_cluster(bool leftovers = true) {
  return std::make_shared<ClickHouseStore>(ClickHouseUrl::parse(cluster_url()), leftovers);
}

/// Every byte of the point columns and every flight field the store keeps.
void expect_same_trails(const TrailSet& a, const TrailSet& b) {
  ASSERT_EQ(a.num_points(), b.num_points());
  ASSERT_EQ(a.num_flights(), b.num_flights());
  auto same = [](const auto& x, const auto& y, const char* name) {
    ASSERT_EQ(x.size(), y.size()) << name;
    EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])), 0) << name << " differs";
  };
  same(a.points().t, b.points().t, "t");
  same(a.points().lat, b.points().lat, "lat");
  same(a.points().lon, b.points().lon, "lon");
  same(a.points().alt, b.points().alt, "alt");
  same(a.points().speed, b.points().speed, "speed");
  same(a.points().track, b.points().track, "track");
  same(a.points().vrate, b.points().vrate, "vrate");
  same(a.points().on_ground, b.points().on_ground, "on_ground");
  for (std::size_t f = 0; f < a.num_flights(); ++f) {
    const Flight &x = a.flights()[f], &y = b.flights()[f];
    ASSERT_TRUE(x.begin == y.begin && x.end == y.end && x.icao24 == y.icao24 && x.callsign == y.callsign)
        << "flight " << f;
  }
}

/// A router over `store` as an admin calls it.
struct Side {
  Side(std::shared_ptr<DatasetStore> s, const fs::path& root) : store(std::move(s)) {
    fs::create_directories(root / "uploads");
    router.token = TokenStore(root / "tokens.json").create("test-admin", Role::admin).token;
    app = std::make_unique<App>(store, root / "uploads", fs::path(), limits::kTileCacheBytes, root);
    router = make_router(*app);
  }
  Response post(const std::string& path, std::string body) const {
    Request r;
    r.method = "POST", r.path = path, r.body = std::move(body);
    r.headers.emplace("content-type", "application/json");
    return router.handle(r);
  }
  Response get(const std::string& path, std::map<std::string, std::string> query = {}) const {
    Request r;
    r.method = "GET", r.path = path, r.query = std::move(query);
    return router.handle(r);
  }
  std::shared_ptr<DatasetStore> store;
  std::unique_ptr<App> app;
  test_routes::AdminRouter router;
};

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// Both backends answer every read route with the same status, content type and bytes. Returns how many
/// requests were compared.
int expect_same_answers(const Side& a, const Side& b, const std::string& id, const TrailSet& t) {
  const std::string base = "/api/v1/datasets/" + id;
  const double t0 = t.t_min(), t1 = t.t_max(), mid = std::floor((t0 + t1) / 2);
  auto num = [](double v) { return std::to_string(static_cast<long long>(v)); };
  const std::string lon0 = std::to_string(t.lon_min()),
                    lon1 = std::to_string((t.lon_min() + t.lon_max()) / 2),
                    lat0 = std::to_string(t.lat_min()),
                    lat1 = std::to_string((t.lat_min() + t.lat_max()) / 2);
  // Two flights' addresses for the icao24 filter (SO6 has none: their callsigns then).
  std::vector<std::string> icaos;
  for (std::size_t f = t.num_flights() / 7; f < t.num_flights() && icaos.size() < 2; f += t.num_flights() / 9)
    if (!t.flights()[f].icao24.empty()) icaos.push_back(t.flights()[f].icao24);
  const std::string ids_key = icaos.size() == 2 ? "icao24" : "callsign";
  const std::string ids_value =
      icaos.size() == 2 ? icaos[0] + "," + icaos[1] : t.flights()[t.num_flights() / 5].callsign;
  std::vector<std::pair<std::string, std::map<std::string, std::string>>> reqs = {
      {"/api/v1/datasets", {}},
      {base, {}},
      {base + "/summary", {}},
      {base + "/summary", {{"t0", num(mid - 3600)}, {"t1", num(mid)}}},
      {base + "/summary",
       {{"t0", num(mid - 3600)}, {"t1", num(mid)}, {"bbox", lon0 + "," + lat0 + "," + lon1 + "," + lat1}}},
      {base + "/summary", {{"alt_min", "20000"}, {"alt_max", "40000"}, {"bins", "12"}}},
      {base + "/flights", {}},
      {base + "/flights", {{"page", "3"}, {"page_size", "1000"}}},
      {base + "/flights", {{"t0", num(mid - 1800)}, {"t1", num(mid)}, {"page_size", "1000"}}},
      {base + "/flights", {{"callsign", "A"}}},
      // Pushed down to the shards (store/clickhouse_store.hpp): more windows and every kind of filter.
      {base + "/summary", {{"t0", num(t0)}, {"t1", num(t0 + 3600)}, {"top", "25"}}},
      {base + "/summary", {{"t0", num(mid - 6 * 3600)}, {"t1", num(mid + 1800.5)}, {"bins", "1000"}}},
      {base + "/summary", {{"t0", num(t1 - 600)}, {"t1", num(t1 + 3600)}, {"alt_unit", "m"}}},
      {base + "/summary", {{"t1", num(t0 - 10)}}},
      {base + "/summary", {{"alt_max", "10000"}, {"on_ground", "false"}}},
      {base + "/summary", {{"alt_min", "3000"}, {"alt_unit", "m"}, {"callsign", "A*"}}},
      {base + "/summary", {{ids_key, ids_value}}},
      {base + "/summary", {{"callsign", "ZZZZZZZZ"}}},
      {base + "/summary", {{"bbox", "170,-90,-170,90"}}},
      {base + "/summary",
       {{"t0", num(mid)},
        {"t1", num(mid + 900)},
        {"bbox", lon0 + "," + lat0 + "," + lon1 + "," + lat1},
        {"alt_min", "5000"},
        {"alt_max", "35000"},
        {"format", "csv"},
        {"table", "time_histogram"}}},
      {base + "/summary",
       {{"format", "csv"}, {"table", "totals"}, {"t0", num(mid - 3600)}, {"t1", num(mid)}}},
      {base + "/flights", {{"sort", "alt_max_m"}, {"order", "desc"}, {"page_size", "1000"}}},
      {base + "/flights", {{"sort", "callsign"}, {"page", "2"}, {"page_size", "500"}, {"alt_min", "35000"}}},
      {base + "/flights",
       {{"sort", "points"},
        {"order", "desc"},
        {"bbox", lon0 + "," + lat0 + "," + lon1 + "," + lat1},
        {"t0", num(mid - 3600)},
        {"t1", num(mid)}}},
      {base + "/flights", {{ids_key, ids_value}, {"sort", "flight_duration_s"}}},
      {base + "/flights", {{"on_ground", "true"}}},
      {base + "/flights",
       {{"sort", "duration_s"}, {"order", "desc"}, {"t0", num(t0)}, {"t1", num(t0 + 7200)}}},
      {base + "/flights/0", {}},
      {base + "/flights/" + std::to_string(t.num_flights() / 2), {}},
      {base + "/flights/" + std::to_string(t.num_flights() / 3), {{"max_points", "10"}}},
      {base + "/positions", {{"t", num(mid)}}},
      {base + "/positions", {{"t", num(mid - 7200)}, {"bbox", lon0 + "," + lat0 + "," + lon1 + "," + lat1}}},
      {base + "/positions", {{"t", num(t0)}}},
      {base + "/positions", {{"t", num(t1)}, {"format", "geojson"}}},
      {base + "/positions", {{"t", num(mid + 1234) + ".5"}, {"alt_min", "20000"}, {"alt_max", "36000"}}},
      {base + "/positions", {{"t", num(mid - 3 * 3600 + 17)}, {"callsign", "A*"}, {"on_ground", "false"}}},
      {base + "/positions", {{"t", num(mid + 4 * 3600)}, {ids_key, ids_value}}},
      {base + "/positions", {{"t", num(mid)}, {"max_positions", "10"}}},
      {base + "/positions", {{"t", num(mid)}, {"t0", num(mid - 10)}}},
      {"/tiles/" + id + "/density/0/0/0.png", {}},
      {"/tiles/" + id + "/density/3/4/2.png", {}},
      {"/tiles/" + id + "/density/5/16/10.png", {{"t0", num(mid - 3600)}, {"t1", num(mid)}}},
      {"/tiles/" + id + "/density/4/3/6.png", {}},
      // Tiles are pushed down under every filter, value and kernel (unless a flight crosses 180°).
      {"/tiles/" + id + "/density/4/8/5.png", {{"size", "512"}}},
      {"/tiles/" + id + "/density/6/32/21.png", {{"how", "log"}, {"cmap", "viridis"}}},
      {"/tiles/" + id + "/density/7/66/44.png", {{"min_level", "0.3"}}},
      {"/tiles/" + id + "/density/5/0/0.png", {}},
      {"/tiles/" + id + "/density/2/1/1.png", {{"how", "linear"}}},
      {"/tiles/" + id + "/density/4/8/5.png", {{"kernel", "2"}}},
      {"/tiles/" + id + "/density/4/8/5.png", {{"value", "altitude"}}},
      {"/tiles/" + id + "/density/4/8/5.png", {{"alt_min", "20000"}}},
      // Every other read route of a dataset: tiles with each kind of filter and value, the density legend
      // (these two on the shards), flight GeoJSON, animation, picking, exports, congestion and flow maps
      // (answered from the copy the ClickHouse store fetches, see store/clickhouse_store.hpp).
      {"/tiles/" + id + "/density/4/8/5.png", {{"callsign", "A*"}}},
      {"/tiles/" + id + "/density/5/16/10.png",
       {{"t0", num(mid - 7200)}, {"t1", num(mid)}, {"callsign", "A*"}, {"kernel", "1"}}},
      {"/tiles/" + id + "/density/5/16/10.png",
       {{"value", "speed"}, {"alt_min", "10000"}, {"alt_max", "30000"}}},
      {"/tiles/" + id + "/density/4/8/5.png",
       {{"bbox", lon0 + "," + lat0 + "," + lon1 + "," + lat1}, {"t0", num(mid - 7200)}, {"t1", num(mid)}}},
      {"/tiles/" + id + "/density/6/33/22.png", {{"on_ground", "false"}, {ids_key, ids_value}}},
      {"/tiles/" + id + "/density/3/4/2.png", {{"value", "altitude"}, {"kernel", "1"}, {"size", "512"}}},
      {"/tiles/" + id + "/density/4/8/5.png",
       {{"value", "speed"}, {"t0", num(mid - 3600)}, {"t1", num(mid)}, {"on_ground", "false"}}},
      {"/tiles/" + id + "/density/5/16/10.png",
       {{"value", "altitude"}, {"bbox", lon0 + "," + lat0 + "," + lon1 + "," + lat1}, {"kernel", "2"}}},
      {base + "/density/legend", {{"z", "4"}}},
      {base + "/density/legend", {{"z", "6"}, {"value", "speed"}, {"t0", num(mid - 3600)}, {"t1", num(mid)}}},
      {base + "/density/legend", {{"z", "5"}, {"how", "log"}, {"stops", "5"}, {"callsign", "A*"}}},
      {base + "/flights/5", {{"clip", "1"}, {"t0", num(mid - 3600)}, {"t1", num(mid)}}},
      // Animation chunks start at multiples of their duration (300 s by default).
      {base + "/animation", {{"t", num(std::floor(mid / 300) * 300)}}},
      {base + "/animation", {{"t", num(std::floor(mid / 300) * 300 - 5 * 3600)}, {"callsign", "A*"}}},
      {base + "/pick", {{"lon", "4.76"}, {"lat", "52.3"}, {"zoom", "7"}, {"limit", "50"}}},
      {base + "/pick",
       {{"lon", "2.55"}, {"lat", "49.0"}, {"zoom", "9"}, {"t0", num(mid - 3600)}, {"t1", num(mid)}}},
      {base + "/export", {{"format", "csv"}, {"t0", num(mid - 600)}, {"t1", num(mid)}}},
      {base + "/export",
       {{"format", "geojson"}, {"callsign", "A*"}, {"t0", num(mid - 1800)}, {"t1", num(mid)}}},
      {"/api/v1/datasets/" + id + "/congestion/tiles/6/32/21.png", {{"t", num(mid)}, {"threshold", "2"}}},
      {"/api/v1/datasets/" + id + "/congestion/tiles/4/8/5.png", {{"t", num(mid - 3600)}, {"how", "linear"}}},
      {base + "/flow",
       {{"grid", "64"},
        {"level", "1.5"},
        {"t0", num(mid - 3600)},
        {"t1", num(mid)},
        {"bbox", "-2,44,12,54"}}},
      {base + "/flow", {{"grid", "64"}, {"format", "json"}, {"t0", num(mid - 1800)}, {"t1", num(mid)}}},
      {base + "/flow/5/16/10.png", {{"t0", num(mid - 3600)}, {"t1", num(mid)}}},
  };
  int n = 0, nonempty = 0;
  for (const auto& [path, q] : reqs) {
    const Response ra = a.get(path, q), rb = b.get(path, q);
    std::string qs;
    for (const auto& [k, v] : q) qs += k + "=" + v + "&";
    EXPECT_EQ(ra.status, rb.status) << path << "?" << qs;
    EXPECT_EQ(ra.content_type, rb.content_type) << path << "?" << qs;
    // The summary reports its own run time (elapsed_ms): every other byte must match.
    std::string ba = ra.bytes(), bb = rb.bytes();
    if (ra.content_type == "application/json" && ra.status == 200) {
      auto ja = nlohmann::json::parse(ba), jb = nlohmann::json::parse(bb);
      // So does the flow map's JSON (times: its stages' run times).
      for (const char* timing : {"elapsed_ms", "times"})
        if (ja.is_object() && ja.contains(timing) && jb.contains(timing)) {
          EXPECT_TRUE(ja[timing].is_number() || ja[timing].is_object()) << timing;
          ja.erase(timing), jb.erase(timing);
          ba = ja.dump(), bb = jb.dump();
        }
    }
    EXPECT_TRUE(ba == bb) << path << "?" << qs << ": " << ba.size() << " vs " << bb.size() << " bytes\n"
                          << ba.substr(0, 400) << "\n"
                          << bb.substr(0, 400);
    if (path.find("/summary") != std::string::npos || path.ends_with("/flights") ||
        path.ends_with("/positions")) {
      // The push-down must have found something in most windows (an empty answer compares trivially).
      if (ra.status == 200 && ra.content_type == "application/json")
        nonempty += nlohmann::json::parse(ba).value("points", std::uint64_t{0}) > 0 ||
                    nlohmann::json::parse(ba).value("total", std::uint64_t{0}) > 0 ||
                    nlohmann::json::parse(ba).value("count", std::uint64_t{0}) > 0;
    }
    EXPECT_TRUE(ra.status == 200 || ra.status == 413 || (ra.status == 400 && q.count("t0")))
        << path << "?" << qs << " → " << ra.status << " " << ra.bytes().substr(0, 300);
    ++n;
  }
  EXPECT_GE(nonempty, 19) << "too few summaries and flight lists found points";
  // Every read route of a dataset in the route table was asked at least once (a new one must join above).
  for (const auto& route : a.router.router.routes()) {
    // Bundle tiles read a stored bundle, not the dataset (compare_backends compares a bundle made from it).
    if (route.method != "GET" || route.websocket != WebSocketKind::none ||
        route.pattern.find("{dataset}") == std::string::npos ||
        route.pattern.find("{bundle}") != std::string::npos)
      continue;
    bool asked = false;
    for (const auto& [path, q] : reqs) {
      PathParams params;
      asked = asked || match_route(route.pattern, path, params);
    }
    EXPECT_TRUE(asked) << "no request of " << route.pattern << " compares the two backends";
  }
  return n;
}

/// Puts `ds` into an embedded store and into the cluster, reads it back through a freshly opened
/// ClickHouse store (nothing cached), and compares rows and answers. `has_implausible_values`: the
/// summaries' quality blocks must find some, unfiltered and filtered (the Europe day's SO6 glitches; the
/// generated demo day has none).
void compare_backends(std::shared_ptr<Dataset> ds, const char* label, bool has_implausible_values) {
  test::TempDir tmp;
  auto embedded = std::make_shared<EmbeddedStore>(tmp.path() / "embedded");
  embedded->put(ds);
  {
    auto cluster = open_cluster();
    if (cluster->contains(ds->id)) cluster->remove(ds->id);
    const auto t0 = std::chrono::steady_clock::now();
    double last = 0;
    cluster->put(ds, [&](double f, std::string_view) {
      EXPECT_GE(f, last);
      last = f;
    });
    const double ms = ms_since(t0);
    EXPECT_DOUBLE_EQ(last, 1.0);
    std::printf(
        "%s: put %zu points, %zu flights into the cluster in %.0f ms (%.0f points/s, with segments)\n", label,
        ds->trails->num_points(), ds->trails->num_flights(), ms, ds->trails->num_points() / (ms / 1000));
  }
  {
    // Describing the dataset, listing its flights and their positions read no point table: a freshly
    // opened store answers them as the embedded store does without fetching the dataset.
    auto lazy = open_cluster();
    EXPECT_EQ(lazy->describe(ds->id)->to_json(), ds->to_json());
    EXPECT_EQ(lazy->describe(ds->id)->trails, nullptr);
    const Side e(embedded, tmp.path() / "le"), l(lazy, tmp.path() / "ll");
    const std::string base = "/api/v1/datasets/" + ds->id;
    const std::string mid =
        std::to_string(static_cast<long long>((ds->trails->t_min() + ds->trails->t_max()) / 2));
    for (const auto& [path, q] : std::vector<std::pair<std::string, std::map<std::string, std::string>>>{
             {"/api/v1/datasets", {}},
             {base, {}},
             {base + "/flights", {{"page_size", "1000"}, {"sort", "alt_max_m"}}},
             {base + "/flights", {{"t0", mid}, {"callsign", "A*"}}},
             {base + "/positions", {{"t", mid}}}}) {
      const Response ra = e.get(path, q), rb = l.get(path, q);
      EXPECT_EQ(ra.status, 200) << path;
      EXPECT_TRUE(ra.bytes() == rb.bytes()) << path;
    }
    EXPECT_EQ(lazy->fetched_copies(), 0u) << "a read that needs no point fetched the dataset";
    EXPECT_GE(lazy->pushed_down_reads(), 3u);
    // Density tiles of every kind, their level's span included, are aggregated on the shards too: values,
    // point filters, windows and kernels (unless a flight crosses 180°: then from the fetched copy).
    bool wraps = false;
    for (const Flight& f : ds->trails->flights()) wraps = wraps || f.crosses_antimeridian;
    const TrailSet& t = *ds->trails;
    const std::string m = mid, m1 = std::to_string(std::stoll(mid) - 3600),
                      m2 = std::to_string(std::stoll(mid) - 7200);
    const std::string box = std::to_string(t.lon_min()) + "," + std::to_string(t.lat_min()) + "," +
                            std::to_string((t.lon_min() + t.lon_max()) / 2) + "," +
                            std::to_string((t.lat_min() + t.lat_max()) / 2);
    const std::string tiles = "/tiles/" + ds->id + "/density/";
    int drawn = 0;
    for (const auto& [path, q] : std::vector<std::pair<std::string, std::map<std::string, std::string>>>{
             {tiles + "4/8/5.png", {{"value", "altitude"}}},
             {tiles + "3/4/2.png", {{"value", "speed"}, {"kernel", "1"}, {"size", "512"}}},
             {tiles + "5/16/10.png", {{"value", "altitude"}, {"t0", m1}, {"t1", m}, {"kernel", "2"}}},
             {tiles + "4/8/5.png", {{"alt_min", "20000"}, {"alt_max", "36000"}}},
             {tiles + "4/8/5.png", {{"alt_max", "10000"}, {"how", "log"}}},
             {tiles + "4/8/5.png", {{"bbox", box}, {"t0", m2}, {"t1", m}}},
             {tiles + "6/33/22.png", {{"on_ground", "false"}, {"callsign", "A*"}}},
             {tiles + "5/16/10.png", {{"on_ground", "true"}}},
             {tiles + "5/16/10.png", {{"t0", m1}, {"t1", m}}},
             {tiles + "4/8/5.png", {{"kernel", "3"}, {"value", "speed"}, {"alt_min", "1000"}}},
             {tiles + "2/1/1.png", {{"bbox", "170,-90,-170,90"}}}}) {
      const Response ra = e.get(path, q), rb = l.get(path, q);
      std::string qs;
      for (const auto& [k, v] : q) qs += k + "=" + v + "&";
      EXPECT_EQ(ra.status, 200) << path << "?" << qs << ": " << ra.bytes().substr(0, 300);
      EXPECT_TRUE(ra.bytes() == rb.bytes()) << path << "?" << qs << ": the backends' tiles differ";
      drawn += ra.bytes().size() > 1000;  // more than a transparent tile
    }
    EXPECT_GE(drawn, 7) << "too few of the compared tiles show data";
    // Their legends, from the same spans: the same bytes, no copy.
    for (const auto& [z, q] : std::vector<std::pair<std::string, std::map<std::string, std::string>>>{
             {"4", {{"value", "altitude"}}},
             {"3", {{"value", "speed"}, {"kernel", "1"}, {"size", "512"}}},
             {"4", {{"alt_min", "20000"}, {"alt_max", "36000"}, {"stops", "5"}}},
             {"5", {{"t0", m1}, {"t1", m}, {"how", "log"}}}}) {
      auto with_z = q;
      with_z["z"] = z;
      const Response ra = e.get("/api/v1/datasets/" + ds->id + "/density/legend", with_z),
                     rb = l.get("/api/v1/datasets/" + ds->id + "/density/legend", with_z);
      EXPECT_EQ(ra.status, 200) << ra.bytes().substr(0, 300);
      EXPECT_EQ(ra.bytes(), rb.bytes()) << "z " << z << ": the backends' legends differ";
    }
    if (!wraps) EXPECT_EQ(lazy->fetched_copies(), 0u) << "a density tile or legend fetched the dataset";
    // Summaries, their data-quality block included (the implausible values stored at ingest), under
    // every kind of filter: computed on the shards, no point fetched.
    const std::size_t before = lazy->fetched_copies();
    std::uint64_t flagged = 0, filtered = 0;
    for (const auto& q : std::vector<std::map<std::string, std::string>>{
             {},
             {{"t0", m1}, {"t1", m}},
             {{"alt_min", "30000"}},
             {{"alt_max", "10000"}, {"on_ground", "false"}, {"top", "3"}},
             {{"bbox", box}, {"t0", m2}},
             {{"bbox", "170,-90,-170,90"}},
             {{"callsign", "A*"}, {"alt_min", "1000"}, {"alt_max", "40000"}},
             {{"on_ground", "true"}},
             {{"t0", m2}, {"t1", m1}, {"bbox", box}, {"alt_min", "5000"}, {"alt_unit", "m"}}}) {
      Response ra = e.get(base + "/summary", q), rb = l.get(base + "/summary", q);
      std::string qs;
      for (const auto& [k, v] : q) qs += k + "=" + v + "&";
      ASSERT_EQ(ra.status, 200) << qs << ra.bytes().substr(0, 300);
      auto ja = nlohmann::json::parse(ra.bytes()), jb = nlohmann::json::parse(rb.bytes());
      ja.erase("elapsed_ms"), jb.erase("elapsed_ms");
      EXPECT_EQ(ja.dump(), jb.dump()) << qs;
      const auto& quality = ja["quality"];
      const std::uint64_t n = quality["speed"]["count"].get<std::uint64_t>() +
                              quality["altitude"]["count"].get<std::uint64_t>() +
                              quality["jumps"]["count"].get<std::uint64_t>();
      (q.empty() ? flagged : filtered) += n;
    }
    if (has_implausible_values) {
      EXPECT_GT(flagged, 0u) << "the dataset has no implausible value to compare";
      EXPECT_GT(filtered, 0u) << "no filtered summary found an implausible value";
    }
    EXPECT_EQ(lazy->fetched_copies(), before) << "a summary fetched the dataset";
  }
  auto fresh = open_cluster();
  ASSERT_TRUE(fresh->contains(ds->id));
  const auto t0 = std::chrono::steady_clock::now();
  const auto back = fresh->get(ds->id);
  std::printf("%s: fetched back in %.0f ms\n", label, ms_since(t0));
  expect_same_trails(*ds->trails, *back->trails);
  EXPECT_EQ(back->ingest, ds->ingest);
  EXPECT_EQ(back->created, ds->created);
  EXPECT_EQ(back->to_json(), ds->to_json());

  int tile_reads = 0;
  fresh->on_read(
      [&](const std::string& sql, double) { tile_reads += sql.find(".segments WHERE") != sql.npos; });
  const Side a(embedded, tmp.path() / "a"), b(fresh, tmp.path() / "b");
  const int n = expect_same_answers(a, b, ds->id, *ds->trails);
  // Bundling fetches what it needs from the backend: the same bundle, drawn the same, from both.
  {
    const double mid = std::floor((ds->trails->t_min() + ds->trails->t_max()) / 2);
    const std::string request =
        R"({"source": {"dataset": ")" + ds->id + R"(", "query": {"t0": )" + std::to_string(mid - 3600) +
        R"(, "t1": )" + std::to_string(mid) +
        R"(}}, "params": {"size": 128, "iterations": 4, "h": 16, "spl": 4}, "backend": "cpu"})";
    std::vector<std::string> answers[2];
    int side = 0;
    for (const Side* s : {&a, &b}) {
      const Response r = s->post("/api/v1/bundles", request);
      ASSERT_EQ(r.status, 202) << r.bytes();
      const auto j = nlohmann::json::parse(r.bytes());
      const JobState done = s->app->jobs.wait(j["job"]["id"].get<std::string>());
      ASSERT_EQ(done.state, "done") << done.to_json().dump();
      const std::string bundle = j["bundle"];
      for (const auto& [path, q] : std::vector<std::pair<std::string, std::map<std::string, std::string>>>{
               {"/api/v1/bundles/" + bundle + "/image.png", {}},
               {"/api/v1/bundles/" + bundle + "/polylines", {}},
               {"/tiles/" + ds->id + "/bundle/" + bundle + "/4/8/5.png", {}}}) {
        const Response g = s->get(path, q);
        EXPECT_EQ(g.status, 200) << path << ": " << g.bytes().substr(0, 300);
        answers[side].push_back(g.bytes());
      }
      ++side;
    }
    for (std::size_t i = 0; i < answers[0].size(); ++i)
      EXPECT_TRUE(answers[0][i] == answers[1][i]) << "bundle answer " << i << " differs between the backends";
  }
  bool wraps = false;
  for (const Flight& f : ds->trails->flights()) wraps = wraps || f.crosses_antimeridian;
  // The 20 tiles were aggregated on the shards, and so were their levels' spans (unless a flight crosses
  // 180°: then every tile is drawn from the fetched copy).
  if (wraps)
    EXPECT_EQ(tile_reads, 0);
  else
    EXPECT_GT(tile_reads, 20);
  std::printf("%s: %d tiles aggregated on the shards\n", label, tile_reads);
  // The summaries, flight lists and positions were computed on the shards, not on the fetched copy.
  EXPECT_GE(fresh->pushed_down_reads(), 25u) << "the reads were not pushed down";
  std::printf("%s: %d answers byte-identical on both backends\n", label, n);

  // Delete: gone from this store, from a fresh one, and its rows dropped on every shard.
  fresh->remove(ds->id);
  EXPECT_FALSE(fresh->contains(ds->id));
  EXPECT_FALSE(open_cluster()->contains(ds->id));
  const std::string q = " WHERE dataset = " + ClickHouseClient::quote(ds->id) + " FORMAT TSV";
  for (const char* table : {"points", "segments", "flights"})
    EXPECT_EQ(fresh->client().query("SELECT count() FROM " + fresh->database() + "." + table + q), "0\n")
        << table;
}

TEST(ClickHouseStore, EuropeDayAnswersTheSameOnBothBackends) {
  REQUIRE_CLUSTER();
  const fs::path so6 = test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
  if (!fs::exists(so6)) GTEST_SKIP() << so6 << " is absent";
  ingest::IngestReport report;
  auto ds = std::make_shared<Dataset>();
  ds->trails = std::make_shared<const TrailSet>(ingest::ingest_file(so6.string(), {}, &report));
  ds->id = "europe", ds->name = "Europe 2018-01-01", ds->format = "so6";
  ds->created = "2026-11-26T10:00:00Z", ds->owner = "tester", ds->ingest = report.to_json();
  compare_backends(ds, "Europe SO6 day", true);
}

TEST(ClickHouseStore, DemoDayAnswersTheSameOnBothBackends) {
  REQUIRE_CLUSTER();
  const fs::path src = test::source_dir() / "web/node_modules/vega-datasets/data";
  if (!fs::exists(src / "airports.csv")) GTEST_SKIP() << src << " is absent (npm ci in web/)";
  ingest::DemoOptions opts;
  opts.airports_csv = (src / "airports.csv").string();
  opts.routes_csv = (src / "flights-airport.csv").string();
  opts.flights = 20000;
  opts.seed = 42;
  auto ds = std::make_shared<Dataset>();
  ds->trails = std::make_shared<const TrailSet>(ingest::generate_demo_traffic(opts));
  ds->id = "demo", ds->name = "demo", ds->format = "demo", ds->created = "2026-11-26T10:00:00Z";
  ds->ingest = {{"generator", "demo_traffic"}, {"seed", 42}, {"flights", 20000}};
  compare_backends(ds, "demo day", false);
}

TEST(ClickHouseStore, ADatabaseMadeBeforeTheSegmentAttributesIsStillRead) {
  // The tables as an earlier version made them: segments with prev_t but without the point attributes
  // and values, no table of implausible values. The store writes and reads that layout, and answers the
  // tiles and quality blocks that need what it lacks from a fetched copy, with the same bytes.
  REQUIRE_CLUSTER();
  const fs::path so6 = test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
  if (!fs::exists(so6)) GTEST_SKIP() << so6 << " is absent";
  ClickHouseUrl url = ClickHouseUrl::parse(cluster_url());
  url.database += "_old";
  const std::string db = url.database, on = " ON CLUSTER " + url.cluster;
  ClickHouseClient c(url.hosts);
  c.query("DROP DATABASE IF EXISTS " + db + on);
  c.query("CREATE DATABASE " + db + on);
  auto replicated = [&](const std::string& table) {
    return "ReplicatedMergeTree('/clickhouse/tables/{shard}/" + db + "/" + table + "', '{replica}')";
  };
  c.query(
      "CREATE TABLE " + db + ".points_local" + on +
      " (dataset String, idx UInt32, flight UInt32, t Float64, lat Float32, lon Float32, alt Float32, "
      "speed Float32, track Float32, vrate Float32, on_ground UInt8, mx UInt32, my UInt32, morton UInt64, "
      "hour Int32) ENGINE = " +
      replicated("points_local") + " PARTITION BY dataset ORDER BY (hour, morton)");
  c.query("CREATE TABLE " + db + ".segments_local" + on +
          " (dataset String, idx UInt32, flight UInt32, t0 Float64, t1 Float64, x0 UInt32, y0 UInt32, x1 "
          "UInt32, y1 UInt32, morton UInt64, hour Int32, prev_t Float64) ENGINE = " +
          replicated("segments_local") + " PARTITION BY dataset ORDER BY (hour, morton)");
  c.query("CREATE TABLE " + db + ".flights_local" + on +
          " (dataset String, flight UInt32, begin UInt32, end UInt32, icao24 String, callsign String, t_min "
          "Float64, t_max Float64, lat_min Float32, lat_max Float32, lon_min Float32, lon_max Float32, "
          "alt_min Float32, alt_max Float32, crosses UInt8) ENGINE = " +
          replicated("flights_local") + " PARTITION BY dataset ORDER BY flight");
  for (const std::string t : {"points", "segments", "flights"})
    c.query("CREATE TABLE " + db + "." + t + on + " AS " + db + "." + t + "_local ENGINE = Distributed(" +
            url.cluster + ", " + db + ", " + t + "_local, intHash32(flight))");
  c.query("CREATE TABLE " + db + ".catalogue" + on +
          " (id String, version UInt64, deleted UInt8, name String, format String, created String, owner "
          "String, ingest String, points UInt64, flights UInt64) ENGINE = ReplicatedMergeTree('/clickhouse/"
          "tables/all/" +
          db + "/catalogue', '{shard}-{replica}') ORDER BY (id, version)");

  ingest::IngestReport report;
  auto ds = std::make_shared<Dataset>();
  ds->trails = std::make_shared<const TrailSet>(ingest::ingest_file(so6.string(), {}, &report));
  ds->id = "europe", ds->name = "Europe 2018-01-01", ds->format = "so6";
  ds->created = "2026-11-26T10:00:00Z", ds->owner = "tester", ds->ingest = report.to_json();
  test::TempDir tmp;
  auto embedded = std::make_shared<EmbeddedStore>(tmp.path() / "embedded");
  embedded->put(ds);
  std::make_shared<ClickHouseStore>(url, true)->put(ds);
  auto old = std::make_shared<ClickHouseStore>(url, true);
  EXPECT_EQ(c.query("SELECT count() FROM system.tables WHERE database = " + ClickHouseClient::quote(db) +
                    " AND name LIKE 'events%' FORMAT TSV"),
            "0\n")
      << "the store added tables to an existing database";
  const Side e(embedded, tmp.path() / "e"), o(old, tmp.path() / "o");
  const double mid = std::floor((ds->trails->t_min() + ds->trails->t_max()) / 2);
  const std::string m = std::to_string(static_cast<long long>(mid)),
                    m1 = std::to_string(static_cast<long long>(mid - 3600));
  const std::string tiles = "/tiles/europe/density/";
  int reads = 0;
  for (const auto& [path, q] : std::vector<std::pair<std::string, std::map<std::string, std::string>>>{
           {tiles + "4/8/5.png", {{"t0", m1}, {"t1", m}}},
           {tiles + "4/8/5.png", {{"value", "altitude"}}},
           {tiles + "4/8/5.png", {{"alt_min", "20000"}, {"kernel", "1"}}},
           {"/api/v1/datasets/europe/summary", {{"bbox", "-5,40,10,55"}, {"t0", m1}}}}) {
    const Response ra = e.get(path, q), rb = o.get(path, q);
    EXPECT_EQ(ra.status, 200) << path;
    std::string ba = ra.bytes(), bb = rb.bytes();
    if (ra.content_type == "application/json") {
      auto ja = nlohmann::json::parse(ba), jb = nlohmann::json::parse(bb);
      ja.erase("elapsed_ms"), jb.erase("elapsed_ms");
      ba = ja.dump(), bb = jb.dump();
    }
    EXPECT_TRUE(ba == bb) << path << ": the backends differ";
    ++reads;
  }
  EXPECT_EQ(reads, 4);
  // The windowed count tile and the summary's counts ran on the shards; the rest needed the copy.
  EXPECT_EQ(old->fetched_copies(), 1u);
  EXPECT_GE(old->pushed_down_reads(), 2u);
  c.query("DROP DATABASE " + db + on);
}

TEST(ClickHouseStore, PutAgainAfterDeleteAndConflicts) {
  REQUIRE_CLUSTER();
  TrailSetBuilder b;
  for (int i = 0; i < 50; ++i) {
    Sample s;
    s.t = 1514764800.0 + i * 10, s.lat = 52.0f + i * 0.01f, s.lon = 4.0f, s.alt = std::nanf("");
    b.add("4ca1d0", "KLM1", s);
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = "it's-not", ds->trails = std::make_shared<const TrailSet>(b.build());
  auto store = open_cluster();
  EXPECT_THROW(store->put(ds), Error);  // not a valid id
  ds->id = "small";
  if (store->contains("small")) store->remove("small");
  store->put(ds);
  try {
    store->put(ds);
    ADD_FAILURE() << "a second put of the same id was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::conflict);
  }
  // The same rows again after a delete (replicated tables would skip identical blocks as duplicates).
  store->remove("small");
  store->put(ds);
  expect_same_trails(*ds->trails, *open_cluster()->get("small")->trails);
  store->remove("small");
  try {
    store->remove("small");
    ADD_FAILURE() << "a second delete was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::not_found);
  }
}

/// The value of `read()` once it equals `want`, or its last value after kDdlQueueWait: a DROP PARTITION that
/// outlived the cluster's distributed_ddl_task_timeout (CLUSTER_DDL_TIMEOUT, 10 s here) is still run from the
/// DDL queue by every node, later.
constexpr auto kDdlQueueWait = std::chrono::seconds(120);
std::string eventually(const std::function<std::string()>& read, const std::string& want) {
  const auto until = std::chrono::steady_clock::now() + kDdlQueueWait;
  std::string got = read();
  while (got != want && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    got = read();
  }
  return got;
}

/// `trailscope ingest --store URL` killed (SIGKILL) at failpoint `point`; returns its wait status.
int killed_ingest(const std::string& point, const std::string& name) {
  const char* bin = std::getenv("TRAILSCOPE_BIN");
  const std::string cmd = "TRAILSCOPE_FAILPOINT='" + point + "' '" + (bin ? bin : TRAILSCOPE_BIN_DEFAULT) +
                          "' ingest --quiet --store '" + cluster_url() + "' --name " + name + " '" +
                          test::shared_data("flights/traffic_europe_20180101_m3.so6.gz").string() +
                          "' >/dev/null 2>&1";
  return std::system(cmd.c_str());
}

TEST(ClickHouseStore, IngestKilledMidwayLeavesNothingVisible) {
  REQUIRE_CLUSTER();
  if (!fs::exists(test::shared_data("flights/traffic_europe_20180101_m3.so6.gz")))
    GTEST_SKIP() << "no SO6 day";
  auto rows = [](ClickHouseStore& s, const std::string& id) {
    std::string total;
    for (const char* table : {"points", "segments", "flights"})
      total += s.client().query("SELECT count() FROM " + s.database() + "." + table +
                                " WHERE dataset = " + ClickHouseClient::quote(id) + " FORMAT TSV");
    return total;
  };
  // After the first batch (the flights; no point yet), and after every row but before the catalogue row.
  for (const auto& [point, id] :
       {std::pair<std::string, std::string>{"clickhouse.insert.batch#1", "killed-mid"},
        {"clickhouse.before_catalogue", "killed-late"}}) {
    const int status = killed_ingest(point, id);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL || WEXITSTATUS(status) == 128 + SIGKILL)
        << point << ": status " << status;
    // A CLI-like open (no leftover removal): rows are there, the dataset is not.
    auto look = open_cluster(false);
    EXPECT_FALSE(look->contains(id)) << point;
    EXPECT_NE(rows(*look, id), "0\n0\n0\n") << point << ": the kill came before any row";
    // The server's open removes them: at once, or, when a node took longer than the DDL timeout (a loaded
    // machine), from ZooKeeper's DDL queue a little later.
    auto server = open_cluster(true);
    EXPECT_FALSE(server->contains(id)) << point;
    // clang 14 cannot capture a structured binding (P1091 came in clang 16): copy the id.
    const std::string dataset = id;
    EXPECT_EQ(eventually([&] { return rows(*server, dataset); }, "0\n0\n0\n"), "0\n0\n0\n") << point;
  }
}

TEST(ClickHouseStore, UnreachableNodesAreReportedNotHung) {
  // Nothing listens on port 1: every node refused, Error(unavailable) at once.
  ClickHouseClient client({{"127.0.0.1", 1}, {"127.0.0.1", 1}});
  try {
    client.query("SELECT 1");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unavailable);
    EXPECT_EQ(e.param(), "store");
  }
}

TEST(ClickHouseStore, FailsOverToTheNextNode) {
  REQUIRE_CLUSTER();
  auto url = ClickHouseUrl::parse(cluster_url());
  url.hosts.insert(url.hosts.begin(), ClickHouseEndpoint{"127.0.0.1", 1});  // a dead first node
  ClickHouseClient client(url.hosts);
  EXPECT_EQ(client.query("SELECT 1 FORMAT TSV"), "1\n");
  try {
    client.query("SELECT no_such_column FORMAT TSV");
    ADD_FAILURE() << "no error";
  } catch (const ClickHouseError& e) {
    EXPECT_EQ(e.code(), 47) << e.what();  // UNKNOWN_IDENTIFIER
  }
}

/// Runs tests/cluster/cluster.sh with `args` on the test cluster; true when it exits 0.
bool cluster_script(const std::string& args) {
  const char* script = std::getenv("CLUSTER_SCRIPT");  // a command line, e.g. "bash tests/cluster/cluster.sh"
  return std::system(((script ? script : TRAILSCOPE_CLUSTER_SCRIPT) + std::string(" ") + args + " >/dev/null")
                         .c_str()) == 0;
}

/// A dataset of `flights` straight flights of 200 points each, distinct per `seed`.
std::shared_ptr<Dataset> straight_flights(const std::string& id, int flights, int seed) {
  TrailSetBuilder b;
  for (int f = 0; f < flights; ++f)
    for (int i = 0; i < 200; ++i) {
      Sample s;
      s.t = 1514764800.0 + seed * 86400 + f * 7 + i * 10;
      s.lat = 40.0f + 0.05f * f + 0.001f * i, s.lon = -5.0f + 0.01f * seed + 0.002f * i;
      s.alt = 3000.0f + i, s.speed = 220, s.track = 80, s.vrate = i % 3 ? 0.0f : std::nanf("");
      b.add("a" + std::to_string(10000 + f), "T" + std::to_string(f), s);
    }
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-11-26T10:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

/// Rows of dataset `id` in `table`_local on node `k` (0..3) alone.
std::string local_rows(int k, const std::string& table, const std::string& id) {
  auto url = ClickHouseUrl::parse(cluster_url());
  ClickHouseClient node({url.hosts.at(k)});
  return node.query("SELECT count() FROM " + url.database + "." + table +
                    "_local WHERE dataset = " + ClickHouseClient::quote(id) + " FORMAT TSV");
}

TEST(ClickHouseStoreFaults, OneReplicaPerShardDownThenBack) {
  REQUIRE_CLUSTER();
  auto store = open_cluster();
  for (const char* id : {"before", "during"})
    if (store->contains(id)) store->remove(id);
  const auto before = straight_flights("before", 300, 1), during = straight_flights("during", 300, 2);
  store->put(before);
  const std::string rows = local_rows(0, "points", "before");
  EXPECT_EQ(local_rows(1, "points", "before"), rows);  // the quorum insert is on both replicas at once

  // Replica 2 of each shard (nodes 1 and 3) killed, and listed first: the client fails over, the
  // Distributed reads pick the live replica of each shard.
  ASSERT_TRUE(cluster_script("kill-node 1") && cluster_script("kill-node 3"));
  auto url = ClickHouseUrl::parse(cluster_url());
  url.hosts = {url.hosts[1], url.hosts[3], url.hosts[0], url.hosts[2]};
  {
    ClickHouseStore degraded(url);
    ASSERT_TRUE(degraded.contains("before"));
    expect_same_trails(*before->trails, *degraded.get("before")->trails);
    // An ingest now cannot reach the quorum (every replica of a shard): refused, and nothing visible.
    try {
      degraded.put(during);
      ADD_FAILURE() << "an ingest with a replica down was accepted";
    } catch (const Error& e) {
      std::printf("ingest with one replica per shard down refused: %s\n", e.what());
    }
    EXPECT_FALSE(degraded.contains("during"));
    EXPECT_FALSE(ClickHouseStore(url).contains("during"));
    // A delete while they are down: the catalogue row reaches the live replicas.
    degraded.remove("before");
    EXPECT_FALSE(ClickHouseStore(url).contains("before"));
  }
  // Back: they catch up with the delete (catalogue and rows) and the refused ingest leaves nothing.
  ASSERT_TRUE(cluster_script("start-node 1") && cluster_script("start-node 3"));
  bool caught_up = false;
  for (int i = 0; i < 120 && !caught_up; ++i) {
    caught_up = local_rows(1, "points", "before") == "0\n" && local_rows(3, "points", "before") == "0\n" &&
                local_rows(1, "points", "during") == "0\n" && local_rows(3, "points", "during") == "0\n";
    if (!caught_up) std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  EXPECT_TRUE(caught_up) << "the restarted replicas still hold rows of a deleted or refused dataset";
  auto node1 = url;
  node1.hosts = {url.hosts[0]};  // node 1 alone
  EXPECT_FALSE(ClickHouseStore(node1).contains("before"));
  // And the cluster takes ingests again, every replica holding them.
  store = open_cluster();
  store->put(during);
  EXPECT_EQ(local_rows(1, "points", "during"), local_rows(0, "points", "during"));
  EXPECT_EQ(local_rows(3, "points", "during"), local_rows(2, "points", "during"));
  expect_same_trails(*during->trails, *open_cluster()->get("during")->trails);
  store->remove("during");
}

/// Waits until node k's replicated tables answer after a restart (at most 60 s).
bool node_answers(int k) {
  auto url = ClickHouseUrl::parse(cluster_url());
  ClickHouseClient node({url.hosts.at(k)}, ClickHouseClient::Timeouts{std::chrono::milliseconds(1000),
                                                                      std::chrono::milliseconds(5000)});
  for (int i = 0; i < 120; ++i) {
    try {
      node.query("SELECT count() FROM " + url.database + ".points_local FORMAT TSV");
      return true;
    } catch (const std::exception&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
  }
  return false;
}

TEST(ClickHouseStoreFaults, PushedDownQueriesAnswerTheSameWhileOneReplicaPerShardDies) {
  REQUIRE_CLUSTER();
  auto store = open_cluster();
  if (store->contains("stream")) store->remove("stream");
  const auto ds = straight_flights("stream", 1500, 3);
  store->put(ds);
  const auto held = open_cluster()->get("stream");  // as a server holds it
  const TrailSet& t = *ds->trails;
  const double mid = std::floor((t.t_min() + t.t_max()) / 2);
  Query w;
  w.t0 = mid - 3600, w.t1 = mid;
  Query band;
  band.alt_min = 3050, band.alt_max = 3150, band.callsign = "T1*";
  // A count tile over the flights (the kind the store aggregates on the shards), its span cached by the
  // renderer after the first request.
  density::DensityRenderer renderer;
  density::TileRequest tile;
  tile.tile = geo::TileId{5, 15, 11};
  tile.max_gap_seconds = std::numeric_limits<double>::infinity();
  // The expected answers from compute/ over the dataset's trails (the embedded store's path).
  const std::vector<std::string> expected = {summarize(t, w, {}).to_json().dump(),
                                             summarize(t, band, {}).to_json().dump(),
                                             list_flights(t, w, 0, 1000, {}).to_json().dump(),
                                             positions_at(t, mid - 60, {}, 100000).to_json().dump(),
                                             renderer.render_tile(t, "stream", {}, tile).png};
  auto ask = [&](const ClickHouseStore& s, std::size_t k) {
    switch (k) {
      case 0:
        return s.summarize(*held, w, {}).to_json().dump();
      case 1:
        return s.summarize(*held, band, {}).to_json().dump();
      case 2:
        return s.list_flights(*held, w, 0, 1000, {}).to_json().dump();
      case 3:
        return s.positions_at(*held, mid - 60, {}, 100000).to_json().dump();
      default:
        return s.density_tile(*held, renderer, "stream", {}, tile);
    }
  };
  ASSERT_GT(nlohmann::json::parse(expected[0])["points"].get<std::uint64_t>(), 10000u);
  ASSERT_GT(renderer.render_tile(t, "stream", {}, tile).max_count, 0u) << "the tile misses the flights";
  for (std::size_t k = 0; k < expected.size(); ++k) ASSERT_EQ(ask(*store, k), expected[k]) << k;

  // A stream of queries through the URL's host list in its order (node 0 first); replica 1 of each shard
  // (nodes 0 and 2, the ones in_order load balancing reads) killed in the middle of it.
  std::atomic<bool> stop{false};
  std::atomic<int> done{0}, wrong{0}, failed{0};
  std::string first_failure;
  std::thread stream([&] {
    ClickHouseStore s(ClickHouseUrl::parse(cluster_url()));
    for (std::size_t i = 0; !stop; ++i) {
      try {
        if (ask(s, i % expected.size()) != expected[i % expected.size()]) ++wrong;
      } catch (const std::exception& e) {
        if (!failed++) first_failure = e.what();
      }
      ++done;
    }
  });
  auto wait_done = [&](int n) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (done < n && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
  };
  wait_done(8);
  ASSERT_TRUE(cluster_script("kill-node 0") && cluster_script("kill-node 2"));
  const int at_kill = done;
  wait_done(at_kill + 24);
  stop = true;
  stream.join();
  std::printf("%d pushed-down queries, %d after nodes 0 and 2 were killed: %d wrong, %d failed\n",
              done.load(), done - at_kill, wrong.load(), failed.load());
  EXPECT_GE(done - at_kill, 24);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(failed, 0) << first_failure;
  ASSERT_TRUE(cluster_script("start-node 0") && cluster_script("start-node 2"));
  ASSERT_TRUE(node_answers(0) && node_answers(2));

  // An ingest with replica 2 of each shard (nodes 1 and 3) killed in the middle of it and restarted a few
  // seconds later: it completes (the quorum reached once they are back) or is refused, never partial.
  if (store->contains("midkill")) store->remove("midkill");
  const auto big = straight_flights("midkill", 3000, 4);
  std::atomic<bool> started{false};
  std::atomic<int> outcome{0};  // 1 completed, 2 refused
  std::string refusal;
  std::thread ingest([&] {
    ClickHouseStore s(ClickHouseUrl::parse(cluster_url()));
    try {
      s.put(big, [&](double f, std::string_view) {
        if (f > 0.2) started = true;
      });
      outcome = 1;
    } catch (const std::exception& e) {
      refusal = e.what();
      outcome = 2;
    }
    started = true;
  });
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!started && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(cluster_script("kill-node 1") && cluster_script("kill-node 3"));
  std::this_thread::sleep_for(std::chrono::seconds(3));
  ASSERT_TRUE(cluster_script("start-node 1") && cluster_script("start-node 3"));
  ingest.join();
  ASSERT_NE(outcome, 0);
  std::printf("ingest with nodes 1 and 3 killed midway: %s%s\n",
              outcome == 1 ? "completed" : "refused: ", refusal.c_str());
  ASSERT_TRUE(node_answers(1) && node_answers(3));
  auto after = open_cluster(true);  // a server's open: leftovers of a refused ingest removed
  // Every replica catches up: the two replicas of each shard hold the same rows of both datasets.
  bool caught_up = false;
  for (int i = 0; i < 240 && !caught_up; ++i) {
    caught_up = true;
    for (const char* id : {"stream", "midkill"})
      for (const char* table : {"points", "segments", "flights"})
        caught_up = caught_up && local_rows(1, table, id) == local_rows(0, table, id) &&
                    local_rows(3, table, id) == local_rows(2, table, id);
    if (!caught_up) std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  EXPECT_TRUE(caught_up) << "the restarted replicas differ from their peers";
  if (outcome == 1) {
    ASSERT_TRUE(after->contains("midkill"));
    expect_same_trails(*big->trails, *after->get("midkill")->trails);
    after->remove("midkill");
  } else {
    EXPECT_FALSE(after->contains("midkill"));
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(eventually([&] { return local_rows(k, "points", "midkill"); }, "0\n"), "0\n") << "node " << k;
  }
  // And the queries still give the same answers on the restarted cluster.
  for (std::size_t k = 0; k < expected.size(); ++k) EXPECT_EQ(ask(*after, k), expected[k]) << k;
  after->remove("stream");
}

}  // namespace
}  // namespace trailscope::server
