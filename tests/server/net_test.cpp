// The network layer against a real server on loopback (net/http_server.cpp), driven with raw sockets so
// that every malformed request is sent exactly as written: protocol limits, Host and Origin, JSON content
// types, early refusal before a body is sent, slow bodies, the compute pool's queue, deadline and
// cancellation, rate limits and connection caps. The server runs a test Router of its own, without an
// access check unless a test installs one.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "net/http_server.hpp"
#include "net/ws_hub.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// A blocking TCP client with a receive timeout, so that a server that never answers fails the test
// instead of hanging it.
class Client {
 public:
  explicit Client(unsigned short port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    timeval tv{20, 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~Client() { close(); }
  bool connected() const { return connected_; }
  void set_timeout(std::chrono::milliseconds t) {
    timeval tv{static_cast<time_t>(t.count() / 1000), static_cast<suseconds_t>(t.count() % 1000 * 1000)};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  bool send(const std::string& s) {
    std::size_t off = 0;
    while (off < s.size()) {
      const ssize_t n = ::send(fd_, s.data() + off, s.size() - off, MSG_NOSIGNAL);
      if (n <= 0) return false;
      off += static_cast<std::size_t>(n);
    }
    return true;
  }
  /// Everything until the server closes the connection (or the timeout).
  std::string read_all() {
    std::string out;
    char buf[8192];
    for (;;) {
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) break;
      out.append(buf, static_cast<std::size_t>(n));
    }
    return out;
  }
  /// Reads until `out` holds a whole header block ("\r\n\r\n"), and the body its Content-Length names.
  std::string read_response() {
    std::string out;
    char buf[8192];
    for (;;) {
      const auto end = out.find("\r\n\r\n");
      if (end != std::string::npos) {
        std::size_t length = 0;
        const auto cl = lower(out.substr(0, end)).find("content-length:");
        if (cl != std::string::npos) length = std::stoul(out.substr(cl + 15));
        if (out.size() >= end + 4 + length) return out;
      }
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) return out;
      out.append(buf, static_cast<std::size_t>(n));
    }
  }
  static std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
};

struct Reply {
  int status = 0;
  std::map<std::string, std::string> headers;  // lower-case names
  std::string body;
  nlohmann::json json() const { return nlohmann::json::parse(body); }
};

// The first response of `raw` (an interim 100 Continue is skipped unless `keep_interim`).
Reply parse(const std::string& raw, bool keep_interim = false) {
  Reply r;
  std::size_t pos = 0;
  for (;;) {
    const auto end = raw.find("\r\n\r\n", pos);
    if (end == std::string::npos || raw.compare(pos, 5, "HTTP/") != 0) return r;
    r.status = std::stoi(raw.substr(pos + 9, 3));
    if (r.status == 100 && !keep_interim) {
      pos = end + 4;
      continue;
    }
    std::size_t line = raw.find("\r\n", pos) + 2;
    while (line < end) {
      const auto next = raw.find("\r\n", line);
      const std::string field = raw.substr(line, next - line);
      const auto colon = field.find(':');
      std::string value = field.substr(colon + 1);
      while (!value.empty() && value.front() == ' ') value.erase(value.begin());
      r.headers[Client::lower(field.substr(0, colon))] = value;
      line = next + 2;
    }
    std::size_t length = raw.size() - end - 4;
    if (auto it = r.headers.find("content-length"); it != r.headers.end()) length = std::stoul(it->second);
    r.body = raw.substr(end + 4, length);
    return r;
  }
}

nlohmann::json error_body(const std::string& error, const std::string& param, const std::string& detail) {
  return {{"error", error}, {"detail", detail}, {"param", param}};
}

// What the test routes saw, shared with the test body.
struct Probe {
  std::mutex mu;
  std::promise<void> started;  // the compute route "hold" began
  std::promise<void> release;  // lets "hold" return
  std::shared_future<void> released = release.get_future().share();
  std::promise<bool> wait_result;  // "wait" saw its token set (true) or gave up (false)
  std::atomic<int> hold_runs{0}, queued_runs{0};
  std::atomic<bool> wait_done{false};
};

Router test_router(Probe& probe) {
  Router r;
  r.add("GET", "/ping", [](const Request&, const PathParams&) {
    return Response::json(200, {{"pong", true}});
  });
  r.add("GET", "/page", [](const Request&, const PathParams&) {
    Response res;
    res.content_type = "text/html; charset=utf-8";
    res.body = "<!doctype html><title>t</title>";
    return res;
  });
  r.add("POST", "/echo", [](const Request& req, const PathParams&) {
    return Response::json(200, {{"echo", nlohmann::json::parse(req.body)}});
  });
  // An in-memory body of image types instead of JSON (as PUT /gaze/{gaze}/stimulus takes).
  r.add(
      "PUT", "/image",
      [](const Request& req, const PathParams&) {
        return Response::json(200, {{"bytes", req.body.size()}});
      },
      BodyRule{1u << 20, false, "image", {"image/png", "image/jpeg"}});
  // An upload with a precheck: `name` required, "taken" is taken, no other parameter.
  r.add(
       "POST", "/upload",
       [](const Request& req, const PathParams&) {
         std::error_code ec;
         const auto size = fs::file_size(req.body_file, ec);
         fs::remove(req.body_file, ec);
         return Response::json(201, {{"bytes", size}});
       },
       BodyRule{1u << 20, true, "upload"})
      .checked_first([](const Request& req, const PathParams&) {
        reject_unknown_params(req, {"name"});
        auto it = req.query.find("name");
        if (it == req.query.end()) throw invalid_argument("name", "name: required");
        if (it->second == "taken") throw Error(Error::Kind::conflict, "name", "'taken' already exists");
      });
  // Compute routes: "hold" runs until the test releases it, "wait" until its CancelToken is set.
  r.add("GET", "/hold", [&probe](const Request&, const PathParams&) {
     if (probe.hold_runs++ == 0) probe.started.set_value();
     probe.released.wait();
     return Response::json(200, {{"held", true}});
   }).on(Lane::compute);
  r.add("GET", "/queued", [&probe](const Request&, const PathParams&) {
     ++probe.queued_runs;
     return Response::json(200, {{"queued", true}});
   }).on(Lane::compute);
  r.add("GET", "/wait", [&probe](const Request& req, const PathParams&) {
     probe.started.set_value();
     const auto give_up = std::chrono::steady_clock::now() + 30s;
     while (!req.cancel->cancelled() && std::chrono::steady_clock::now() < give_up)
       std::this_thread::sleep_for(1ms);
     probe.wait_result.set_value(req.cancel->cancelled());
     req.cancel->throw_if_cancelled();
     return Response::json(200, {});
   }).on(Lane::compute);
  r.add_websocket("/ws", WebSocketKind::events,
                  [](const Request&, const PathParams&) { return Response::status_only(101); });
  return r;
}

class NetTest : public ::testing::Test {
 protected:
  /// Starts the server with `limits` (rate limits off unless a test turns them on).
  void start(NetLimits limits = quiet()) {
    uploads_ = fs::temp_directory_path() / ("net_test_" + std::to_string(::getpid()));
    fs::create_directories(uploads_);
    router_ = std::make_unique<Router>(test_router(probe_));
    if (access_) router_->set_access(access_);
    std::promise<unsigned short> listening;
    auto port = listening.get_future();
    server_ = std::thread([&, limits] {
      ServerOptions so{"127.0.0.1", 0, 2};
      so.limits = limits;
      so.allowed_origins = {"https://dashboard.example.org"};
      run_http_server(so, *router_, hub_, uploads_, [&](unsigned short p) { listening.set_value(p); });
    });
    port_ = port.get();
  }
  void TearDown() override {
    if (!server_.joinable()) return;
    try {
      probe_.release.set_value();  // let any held compute request end
    } catch (const std::future_error&) {
    }
    std::raise(SIGTERM);  // run_http_server stops on SIGTERM
    server_.join();
    std::error_code ec;
    fs::remove_all(uploads_, ec);
  }
  static NetLimits quiet() {
    NetLimits l;
    l.per_address_rate = 0;
    l.per_token_rate = 0;
    return l;
  }
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
  /// Sends `raw` on a new connection and reads until the server closes it.
  Reply exchange(const std::string& raw) {
    Client c(port_);
    EXPECT_TRUE(c.connected());
    c.send(raw);
    return parse(c.read_all());
  }
  Reply get(const std::string& target, const std::string& extra = "") {
    return exchange("GET " + target + " HTTP/1.1\r\nHost: " + host() + "\r\n" + extra +
                    "Connection: close\r\n\r\n");
  }

  Probe probe_;
  Router::AccessCheck access_;
  std::unique_ptr<Router> router_;
  WsHub hub_;
  fs::path uploads_;
  std::thread server_;
  unsigned short port_ = 0;
};

TEST_F(NetTest, AnAnswerCarriesTheSecurityHeaders) {
  start();
  const Reply r = get("/ping");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(r.json(), nlohmann::json({{"pong", true}}));
  EXPECT_EQ(r.headers.at("x-content-type-options"), "nosniff");
  EXPECT_EQ(r.headers.at("referrer-policy"), "no-referrer");
  EXPECT_EQ(r.headers.count("content-security-policy"), 0u);  // JSON is not a page
  const Reply page = get("/page");
  ASSERT_EQ(page.status, 200);
  const std::string csp = page.headers.at("content-security-policy");
  EXPECT_NE(csp.find("script-src 'self';"), std::string::npos) << csp;
  EXPECT_NE(csp.find("frame-ancestors 'none'"), std::string::npos) << csp;
  EXPECT_EQ(csp.find("unsafe-eval"), std::string::npos) << csp;
  // 'unsafe-inline' only for styles: the script directive does not carry it.
  const auto script =
      csp.substr(csp.find("script-src"), csp.find(';', csp.find("script-src")) - csp.find("script-src"));
  EXPECT_EQ(script, "script-src 'self'");
  EXPECT_EQ(page.headers.at("x-content-type-options"), "nosniff");
}

TEST_F(NetTest, AHeaderOver16KiBIs431) {
  start();
  const Reply r = get("/ping", "X-Big: " + std::string(17 * 1024, 'a') + "\r\n");
  EXPECT_EQ(r.status, 431);
  EXPECT_EQ(r.json(), error_body("request_header_fields_too_large", "header",
                                 "the request header exceeds the limit of 16 KiB"));
}

TEST_F(NetTest, MalformedFramingIs400) {
  start();
  const std::string head =
      "POST /echo HTTP/1.1\r\nHost: " + host() + "\r\nContent-Type: application/json\r\n";
  struct Case {
    std::string name, raw, detail;
  };
  const std::vector<Case> cases = {
      {"bad Content-Length", head + "Content-Length: 12x\r\n\r\n{}", "malformed request: bad Content-Length"},
      {"two equal Content-Lengths", head + "Content-Length: 2\r\nContent-Length: 2\r\n\r\n{}",
       "malformed request: more than one Content-Length"},
      {"two different Content-Lengths", head + "Content-Length: 2\r\nContent-Length: 3\r\n\r\n{}",
       "malformed request: multiple Content-Length"},
      {"chunked and Content-Length", head + "Content-Length: 2\r\nTransfer-Encoding: chunked\r\n\r\n{}",
       "malformed request: bad Transfer-Encoding"},
      {"bare LF", "GET /ping HTTP/1.1\nHost: " + host() + "\n\n",
       "malformed request: a line ends in a bare LF, not CRLF"},
      {"bare LF in a field", "GET /ping HTTP/1.1\r\nHost: " + host() + "\nX: y\r\n\r\n",
       "malformed request: a line ends in a bare LF, not CRLF"},
  };
  for (const auto& c : cases) {
    const Reply r = exchange(c.raw);
    EXPECT_EQ(r.status, 400) << c.name;
    EXPECT_EQ(r.body.empty() ? nlohmann::json() : r.json(),
              error_body("invalid_argument", "header", c.detail))
        << c.name;
  }
}

TEST_F(NetTest, AnUnsupportedVersionIs505) {
  start();
  const Reply r = exchange("GET /ping HTTP/9.9\r\nHost: " + host() + "\r\n\r\n");
  EXPECT_EQ(r.status, 505);
  EXPECT_EQ(r.json(), error_body("http_version_not_supported", "version",
                                 "HTTP/9.9 is not supported (HTTP/1.0 and HTTP/1.1 are)"));
}

TEST_F(NetTest, Http11WithoutHostIs400AndHttp10IsServed) {
  start();
  const Reply r = exchange("GET /ping HTTP/1.1\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(r.status, 400);
  EXPECT_EQ(r.json(), error_body("invalid_argument", "host", "an HTTP/1.1 request needs a Host header"));
  EXPECT_EQ(exchange("GET /ping HTTP/1.0\r\n\r\n").status, 200);
}

TEST_F(NetTest, HostMustBeANameOfTheServer) {
  start();
  const std::string port = std::to_string(port_);
  for (const std::string ok :
       {"127.0.0.1:" + port, "localhost:" + port, "LOCALHOST:" + port, "[::1]:" + port})
    EXPECT_EQ(exchange("GET /ping HTTP/1.1\r\nHost: " + ok + "\r\nConnection: close\r\n\r\n").status, 200)
        << ok;
  // DNS rebinding: a page of attacker.example whose name now resolves to 127.0.0.1.
  const Reply r = exchange("GET /ping HTTP/1.1\r\nHost: attacker.example:" + port + "\r\n\r\n");
  EXPECT_EQ(r.status, 403);
  EXPECT_EQ(r.json(), error_body("forbidden", "host",
                                 "Host 'attacker.example:" + port +
                                     "' is not a name of this server (serve --server-name)"));
  // A local name without a port (clients that are not browsers) is served; another port is another server.
  EXPECT_EQ(exchange("GET /ping HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n").status, 200);
  EXPECT_EQ(exchange("GET /ping HTTP/1.1\r\nHost: localhost:1\r\n\r\n").status, 403);
}

TEST_F(NetTest, ForeignOriginsMayNotChangeState) {
  start();
  const auto post = [&](const std::string& origin, const std::string& type) {
    const std::string body = R"({"a":1})";
    return exchange("POST /echo HTTP/1.1\r\nHost: " + host() + "\r\n" +
                    (origin.empty() ? "" : "Origin: " + origin + "\r\n") + "Content-Type: " + type +
                    "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" +
                    body);
  };
  // A text/plain "simple request" from another site, the classic cross-site request forgery.
  const Reply foreign = post("http://attacker.example", "text/plain");
  EXPECT_EQ(foreign.status, 403);
  EXPECT_EQ(foreign.json(), error_body("forbidden", "origin",
                                       "Origin 'http://attacker.example' may not send this request "
                                       "(serve --allow-origin)"));
  EXPECT_EQ(post("null", "application/json").status, 403);
  EXPECT_EQ(post("http://attacker.example", "application/json").status, 403);
  // The same origin, an allowed origin and a client that is not a browser (no Origin) are served...
  EXPECT_EQ(post("http://" + host(), "application/json").status, 200);
  EXPECT_EQ(post("https://dashboard.example.org", "application/json").status, 200);
  const Reply plain = post("", "application/json");
  EXPECT_EQ(plain.status, 200);
  EXPECT_EQ(plain.json(), nlohmann::json({{"echo", {{"a", 1}}}}));
  EXPECT_EQ(post("", "application/vnd.api+json; charset=utf-8").status, 200);
  // ...but a JSON route wants JSON, whatever the origin.
  const Reply text = post("http://" + host(), "text/plain");
  EXPECT_EQ(text.status, 415);
  EXPECT_EQ(text.json(), error_body("unsupported_format", "content-type",
                                    "Content-Type must be application/json, got 'text/plain'"));
  EXPECT_EQ(post("", "application/x-www-form-urlencoded").status, 415);
  // A route that names its media types takes those and nothing else (neither JSON nor text/plain).
  const auto put_image = [&](const std::string& type) {
    return exchange("PUT /image HTTP/1.1\r\nHost: " + host() + "\r\nContent-Type: " + type +
                    "\r\nContent-Length: 4\r\nConnection: close\r\n\r\n\x89PNG");
  };
  const Reply png = put_image("image/png");
  EXPECT_EQ(png.status, 200);
  EXPECT_EQ(png.json(), nlohmann::json({{"bytes", 4}}));
  EXPECT_EQ(put_image("IMAGE/JPEG; q=1").status, 200);
  const Reply not_image = put_image("text/plain");
  EXPECT_EQ(not_image.status, 415);
  EXPECT_EQ(not_image.json(), error_body("unsupported_format", "content-type",
                                         "Content-Type must be image/png or image/jpeg, got 'text/plain'"));
  EXPECT_EQ(put_image("application/json").status, 415);
  // Reads are not checked: a page may embed a tile.
  EXPECT_EQ(get("/ping", "Origin: http://attacker.example\r\n").status, 200);
}

TEST_F(NetTest, AWebSocketFromAForeignOriginIsRefused) {
  start();
  const auto handshake = [&](const std::string& origin) {
    Client c(port_);
    c.send("GET /ws HTTP/1.1\r\nHost: " + host() +
           "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
           "Sec-WebSocket-Version: 13\r\nOrigin: " +
           origin + "\r\n\r\n");
    return parse(c.read_response());
  };
  const Reply foreign = handshake("http://attacker.example");
  EXPECT_EQ(foreign.status, 403);
  EXPECT_EQ(foreign.json()["param"], "origin");
  const Reply own = handshake("http://" + host());
  EXPECT_EQ(own.status, 101);
  EXPECT_EQ(own.headers.at("sec-websocket-accept"), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");  // RFC 6455 1.3
}

TEST_F(NetTest, AnUploadIsRefusedBeforeItsBodyIsSent) {
  start();
  // With Expect: 100-continue the refusal comes instead of the 100, and no byte of the body is sent.
  Client c(port_);
  c.send("POST /upload?name=taken HTTP/1.1\r\nHost: " + host() +
         "\r\nContent-Length: 500000\r\nExpect: 100-continue\r\n\r\n");
  const std::string raw = c.read_all();  // the server answers and closes without waiting for the body
  const Reply r = parse(raw, true);
  EXPECT_EQ(r.status, 409);
  EXPECT_EQ(r.json(), error_body("conflict", "name", "'taken' already exists"));
  EXPECT_EQ(raw.find("100 Continue"), std::string::npos);
  // The other checks of the precheck, without Expect: answered on the header too.
  Client d(port_);
  d.send("POST /upload?name=x&colour=red HTTP/1.1\r\nHost: " + host() + "\r\nContent-Length: 500000\r\n\r\n");
  const Reply unknown = parse(d.read_all());
  EXPECT_EQ(unknown.status, 400);
  EXPECT_EQ(unknown.json(), error_body("invalid_argument", "colour", "unknown query parameter 'colour'"));
  // Over the route's body limit (1 MiB here): 413 on the header.
  Client e(port_);
  e.send("POST /upload?name=x HTTP/1.1\r\nHost: " + host() + "\r\nContent-Length: 2000000\r\n\r\n");
  EXPECT_EQ(parse(e.read_all()).json(),
            error_body("payload_too_large", "body", "upload exceeds the limit of 1 MiB"));
  // An admitted upload gets its 100 first, then sends its body.
  Client ok(port_);
  ok.send("POST /upload?name=fresh HTTP/1.1\r\nHost: " + host() +
          "\r\nContent-Length: 5\r\nExpect: 100-continue\r\nConnection: close\r\n\r\n");
  const Reply interim = parse(ok.read_response(), true);
  EXPECT_EQ(interim.status, 100);
  ok.send("hello");
  const Reply done = parse(ok.read_all());
  EXPECT_EQ(done.status, 201);
  EXPECT_EQ(done.json(), nlohmann::json({{"bytes", 5}}));
}

TEST_F(NetTest, ASlowBodyIs408) {
  NetLimits l = quiet();
  l.body_rate_grace = 300ms;
  l.min_body_bytes_per_second = 1000;
  start(l);
  Client c(port_);
  c.send("POST /upload?name=slow HTTP/1.1\r\nHost: " + host() + "\r\nContent-Length: 100000\r\n\r\nabc");
  const Reply r = parse(c.read_all());
  EXPECT_EQ(r.status, 408);
  EXPECT_EQ(r.json(),
            error_body("request_timeout", "body", "the request body arrived slower than 1000 bytes/s"));
}

TEST_F(NetTest, AnUnfinishedHeaderIs408AndAnIdleConnectionIsClosed) {
  NetLimits l = quiet();
  l.request_timeout = 300ms;
  start(l);
  Client partial(port_);
  partial.send("GET /ping HTTP/1.1\r\nHost: ");
  const Reply late = parse(partial.read_all());
  EXPECT_EQ(late.status, 408);
  EXPECT_EQ(late.json(),
            error_body("request_timeout", "header", "the request header did not arrive within 0.3 s"));
  Client idle(port_);
  EXPECT_EQ(idle.read_all(), "");
}

TEST_F(NetTest, AFullComputeQueueIs503WithRetryAfter) {
  NetLimits l = quiet();
  l.compute_workers = 1;
  l.max_queued_compute = 0;
  start(l);
  Client first(port_);
  first.send("GET /hold HTTP/1.1\r\nHost: " + host() + "\r\nConnection: close\r\n\r\n");
  probe_.started.get_future().wait();
  // The one worker is busy and nothing may wait.
  const Reply r = get("/queued");
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(r.headers.at("retry-after"), "2");
  EXPECT_EQ(r.json(), error_body("unavailable", "",
                                 "the server is at capacity: 0 requests are waiting for the compute pool"));
  // The I/O lane still answers.
  EXPECT_EQ(get("/ping").status, 200);
  probe_.release.set_value();
  EXPECT_EQ(parse(first.read_all()).json(), nlohmann::json({{"held", true}}));
  EXPECT_EQ(probe_.queued_runs, 0);
  // Once the worker is idle again, a request runs (poll: the worker returns to the queue after answering).
  int status = 0;
  for (int i = 0; i < 200 && status != 200; ++i) {
    status = get("/queued").status;
    if (status != 200) std::this_thread::sleep_for(10ms);
  }
  EXPECT_EQ(status, 200);
  EXPECT_EQ(probe_.queued_runs, 1);
}

TEST_F(NetTest, AClientThatLeavesCancelsItsRunningRequest) {
  start();
  auto result = probe_.wait_result.get_future();
  {
    Client c(port_);
    c.send("GET /wait HTTP/1.1\r\nHost: " + host() + "\r\n\r\n");
    probe_.started.get_future().wait();
  }  // closed while the handler runs
  ASSERT_EQ(result.wait_for(20s), std::future_status::ready);
  EXPECT_TRUE(result.get());
}

TEST_F(NetTest, AClientThatLeavesIsDroppedFromTheQueue) {
  NetLimits l = quiet();
  l.compute_workers = 1;
  l.max_queued_compute = 1;
  start(l);
  Client first(port_);
  first.send("GET /hold HTTP/1.1\r\nHost: " + host() + "\r\nConnection: close\r\n\r\n");
  probe_.started.get_future().wait();
  const std::string queued_request =
      "GET /queued HTTP/1.1\r\nHost: " + host() + "\r\nConnection: close\r\n\r\n";
  {
    Client queued(port_);
    queued.send(queued_request);
    std::this_thread::sleep_for(200ms);     // let the server queue it
    EXPECT_EQ(get("/queued").status, 503);  // the queue's one place is taken
  }                                         // the client leaves while its request waits
  // Once the server has seen it leave, the queue has room again: a request then waits (no answer)
  // instead of a 503.
  std::unique_ptr<Client> next;
  for (int i = 0; i < 500 && !next; ++i) {
    auto c = std::make_unique<Client>(port_);
    c->send(queued_request);
    c->set_timeout(100ms);
    if (c->read_response().empty()) next = std::move(c);  // waiting in the queue
  }
  ASSERT_TRUE(next);
  next->set_timeout(20s);
  probe_.release.set_value();
  EXPECT_EQ(parse(first.read_all()).json(), nlohmann::json({{"held", true}}));
  EXPECT_EQ(parse(next->read_all()).json(), nlohmann::json({{"queued", true}}));
  EXPECT_EQ(probe_.queued_runs, 1);  // the request of the client that left never ran
}

TEST_F(NetTest, AComputeRequestPastItsDeadlineIsCancelledAnd503) {
  NetLimits l = quiet();
  l.compute_deadline = 1s;
  start(l);
  auto result = probe_.wait_result.get_future();
  const Reply r = get("/wait");
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(r.headers.at("retry-after"), "2");
  EXPECT_EQ(r.json(),
            error_body("unavailable", "", "the request did not finish within 1 s; it was cancelled"));
  ASSERT_EQ(result.wait_for(20s), std::future_status::ready);
  EXPECT_TRUE(result.get());  // the handler saw its token set
}

TEST_F(NetTest, RateLimitsPerAddressAndPerTokenAre429) {
  NetLimits l = quiet();
  l.per_address_rate = 0.01;  // a token every 100 s
  l.per_address_burst = 3;
  start(l);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(get("/ping").status, 200) << i;
  const Reply r = get("/ping");
  EXPECT_EQ(r.status, 429);
  const int retry = std::stoi(r.headers.at("retry-after"));
  EXPECT_GE(retry, 99);
  EXPECT_LE(retry, 100);
  EXPECT_EQ(r.json(),
            error_body("too_many_requests", "", "more than 0.01 requests per second from this address"));
}

TEST_F(NetTest, RateLimitPerToken) {
  access_ = [](Request& req, const Router::Route*) {
    const std::string t = req.header("authorization");
    if (!t.empty()) req.principal = Principal{t, "owner-" + t, Role::reader};
  };
  NetLimits l = quiet();
  l.per_token_rate = 0.01;
  l.per_token_burst = 2;
  start(l);
  const std::string a = "Authorization: a\r\n", b = "Authorization: b\r\n";
  EXPECT_EQ(get("/ping", a).status, 200);
  EXPECT_EQ(get("/ping", a).status, 200);
  const Reply r = get("/ping", a);
  EXPECT_EQ(r.status, 429);
  EXPECT_EQ(r.json(),
            error_body("too_many_requests", "", "more than 0.01 requests per second with this token"));
  EXPECT_EQ(get("/ping", b).status, 200);  // another token has its own bucket
  EXPECT_EQ(get("/ping").status, 200);     // anonymous requests count by address only
}

TEST_F(NetTest, ConnectionsBeyondThePerAddressCapAre503) {
  NetLimits l = quiet();
  l.max_connections_per_address = 2;
  start(l);
  Client a(port_), b(port_);
  ASSERT_TRUE(a.connected() && b.connected());
  Client c(port_);
  const Reply r = parse(c.read_all());  // answered without a request, then closed
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(r.headers.at("retry-after"), "2");
  EXPECT_EQ(r.json(), error_body("unavailable", "", "too many open connections from this address"));
  a.close();
  // Once one closes, a new connection is served (poll: the server notices the close asynchronously).
  int status = 0;
  for (int i = 0; i < 200 && status != 200; ++i) {
    status = get("/ping").status;
    if (status != 200) std::this_thread::sleep_for(10ms);
  }
  EXPECT_EQ(status, 200);
}

}  // namespace
}  // namespace trailscope::server
