// Mixed load against a running TrailScope server (started by tests/bench/load_test.sh, `make load`): for a
// fixed time, N keep-alive HTTP connections send density tiles (warm: a fixed set the cache holds; cold: a
// new time window per request, so a new cache key), summaries and flight lists over varying windows; one
// client uploads a small dataset at a fixed interval and times its 202; one client polls health; WebSocket
// clients hold the job-event stream and bundle streams whose clock moves. The server's RSS is read from
// /proc/<pid>/status before, during and after.
//
// Prints JSON lines (bench_util.hpp's emit): one "load_kind" record per request kind (count, errors,
// refusals, latency percentiles), one "load_ws" record per WebSocket kind, one "load" summary record.
// Bounded: every request has a 30 s deadline (an upload 90 s), the run stops at --seconds (the clients finish
// the request in flight, then close), at most --connections + 2 HTTP connections and --ws WebSockets are ever
// open.
//
//   load_bench --host 127.0.0.1 --port P --pid SERVER_PID [--token T] [--connections 100] [--seconds 60]
//              [--ws 10] [--upload-every-s 5] [--dataset demo] [--seed 1]
//
// Errors are responses other than 2xx/3xx that are not refusals, and transport errors (connect, reset,
// timeout). Refusals are 429 (rate limit) and 503 (admission control) with Retry-After: counted apart.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "bench_util.hpp"

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using asio::use_awaitable;
using bench::Clock;
using bench::json;

namespace {

struct Config {
  std::string host = "127.0.0.1";
  std::string port;
  int pid = 0;
  std::string token;
  int connections = 100;
  double seconds = 60;
  int ws = 10;
  double upload_every_s = 5;
  std::string dataset = "demo";
  std::uint64_t seed = 1;
};

/// Per request kind: latencies of answered requests, and how each ended.
struct KindStats {
  std::vector<double> ms;
  long ok = 0, errors = 0, refused = 0, transport = 0;
  std::map<int, long> status;  // every status seen other than 200
};

struct WsStats {
  long connected = 0, refused = 0, errors = 0, messages = 0, bytes = 0;
  std::vector<double> handshake_ms, first_message_ms;
};

/// Everything runs on one thread (one io_context, one thread): no locks.
struct Run {
  Config cfg;
  tcp::endpoint ep;
  Clock::time_point start, end;
  std::map<std::string, KindStats> kinds;
  std::map<std::string, WsStats> ws;
  std::vector<double> upload_202_ms;
  long uploads_ingested = 0;
  // From the dataset, for the requests: its time range and extent.
  double t_min = 0, t_max = 0;
  double lon0 = -180, lat0 = -85, lon1 = 180, lat1 = 85;
  std::vector<std::string> warm_tiles;

  bool over() const { return Clock::now() >= end; }
};

bool refusal(int status) {
  return status == 429 || status == 503;
}

void record(Run& run, const std::string& kind, double ms, int status) {
  KindStats& k = run.kinds[kind];
  if (status >= 200 && status < 400) {
    ++k.ok;
    k.ms.push_back(ms);
  } else if (refusal(status)) {
    ++k.refused;
  } else {
    ++k.errors;
  }
  if (status != 200) ++k.status[status];
}

/// Slippy-map tile of a point (Web Mercator, OSM numbering).
std::pair<int, int> tile_of(double lon, double lat, int z) {
  const double n = std::ldexp(1.0, z);
  const double lat_r = std::clamp(lat, -85.05, 85.05) * M_PI / 180.0;
  const int x = static_cast<int>(std::floor((lon + 180.0) / 360.0 * n));
  const int y = static_cast<int>(std::floor((1.0 - std::asinh(std::tan(lat_r)) / M_PI) / 2.0 * n));
  const int hi = static_cast<int>(n) - 1;
  return {std::clamp(x, 0, hi), std::clamp(y, 0, hi)};
}

/// One HTTP/1.1 keep-alive connection: send, read, reconnect after a transport error or a close.
class Connection {
 public:
  Connection(Run& run, asio::any_io_executor ex) : run_(run), stream_(ex) {}

  /// Sends one request; returns the status (0 on a transport error, which is recorded as such) and the
  /// body in `body`. `ms` is the time from sending to the whole response.
  asio::awaitable<int> send(http::verb verb, const std::string& target, std::string body_in,
                            const std::string& content_type, std::string& body, double& ms,
                            int timeout_s = 30) {
    try {
      if (!open_) {
        stream_.expires_after(std::chrono::seconds(10));
        co_await stream_.async_connect(run_.ep, use_awaitable);
        stream_.socket().set_option(tcp::no_delay(true));
        open_ = true;
      }
      http::request<http::string_body> req{verb, target, 11};
      req.set(http::field::host, run_.cfg.host + ":" + run_.cfg.port);
      req.set(http::field::user_agent, "trailscope-load-bench");
      if (!run_.cfg.token.empty()) req.set(http::field::authorization, "Bearer " + run_.cfg.token);
      if (!content_type.empty()) req.set(http::field::content_type, content_type);
      req.body() = std::move(body_in);
      req.prepare_payload();
      req.keep_alive(true);
      const auto t0 = Clock::now();
      stream_.expires_after(std::chrono::seconds(timeout_s));
      co_await http::async_write(stream_, req, use_awaitable);
      http::response_parser<http::string_body> parser;
      parser.body_limit(256u << 20);
      co_await http::async_read(stream_, buffer_, parser, use_awaitable);
      ms = bench::ms_since(t0);
      auto res = parser.release();
      if (!res.keep_alive()) close();
      body = std::move(res.body());
      co_return static_cast<int>(res.result_int());
    } catch (const std::exception&) {
      close();
      co_return 0;
    }
  }

  void close() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.close();
    buffer_.clear();
    open_ = false;
  }

 private:
  Run& run_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  bool open_ = false;
};

/// A request and its kind, chosen at random with fixed weights.
struct Pick {
  std::string kind, target;
};

Pick pick_request(Run& run, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double r = u(rng);
  const std::string& ds = run.cfg.dataset;
  const double span = std::max(60.0, run.t_max - run.t_min);
  // A window of 10 min to 6 h somewhere in the data's day.
  const auto window = [&] {
    const double w = std::min(span, 600.0 + u(rng) * (6 * 3600.0 - 600.0));
    const double t0 = run.t_min + u(rng) * (span - w);
    return std::make_pair(std::floor(t0), std::floor(t0 + w));
  };
  if (r < 0.35) {  // a tile from the warm set
    std::uniform_int_distribution<std::size_t> i(0, run.warm_tiles.size() - 1);
    return {"tile_warm", run.warm_tiles[i(rng)]};
  }
  if (r < 0.50) {  // a cold tile: a new window, hence a new cache key
    std::uniform_int_distribution<int> zd(3, 7);
    const int z = zd(rng);
    const double lon = run.lon0 + u(rng) * (run.lon1 - run.lon0),
                 lat = run.lat0 + u(rng) * (run.lat1 - run.lat0);
    const auto [x, y] = tile_of(lon, lat, z);
    const auto [t0, t1] = window();
    std::ostringstream t;
    t << "/tiles/" << ds << "/density/" << z << "/" << x << "/" << y
      << ".png?t0=" << static_cast<long long>(t0) << "&t1=" << static_cast<long long>(t1);
    return {"tile_cold", t.str()};
  }
  if (r < 0.75) {
    const auto [t0, t1] = window();
    std::ostringstream t;
    t << "/api/v1/datasets/" << ds << "/summary?t0=" << static_cast<long long>(t0)
      << "&t1=" << static_cast<long long>(t1);
    if (u(rng) < 0.5) {  // and half of them a bbox: the western or eastern half of the data
      const double mid = (run.lon0 + run.lon1) / 2;
      const bool west = u(rng) < 0.5;
      t << "&bbox=" << (west ? run.lon0 : mid) << "," << run.lat0 << "," << (west ? mid : run.lon1) << ","
        << run.lat1;
    }
    return {"summary", t.str()};
  }
  const auto [t0, t1] = window();
  std::uniform_int_distribution<int> page(0, 4);
  std::ostringstream t;
  t << "/api/v1/datasets/" << ds << "/flights?t0=" << static_cast<long long>(t0)
    << "&t1=" << static_cast<long long>(t1) << "&page_size=100&page=" << page(rng);
  return {"flights", t.str()};
}

asio::awaitable<void> http_client(Run& run, int index) {
  Connection conn(run, co_await asio::this_coro::executor);
  std::mt19937_64 rng(run.cfg.seed * 1000003 + static_cast<std::uint64_t>(index));
  std::string body;
  while (!run.over()) {
    const Pick p = pick_request(run, rng);
    double ms = 0;
    const int status = co_await conn.send(http::verb::get, p.target, "", "", body, ms);
    if (status == 0) {
      ++run.kinds[p.kind].transport;
      asio::steady_timer t(co_await asio::this_coro::executor, std::chrono::milliseconds(100));
      co_await t.async_wait(use_awaitable);  // no tight reconnect loop against a dead server
      continue;
    }
    record(run, p.kind, ms, status);
  }
  conn.close();
}

/// Health every 100 ms on its own connection: what an operator's probe would see during the load.
asio::awaitable<void> health_client(Run& run) {
  Connection conn(run, co_await asio::this_coro::executor);
  asio::steady_timer t(co_await asio::this_coro::executor);
  std::string body;
  while (!run.over()) {
    double ms = 0;
    const int status = co_await conn.send(http::verb::get, "/api/v1/health", "", "", body, ms);
    if (status == 0)
      ++run.kinds["health"].transport;
    else
      record(run, "health", ms, status);
    t.expires_after(std::chrono::milliseconds(100));
    co_await t.async_wait(use_awaitable);
  }
  conn.close();
}

/// An OpenSky CSV of `aircraft` straight flights of `samples` points each, 10 s apart, in the data's day
/// and extent (about 60 bytes a row).
std::string make_upload(const Run& run, int aircraft, int samples, int salt) {
  std::ostringstream csv;
  csv << "time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude\n";
  csv.setf(std::ios::fixed);
  csv.precision(5);
  const double lat = (run.lat0 + run.lat1) / 2, lon = (run.lon0 + run.lon1) / 2;
  for (int a = 0; a < aircraft; ++a)
    for (int k = 0; k < samples; ++k) {
      char icao[8];
      std::snprintf(icao, sizeof icao, "%06x", 0xf00000 + salt * 997 + a);
      csv << static_cast<long long>(run.t_min) + 10 * k << "," << icao << "," << lat + 0.01 * a + 0.0004 * k
          << "," << lon + 0.0004 * k << ",220,45,0,LOAD" << a << ",false," << 9000 + 10 * a << "\n";
    }
  return csv.str();
}

/// An upload's deadline: longer than the other requests', so that a slow 202 is measured, not cut off.
constexpr int kUploadTimeoutS = 90;

/// Uploads a small dataset every --upload-every-s, times the 202, waits for its ingest job, deletes it.
asio::awaitable<void> upload_client(Run& run) {
  auto ex = co_await asio::this_coro::executor;
  Connection conn(run, ex);
  asio::steady_timer t(ex);
  std::string body;
  const auto seq = static_cast<int>(
      std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch())
          .count() %
      100000);
  for (int n = 0; !run.over(); ++n) {
    const auto slot = Clock::now();
    const std::string name = "load-" + std::to_string(seq) + "-" + std::to_string(n);
    std::string csv = make_upload(run, 40, 80, n);  // 3,200 rows, ~200 KB
    double ms = 0;
    const int status = co_await conn.send(http::verb::post, "/api/v1/datasets?name=" + name, std::move(csv),
                                          "text/csv", body, ms, kUploadTimeoutS);
    if (status == 0) {
      ++run.kinds["upload"].transport;
    } else {
      record(run, "upload", ms, status);
      if (status == 202) {
        run.upload_202_ms.push_back(ms);
        std::string job;
        try {
          job = json::parse(body).at("job").at("id").get<std::string>();
        } catch (const std::exception&) {
        }
        // Its ingest: polled every 200 ms up to 60 s (not timed as load), then the dataset deleted.
        for (int i = 0; i < 300 && !job.empty(); ++i) {
          t.expires_after(std::chrono::milliseconds(200));
          co_await t.async_wait(use_awaitable);
          double poll_ms = 0;
          const int s = co_await conn.send(http::verb::get, "/api/v1/jobs/" + job, "", "", body, poll_ms);
          if (s != 200) continue;
          const std::string state = json::parse(body).value("state", "");
          if (state == "done") ++run.uploads_ingested;
          if (state == "done" || state == "failed" || state == "cancelled") break;
        }
        double del_ms = 0;
        const int d =
            co_await conn.send(http::verb::delete_, "/api/v1/datasets/" + name, "", "", body, del_ms);
        if (d == 0)
          ++run.kinds["delete"].transport;
        else
          record(run, "delete", del_ms, d);
      }
    }
    t.expires_at(slot + std::chrono::milliseconds(static_cast<long>(run.cfg.upload_every_s * 1000)));
    co_await t.async_wait(use_awaitable);
  }
  conn.close();
}

/// One WebSocket client: the job-event stream (kind "events", reads only) or a bundle stream (kind
/// "bundle_stream": sends its clock every 500 ms, moving 60 s of data time per step).
asio::awaitable<void> ws_client(Run& run, std::string kind, int index) {
  auto ex = co_await asio::this_coro::executor;
  WsStats& st = run.ws[kind];
  websocket::stream<beast::tcp_stream> ws(ex);
  const std::string target =
      kind == "events" ? "/api/v1/ws" : "/api/v1/datasets/" + run.cfg.dataset + "/bundles/stream";
  try {
    const auto t0 = Clock::now();
    beast::get_lowest_layer(ws).expires_after(std::chrono::seconds(10));
    co_await beast::get_lowest_layer(ws).async_connect(run.ep, use_awaitable);
    beast::get_lowest_layer(ws).expires_never();
    ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::client));
    const std::string token = run.cfg.token;
    ws.set_option(websocket::stream_base::decorator([token](websocket::request_type& req) {
      req.set(http::field::user_agent, "trailscope-load-bench");
      if (!token.empty()) req.set(http::field::authorization, "Bearer " + token);
    }));
    websocket::response_type res;
    try {
      co_await ws.async_handshake(res, run.cfg.host + ":" + run.cfg.port, target, use_awaitable);
    } catch (const std::exception&) {
      const int status = static_cast<int>(res.result_int());
      if (refusal(status) || status == 409)  // 409: the server's cap on open bundle streams
        ++st.refused;
      else
        ++st.errors;
      std::cerr << "load_bench: " << kind << " #" << index << " handshake refused: " << status << "\n";
      co_return;
    }
    st.handshake_ms.push_back(bench::ms_since(t0));
    ++st.connected;
    const auto opened = Clock::now();
    bool first = true;
    // The clock of a bundle stream: sent by a second coroutine while this one reads.
    bool reading = true;
    if (kind == "bundle_stream") {
      asio::co_spawn(
          ex,
          [&run, &ws, &reading, index]() -> asio::awaitable<void> {
            asio::steady_timer t(co_await asio::this_coro::executor);
            double clock = run.t_min + 3600 + 600.0 * index;
            try {
              while (reading && !run.over()) {
                const std::string msg = "{\"t\": " + std::to_string(static_cast<long long>(clock)) + "}";
                co_await ws.async_write(asio::buffer(msg), use_awaitable);
                clock += 60;
                if (clock > run.t_max) clock = run.t_min + 3600;
                t.expires_after(std::chrono::milliseconds(500));
                co_await t.async_wait(use_awaitable);
              }
            } catch (const std::exception&) {
            }
          },
          asio::detached);
    }
    // Reads until the run ends; a timer closes the socket at the end so that the read returns.
    asio::steady_timer stop(ex);
    stop.expires_at(run.end);
    stop.async_wait([&](const beast::error_code&) {
      reading = false;
      beast::error_code ec;
      beast::get_lowest_layer(ws).socket().close(ec);
    });
    beast::flat_buffer buf;
    try {
      for (;;) {
        const std::size_t n = co_await ws.async_read(buf, use_awaitable);
        if (first) st.first_message_ms.push_back(bench::ms_since(opened)), first = false;
        ++st.messages, st.bytes += static_cast<long>(n);
        buf.consume(buf.size());
      }
    } catch (const std::exception&) {
      if (!run.over()) {
        ++st.errors;
        std::cerr << "load_bench: " << kind << " #" << index << " closed early\n";
      }
    }
    reading = false;
    stop.cancel();
    // Let the clock coroutine see `reading` false before `ws` goes out of scope.
    asio::steady_timer grace(ex, std::chrono::milliseconds(600));
    co_await grace.async_wait(use_awaitable);
  } catch (const std::exception& e) {
    ++st.errors;
    std::cerr << "load_bench: " << kind << " #" << index << ": " << e.what() << "\n";
  }
}

/// VmRSS of the server, MiB (NaN when it cannot be read).
double rss_mib(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return NAN;
}

asio::awaitable<void> rss_sampler(Run& run, std::vector<double>& samples) {
  asio::steady_timer t(co_await asio::this_coro::executor);
  while (!run.over()) {
    samples.push_back(rss_mib(run.cfg.pid));
    t.expires_after(std::chrono::seconds(1));
    co_await t.async_wait(use_awaitable);
  }
}

json percentiles(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const auto r = [](double x) { return std::round(x * 100.0) / 100.0; };
  if (v.empty()) return {{"n", 0}};
  return {{"n", v.size()},
          {"p50_ms", r(bench::Stats::percentile(v, 0.50))},
          {"p90_ms", r(bench::Stats::percentile(v, 0.90))},
          {"p99_ms", r(bench::Stats::percentile(v, 0.99))},
          {"max_ms", r(v.back())}};
}

/// GET over a fresh connection, run to completion (set-up only).
int get_sync(Run& run, asio::io_context& io, const std::string& target, std::string& body) {
  int status = 0;
  asio::co_spawn(
      io,
      [&]() -> asio::awaitable<void> {
        Connection c(run, co_await asio::this_coro::executor);
        double ms = 0;
        status = co_await c.send(http::verb::get, target, "", "", body, ms);
        c.close();
      },
      asio::detached);
  io.run();
  io.restart();
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const bench::Args a(argc, argv);
    Run run;
    Config& c = run.cfg;
    c.host = a.get("host", c.host);
    c.port = a.get("port");
    c.pid = static_cast<int>(a.num("pid", 0));
    c.token = a.get("token");
    c.connections = static_cast<int>(a.num("connections", c.connections));
    c.seconds = std::stod(a.get("seconds", "60"));
    c.ws = static_cast<int>(a.num("ws", c.ws));
    c.upload_every_s = std::stod(a.get("upload-every-s", "5"));
    c.dataset = a.get("dataset", c.dataset);
    c.seed = static_cast<std::uint64_t>(a.num("seed", 1));
    if (c.port.empty() || c.pid <= 0) throw std::invalid_argument("--port and --pid are required");
    if (c.connections < 1 || c.connections > 1000 || c.seconds <= 0 || c.seconds > 3600 || c.ws < 0 ||
        c.ws > 100 || c.upload_every_s < 0.1)
      throw std::invalid_argument(
          "--connections 1..1000, --seconds 0..3600, --ws 0..100, --upload-every-s >= 0.1");

    asio::io_context io(1);
    run.ep = tcp::endpoint(asio::ip::make_address(c.host), static_cast<unsigned short>(std::stoi(c.port)));

    // The dataset's time range and extent, and the warm tiles (z 3-6 over the extent's middle).
    std::string body;
    const int st = get_sync(run, io, "/api/v1/datasets/" + c.dataset, body);
    if (st != 200)
      throw std::runtime_error("GET /api/v1/datasets/" + c.dataset + ": " + std::to_string(st) + " " + body);
    const json ds = json::parse(body);
    run.t_min = ds.at("t_min").get<double>(), run.t_max = ds.at("t_max").get<double>();
    const auto& bb = ds.at("bbox");
    run.lon0 = bb[0].get<double>(), run.lat0 = bb[1].get<double>();
    run.lon1 = bb[2].get<double>(), run.lat1 = bb[3].get<double>();
    for (int z = 3; z <= 6; ++z)
      for (const double f : {0.3, 0.5, 0.7}) {
        const auto [x, y] =
            tile_of(run.lon0 + f * (run.lon1 - run.lon0), run.lat0 + f * (run.lat1 - run.lat0), z);
        const std::string tile = "/tiles/" + c.dataset + "/density/" + std::to_string(z) + "/" +
                                 std::to_string(x) + "/" + std::to_string(y) + ".png";
        if (std::find(run.warm_tiles.begin(), run.warm_tiles.end(), tile) == run.warm_tiles.end())
          run.warm_tiles.push_back(tile);
      }
    for (const auto& t : run.warm_tiles) get_sync(run, io, t, body);  // into the cache

    const double rss_before = rss_mib(c.pid);
    bench::log("load_bench: " + std::to_string(c.connections) + " connections, " + std::to_string(c.ws) +
               " WebSockets, " + std::to_string(static_cast<int>(c.seconds)) + " s against " + c.host + ":" +
               c.port + " (server RSS " + std::to_string(static_cast<int>(rss_before)) + " MiB)");
    run.start = Clock::now();
    run.end = run.start + std::chrono::milliseconds(static_cast<long>(c.seconds * 1000));
    std::vector<double> rss_during;
    for (int i = 0; i < c.connections; ++i) asio::co_spawn(io, http_client(run, i), asio::detached);
    asio::co_spawn(io, health_client(run), asio::detached);
    asio::co_spawn(io, upload_client(run), asio::detached);
    // The job-event stream and the bundle streams (the server allows kMaxBundleStreams = 4 at once).
    const int streams = std::min(c.ws / 2, 4);
    for (int i = 0; i < c.ws; ++i)
      asio::co_spawn(io, ws_client(run, i < streams ? "bundle_stream" : "events", i), asio::detached);
    asio::co_spawn(io, rss_sampler(run, rss_during), asio::detached);
    io.run();
    const double elapsed_s = bench::ms_since(run.start) / 1000.0;
    // After: the server idle for 5 s (jobs of the last upload finished, connections closed).
    std::this_thread::sleep_for(std::chrono::seconds(5));
    const double rss_after = rss_mib(c.pid);

    long total = 0, errors = 0, refused = 0, transport = 0;
    std::vector<double> all_ms;
    for (auto& [kind, k] : run.kinds) {
      json r = {{"bench", "load_kind"}, {"kind", kind},         {"ok", k.ok},
                {"errors", k.errors},   {"refused", k.refused}, {"transport_errors", k.transport}};
      r.update(percentiles(k.ms));
      json statuses = json::object();
      for (const auto& [s, n] : k.status) statuses[std::to_string(s)] = n;
      r["statuses"] = statuses;
      r["requests_per_s"] =
          std::round(static_cast<double>(k.ok + k.errors + k.refused) / elapsed_s * 10) / 10;
      bench::emit(r);
      if (kind != "health") {  // the probe is reported on its own
        total += k.ok + k.errors + k.refused;
        all_ms.insert(all_ms.end(), k.ms.begin(), k.ms.end());
      }
      errors += k.errors, refused += k.refused, transport += k.transport;
    }
    long ws_errors = 0;
    for (auto& [kind, w] : run.ws) {
      json r = {{"bench", "load_ws"},   {"kind", kind},       {"connected", w.connected},
                {"refused", w.refused}, {"errors", w.errors}, {"messages", w.messages},
                {"bytes", w.bytes}};
      r["handshake"] = percentiles(w.handshake_ms);
      r["first_message"] = percentiles(w.first_message_ms);
      bench::emit(r);
      ws_errors += w.errors;
    }
    double rss_max = rss_before;
    for (double x : rss_during)
      if (std::isfinite(x)) rss_max = std::max(rss_max, x);
    const auto r1 = [](double x) { return std::isfinite(x) ? json(std::round(x * 10) / 10) : json(nullptr); };
    json s = {{"bench", "load"},
              {"connections", c.connections},
              {"seconds", std::round(elapsed_s * 10) / 10},
              {"websockets", c.ws},
              {"upload_every_s", c.upload_every_s},
              {"dataset", c.dataset},
              {"dataset_points", ds.value("points", 0L)},
              {"dataset_flights", ds.value("flights", 0L)},
              {"token", !c.token.empty()},
              {"requests", total},
              {"requests_per_s", std::round(static_cast<double>(total) / elapsed_s * 10) / 10},
              {"errors", errors + transport + ws_errors},
              {"http_errors", errors},
              {"transport_errors", transport},
              {"ws_errors", ws_errors},
              {"refused", refused},
              {"uploads", run.upload_202_ms.size()},
              {"uploads_ingested", run.uploads_ingested},
              {"upload_timeout_s", kUploadTimeoutS},
              {"upload_transport_errors", run.kinds["upload"].transport},
              {"upload_202", percentiles(run.upload_202_ms)},
              {"latency", percentiles(all_ms)},
              {"health", percentiles(run.kinds["health"].ms)},
              {"rss_before_mib", r1(rss_before)},
              {"rss_max_mib", r1(rss_max)},
              {"rss_after_mib", r1(rss_after)}};
    bench::emit(s);
    bench::log("load_bench: " + std::to_string(total) + " requests, " +
               std::to_string(errors + transport + ws_errors) + " errors, " + std::to_string(transport) +
               " transport errors, " + std::to_string(refused) + " refused; p99 " +
               s["latency"].value("p99_ms", json(0)).dump() + " ms");
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "load_bench: " << e.what() << "\n";
    return 1;
  }
}
