// Bundle streams (proto/bundle_stream.md) over loopback with the real server and a Beast client: the
// refusals before the upgrade (404, 400, 409 at kMaxBundleStreams), the hello, TSBS frames checked
// against the dataset (which flights are in the window, their fades, their fixed endpoints in lon/lat),
// the clock followed, and the exact error of every bad control message without losing the connection.
#include <csignal>
#include <cstring>
#include <future>
#include <set>
#include <thread>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <gtest/gtest.h>

#include "net/http_server.hpp"
#include "net/ws_hub.hpp"
#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {
namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

constexpr double kT0 = 1514764800.0;  // 2018-01-01T00:00:00Z

// 40 flights between four European cities, one every 5 minutes, each lasting 40 minutes, sampled every
// 2 minutes along the straight lon/lat line.
struct FlightSpec {
  double t0, t1, lon0, lat0, lon1, lat1;
};
std::vector<FlightSpec> specs() {
  const double cities[4][2] = {{2.35, 48.86}, {13.40, 52.52}, {-0.13, 51.51}, {12.50, 41.90}};
  std::vector<FlightSpec> f;
  for (int i = 0; i < 40; ++i) {
    const int a = i % 4, b = (i / 4 + 1 + a) % 4 == a ? (a + 1) % 4 : (i / 4 + 1 + a) % 4;
    f.push_back(
        {kT0 + 300.0 * i, kT0 + 300.0 * i + 2400, cities[a][0], cities[a][1], cities[b][0], cities[b][1]});
  }
  return f;
}

std::shared_ptr<Dataset> dataset(const std::string& id) {
  TrailSetBuilder b;
  const auto f = specs();
  for (std::size_t i = 0; i < f.size(); ++i) {
    char icao[8];
    std::snprintf(icao, sizeof icao, "4ca%03zx", i);
    for (int k = 0; k <= 20; ++k) {
      Sample s;
      const double u = k / 20.0;
      s.t = f[i].t0 + u * (f[i].t1 - f[i].t0);
      s.lon = f[i].lon0 + u * (f[i].lon1 - f[i].lon0), s.lat = f[i].lat0 + u * (f[i].lat1 - f[i].lat0);
      s.alt = 10000, s.speed = 230, s.track = 90, s.vrate = 0;
      b.add(icao, (i % 2 ? "KLM" : "AFR") + std::to_string(i), s);
    }
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

struct Frame {
  double t = 0;
  std::uint32_t n = 0, m = 0, sequence = 0;
  float window = 0, drift = 0;
  std::vector<std::uint32_t> ids, offsets;
  std::vector<float> opacity, points;
};

template <class T>
T read_le(const std::string& b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);  // the test machine is little-endian, as the format
  return v;
}

Frame parse(const std::string& b) {
  Frame f;
  EXPECT_GE(b.size(), 44u);
  EXPECT_EQ(b.substr(0, 4), "TSBS");
  EXPECT_EQ(read_le<std::uint32_t>(b, 4), 1u);
  f.n = read_le<std::uint32_t>(b, 8), f.m = read_le<std::uint32_t>(b, 12);
  EXPECT_EQ(b.size(), 44 + 12 * f.n + 8 * f.m);
  f.t = read_le<double>(b, 16);
  f.sequence = read_le<std::uint32_t>(b, 24);
  f.window = read_le<float>(b, 28), f.drift = read_le<float>(b, 32);
  std::size_t at = 40;
  for (std::uint32_t i = 0; i < f.n; ++i, at += 4) f.ids.push_back(read_le<std::uint32_t>(b, at));
  for (std::uint32_t i = 0; i < f.n; ++i, at += 4) f.opacity.push_back(read_le<float>(b, at));
  for (std::uint32_t i = 0; i <= f.n; ++i, at += 4) f.offsets.push_back(read_le<std::uint32_t>(b, at));
  for (std::uint32_t i = 0; i < 2 * f.m; ++i, at += 4) f.points.push_back(read_le<float>(b, at));
  return f;
}

class Client {
 public:
  Client(net::io_context& ioc, unsigned short port, const std::string& target, const std::string& token)
      : ws_(ioc) {
    tcp::resolver resolver(ioc);
    net::connect(ws_.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port)));
    // Access control is on: the fixture's admin token on the handshake.
    ws_.set_option(websocket::stream_base::decorator([token](websocket::request_type& req) {
      req.set(beast::http::field::authorization, "Bearer " + token);
    }));
    ws_.handshake("127.0.0.1", target);
  }
  struct Msg {
    bool binary = false;
    std::string data;
    nlohmann::json json() const { return nlohmann::json::parse(data); }
  };
  Msg read() {
    beast::flat_buffer buf;
    ws_.read(buf);
    return {!ws_.got_text(), beast::buffers_to_string(buf.data())};
  }
  Frame next_frame() {
    for (int i = 0; i < 1000; ++i) {
      const Msg m = read();
      if (m.binary) return parse(m.data);
      ADD_FAILURE() << "unexpected text " << m.data;
    }
    return {};
  }
  nlohmann::json next_text() {
    for (int i = 0; i < 1000; ++i) {
      const Msg m = read();
      if (!m.binary) return m.json();
    }
    ADD_FAILURE() << "no text message";
    return {};
  }
  void send(const std::string& text) {
    ws_.text(true);
    ws_.write(net::buffer(text));
  }
  void send_binary(const std::string& bytes) {
    ws_.binary(true);
    ws_.write(net::buffer(bytes));
  }

 private:
  websocket::stream<tcp::socket> ws_;
};

class BundleStreamTest : public test_routes::RouteFixture {
 protected:
  void SetUp() override {
    open(dataset("eu"));
    std::promise<unsigned short> listening;
    auto port_future = listening.get_future();
    server_ = std::thread([&] {
      ServerOptions so{"127.0.0.1", 0, 2};
      run_http_server(
          so, router, hub_, store->upload_dir(), [&](unsigned short port) { listening.set_value(port); },
          app->replays.get(), app->bundle_streams.get());
    });
    port_ = port_future.get();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the SIGTERM handler is installed
  }
  void TearDown() override {
    std::raise(SIGTERM);
    server_.join();
  }
  /// The refusal of an upgrade of `target`: status and error body.
  std::pair<int, nlohmann::json> refused(const std::string& target) {
    tcp::resolver resolver(ioc_);
    websocket::stream<tcp::socket> ws(ioc_);
    net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port_)));
    const std::string token = router.token;
    ws.set_option(websocket::stream_base::decorator([token](websocket::request_type& req) {
      req.set(beast::http::field::authorization, "Bearer " + token);
    }));
    websocket::response_type res;
    beast::error_code ec;
    ws.handshake(res, "127.0.0.1", target, ec);
    EXPECT_TRUE(ec);
    return {res.result_int(), nlohmann::json::parse(res.body())};
  }
  WsHub hub_;
  std::thread server_;
  unsigned short port_ = 0;
  net::io_context ioc_;
  static constexpr const char* kPath = "/api/v1/datasets/eu/bundles/stream";
};

TEST_F(BundleStreamTest, RefusalsBeforeTheUpgrade) {
  auto [status, j] = refused("/api/v1/datasets/nope/bundles/stream");
  EXPECT_EQ(status, 404);
  EXPECT_EQ(j["error"], "not_found");
  EXPECT_EQ(j["param"], "dataset");
  EXPECT_EQ(j["detail"], "dataset 'nope' does not exist");
  std::tie(status, j) = refused(std::string(kPath) + "?t=1514764800");
  EXPECT_EQ(status, 400);
  EXPECT_EQ(j["param"], "t");
  EXPECT_EQ(j["detail"], "unknown query parameter 't'");
  // kMaxBundleStreams at once; the next is refused, and a closed one frees its place.
  std::vector<std::unique_ptr<Client>> open;
  for (std::size_t i = 0; i < limits::kMaxBundleStreams; ++i) {
    open.push_back(std::make_unique<Client>(ioc_, port_, kPath, router.token));
    EXPECT_EQ(open.back()->next_text()["type"], "hello");
  }
  std::tie(status, j) = refused(kPath);
  EXPECT_EQ(status, 409);
  EXPECT_EQ(j["error"], "conflict");
  EXPECT_EQ(j["param"], "stream");
  EXPECT_EQ(j["detail"], "at most 4 bundle streams are open at once (kMaxBundleStreams); close one first");
  open.pop_back();  // closes the socket
  bool reopened = false;
  for (int i = 0; i < 100 && !reopened; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    reopened = app->bundle_streams->open_streams() < limits::kMaxBundleStreams;
  }
  ASSERT_TRUE(reopened);
  Client again(ioc_, port_, kPath, router.token);
  EXPECT_EQ(again.next_text()["type"], "hello");
}

TEST_F(BundleStreamTest, FramesFollowTheClock) {
  Client c(ioc_, port_, kPath, router.token);
  const auto hello = c.next_text();
  EXPECT_EQ(hello["type"], "hello");
  EXPECT_EQ(hello["dataset"], "eu");
  EXPECT_EQ(hello["format"], "TSBS 1");
  EXPECT_EQ(hello["params"]["window_s"], 3600);
  EXPECT_EQ(hello["limits"]["min_interval_ms"], limits::kBundleStreamMinIntervalMs);
  const auto f = specs();
  const TrailSet& trails = *store->get("eu")->trails;
  std::uint32_t last_sequence = 0;
  for (double t : {kT0 + 3000.5, kT0 + 6000.25, kT0 + 9000.0}) {
    c.send(nlohmann::json{{"t", t}, {"window_s", 1800}, {"fade_s", 600}}.dump());
    Frame fr;
    do fr = c.next_frame();
    while (fr.t != t);  // settling frames of the previous clock may come first
    EXPECT_GT(fr.sequence, last_sequence);
    last_sequence = fr.sequence;
    EXPECT_EQ(fr.window, 1800.0f);
    // The window's flights by brute force over the specification, and their fades.
    std::set<std::uint32_t> want;
    for (std::size_t fi = 0; fi < trails.num_flights(); ++fi) {
      const Flight& fl = trails.flights()[fi];
      if (fl.t_min <= t && t <= fl.t_max + 1800) want.insert(static_cast<std::uint32_t>(fi));
    }
    ASSERT_EQ(std::set<std::uint32_t>(fr.ids.begin(), fr.ids.end()), want) << "t = " << t;
    ASSERT_EQ(fr.offsets.size(), fr.n + 1u);
    for (std::uint32_t e = 0; e < fr.n; ++e) {
      const Flight& fl = trails.flights()[fr.ids[e]];
      const double o = std::clamp(std::min(t - fl.t_min, fl.t_max + 1800 - t) / 600, 0.0, 1.0);
      EXPECT_NEAR(fr.opacity[e], o, 1e-6);
      // The endpoints never move: the flight's first and last positions (float32 lon/lat, and the
      // round trip through the 512-px frame: well under a metre at these zooms).
      const auto& pts = trails.points();
      const std::size_t a = fr.offsets[e], b = fr.offsets[e + 1] - 1;
      ASSERT_GE(b, a + 1);
      EXPECT_NEAR(fr.points[2 * a], pts.lon[fl.begin], 1e-4);
      EXPECT_NEAR(fr.points[2 * a + 1], pts.lat[fl.begin], 1e-4);
      EXPECT_NEAR(fr.points[2 * b], pts.lon[fl.end - 1], 1e-4);
      EXPECT_NEAR(fr.points[2 * b + 1], pts.lat[fl.end - 1], 1e-4);
    }
  }
  // With the clock standing still the bundles settle: more frames at the same t, drift falling.
  const Frame a = c.next_frame();
  EXPECT_EQ(a.t, kT0 + 9000.0);
  EXPECT_GT(a.sequence, last_sequence);
}

TEST_F(BundleStreamTest, BadControlMessagesAreAnsweredExactly) {
  Client c(ioc_, port_, kPath, router.token);
  EXPECT_EQ(c.next_text()["type"], "hello");
  const auto expect = [&](const std::string& msg, const std::string& param, const std::string& detail) {
    c.send(msg);
    const auto j = c.next_text();
    EXPECT_EQ(j["type"], "error") << msg;
    EXPECT_EQ(j["error"], "invalid_argument") << msg;
    EXPECT_EQ(j["param"], param) << msg;
    if (!detail.empty()) EXPECT_EQ(j["detail"], detail) << msg;
  };
  expect("not json", "message",
         "a control message must be a JSON object such as {\"t\": 1514800000, \"window_s\": 3600}");
  expect("[1,2]", "message",
         "a control message must be a JSON object such as {\"t\": 1514800000, \"window_s\": 3600}");
  expect(R"({"t": 1514764800, "speed": 2})", "speed",
         "unknown field 'speed'; a control message has t, window_s, fade_s, bbox, callsign and icao24");
  expect(R"({"t": true})", "t", "t must be a number of Unix seconds or an ISO 8601 time");
  expect(R"({"t": "yesterday"})", "t", "");
  expect(R"({"window_s": 10})", "window_s",
         "window_s must be in 60..86400 seconds (limits::kMaxStreamWindowSeconds), got 10");
  expect(R"({"window_s": "1h"})", "window_s", "window_s must be a number of seconds");
  expect(R"({"fade_s": 4000})", "fade_s", "fade_s must be in 0..window_s (3600) seconds, got 4000");
  expect(R"({"bbox": "1,2,3"})", "bbox", "");
  expect(R"({"bbox": 5})", "bbox", "bbox must be a string (or null to clear)");
  expect(R"({"icao24": "xyz"})", "icao24", "");
  c.send_binary("TSBS");
  const auto j = c.next_text();
  EXPECT_EQ(j["param"], "message");
  EXPECT_EQ(j["detail"], "control messages are JSON text such as {\"t\": 1514800000}");
  // None of them changed anything, and the connection still works.
  c.send(R"({"t": "2018-01-01T01:00:00Z"})");
  const Frame fr = c.next_frame();
  EXPECT_EQ(fr.t, kT0 + 3600);
  EXPECT_EQ(fr.window, 3600.0f);
  EXPECT_GT(fr.n, 0u);
}

TEST_F(BundleStreamTest, FiltersAndViewSelectTheFlights) {
  Client c(ioc_, port_, kPath, router.token);
  EXPECT_EQ(c.next_text()["type"], "hello");
  const double t = kT0 + 6000;
  c.send(nlohmann::json{{"t", t}, {"callsign", "KLM"}}.dump());
  Frame fr = c.next_frame();
  const TrailSet& trails = *store->get("eu")->trails;
  ASSERT_GT(fr.n, 0u);
  for (std::uint32_t id : fr.ids) EXPECT_EQ(trails.flights()[id].callsign.rfind("KLM", 0), 0u);
  // A bbox around Rome: only flights whose extent reaches it.
  c.send(nlohmann::json{{"callsign", nullptr}, {"bbox", "11,40,14,43"}}.dump());
  do fr = c.next_frame();
  while (std::any_of(fr.ids.begin(), fr.ids.end(),
                     [&](std::uint32_t id) { return trails.flights()[id].lat_min > 43; }));
  ASSERT_GT(fr.n, 0u);
  for (std::uint32_t id : fr.ids) EXPECT_LE(trails.flights()[id].lat_min, 43.0f);
}

}  // namespace
}  // namespace trailscope::server
