#include "store/clickhouse_client.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/url/encode.hpp>
#include <boost/url/rfc/unreserved_chars.hpp>

namespace trailscope::server {
namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;

namespace {

bool name_ok(const std::string& s) {
  return !s.empty() && s.size() <= 64 &&
         s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") ==
             std::string::npos;
}

std::string url_encode(std::string_view s) {
  return boost::urls::encode(s, boost::urls::unreserved_chars);
}

/// Where a request failed: before anything was sent (another node may take it), or after.
struct TransportError {
  bool before_send;
  std::string what;
  bool timed_out = false;
};

}  // namespace

ClickHouseUrl ClickHouseUrl::parse(const std::string& url, const std::string& param) {
  const std::string scheme = "clickhouse://";
  auto bad = [&](const std::string& why) {
    return invalid_argument(param, param + ": '" + url + "' " + why +
                                       " (expected clickhouse://HOST:PORT[,HOST:PORT...]/DB?cluster=NAME)");
  };
  if (url.rfind(scheme, 0) != 0) throw bad("does not start with clickhouse://");
  const std::string rest = url.substr(scheme.size());
  const auto slash = rest.find('/');
  if (slash == std::string::npos) throw bad("names no database");
  ClickHouseUrl out;
  std::string hosts = rest.substr(0, slash), tail = rest.substr(slash + 1);
  std::size_t start = 0;
  while (start <= hosts.size()) {
    const auto comma = std::min(hosts.find(',', start), hosts.size());
    const std::string hp = hosts.substr(start, comma - start);
    const auto colon = hp.rfind(':');
    if (hp.empty() || colon == std::string::npos || colon == 0) throw bad("has a host without HOST:PORT");
    ClickHouseEndpoint ep;
    ep.host = hp.substr(0, colon);
    const std::string port = hp.substr(colon + 1);
    if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
        std::stoul(port) == 0 || std::stoul(port) > 65535)
      throw bad("has a port that is not 1..65535");
    if (ep.host.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-") !=
        std::string::npos)
      throw bad("has a host name with characters other than letters, digits, '.' and '-'");
    ep.port = static_cast<unsigned short>(std::stoul(port));
    out.hosts.push_back(ep);
    start = comma + 1;
  }
  if (out.hosts.size() > 16) throw bad("lists more than 16 hosts");
  const auto q = tail.find('?');
  out.database = tail.substr(0, q);
  if (!name_ok(out.database)) throw bad("has a database name that is not 1-64 of A-Z a-z 0-9 _");
  std::string query = q == std::string::npos ? "" : tail.substr(q + 1);
  start = 0;
  while (start < query.size()) {
    const auto amp = std::min(query.find('&', start), query.size());
    const std::string kv = query.substr(start, amp - start);
    const auto eq = kv.find('=');
    const std::string key = kv.substr(0, eq), value = eq == std::string::npos ? "" : kv.substr(eq + 1);
    if (key == "cluster")
      out.cluster = value;
    else
      throw bad("has an unknown parameter '" + key + "' (known: cluster)");
    start = amp + 1;
  }
  if (!name_ok(out.cluster)) throw bad("needs cluster=NAME, 1-64 of A-Z a-z 0-9 _");
  return out;
}

ClickHouseClient::ClickHouseClient(std::vector<ClickHouseEndpoint> hosts, Timeouts timeouts)
    : hosts_(std::move(hosts)), timeouts_(timeouts) {
  if (hosts_.empty()) throw invalid_argument("store", "store: no ClickHouse host");
}

std::string ClickHouseClient::quote(std::string_view s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\\' || c == '\'') out.push_back('\\');
    out.push_back(c);
  }
  return out + "'";
}

namespace {

/// One request to one node; throws TransportError or ClickHouseError.
std::string request_once(const ClickHouseEndpoint& ep, const std::string& target, std::string_view body,
                         const ClickHouseClient::Timeouts& to) {
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  beast::error_code ec;
  // Every step runs asynchronously on this thread's own io_context so that the stream's deadline applies.
  auto run = [&] {
    ioc.run();
    ioc.restart();
  };
  tcp::resolver resolver(ioc);
  tcp::resolver::results_type endpoints;
  resolver.async_resolve(
      ep.host, std::to_string(ep.port),
      [&](beast::error_code e, tcp::resolver::results_type r) { ec = e, endpoints = std::move(r); });
  run();
  if (ec) throw TransportError{true, "resolve " + ep.to_string() + ": " + ec.message()};
  stream.expires_after(to.connect);
  stream.async_connect(endpoints, [&](beast::error_code e, const tcp::endpoint&) { ec = e; });
  run();
  if (ec) throw TransportError{true, "connect " + ep.to_string() + ": " + ec.message()};

  http::request<http::buffer_body> req{http::verb::post, target, 11};
  req.set(http::field::host, ep.to_string());
  req.set(http::field::connection, "close");
  req.set(http::field::content_type, "application/octet-stream");
  req.content_length(body.size());
  req.body().data = const_cast<char*>(body.data());
  req.body().size = body.size();
  req.body().more = false;
  stream.expires_after(to.request);
  http::async_write(stream, req, [&](beast::error_code e, std::size_t) { ec = e; });
  run();
  if (ec)
    throw TransportError{false, "send to " + ep.to_string() + ": " + ec.message(),
                         ec == beast::error::timeout};

  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(boost::none);  // datasets are bounded by the ingest limits, not here
  http::async_read(stream, buffer, parser, [&](beast::error_code e, std::size_t) { ec = e; });
  run();
  if (ec)
    throw TransportError{false, "read from " + ep.to_string() + ": " + ec.message(),
                         ec == beast::error::timeout};
  auto res = parser.release();
  stream.socket().shutdown(tcp::socket::shutdown_both, ec);
  if (res.result() != http::status::ok) {
    std::string msg = res.body();
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    int code = 0;
    if (msg.rfind("Code: ", 0) == 0) code = std::atoi(msg.c_str() + 6);
    if (msg.size() > 2000) msg.resize(2000);
    throw ClickHouseError(code, ep.to_string() + ": " + msg);
  }
  return std::move(res.body());
}

}  // namespace

std::string ClickHouseClient::query(const std::string& sql, const Settings& settings, std::string_view data) {
  std::string target = "/?";
  for (const auto& [k, v] : settings) target += url_encode(k) + "=" + url_encode(v) + "&";
  std::string body_holder;
  std::string_view body = data;
  const bool insert = !data.empty();
  if (insert)
    target += "query=" + url_encode(sql);
  else
    body = sql;
  std::size_t first;
  {
    std::lock_guard lock(mu_);
    first = preferred_;
  }
  std::string failures;
  for (std::size_t i = 0; i < hosts_.size(); ++i) {
    const std::size_t k = (first + i) % hosts_.size();
    try {
      std::string out = request_once(hosts_[k], target, body, timeouts_);
      std::lock_guard lock(mu_);
      preferred_ = k;
      return out;
    } catch (const TransportError& te) {
      if (te.timed_out)
        throw Error(Error::Kind::request_timeout, "store", "ClickHouse did not answer in time: " + te.what);
      failures += (failures.empty() ? "" : "; ") + te.what;
      // A request whose body went out may have been applied: only a SELECT (or DDL, which is idempotent
      // here: IF [NOT] EXISTS) is sent again to another node.
      if (!te.before_send && insert) break;
    }
  }
  throw Error(Error::Kind::unavailable, "store", "no ClickHouse node answered: " + failures);
}

}  // namespace trailscope::server
