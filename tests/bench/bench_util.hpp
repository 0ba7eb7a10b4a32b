#pragma once
// Shared helpers of the benchmark programs (tests/bench/*_bench.cpp): timing statistics, JSON-line output,
// a tiny blocking HTTP/1.1 client for loopback (ClickHouse's HTTP interface and the TrailScope server),
// and the ClickHouse side of the peer comparison (loading a TrailSet as RowBinary, SQL for the same
// summary and tile). Header-only so that every *_bench.cpp stays a single translation unit.
//
// Every program prints one JSON object per line on stdout (records that run_benchmarks.sh collects and
// bench_report turns into BENCHMARKS.md); human-readable progress goes to stderr.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/resource.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/geo/tile_id.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/ingest/demo_traffic.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace bench {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

inline double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
inline double ms_since(Clock::time_point a) {
  return ms_between(a, Clock::now());
}

/// Order statistics of a sample of timings. Percentiles interpolate linearly between order statistics
/// (numpy's default), so p50 of an even-sized sample is the mean of the two middle values.
struct Stats {
  std::size_t n = 0;
  double min = 0, p50 = 0, p95 = 0, max = 0, mean = 0;

  static double percentile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0;
    const double pos = q * static_cast<double>(sorted.size() - 1);
    const auto lo = static_cast<std::size_t>(pos);
    const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - static_cast<double>(lo));
  }
  static Stats of(std::vector<double> v) {
    Stats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.n = v.size();
    s.min = v.front(), s.max = v.back();
    s.p50 = percentile(v, 0.50), s.p95 = percentile(v, 0.95);
    double sum = 0;
    for (double x : v) sum += x;
    s.mean = sum / static_cast<double>(v.size());
    return s;
  }
  /// {"n", "min", "p50", "p95", "max", "mean"} with a prefix, e.g. "ms_" → "ms_p50".
  void put(json& j, const std::string& prefix) const {
    const auto r = [](double x) { return std::round(x * 1000.0) / 1000.0; };
    j[prefix + "n"] = n;
    j[prefix + "min"] = r(min);
    j[prefix + "p50"] = r(p50);
    j[prefix + "p95"] = r(p95);
    j[prefix + "max"] = r(max);
    j[prefix + "mean"] = r(mean);
  }
};

/// Prints one record (a JSON object on one line) on stdout and flushes.
inline void emit(const json& j) {
  std::cout << j.dump() << std::endl;
}
inline void log(const std::string& s) {
  std::cerr << s << std::endl;
}

/// Peak resident set size of this process so far, MiB.
inline double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

/// "--key value" and "--flag" arguments. Repeated keys keep every value (all()).
class Args {
 public:
  Args(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
      std::string a = argv[i];
      if (a.rfind("--", 0) != 0) throw std::invalid_argument("unexpected argument: " + a);
      a = a.substr(2);
      const auto eq = a.find('=');
      if (eq != std::string::npos) {
        kv_.emplace_back(a.substr(0, eq), a.substr(eq + 1));
      } else if (i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0) {
        kv_.emplace_back(a, argv[++i]);
      } else {
        kv_.emplace_back(a, "");
      }
    }
  }
  bool has(const std::string& k) const {
    for (const auto& [key, v] : kv_)
      if (key == k) return true;
    return false;
  }
  std::string get(const std::string& k, const std::string& def = "") const {
    for (auto it = kv_.rbegin(); it != kv_.rend(); ++it)
      if (it->first == k) return it->second;
    return def;
  }
  long long num(const std::string& k, long long def) const {
    const std::string v = get(k);
    return v.empty() ? def : std::stoll(v);
  }
  std::vector<std::string> all(const std::string& k) const {
    std::vector<std::string> out;
    for (const auto& [key, v] : kv_)
      if (key == k) out.push_back(v);
    return out;
  }

 private:
  std::vector<std::pair<std::string, std::string>> kv_;
};

/// Folder of vega-datasets' airports.csv and flights-airport.csv: --demo-source, else
/// $TRAILSCOPE_SOURCE/web/node_modules/vega-datasets/data, else ./web/node_modules/vega-datasets/data.
inline std::string demo_source(const Args& a) {
  if (a.has("demo-source")) return a.get("demo-source");
  const char* src = std::getenv("TRAILSCOPE_SOURCE");
  return std::string(src ? src : ".") + "/web/node_modules/vega-datasets/data";
}

/// Generates the demo day (same options → identical TrailSet) and logs how long it took.
inline trailscope::TrailSet generate_demo(const std::string& source, std::size_t flights, std::uint64_t seed,
                                          double* seconds = nullptr) {
  trailscope::ingest::DemoOptions o;
  o.airports_csv = source + "/airports.csv";
  o.routes_csv = source + "/flights-airport.csv";
  o.flights = flights;
  o.seed = seed;
  const auto t0 = Clock::now();
  trailscope::TrailSet set = trailscope::ingest::generate_demo_traffic(o);
  const double s = ms_since(t0) / 1000.0;
  if (seconds) *seconds = s;
  log("generated demo traffic: " + std::to_string(set.num_flights()) + " flights, " +
      std::to_string(set.num_points()) + " points in " + std::to_string(s) + " s");
  return set;
}

// ------------------------------------------------------------------------------------------------
// HTTP/1.1 client (blocking, keep-alive, loopback only). Enough for ClickHouse and TrailScope: GET and
// POST with Content-Length, responses with Content-Length, chunked encoding, or read-until-close.

struct HttpResponse {
  int status = 0;
  std::map<std::string, std::string> headers;  ///< names lower-cased
  std::string body;
};

inline std::string url_encode(const std::string& s) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

class HttpClient {
 public:
  /// `base` is "http://127.0.0.1:PORT" (only numeric IPv4 hosts: this client is for loopback).
  explicit HttpClient(const std::string& base) {
    std::string s = base;
    if (s.rfind("http://", 0) == 0) s = s.substr(7);
    if (const auto slash = s.find('/'); slash != std::string::npos) s = s.substr(0, slash);
    const auto colon = s.find(':');
    host_ = colon == std::string::npos ? s : s.substr(0, colon);
    port_ = colon == std::string::npos ? 80 : std::stoi(s.substr(colon + 1));
  }
  ~HttpClient() { close_(); }
  HttpClient(const HttpClient&) = delete;
  HttpClient& operator=(const HttpClient&) = delete;

  HttpResponse request(const std::string& method, const std::string& target, const std::string& body = {},
                       const std::vector<std::pair<std::string, std::string>>& headers = {}) {
    for (int attempt = 0;; ++attempt) {
      const bool reused = fd_ >= 0;
      try {
        if (fd_ < 0) connect_();
        std::string head = method + " " + target + " HTTP/1.1\r\nHost: " + host_ + ":" +
                           std::to_string(port_) + "\r\nConnection: keep-alive\r\n";
        for (const auto& [k, v] : headers) head += k + ": " + v + "\r\n";
        // Access control is on: the token run_benchmarks.sh made (`trailscope token create`), unless the
        // caller sends its own.
        const char* token = std::getenv("TRAILSCOPE_TOKEN");
        if (token && *token && std::none_of(headers.begin(), headers.end(), [](const auto& h) {
              return strcasecmp(h.first.c_str(), "authorization") == 0;
            }))
          head += "Authorization: Bearer " + std::string(token) + "\r\n";
        if (!body.empty() || method == "POST")
          head += "Content-Length: " + std::to_string(body.size()) + "\r\n";
        head += "\r\n";
        send_all_(head.data(), head.size());
        send_all_(body.data(), body.size());
        return read_response_(method == "HEAD");
      } catch (const std::exception&) {
        close_();
        // A kept-alive connection the server closed meanwhile: retry once on a fresh one.
        if (!reused || attempt > 0) throw;
      }
    }
  }

 private:
  std::string host_;
  int port_ = 80;
  int fd_ = -1;
  std::string buf_;  // received, not yet consumed

  void close_() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    buf_.clear();
  }
  void connect_() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd_ < 0) throw std::runtime_error("socket: " + std::string(std::strerror(errno)));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port_));
    if (::inet_pton(AF_INET, host_.c_str(), &a.sin_addr) != 1) throw std::runtime_error("bad host " + host_);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      const std::string e = std::strerror(errno);
      close_();
      throw std::runtime_error("connect " + host_ + ":" + std::to_string(port_) + ": " + e);
    }
    int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  }
  void send_all_(const char* p, std::size_t n) {
    while (n > 0) {
      const ssize_t k = ::send(fd_, p, n, MSG_NOSIGNAL);
      if (k < 0 && errno == EINTR) continue;
      if (k <= 0) throw std::runtime_error("send: " + std::string(std::strerror(errno)));
      p += k, n -= static_cast<std::size_t>(k);
    }
  }
  bool fill_() {
    char tmp[1 << 16];
    for (;;) {
      const ssize_t k = ::recv(fd_, tmp, sizeof tmp, 0);
      if (k < 0 && errno == EINTR) continue;
      if (k < 0) throw std::runtime_error("recv: " + std::string(std::strerror(errno)));
      if (k == 0) return false;
      buf_.append(tmp, static_cast<std::size_t>(k));
      return true;
    }
  }
  std::string take_line_() {
    for (;;) {
      const auto e = buf_.find("\r\n");
      if (e != std::string::npos) {
        std::string line = buf_.substr(0, e);
        buf_.erase(0, e + 2);
        return line;
      }
      if (!fill_()) throw std::runtime_error("connection closed in the middle of a response");
    }
  }
  std::string take_bytes_(std::size_t n) {
    while (buf_.size() < n)
      if (!fill_()) throw std::runtime_error("connection closed in the middle of a body");
    std::string out = buf_.substr(0, n);
    buf_.erase(0, n);
    return out;
  }
  HttpResponse read_response_(bool head_only) {
    HttpResponse r;
    const std::string status = take_line_();
    if (status.size() < 12 || status.rfind("HTTP/1.", 0) != 0)
      throw std::runtime_error("bad status line: " + status);
    r.status = std::stoi(status.substr(9, 3));
    for (;;) {
      const std::string line = take_line_();
      if (line.empty()) break;
      const auto c = line.find(':');
      if (c == std::string::npos) continue;
      std::string k = line.substr(0, c), v = line.substr(c + 1);
      std::transform(k.begin(), k.end(), k.begin(), [](unsigned char ch) { return std::tolower(ch); });
      v.erase(0, v.find_first_not_of(" \t"));
      r.headers[k] = v;
    }
    const auto te = r.headers.find("transfer-encoding");
    const auto cl = r.headers.find("content-length");
    if (head_only || r.status == 304 || r.status == 204) {
      // no body
    } else if (te != r.headers.end() && te->second.find("chunked") != std::string::npos) {
      for (;;) {
        const std::size_t n = std::stoul(take_line_(), nullptr, 16);
        if (n == 0) {
          while (!take_line_().empty()) {
          }  // trailers
          break;
        }
        r.body += take_bytes_(n);
        take_line_();
      }
    } else if (cl != r.headers.end()) {
      r.body = take_bytes_(std::stoul(cl->second));
    } else {
      while (fill_()) {
      }
      r.body = std::move(buf_);
      buf_.clear();
      close_();
      return r;
    }
    const auto conn = r.headers.find("connection");
    if (conn != r.headers.end() && conn->second.find("close") != std::string::npos) close_();
    return r;
  }
};

// ------------------------------------------------------------------------------------------------
// ClickHouse (the peer): its HTTP interface, loading a TrailSet, and the same summary and tile in SQL.

/// Interleaves x (even bits) and y (odd bits): the Z-order key adsb.exposed sorts by
/// (ClickHouse 18.16 has no mortonEncode, so the key is computed here and loaded as a column).
inline std::uint64_t morton(std::uint32_t x, std::uint32_t y) {
  auto spread = [](std::uint64_t v) {
    v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
    v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
    v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
    return v;
  };
  return spread(x) | (spread(y) << 1);
}

/// A number as SQL literal text that reads back to the same double.
inline std::string lit(double v) {
  char b[64];
  auto [p, ec] = std::to_chars(b, b + sizeof b, v);
  (void)ec;
  std::string s(b, p);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // keep it a Float64 literal
  return s;
}
inline std::string lit(std::uint64_t v) {
  return std::to_string(v);
}

class ClickHouse {
 public:
  explicit ClickHouse(const std::string& base) : http_(base) {}

  /// Runs a statement (no result wanted); throws with ClickHouse's message on an error.
  std::string exec(const std::string& sql, const std::string& settings = "") {
    const HttpResponse r = http_.request("POST", "/?" + settings, sql);
    if (r.status != 200)
      throw std::runtime_error("ClickHouse " + std::to_string(r.status) + ": " + r.body.substr(0, 2000) +
                               "\nSQL: " + sql);
    return r.body;
  }
  /// INSERT with a binary body.
  void insert(const std::string& table, const std::string& format, const std::string& body) {
    const std::string q = "INSERT INTO " + table + " FORMAT " + format;
    const HttpResponse r = http_.request("POST", "/?query=" + url_encode(q), body);
    if (r.status != 200)
      throw std::runtime_error("ClickHouse insert " + std::to_string(r.status) + ": " +
                               r.body.substr(0, 2000));
  }

  struct Timed {
    json result;           ///< the JSONCompact document ("data", "statistics", ...)
    double wall_ms = 0;    ///< HTTP round trip: request sent → whole response received (loopback)
    double server_ms = 0;  ///< statistics.elapsed: ClickHouse's own execution time
  };
  /// Runs a SELECT with FORMAT JSONCompact and times it. 64-bit integers come back as numbers.
  Timed query(const std::string& select) {
    const std::string sql = select + " FORMAT JSONCompact";
    const auto t0 = Clock::now();
    const HttpResponse r = http_.request(
        "POST", "/?output_format_json_quote_64bit_integers=0&output_format_json_quote_denormals=1", sql);
    Timed t;
    t.wall_ms = ms_since(t0);
    if (r.status != 200)
      throw std::runtime_error("ClickHouse " + std::to_string(r.status) + ": " + r.body.substr(0, 2000) +
                               "\nSQL: " + sql);
    t.result = json::parse(r.body);
    t.server_ms = t.result["statistics"]["elapsed"].get<double>() * 1000.0;
    return t;
  }
  std::uint64_t count(const std::string& table) {
    const std::string body = exec("SELECT count() FROM " + table);
    return std::stoull(body);
  }
  bool table_exists(const std::string& table) { return std::stoi(exec("EXISTS TABLE " + table)) == 1; }
  std::string version() {
    std::string v = exec("SELECT version()");
    while (!v.empty() && (v.back() == '\n' || v.back() == '\r')) v.pop_back();
    return v;
  }

 private:
  HttpClient http_;
};

/// The columns every peer table has: one row per TrailSet point, flight_id = index of its flight.
inline const char* kPeerColumns =
    "(t Float64, flight_id UInt32, callsign String, lat Float32, lon Float32, alt Float32, speed Float32, "
    "on_ground UInt8, mx UInt32, my UInt32, morton UInt64)";

/// The two layouts loaded for every data set; the peer's figure for a query is its faster layout.
///  - "m":  ORDER BY (morton, t), one part after OPTIMIZE FINAL: adsb.exposed's key, best for tiles;
///  - "hm": PARTITION BY hour, ORDER BY (morton, t): the time-first layout; hourly partitions let a 1-hour
///          window skip the other hours' parts (a scan of the bbox region of every day otherwise).
struct PeerLayout {
  const char* suffix;
  const char* engine;
};
inline const std::vector<PeerLayout>& peer_layouts() {
  static const std::vector<PeerLayout> l = {
      {"m", "ENGINE = MergeTree ORDER BY (morton, t) SETTINGS index_granularity = 8192"},
      {"hm",
       "ENGINE = MergeTree PARTITION BY intDiv(toUInt32(t), 3600) ORDER BY (morton, t) SETTINGS "
       "index_granularity = 8192"},
  };
  return l;
}

/// Fills every layout after the first (`prefix` + suffix names a table) from the first one, by
/// INSERT … SELECT inside ClickHouse, and merges each to its final parts.
inline void copy_to_other_layouts(ClickHouse& ch, const std::string& prefix,
                                  const std::vector<PeerLayout>& layouts) {
  const std::string first = prefix + layouts.at(0).suffix;
  for (std::size_t k = 1; k < layouts.size(); ++k) {
    const std::string t = prefix + layouts[k].suffix;
    ch.exec("INSERT INTO " + t + " SELECT * FROM " + first);
    ch.exec("OPTIMIZE TABLE " + t + " FINAL");
  }
}

/// Throws unless every layout's table holds exactly `n` rows.
inline void check_layout_counts(ClickHouse& ch, const std::string& prefix,
                                const std::vector<PeerLayout>& layouts, std::size_t n) {
  for (const auto& l : layouts) {
    const std::string t = prefix + l.suffix;
    if (ch.count(t) != n)
      throw std::runtime_error("ClickHouse table " + t + " holds " + std::to_string(ch.count(t)) +
                               " rows, expected " + std::to_string(n));
  }
}

/// True when every table `<prefix><layout>` already holds exactly `n` rows (the same generator options
/// give the same data, so a table loaded by an earlier program is reused); otherwise (re)creates them all
/// empty with `columns` and each layout's engine, and returns false.
inline bool reuse_or_recreate(ClickHouse& ch, const std::string& prefix,
                              const std::vector<PeerLayout>& layouts, const char* columns, std::size_t n) {
  bool fresh = true;
  for (const auto& l : layouts)
    if (!ch.table_exists(prefix + l.suffix) || ch.count(prefix + l.suffix) != n) fresh = false;
  if (fresh) {
    log("ClickHouse: reusing " + prefix + "* (" + std::to_string(n) + " rows)");
    return true;
  }
  for (const auto& l : layouts) {
    ch.exec("DROP TABLE IF EXISTS " + prefix + l.suffix);
    ch.exec(std::string("CREATE TABLE ") + prefix + l.suffix + " " + columns + " " + l.engine);
  }
  return false;
}

/// Loads `set` into `<base>_m` and `<base>_hm` unless both already hold exactly its points (the same
/// generator options give the same set, so a table loaded by an earlier program is reused). The data goes
/// over HTTP as RowBinary in batches of `batch` rows (exact float bits: no text round trip), into the
/// first layout; the second is filled by INSERT … SELECT inside ClickHouse; both are then merged to their
/// final parts (OPTIMIZE … FINAL). Returns a record of the load timings.
inline json load_peer(ClickHouse& ch, const std::string& base, const trailscope::TrailSet& set,
                      std::size_t batch = 1u << 20) {
  const std::size_t n = set.num_points();
  json rec = {{"bench", "peer_load"}, {"impl", "clickhouse"}, {"table", base}, {"rows", n}};
  if (reuse_or_recreate(ch, base + "_", peer_layouts(), kPeerColumns, n)) {
    rec["reused"] = true;
    return rec;
  }
  const auto& p = set.points();
  const auto& mx = set.merc_x();
  const auto& my = set.merc_y();
  std::vector<std::uint32_t> fid(n);
  for (std::size_t f = 0; f < set.num_flights(); ++f)
    for (std::uint32_t i = set.flights()[f].begin; i < set.flights()[f].end; ++i)
      fid[i] = static_cast<std::uint32_t>(f);
  auto put = [](std::string& s, const auto& v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
  const std::string first = base + "_" + peer_layouts()[0].suffix;
  double encode_ms = 0, send_ms = 0;
  const auto t_all = Clock::now();
  std::string body;
  for (std::size_t lo = 0; lo < n; lo += batch) {
    const std::size_t hi = std::min(n, lo + batch);
    const auto t0 = Clock::now();
    body.clear();
    body.reserve((hi - lo) * 64);
    for (std::size_t i = lo; i < hi; ++i) {
      put(body, p.t[i]);
      put(body, fid[i]);
      const std::string& cs = set.flights()[fid[i]].callsign;
      for (std::size_t len = cs.size();;) {  // LEB128 length
        const auto byte = static_cast<std::uint8_t>(len & 0x7f);
        len >>= 7;
        body += static_cast<char>(len ? byte | 0x80 : byte);
        if (!len) break;
      }
      body += cs;
      put(body, p.lat[i]);
      put(body, p.lon[i]);
      put(body, p.alt[i]);
      put(body, p.speed[i]);
      put(body, p.on_ground[i]);
      put(body, mx[i]);
      put(body, my[i]);
      put(body, morton(mx[i], my[i]));
    }
    const auto t1 = Clock::now();
    ch.insert(first, "RowBinary", body);
    encode_ms += ms_between(t0, t1), send_ms += ms_since(t1);
  }
  const double insert_ms = ms_since(t_all);
  auto t0 = Clock::now();
  ch.exec("OPTIMIZE TABLE " + first + " FINAL");
  const double optimize_first_ms = ms_since(t0);
  t0 = Clock::now();
  copy_to_other_layouts(ch, base + "_", peer_layouts());
  const double copy_ms = ms_since(t0);
  check_layout_counts(ch, base + "_", peer_layouts(), n);
  rec["reused"] = false;
  rec["encode_ms"] = std::round(encode_ms);
  rec["insert_http_ms"] = std::round(send_ms);
  rec["insert_rows_per_s"] = std::round(static_cast<double>(n) / (send_ms / 1000.0));
  rec["insert_total_ms"] = std::round(insert_ms);
  rec["optimize_ms"] = std::round(optimize_first_ms);
  rec["second_layout_ms"] = std::round(copy_ms);
  log("ClickHouse: loaded " + std::to_string(n) + " rows into " + base + "_* in " +
      std::to_string(insert_ms / 1000) + " s (+ " + std::to_string((optimize_first_ms + copy_ms) / 1000) +
      " s optimize/copy)");
  return rec;
}

/// The WHERE clause equivalent to PointFilter (trails/point_filter.hpp) (ClickHouse compares Float32 columns
/// with Float64 literals exactly, as C++ promotes float to double). `with_key` adds predicates that do not
/// change the result but let the primary key skip granules: the Morton ranges of the tiles covering the bbox.
inline std::string peer_where(const trailscope::Query& q, bool with_key) {
  std::vector<std::string> c;
  if (q.t0) c.push_back("t >= " + lit(*q.t0));
  if (q.t1) c.push_back("t < " + lit(*q.t1));
  if (q.alt_min) c.push_back("alt >= " + lit(*q.alt_min));
  if (q.alt_max) c.push_back("alt <= " + lit(*q.alt_max));
  if (q.on_ground) c.push_back(std::string("on_ground = ") + (*q.on_ground ? "1" : "0"));
  if (q.bbox) {
    const auto& b = *q.bbox;
    if (b.west > b.east) throw std::runtime_error("peer_where: antimeridian boxes are not benchmarked");
    c.push_back("lat >= " + lit(b.south) + " AND lat <= " + lit(b.north) + " AND lon >= " + lit(b.west) +
                " AND lon <= " + lit(b.east));
    if (with_key) {
      // Deepest zoom whose tile cover of the box has at most 16 tiles; merge adjacent Morton ranges.
      namespace geo = trailscope::geo;
      for (int z = 16; z >= 1; --z) {
        const auto nw = geo::tile_for_lonlat(b.west, b.north, z),
                   se = geo::tile_for_lonlat(b.east, b.south, z);
        const long long cnt = static_cast<long long>(se.x - nw.x + 1) * (se.y - nw.y + 1);
        if (cnt > 16) continue;
        std::vector<std::pair<std::uint64_t, std::uint64_t>> r;
        const int shift = 2 * (32 - z);
        for (int y = nw.y; y <= se.y; ++y)
          for (int x = nw.x; x <= se.x; ++x) {
            const std::uint64_t m0 = morton(static_cast<std::uint32_t>(geo::tile_origin_x({z, x, y})),
                                            static_cast<std::uint32_t>(geo::tile_origin_y({z, x, y})));
            r.emplace_back(m0, m0 + (std::uint64_t{1} << shift));
          }
        std::sort(r.begin(), r.end());
        std::vector<std::pair<std::uint64_t, std::uint64_t>> merged;
        for (const auto& iv : r) {
          if (!merged.empty() && merged.back().second == iv.first)
            merged.back().second = iv.second;
          else
            merged.push_back(iv);
        }
        std::string k = "(";
        for (std::size_t i = 0; i < merged.size(); ++i) {
          if (i) k += " OR ";
          k += "(morton >= " + lit(merged[i].first) + " AND morton < " + lit(merged[i].second) + ")";
        }
        c.push_back(k + ")");
        break;
      }
    }
  }
  if (c.empty()) return "1";
  std::string w;
  for (std::size_t i = 0; i < c.size(); ++i) w += (i ? " AND " : "") + c[i];
  return w;
}

/// Mirrors the private constant of compute/src/trails/summary.cpp (a change there shows up as a mismatch,
/// with the differing bins listed).
inline constexpr double kAltEdgeNudge = 1e-4;

/// The same summary as trailscope::summarize with default options (ft altitude bins of 1000 ft, top 10),
/// binned exactly as `ours` was (its time-histogram origin, width and bin count, its altitude bin count).
/// Three queries, each a scan of the filtered rows: the scalars (counts, time range, speed statistics with
/// t-digest percentiles), both histograms in one GROUP BY (time bin, altitude bin), and the top callsigns.
/// This split was the fastest formulation tried: one aggregate with sumMap([bin], [1]) for the histograms
/// (one pass + the top list) took 2-3x longer on 18.16 (array construction per row).
inline std::vector<std::string> peer_summary_sql(const std::string& table, const trailscope::Query& q,
                                                 const trailscope::Summary& ours, bool with_key) {
  const std::string w = peer_where(q, with_key);
  const auto tb = ours.time_histogram.counts.size(), ab = ours.altitude_histogram.counts.size();
  // The binning of compute/src/trails/summary.cpp, operation for operation (so that edge cases round the
  // same way): time bin = min(trunc(max(0, (t − t0) · (1/bin))), n − 1), moved up one bin when t is at or
  // past the next edge t0 + (bin + 1) · bin_seconds; altitude bin (a in metres, Float32 promoted to
  // Float64 as in C++) = min(trunc(a · (1/(0.3048 · 1000)) + kAltEdgeNudge), n − 1), 0 when ≤ 0; the
  // nudge (1e-4 of a bin) puts values a rounding error below an edge (FL300 = 9144 m) into the upper bin.
  const double t0 = ours.time_histogram.t0, bin = ours.time_histogram.bin_seconds;
  const std::string n1 = std::to_string(tb - 1);
  const std::string tb0 =
      "toUInt32(least(" + n1 + ", greatest(0, (t - " + lit(t0) + ") * " + lit(1.0 / bin) + ")))";
  const std::string time_bin = "(" + tb0 + " + ((" + tb0 + " < " + n1 + ") AND (t >= " + lit(t0) + " + (" +
                               tb0 + " + 1) * " + lit(bin) + ")))";
  const std::string alt_bin = "if(isNaN(alt), 4294967295, toUInt32(least(" + std::to_string(ab - 1) +
                              ", greatest(0, alt * " + lit(1.0 / (0.3048 * 1000.0)) + " + " +
                              lit(kAltEdgeNudge) + "))))";
  const std::string known = "NOT isNaN(speed)";
  return {
      "SELECT count(), uniqExact(flight_id), min(t), max(t), countIf(" + known +
          "), toFloat64(minIf(speed, " + known + ")), toFloat64(maxIf(speed, " + known + ")), avgIf(speed, " +
          known + "), quantilesTDigestIf(0.5, 0.95)(speed, " + known + ") FROM " + table + " WHERE " + w,
      "SELECT " + time_bin + " AS tb, " + alt_bin + " AS ab, count() FROM " + table + " WHERE " + w +
          " GROUP BY tb, ab",
      "SELECT callsign, uniqExact(flight_id) AS f, count() AS c FROM " + table + " WHERE " + w +
          " AND callsign != '' GROUP BY callsign ORDER BY c DESC, callsign ASC LIMIT 10",
  };
}

/// Compares a ClickHouse summary (the JSONCompact results of peer_summary_sql) with ours. Counts,
/// histograms, time range, speed min/max/count and the top list must be identical; the mean within 1e-6
/// relative; the percentiles (ours from a 0.25 m/s histogram, ClickHouse's t-digest) within 2 m/s.
/// Returns the list of differences (empty = agree).
inline std::vector<std::string> compare_summary(const trailscope::Summary& s, const json& r1, const json& r2,
                                                const json& r3) {
  std::vector<std::string> diff;
  const json& row = r1["data"][0];
  auto check = [&](const std::string& what, double ours, double theirs, double tol = 0) {
    if (!(std::fabs(ours - theirs) <= tol))
      diff.push_back(what + ": trailscope " + lit(ours) + " vs clickhouse " + lit(theirs));
  };
  check("points", static_cast<double>(s.points), row[0].get<double>());
  check("flights", static_cast<double>(s.flights), row[1].get<double>());
  if (s.points) {
    check("t_min", s.t_min, row[2].get<double>());
    check("t_max", s.t_max, row[3].get<double>());
  }
  std::vector<std::uint64_t> th(s.time_histogram.counts.size(), 0), ah(s.altitude_histogram.counts.size(), 0);
  for (const auto& g : r2["data"]) {
    const auto tb = g[0].get<std::uint64_t>(), ab = g[1].get<std::uint64_t>(), c = g[2].get<std::uint64_t>();
    if (tb < th.size())
      th[tb] += c;
    else
      diff.push_back("time_histogram: clickhouse bin " + std::to_string(tb) + " beyond " +
                     std::to_string(th.size()));
    if (ab == 4294967295ull) continue;  // unknown altitude
    if (ab < ah.size())
      ah[ab] += c;
    else
      diff.push_back("altitude_histogram: clickhouse bin " + std::to_string(ab) + " beyond " +
                     std::to_string(ah.size()));
  }
  auto hist = [&](const std::string& what, const std::vector<std::uint64_t>& ours,
                  const std::vector<std::uint64_t>& theirs) {
    std::size_t bad = 0;
    std::string first;
    for (std::size_t i = 0; i < ours.size(); ++i)
      if (ours[i] != theirs[i] && bad++ < 4)
        first += " [" + std::to_string(i) + "] " + std::to_string(ours[i]) + " vs " +
                 std::to_string(theirs[i]) + ";";
    if (bad)
      diff.push_back(what + ": " + std::to_string(bad) + " of " + std::to_string(ours.size()) +
                     " bins differ (trailscope vs clickhouse:" + first + " ...)");
  };
  hist("time_histogram", s.time_histogram.counts, th);
  hist("altitude_histogram", s.altitude_histogram.counts, ah);
  check("speed.count", static_cast<double>(s.speed.count), row[4].get<double>());
  if (s.speed.count) {
    check("speed.min", s.speed.min, row[5].get<double>());
    check("speed.max", s.speed.max, row[6].get<double>());
    check("speed.mean", s.speed.mean, row[7].get<double>(), 1e-6 * std::fabs(s.speed.mean));
    check("speed.p50", s.speed.p50, row[8][0].get<double>(), 2.0);
    check("speed.p95", s.speed.p95, row[8][1].get<double>(), 2.0);
  }
  const json& top = r3["data"];
  if (top.size() != s.top_callsigns.size()) {
    diff.push_back("top_callsigns: " + std::to_string(s.top_callsigns.size()) + " vs " +
                   std::to_string(top.size()) + " entries");
  } else {
    for (std::size_t i = 0; i < top.size(); ++i) {
      const auto& c = s.top_callsigns[i];
      if (c.callsign != top[i][0].get<std::string>() || c.flights != top[i][1].get<std::uint64_t>() ||
          c.points != top[i][2].get<std::uint64_t>())
        diff.push_back("top_callsigns[" + std::to_string(i) + "]: " + c.callsign + " " +
                       std::to_string(c.flights) + "/" + std::to_string(c.points) + " vs " + top[i].dump());
    }
  }
  return diff;
}

/// The adsb.exposed tile: points per pixel of XYZ tile `t` at `size` px (size a power of two), by integer
/// shifts of the UInt32 Mercator columns, with the tile's Morton range as the key predicate
/// (omitted at z = 0, where it is the whole key space). `pos` = row * size + column.
inline std::string peer_tile_sql(const std::string& table, const trailscope::geo::TileId& t, int size,
                                 const std::string& extra_where = "") {
  namespace geo = trailscope::geo;
  const std::uint64_t x0 = static_cast<std::uint64_t>(geo::tile_origin_x(t)),
                      y0 = static_cast<std::uint64_t>(geo::tile_origin_y(t));
  const std::uint64_t span = static_cast<std::uint64_t>(geo::tile_size_units(t.z));
  int size_bits = 0;
  while ((1 << size_bits) < size) ++size_bits;
  const int shift = 32 - t.z - size_bits;
  std::string w = "mx >= " + lit(x0) + " AND mx < " + lit(x0 + span) + " AND my >= " + lit(y0) +
                  " AND my < " + lit(y0 + span);
  if (t.z > 0) {
    const std::uint64_t m0 = morton(static_cast<std::uint32_t>(x0), static_cast<std::uint32_t>(y0));
    w += " AND morton >= " + lit(m0) + " AND morton < " + lit(m0 + (std::uint64_t{1} << (2 * (32 - t.z))));
  }
  if (!extra_where.empty()) w += " AND " + extra_where;
  return "SELECT bitShiftRight(my - " + lit(y0) + ", " + std::to_string(shift) + ") * " +
         std::to_string(size) + " + bitShiftRight(mx - " + lit(x0) + ", " + std::to_string(shift) +
         ") AS pos, count() AS c FROM " + table + " WHERE " + w + " GROUP BY pos";
}

/// The same point raster in C++ (the check of the ClickHouse tile, not a TrailScope code path): counts of
/// points per pixel of tile `t`, row-major, `size` × `size`.
inline std::vector<std::uint32_t> point_raster(const trailscope::TrailSet& set,
                                               const trailscope::geo::TileId& t, int size) {
  namespace geo = trailscope::geo;
  const std::uint64_t x0 = static_cast<std::uint64_t>(geo::tile_origin_x(t)),
                      y0 = static_cast<std::uint64_t>(geo::tile_origin_y(t));
  const std::uint64_t span = static_cast<std::uint64_t>(geo::tile_size_units(t.z));
  int size_bits = 0;
  while ((1 << size_bits) < size) ++size_bits;
  const int shift = 32 - t.z - size_bits;
  std::vector<std::uint32_t> px(static_cast<std::size_t>(size) * size, 0);
  const auto& mx = set.merc_x();
  const auto& my = set.merc_y();
  for (std::size_t i = 0; i < mx.size(); ++i) {
    const std::uint64_t dx = mx[i] - x0, dy = my[i] - y0;  // wraps to huge when left of / above the tile
    if (mx[i] < x0 || my[i] < y0 || dx >= span || dy >= span) continue;
    ++px[(dy >> shift) * static_cast<std::uint64_t>(size) + (dx >> shift)];
  }
  return px;
}

/// Compares a ClickHouse tile result ({"data": [[pos, c], ...]}) with point_raster(); returns differences.
inline std::vector<std::string> compare_tile(const std::vector<std::uint32_t>& ours, const json& r) {
  std::vector<std::uint32_t> theirs(ours.size(), 0);
  std::vector<std::string> diff;
  for (const auto& row : r["data"]) {
    const auto pos = row[0].get<std::uint64_t>();
    if (pos >= theirs.size()) {
      diff.push_back("clickhouse pixel " + std::to_string(pos) + " outside the tile");
      continue;
    }
    theirs[pos] = row[1].get<std::uint32_t>();
  }
  std::size_t bad = 0;
  std::uint64_t sum_o = 0, sum_t = 0;
  for (std::size_t i = 0; i < ours.size(); ++i)
    bad += ours[i] != theirs[i], sum_o += ours[i], sum_t += theirs[i];
  if (bad)
    diff.push_back(std::to_string(bad) + " pixels differ (points in tile: bench " + std::to_string(sum_o) +
                   ", clickhouse " + std::to_string(sum_t) + ")");
  return diff;
}

// ---- the LINE-density tile in ClickHouse (the same counts as density::density_lines) ----------------

/// The segment table a ClickHouse user would materialise for line tiles: one row per pair of consecutive
/// samples (i, i+1) of a flight, with both endpoints' 32-bit Mercator positions (b unwrapped the short way
/// across 180°, as append_segment does), their bounding box (the tile filter), the times and altitudes of
/// both endpoints (window filters) and prev_dt = t[i] − t[i−1] (+inf for a flight's first segment: it
/// decides whether the segment continues a run, see SHARED ENDPOINTS in density_lines.hpp).
inline const char* kPeerSegColumns =
    "(flight_id UInt32, seg UInt32, t0 Float64, t1 Float64, prev_dt Float64, alt0 Float32, alt1 Float32, "
    "xa Int64, ya Int64, xb Int64, yb Int64, xmin Int64, xmax Int64, ymin Int64, ymax Int64)";

/// Two layouts; the peer's figure is the faster: "f" ORDER BY (flight_id, seg) (insertion order), and
/// "y" ORDER BY (ymin, xmin) (the key prunes segments that start below the tile).
inline const std::vector<PeerLayout>& peer_seg_layouts() {
  static const std::vector<PeerLayout> l = {
      {"f", "ENGINE = MergeTree ORDER BY (flight_id, seg) SETTINGS index_granularity = 8192"},
      {"y", "ENGINE = MergeTree ORDER BY (ymin, xmin) SETTINGS index_granularity = 8192"},
  };
  return l;
}

/// Loads the segment table `<base>_seg_<layout>` (as load_peer: RowBinary into the first layout,
/// INSERT … SELECT into the second, OPTIMIZE FINAL; reused when both already hold the right row count).
inline json load_peer_segments(ClickHouse& ch, const std::string& base, const trailscope::TrailSet& set,
                               std::size_t batch = 1u << 20) {
  std::size_t n = 0;
  for (const auto& f : set.flights()) n += f.end > f.begin ? f.end - f.begin - 1 : 0;
  json rec = {{"bench", "peer_load"}, {"impl", "clickhouse"}, {"table", base + "_seg"}, {"rows", n}};
  if (reuse_or_recreate(ch, base + "_seg_", peer_seg_layouts(), kPeerSegColumns, n)) {
    rec["reused"] = true;
    return rec;
  }
  const auto& p = set.points();
  const auto& mx = set.merc_x();
  const auto& my = set.merc_y();
  auto put = [](std::string& s, const auto& v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
  const std::string first = base + "_seg_" + peer_seg_layouts()[0].suffix;
  const auto t_all = Clock::now();
  std::string body;
  std::size_t rows = 0;
  auto flush = [&] {
    if (rows) ch.insert(first, "RowBinary", body);
    body.clear();
    rows = 0;
  };
  constexpr std::int64_t kWorld = std::int64_t{1} << 32, kHalf = std::int64_t{1} << 31;
  for (std::size_t f = 0; f < set.num_flights(); ++f) {
    const auto& fl = set.flights()[f];
    for (std::uint32_t i = fl.begin; i + 1 < fl.end; ++i) {
      const std::int64_t xa = mx[i], ya = my[i];
      std::int64_t xb = mx[i + 1];
      const std::int64_t yb = my[i + 1];
      if (xb - xa > kHalf)
        xb -= kWorld;
      else if (xa - xb > kHalf)
        xb += kWorld;
      const double prev_dt = i > fl.begin ? p.t[i] - p.t[i - 1] : std::numeric_limits<double>::infinity();
      put(body, static_cast<std::uint32_t>(f));
      put(body, static_cast<std::uint32_t>(i - fl.begin));
      put(body, p.t[i]);
      put(body, p.t[i + 1]);
      put(body, prev_dt);
      put(body, p.alt[i]);
      put(body, p.alt[i + 1]);
      for (const std::int64_t v :
           {xa, ya, xb, yb, std::min(xa, xb), std::max(xa, xb), std::min(ya, yb), std::max(ya, yb)})
        put(body, v);
      if (++rows == batch) flush();
    }
  }
  flush();
  const double insert_ms = ms_since(t_all);
  auto t0 = Clock::now();
  ch.exec("OPTIMIZE TABLE " + first + " FINAL");
  copy_to_other_layouts(ch, base + "_seg_", peer_seg_layouts());
  const double opt_ms = ms_since(t0);
  check_layout_counts(ch, base + "_seg_", peer_seg_layouts(), n);
  rec["reused"] = false;
  rec["insert_total_ms"] = std::round(insert_ms);
  rec["optimize_ms"] = std::round(opt_ms);
  log("ClickHouse: loaded " + std::to_string(n) + " segments into " + base + "_seg_* in " +
      std::to_string(insert_ms / 1000) + " s (+ " + std::to_string(opt_ms / 1000) + " s optimize/copy)");
  return rec;
}

/// Prints a mismatch so that nobody can miss it (stderr), and returns the record's "match" fields.
inline void report_match(json& rec, const std::vector<std::string>& diff, const std::string& what) {
  rec["match"] = diff.empty();
  if (!diff.empty()) {
    rec["mismatch"] = diff;
    std::cerr << "\n!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!\n"
              << "!!! MISMATCH between TrailScope and ClickHouse: " << what << "\n";
    for (const auto& d : diff) std::cerr << "!!!   " << d << "\n";
    std::cerr << "!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!\n\n";
  }
}

}  // namespace bench
