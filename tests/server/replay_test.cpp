// Live replays: the REST routes in process, and the WebSocket protocol (proto/replay_ws.md) over loopback
// with the real server and Beast clients: two independent viewers (one plays, one seeks and steps), the
// binary frame message, bad ops answered without closing, 404 before the upgrade, DELETE closing viewers.
#include <csignal>
#include <cstring>
#include <future>
#include <thread>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <gtest/gtest.h>

#include "net/http_server.hpp"
#include "net/ws_hub.hpp"
#include "tracker_fixture.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::server {
namespace {
namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

constexpr std::size_t kFrames = 60;

class ReplayTest : public test_routes::TrackerFixture {
 protected:
  std::string create_replay(const std::string& video) {
    const Response r = send("POST", "/api/v1/replays", R"({"video": ")" + video + R"("})");
    EXPECT_EQ(r.status, 201) << r.body;
    return r.status == 201 ? body(r).at("id").get<std::string>() : "";
  }
  /// Polls GET /replays/{id} until the tracking is done (at most 30 s).
  nlohmann::json wait_done(const std::string& id) {
    for (int i = 0; i < 3000; ++i) {
      const auto j = body(get("/api/v1/replays/" + id));
      if (j["done"] == true) return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "replay " << id << " did not finish";
    return {};
  }
};

TEST_F(ReplayTest, RestRoutes) {
  const std::string video = upload_video(kFrames);
  const Response r =
      send("POST", "/api/v1/replays", R"({"video": ")" + video + R"(", "params": {"ncc_min": 0.5}})");
  ASSERT_EQ(r.status, 201) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["id"], "rp1");
  EXPECT_EQ(header(r, "Location"), "/api/v1/replays/rp1");
  EXPECT_EQ(j["video"], video);
  EXPECT_EQ(j["frames"], kFrames);
  EXPECT_EQ(j["fps"], 25.0);
  EXPECT_EQ(j["width"], 176);
  EXPECT_EQ(j["height"], 144);
  EXPECT_EQ(j["params"]["ncc_min"], 0.5);
  EXPECT_EQ(j["ws"], "/api/v1/replays/rp1/ws");
  EXPECT_EQ(j["colormap"], "viridis");
  EXPECT_LT(j["depth_range_mm"][0].get<double>(), j["depth_range_mm"][1].get<double>());
  // The stored video offers the same range, so a stored run's pictures are coloured as the replay's.
  EXPECT_EQ(body(get("/api/v1/videos/" + video))["depth_range_mm"], j["depth_range_mm"]);
  const auto done = wait_done("rp1");
  EXPECT_EQ(done["computed"], kFrames);
  EXPECT_TRUE(done["error"].is_null()) << done.dump();
  // The run's log is kept when it ends.
  ASSERT_TRUE(done["run"].is_string()) << done.dump();
  const auto run = body(get("/api/v1/runs/" + done["run"].get<std::string>()));
  EXPECT_EQ(run["origin"], "replay");
  EXPECT_EQ(run["summary"]["frames"], kFrames);
  EXPECT_EQ(body(get("/api/v1/replays"))["replays"].size(), 1u);

  expect_detail(send("POST", "/api/v1/replays", R"({"video": "v42"})"), 404, "not_found", "video",
                "video 'v42' does not exist");
  expect_error(send("POST", "/api/v1/replays", R"({"video": ")" + video + R"(", "params": {"n_lost": 0}})"),
               400, "invalid_argument", "n_lost");
  expect_error(send("POST", "/api/v1/replays", R"({"video": ")" + video + R"(", "colormap": "jet"})"), 400,
               "invalid_argument", "colormap");
  expect_detail(send("POST", "/api/v1/replays", R"({"video": ")" + video + R"(", "loop": true})"), 400,
                "invalid_argument", "loop", "unknown field 'loop'");

  EXPECT_EQ(send("DELETE", "/api/v1/replays/rp1").status, 204);
  expect_detail(get("/api/v1/replays/rp1"), 404, "not_found", "replay", "replay 'rp1' does not exist");
  expect_detail(send("DELETE", "/api/v1/replays/rp1"), 404, "not_found", "replay",
                "replay 'rp1' does not exist");
  // The stored run stays.
  EXPECT_EQ(get("/api/v1/runs/" + done["run"].get<std::string>()).status, 200);
}

TEST_F(ReplayTest, AtMostMaxReplays) {
  const std::string video = upload_video(3);
  for (std::size_t i = 0; i < limits::kMaxReplays; ++i) ASSERT_FALSE(create_replay(video).empty());
  expect_detail(send("POST", "/api/v1/replays", R"({"video": ")" + video + R"("})"), 409, "conflict",
                "replay", "at most 8 replays run at once (kMaxReplays); delete one first");
  EXPECT_EQ(send("DELETE", "/api/v1/replays/rp3").status, 204);
  EXPECT_EQ(create_replay(video), "rp9");
}

/// A parsed binary frame message.
struct FrameMsg {
  nlohmann::json header;
  density::Image depth, amplitude;
};

FrameMsg parse_frame(const std::string& bytes) {
  FrameMsg m;
  EXPECT_GE(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(0, 4), "TSRF");
  std::uint32_t len = 0;
  for (int i = 0; i < 4; ++i)
    len |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[4 + i])) << (8 * i);
  m.header = nlohmann::json::parse(bytes.substr(8, len));
  const std::string rest = bytes.substr(8 + len);
  const auto d = m.header["depth_png"], a = m.header["amplitude_png"];
  EXPECT_EQ(d[1].get<std::size_t>() + a[1].get<std::size_t>(), rest.size());
  m.depth = density::decode_png(rest.substr(d[0].get<std::size_t>(), d[1].get<std::size_t>()));
  m.amplitude = density::decode_png(rest.substr(a[0].get<std::size_t>(), a[1].get<std::size_t>()));
  return m;
}

/// A blocking WebSocket client of one replay.
class Viewer {
 public:
  Viewer(net::io_context& ioc, unsigned short port, const std::string& target, const std::string& token)
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
  /// Reads until a text message of `type` arrives; binary frames met on the way go to `frames`.
  nlohmann::json read_until(const std::string& type, std::vector<FrameMsg>* frames = nullptr) {
    for (int i = 0; i < 10000; ++i) {
      const Msg m = read();
      if (m.binary) {
        if (frames) frames->push_back(parse_frame(m.data));
        continue;
      }
      const auto j = m.json();
      if (j["type"] == type) return j;
    }
    ADD_FAILURE() << "no " << type << " message";
    return {};
  }
  /// The next binary frame (text messages skipped).
  FrameMsg next_frame() {
    for (int i = 0; i < 1000; ++i) {
      const Msg m = read();
      if (m.binary) return parse_frame(m.data);
    }
    ADD_FAILURE() << "no frame message";
    return {};
  }
  void send(const std::string& text) {
    ws_.text(true);
    ws_.write(net::buffer(text));
  }
  websocket::stream<tcp::socket>& stream() { return ws_; }

 private:
  websocket::stream<tcp::socket> ws_;
};

class ReplayWsTest : public ReplayTest {
 protected:
  void SetUp() override {
    std::promise<unsigned short> listening;
    auto port_future = listening.get_future();
    server_ = std::thread([&] {
      ServerOptions so{"127.0.0.1", 0, 2};
      run_http_server(
          so, router, hub_, store->upload_dir(), [&](unsigned short port) { listening.set_value(port); },
          app->replays.get());
    });
    port_ = port_future.get();
    // The server installs its SIGTERM handler just after it reports the port; give it a moment so that
    // TearDown's signal stops it instead of the test process.
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  void TearDown() override {
    std::raise(SIGTERM);  // run_http_server stops on SIGTERM
    server_.join();
  }
  WsHub hub_;
  std::thread server_;
  unsigned short port_ = 0;
  net::io_context ioc_;
};

TEST_F(ReplayWsTest, TwoViewersWithTheirOwnCursors) {
  const std::string video = upload_video(kFrames);
  const std::string id = create_replay(video);
  const std::string target = "/api/v1/replays/" + id + "/ws";
  Viewer a(ioc_, port_, target, router.token), b(ioc_, port_, target, router.token);

  for (Viewer* v : {&a, &b}) {
    const auto hello = v->read().json();
    ASSERT_EQ(hello["type"], "hello") << hello.dump();
    EXPECT_EQ(hello["replay"]["id"], id);
    EXPECT_EQ(hello["replay"]["frames"], kFrames);
    EXPECT_EQ(hello["state"], nlohmann::json({{"playing", false}, {"frame", 0}, {"speed", 1}}));
    EXPECT_TRUE(hello["header"].is_object());
    const FrameMsg f0 = v->next_frame();
    EXPECT_EQ(f0.header["type"], "frame");
    EXPECT_EQ(f0.header["index"], 0);
    EXPECT_EQ(f0.depth.width, 176);
    EXPECT_EQ(f0.depth.height, 144);
    EXPECT_EQ(f0.amplitude.width, 176);
    EXPECT_TRUE(f0.header["frame"].is_object());
    ASSERT_TRUE(f0.header["truth"].is_object());
    EXPECT_EQ(f0.header["truth"]["teats"].size(), 4u);
  }

  // A plays at 16x: increasing frame indices up to the last one, then a state with playing false.
  a.send(R"({"op": "speed", "value": 16})");
  EXPECT_EQ(a.read_until("state")["speed"], 16);
  a.send(R"({"op": "play"})");
  const auto playing = a.read_until("state");
  EXPECT_EQ(playing["playing"], true);
  std::vector<FrameMsg> played;
  nlohmann::json end;
  for (;;) {
    end = a.read_until("state", &played);
    if (end["playing"] == false) break;
  }
  EXPECT_EQ(end["frame"], kFrames - 1);
  ASSERT_FALSE(played.empty());
  // The last frame may still wait for a write slot when the state goes out; it is never dropped.
  if (played.back().header["index"] != kFrames - 1) played.push_back(a.next_frame());
  for (std::size_t i = 1; i < played.size(); ++i)
    EXPECT_LT(played[i - 1].header["index"].get<int>(), played[i].header["index"].get<int>());
  EXPECT_EQ(played.back().header["index"], kFrames - 1);

  // B, meanwhile untouched, is still at frame 0: it seeks and steps on its own cursor.
  b.send(R"({"op": "seek", "frame": 30})");
  auto st = b.read_until("state");
  EXPECT_EQ(st["frame"], 30);
  EXPECT_EQ(st["playing"], false);
  EXPECT_EQ(b.next_frame().header["index"], 30);
  b.send(R"({"op": "step", "delta": -5})");
  EXPECT_EQ(b.read_until("state")["frame"], 25);
  const FrameMsg f25 = b.next_frame();
  EXPECT_EQ(f25.header["index"], 25);
  EXPECT_DOUBLE_EQ(f25.header["timestamp_s"].get<double>(), 1.0);

  // Bad ops are answered with an error naming the field; the connection stays open.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"op": "rewind"})", "op"},
      {R"(not json)", "op"},
      {R"({"op": "seek", "frame": 60})", "frame"},
      {R"({"op": "seek", "frame": 1.5})", "frame"},
      {R"({"op": "step"})", "delta"},
      {R"({"op": "speed", "value": 20})", "value"},
      {R"({"op": "speed", "value": "fast"})", "value"}};
  for (const auto& [msg, param] : bad) {
    b.send(msg);
    const auto err = b.read_until("error");
    EXPECT_EQ(err["error"], "invalid_argument") << msg;
    EXPECT_EQ(err["param"], param) << msg;
    EXPECT_FALSE(err["detail"].get<std::string>().empty());
  }
  b.send(R"({"op": "seek", "frame": 10})");
  EXPECT_EQ(b.read_until("state")["frame"], 10);
  EXPECT_EQ(b.next_frame().header["index"], 10);
}

TEST_F(ReplayWsTest, UnknownReplayIs404BeforeTheUpgrade) {
  tcp::resolver resolver(ioc_);
  websocket::stream<tcp::socket> ws(ioc_);
  net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port_)));
  const std::string token = router.token;
  ws.set_option(websocket::stream_base::decorator([token](websocket::request_type& req) {
    req.set(beast::http::field::authorization, "Bearer " + token);
  }));
  websocket::response_type res;
  beast::error_code ec;
  ws.handshake(res, "127.0.0.1", "/api/v1/replays/rp404/ws", ec);
  EXPECT_TRUE(ec);
  EXPECT_EQ(res.result_int(), 404);
  const auto j = nlohmann::json::parse(res.body());
  EXPECT_EQ(j["param"], "replay");
  EXPECT_EQ(j["detail"], "replay 'rp404' does not exist");
}

TEST_F(ReplayWsTest, DeleteClosesTheViewers) {
  const std::string id = create_replay(upload_video(10));
  Viewer v(ioc_, port_, "/api/v1/replays/" + id + "/ws", router.token);
  EXPECT_EQ(v.read().json()["type"], "hello");
  EXPECT_EQ(send("DELETE", "/api/v1/replays/" + id).status, 204);
  beast::error_code ec;
  for (int i = 0; i < 100 && !ec; ++i) {
    beast::flat_buffer buf;
    v.stream().read(buf, ec);
  }
  EXPECT_EQ(ec, websocket::error::closed);
  EXPECT_EQ(v.stream().reason().code, websocket::close_code::going_away);
}

}  // namespace
}  // namespace trailscope::server
