#include "net/http_server.hpp"

#include <algorithm>
#include <atomic>
#include <optional>

#include <sys/resource.h>
#include <sys/socket.h>
#include <iostream>
#include <random>
#include <thread>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/write.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/http/span_body.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/url/parse.hpp>

#include "errors/error_table.hpp"
#include "net/compute_pool.hpp"
#include "net/origin_policy.hpp"
#include "net/rate_limit.hpp"
#include "net/websocket_session.hpp"
#include "net/ws_hub.hpp"
#include "replay/replay_manager.hpp"
#include "replay/replay_viewer.hpp"
#include "bundle_stream/bundle_stream_session.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "limits.hpp"

namespace trailscope::server {
namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

// "2 GiB", "256 MiB": the limit as the error detail names it.
std::string size_text(std::uint64_t bytes) {
  if (bytes >= (1ull << 30) && bytes % (1ull << 30) == 0) return std::to_string(bytes >> 30) + " GiB";
  if (bytes >= (1ull << 20)) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes >> 10) + " KiB";
}

// "30 s", "0.3 s": a configured duration as an error detail names it.
std::string seconds_text(std::chrono::milliseconds d) {
  return format_double(double(d.count()) / 1000) + " s";
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The Content-Security-Policy of the browser app: scripts, styles, workers and connections from the server
// only (MapLibre starts its worker from its own module file or a blob: URL and decodes images from blob:
// and data: URLs); no inline script, no plugins, and no framing by other pages (clickjacking).
constexpr const char* kAppCsp =
    "default-src 'self'; script-src 'self'; worker-src 'self' blob:; style-src 'self' 'unsafe-inline'; "
    "img-src 'self' data: blob:; connect-src 'self'; font-src 'self' data:; object-src 'none'; "
    "base-uri 'none'; form-action 'self'; frame-ancestors 'none'";

// Turns Beast's header + body into the router's Request; a malformed target is a 400 via the table.
Request to_request(const http::request_header<>& h, std::string body, fs::path body_file,
                   const std::string& remote) {
  Request req;
  req.remote_address = remote;
  req.method = std::string(h.method_string());
  auto parsed = boost::urls::parse_origin_form(h.target());
  if (!parsed) throw invalid_argument("path", "malformed request target");
  req.path = parsed->path();
  for (auto param : parsed->params()) req.query[param.key] = param.value;
  for (const auto& f : h) req.headers[lower(std::string(f.name_string()))] = std::string(f.value());
  req.body = std::move(body);
  req.body_file = std::move(body_file);
  return req;
}

// Status, headers and keep-alive of any Beast response from the router's Response, with the security
// headers every response carries.
template <typename Body>
void set_head(http::response<Body>& out, const Response& res, bool keep_alive) {
  out.set(http::field::server, "trailscope/" TRAILSCOPE_VERSION);
  if (!res.content_type.empty()) out.set(http::field::content_type, res.content_type);
  out.set("X-Content-Type-Options", "nosniff");
  out.set("Referrer-Policy", "no-referrer");
  if (res.content_type.rfind("text/html", 0) == 0) out.set("Content-Security-Policy", kAppCsp);
  for (const auto& [k, v] : res.headers) out.set(k, v);
  out.keep_alive(keep_alive);
}

http::response<http::string_body> to_beast(Response res, unsigned version, bool keep_alive) {
  http::response<http::string_body> out{static_cast<http::status>(res.status), version};
  set_head(out, res, keep_alive);
  out.body() = std::move(res.body);
  out.prepare_payload();
  return out;
}

// Writes a response; shared bodies (cached tiles) go out without a copy, kept alive by `res`.
net::awaitable<void> write_response(beast::tcp_stream& stream, Response res, unsigned version,
                                    bool keep_alive, beast::error_code& ec) {
  if (res.stream) {
    // Chunked transfer (RFC 9112 §7.1): the header, one chunk per piece the route's producer appends, the
    // last chunk. A HEAD gets the header only.
    http::response<http::empty_body> out{static_cast<http::status>(res.status), version};
    set_head(out, res, keep_alive);
    out.chunked(true);
    http::response_serializer<http::empty_body> sr{out};
    co_await http::async_write_header(stream, sr, net::redirect_error(net::use_awaitable, ec));
    if (res.head_only) co_return;
    std::string piece;
    for (bool more = true; more && !ec;) {
      piece.clear();
      try {
        more = res.stream(piece);
      } catch (const std::exception&) {
        // Mid-body there is no status left to send: the connection closes without the last chunk, which
        // a client reads as a truncated transfer.
        ec = net::error::operation_aborted;
        break;
      }
      if (!piece.empty())
        co_await net::async_write(stream, http::make_chunk(net::buffer(piece)),
                                  net::redirect_error(net::use_awaitable, ec));
    }
    if (!ec)
      co_await net::async_write(stream, http::make_chunk_last(), net::redirect_error(net::use_awaitable, ec));
  } else if (res.head_only) {
    http::response<http::empty_body> out{static_cast<http::status>(res.status), version};
    set_head(out, res, keep_alive);
    out.content_length(res.bytes().size());
    http::response_serializer<http::empty_body> sr{out};
    co_await http::async_write_header(stream, sr, net::redirect_error(net::use_awaitable, ec));
  } else if (res.shared_body) {
    http::response<http::span_body<const char>> out{static_cast<http::status>(res.status), version};
    set_head(out, res, keep_alive);
    out.body() = boost::span<const char>(res.shared_body->data(), res.shared_body->size());
    out.prepare_payload();
    co_await http::async_write(stream, out, net::redirect_error(net::use_awaitable, ec));
  } else {
    auto out = to_beast(std::move(res), version, keep_alive);
    co_await http::async_write(stream, out, net::redirect_error(net::use_awaitable, ec));
  }
}

fs::path upload_path(const fs::path& dir) {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  return dir / ("upload-" + std::to_string(rd()) + "-" + std::to_string(counter++));
}

// A deadline for the reads of one connection that, unlike tcp_stream's, leaves the socket open (it cancels
// the pending read), so that a 408 can still be sent. Callbacks run on the connection's strand; a stale
// one (its read already resumed) is recognised by its generation and does nothing.
class ReadDeadline {
 public:
  explicit ReadDeadline(beast::tcp_stream& s) : timer_(s.get_executor()), stream_(&s) {}
  void arm(Clock::time_point at) {
    const unsigned gen = ++state_->gen;
    state_->fired = false;
    timer_.expires_at(at);
    timer_.async_wait([st = state_, gen, s = stream_](const beast::error_code& ec) {
      if (ec || st->gen != gen) return;
      st->fired = true;
      s->socket().cancel();
    });
  }
  /// Stops the deadline; true when it fired (the read was cancelled by it).
  bool disarm() {
    ++state_->gen;
    timer_.cancel();
    return state_->fired;
  }

 private:
  struct State {
    unsigned gen = 0;
    bool fired = false;
  };
  net::steady_timer timer_;
  beast::tcp_stream* stream_;
  std::shared_ptr<State> state_ = std::make_shared<State>();
};

// What run_http_server shares with every connection.
struct Server {
  const Router& router;
  WsHub& hub;
  fs::path upload_dir;
  ReplayManager* replays;
  BundleStreams* streams;
  NetLimits lim;
  OriginPolicy policy;
  TokenBuckets per_address, per_token;
  ConnectionCounter connections;
  ComputePool pool;
};

Response retry_later(Error::Kind kind, const std::string& detail, int seconds) {
  return error_response(RetryLater(kind, "", detail, seconds));
}

// The answer to a header Beast could not parse (`raw`: the bytes read so far); nothing when the client just
// went away. Beast reports a bare LF and a version other than 1.x both as a bad version: the raw request
// line tells them apart.
std::optional<Response> header_refusal(const beast::error_code& ec, std::string_view raw,
                                       const NetLimits& lim) {
  if (ec == http::error::header_limit)
    return error_response(431, "request_header_fields_too_large", "header",
                          "the request header exceeds the limit of " + size_text(lim.max_header_bytes));
  if (ec.category() != http::make_error_code(http::error::bad_method).category() ||
      ec == http::error::end_of_stream || ec == http::error::partial_message)
    return std::nullopt;
  for (auto at = raw.find('\n'); at != std::string_view::npos; at = raw.find('\n', at + 1))
    if (at == 0 || raw[at - 1] != '\r')
      return error_response(400, "invalid_argument", "header",
                            "malformed request: a line ends in a bare LF, not CRLF");
  const auto lf = raw.find('\n');
  if (ec == http::error::bad_version && lf != std::string_view::npos && lf >= 10) {
    const std::string_view v = raw.substr(lf - 9, 8);  // "HTTP/x.y" before the CRLF
    if (v.substr(0, 5) == "HTTP/" && std::isdigit(static_cast<unsigned char>(v[5])) && v[6] == '.' &&
        std::isdigit(static_cast<unsigned char>(v[7])))
      return error_response(505, "http_version_not_supported", "version",
                            std::string(v) + " is not supported (HTTP/1.0 and HTTP/1.1 are)");
  }
  return error_response(400, "invalid_argument", "header", "malformed request: " + ec.message());
}

// Sends a last response and closes the connection. When the request's body was left unread (`drain`), the
// sending side is shut first and what the client still sends is read and dropped for a moment, so that
// closing does not reset the connection before the client has read the answer.
net::awaitable<void> answer_and_close(beast::tcp_stream& stream, beast::flat_buffer& buffer, Response res,
                                      unsigned version, bool drain) {
  beast::error_code ec;
  stream.expires_after(std::chrono::seconds(limits::kRequestTimeoutSeconds));
  co_await write_response(stream, std::move(res), version ? version : 11, false, ec);
  stream.socket().shutdown(tcp::socket::shutdown_send, ec);
  if (ec || !drain) co_return;
  stream.expires_after(std::chrono::seconds(2));
  std::size_t drained = 0;
  while (drained < (4u << 20)) {
    buffer.clear();
    const std::size_t n = co_await stream.async_read_some(buffer.prepare(64 << 10),
                                                          net::redirect_error(net::use_awaitable, ec));
    if (ec) break;
    drained += n;
  }
}

// The media type of a Content-Type value, lower-case, without parameters.
std::string media_type(const std::string& content_type) {
  std::string t = lower(content_type.substr(0, content_type.find(';')));
  while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.pop_back();
  while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front()))) t.erase(t.begin());
  return t;
}

bool is_json_type(const std::string& content_type) {
  const std::string t = media_type(content_type);
  return t == "application/json" || (t.size() > 5 && t.compare(t.size() - 5, 5, "+json") == 0);
}

// Whether an in-memory body of this Content-Type may be read for `rule` (BodyRule::media_types).
bool accepts_media_type(const BodyRule& rule, const std::string& content_type) {
  if (rule.media_types.empty()) return is_json_type(content_type);
  const std::string t = media_type(content_type);
  return std::find(rule.media_types.begin(), rule.media_types.end(), t) != rule.media_types.end();
}

std::string accepted_media_types(const BodyRule& rule) {
  if (rule.media_types.empty()) return "application/json";
  std::string s;
  for (std::size_t i = 0; i < rule.media_types.size(); ++i)
    s += (i == 0 ? "" : i + 1 == rule.media_types.size() ? " or " : ", ") + rule.media_types[i];
  return s;
}

// Reads the body of `parser` (header already read) with the total deadline `total` and the minimum rate:
// after the grace period the body must have arrived at min_body_bytes_per_second on average. Throws
// Error(request_timeout) when it does not, Error(payload_too_large) over the body limit, and
// beast::system_error when the connection fails.
template <typename Parser>
net::awaitable<void> read_body(beast::tcp_stream& stream, beast::flat_buffer& buffer, Parser& parser,
                               ReadDeadline& deadline, const NetLimits& lim, std::chrono::milliseconds total,
                               const std::string& too_large) {
  const auto start = Clock::now();
  std::uint64_t got = 0;
  beast::error_code ec;
  while (!parser.is_done()) {
    auto at = start + total;
    if (lim.min_body_bytes_per_second > 0) {
      const auto rate_at = start + lim.body_rate_grace +
                           std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                               double(got) / double(lim.min_body_bytes_per_second)));
      at = std::min(at, rate_at);
    }
    deadline.arm(at);
    const std::size_t n =
        co_await http::async_read_some(stream, buffer, parser, net::redirect_error(net::use_awaitable, ec));
    if (deadline.disarm()) {
      const bool rate = Clock::now() < start + total - std::chrono::milliseconds(100);
      throw Error(Error::Kind::request_timeout, "body",
                  rate ? "the request body arrived slower than " +
                             std::to_string(lim.min_body_bytes_per_second) + " bytes/s"
                       : "the request body did not arrive within " +
                             seconds_text(std::chrono::duration_cast<std::chrono::milliseconds>(total)));
    }
    if (ec == http::error::body_limit) throw Error(Error::Kind::payload_too_large, "body", too_large);
    if (ec) throw beast::system_error(ec);
    got += n;
  }
}

// Runs a Lane::compute request on the pool and waits for it without holding the strand: the worker posts
// its answer back; meanwhile the socket is watched for the client leaving and the deadline runs.
// Returns the answer, or nothing when the client has gone (no one to answer).
net::awaitable<std::optional<Response>> run_on_pool(Server& S, beast::tcp_stream& stream,
                                                    const Router::Route* route, Request req,
                                                    PathParams params) {
  auto ex = co_await net::this_coro::executor;
  struct Call {
    explicit Call(net::any_io_executor ex) : wake(ex, Clock::time_point::max()), deadline(ex) {}
    net::steady_timer wake, deadline;
    std::optional<Response> res;
    bool timed_out = false, gone = false, watching = true;
  };
  auto call = std::make_shared<Call>(ex);
  auto token = std::make_shared<CancelToken>();
  req.cancel = token;
  auto shared_req = std::make_shared<const Request>(std::move(req));
  const Router& router = S.router;
  auto ticket =
      S.pool.submit(token, [call, token, shared_req, params = std::move(params), route, &router, ex] {
        Response r = token->cancelled()
                         ? error_response(Error(Error::Kind::cancelled, "", "operation cancelled"))
                         : router.respond(route, *shared_req, params);
        net::post(ex, [call, r = std::move(r)]() mutable {
          call->res = std::move(r);
          call->wake.cancel();
        });
      });
  if (!ticket)
    co_return retry_later(Error::Kind::unavailable,
                          "the server is at capacity: " + std::to_string(S.lim.max_queued_compute) +
                              " requests are waiting for the compute pool",
                          limits::kRetryAfterSeconds);
  // The client leaving: the socket turns readable with nothing to read (EOF) or with an error (reset).
  // Readable with data is a pipelined request: the client is there, the watch stops.
  auto* socket = &stream.socket();
  socket->async_wait(tcp::socket::wait_read, [call, socket, token](const beast::error_code& ec) {
    if (ec || !call->watching) return;
    char c;
    const ssize_t n = ::recv(socket->native_handle(), &c, 1, MSG_PEEK | MSG_DONTWAIT);
    if (n > 0 || (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))) return;
    call->gone = true;
    token->cancel();
    call->wake.cancel();
  });
  call->deadline.expires_after(S.lim.compute_deadline);
  call->deadline.async_wait([call, token](const beast::error_code& ec) {
    if (ec || call->res) return;
    call->timed_out = true;
    token->cancel();
    call->wake.cancel();
  });
  beast::error_code ec;
  while (!call->res && !call->timed_out && !call->gone)
    co_await call->wake.async_wait(net::redirect_error(net::use_awaitable, ec));
  call->watching = false;
  call->deadline.cancel();
  socket->cancel(ec);  // ends the watch
  // Once the deadline has fired it decides the answer: the handler's own answer to the cancellation it
  // caused (409 "operation cancelled") can be posted before this coroutine resumes (seen under load),
  // and the client is owed the 503 that says why.
  if (call->res && !call->timed_out) co_return std::move(call->res);
  S.pool.withdraw(*ticket);
  if (call->gone) co_return std::nullopt;
  co_return retry_later(
      Error::Kind::unavailable,
      "the request did not finish within " + seconds_text(S.lim.compute_deadline) + "; it was cancelled",
      limits::kRetryAfterSeconds);
}

net::awaitable<void> session(beast::tcp_stream stream, Server& S, ConnectionCounter::Slot slot) {
  beast::flat_buffer buffer;
  beast::error_code ec;
  const std::string remote = [&] {
    auto ep = stream.socket().remote_endpoint(ec);
    return ec ? std::string() : ep.address().to_string();
  }();
  const std::string key = client_key(remote);
  ReadDeadline deadline(stream);
  for (;;) {
    http::request_parser<http::empty_body> head;
    head.header_limit(static_cast<std::uint32_t>(S.lim.max_header_bytes));
    // The body limit depends on the route, so it is checked below, not by this header-only parser
    // (whose default 1 MB limit would otherwise reject every large upload while reading the header).
    head.body_limit(boost::none);
    stream.expires_never();
    deadline.arm(Clock::now() + S.lim.request_timeout);
    co_await http::async_read_header(stream, buffer, head, net::redirect_error(net::use_awaitable, ec));
    if (deadline.disarm()) {
      // A header begun and not finished in time is answered; an idle keep-alive connection just closed.
      if (buffer.size() > 0)
        co_await answer_and_close(stream, buffer,
                                  error_response(Error(Error::Kind::request_timeout, "header",
                                                       "the request header did not arrive within " +
                                                           seconds_text(S.lim.request_timeout))),
                                  11, false);
      break;
    }
    if (ec) {
      const auto data = buffer.data();
      const std::string_view raw(static_cast<const char*>(data.data()), data.size());
      if (auto res = header_refusal(ec, raw, S.lim))
        co_await answer_and_close(stream, buffer, *res, 11, true);
      break;  // closed, or not HTTP
    }
    const auto& h = head.get();
    const unsigned version = h.version();
    const bool has_body = head.chunked() || (head.content_length() && *head.content_length() > 0);
    const bool websocket = beast::websocket::is_upgrade(h);

    // Everything known from the header: refusals here leave the body unread.
    Request req;
    PathParams params;
    const Router::Route* route = nullptr;
    BodyRule rule;
    std::optional<Response> refusal;
    try {
      if (version != 10 && version != 11) {
        co_await answer_and_close(
            stream, buffer,
            error_response(505, "http_version_not_supported", "version",
                           "HTTP/" + std::to_string(version / 10) + "." + std::to_string(version % 10) +
                               " is not supported (HTTP/1.0 and HTTP/1.1 are)"),
            11, has_body);
        break;
      }
      // Beast takes two equal Content-Lengths as one (RFC 9110 allows it); a request that sends two is
      // refused all the same, as a proxy in front may have read the other one.
      if (h.count(http::field::content_length) > 1)
        throw invalid_argument("header", "malformed request: more than one Content-Length");
      if (h.count(http::field::host) > 1) throw invalid_argument("host", "more than one Host header");
      const std::string host(h[http::field::host]);
      S.policy.check_host(host, version == 11);
      if (const int wait = S.per_address.take(key))
        throw RetryLater(
            Error::Kind::too_many_requests, "",
            "more than " + format_double(S.lim.per_address_rate) + " requests per second from this address",
            wait);
      req = to_request(h, {}, {}, remote);
      if (websocket || OriginPolicy::state_changing(req.method))
        S.policy.check_origin(req.header("origin"), host);
      if (!websocket) {
        route = S.router.admit(req, params);
        if (!req.principal.anonymous())
          if (const int wait = S.per_token.take(req.principal.token_id))
            throw RetryLater(
                Error::Kind::too_many_requests, "",
                "more than " + format_double(S.lim.per_token_rate) + " requests per second with this token",
                wait);
        if (route) rule = route->body;
        if (head.content_length() && *head.content_length() > rule.limit)
          throw Error(Error::Kind::payload_too_large, "body",
                      rule.name + " exceeds the limit of " + size_text(rule.limit));
        if (route && has_body && !rule.to_file && !accepts_media_type(rule, req.header("content-type")))
          throw Error(Error::Kind::unsupported_format, "content-type",
                      "Content-Type must be " + accepted_media_types(rule) + ", got '" +
                          req.header("content-type") + "'");
      }
    } catch (const std::exception& e) {
      refusal = error_response(e);
    }
    if (refusal) {
      co_await answer_and_close(stream, buffer, std::move(*refusal), version, has_body);
      break;
    }

    if (websocket) {
      // The route table decides: an unknown endpoint, an unknown replay or a full one is answered before
      // upgrading.
      Router::Upgrade up;
      std::shared_ptr<Replay> replay;
      try {
        up = S.router.upgrade(std::move(req));
        if (up.route && up.route->websocket == WebSocketKind::replay) {
          if (!S.replays) throw not_found("replay", "replay '" + up.params.at("replay") + "' does not exist");
          replay = S.replays->get(up.params.at("replay"));
        }
        if (up.route && up.route->websocket == WebSocketKind::bundle_stream && !S.streams)
          throw Error(Error::Kind::internal, "", "this server was started without bundle streams");
      } catch (const std::exception& e) {
        up.route = nullptr;
        up.refusal = error_response(e);
      }
      if (!up.route) {
        co_await answer_and_close(stream, buffer, std::move(up.refusal), version, has_body);
        break;
      }
      stream.expires_never();
      // Replay viewers and bundle streams have caps of their own (kMaxReplayViewers, kMaxBundleStreams);
      // job-event sockets keep their connection slot.
      if (up.route->websocket == WebSocketKind::bundle_stream)
        S.streams->open(std::move(stream), head.release(), up.params.at("dataset"));
      else if (replay)
        std::make_shared<ReplayViewer>(std::move(stream), replay)->run(head.release());
      else {
        auto ws = std::make_shared<WebSocketSession>(std::move(stream), S.hub);
        ws->hold(std::move(slot));
        ws->run(head.release());
      }
      co_return;
    }

    if (has_body && lower(std::string(h[http::field::expect])) == "100-continue" && version == 11) {
      static const std::string kContinue = "HTTP/1.1 100 Continue\r\n\r\n";
      stream.expires_after(S.lim.request_timeout);
      co_await net::async_write(stream, net::buffer(kContinue), net::redirect_error(net::use_awaitable, ec));
      if (ec) break;
      stream.expires_never();
    }

    Response res;
    bool keep_alive = h.keep_alive();
    fs::path file;
    bool unread = false;  // a refusal while reading leaves the rest of the body unread
    try {
      const std::string too_large = rule.name + " exceeds the limit of " + size_text(rule.limit);
      if (rule.to_file) {
        // Uploads stream to disk with their own limit and timeout; memory stays flat.
        file = upload_path(S.upload_dir);
        http::request_parser<http::file_body> p{std::move(head)};
        p.body_limit(rule.limit);
        p.get().body().open(file.c_str(), beast::file_mode::write, ec);
        if (ec) throw Error(Error::Kind::internal, "", "cannot open upload file: " + ec.message());
        unread = true;
        co_await read_body(stream, buffer, p, deadline, S.lim, S.lim.upload_timeout, too_large);
        unread = false;
        p.get().body().close();
        req.body_file = file;
        keep_alive = p.get().keep_alive();
      } else {
        http::request_parser<http::string_body> p{std::move(head)};
        p.body_limit(rule.limit);
        unread = has_body;
        co_await read_body(stream, buffer, p, deadline, S.lim, S.lim.request_timeout, too_large);
        unread = false;
        req.body = std::move(p.get().body());
      }
      if (route && route->lane == Lane::compute) {
        auto answer = co_await run_on_pool(S, stream, route, std::move(req), std::move(params));
        if (!answer) break;  // the client has gone
        res = std::move(*answer);
      } else {
        res = S.router.respond(route, req, params);
      }
      if (!file.empty() && res.status >= 400) fs::remove(file, ec);  // the handler did not take it
    } catch (const beast::system_error& e) {
      if (!file.empty()) fs::remove(file, ec);
      std::cerr << "connection dropped mid-request: " << e.code().message() << "\n";
      break;  // the connection failed mid-request; nobody to answer
    } catch (const std::exception& e) {
      if (!file.empty()) fs::remove(file, ec);
      refusal = error_response(e);
    }
    if (refusal) {
      co_await answer_and_close(stream, buffer, std::move(*refusal), version, unread);
      break;
    }
    stream.expires_after(S.lim.request_timeout);
    co_await write_response(stream, std::move(res), version, keep_alive, ec);
    if (ec || !keep_alive) break;
  }
  stream.socket().shutdown(tcp::socket::shutdown_send, ec);
}

// Answers a connection over a cap and closes it at once (no draining: a flood of refused connections must
// not hold file descriptors).
net::awaitable<void> refuse_connection(beast::tcp_stream stream, std::string why) {
  beast::flat_buffer buffer;
  co_await answer_and_close(stream, buffer,
                            retry_later(Error::Kind::unavailable,
                                        why == "address" ? "too many open connections from this address"
                                                         : "too many open connections",
                                        limits::kRetryAfterSeconds),
                            11, false);
}

net::awaitable<void> listen(tcp::acceptor& acceptor, Server& S) {
  for (;;) {
    beast::error_code ec;
    auto socket = co_await acceptor.async_accept(net::make_strand(acceptor.get_executor()),
                                                 net::redirect_error(net::use_awaitable, ec));
    if (ec) {
      if (ec == net::error::operation_aborted) co_return;
      // E.g. too many open files: keep serving the others, after a pause rather than in a busy loop.
      net::steady_timer pause(acceptor.get_executor(), std::chrono::milliseconds(50));
      co_await pause.async_wait(net::redirect_error(net::use_awaitable, ec));
      continue;
    }
    auto ex = socket.get_executor();
    const auto ep = socket.remote_endpoint(ec);
    std::string why;
    auto slot = S.connections.acquire(client_key(ec ? std::string() : ep.address().to_string()), &why);
    if (!slot)
      net::co_spawn(ex, refuse_connection(beast::tcp_stream(std::move(socket)), why), net::detached);
    else
      net::co_spawn(ex, session(beast::tcp_stream(std::move(socket)), S, std::move(slot)), net::detached);
  }
}

}  // namespace

void run_http_server(const ServerOptions& opts, const Router& router, WsHub& hub, const fs::path& upload_dir,
                     const std::function<void(unsigned short)>& on_listening, ReplayManager* replays,
                     BundleStreams* streams) {
  net::io_context ioc(static_cast<int>(opts.threads));
  tcp::acceptor acceptor(ioc);
  beast::error_code ec;
  const auto address = net::ip::make_address(opts.host, ec);
  if (ec) throw invalid_argument("host", "host: '" + opts.host + "' is not an IP address");
  const tcp::endpoint ep{address, opts.port};
  acceptor.open(ep.protocol(), ec);
  if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(ep, ec);
  if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec)
    throw Error(Error::Kind::internal, "port",
                "cannot listen on " + opts.host + ":" + std::to_string(opts.port) + ": " + ec.message());
  const unsigned short port = acceptor.local_endpoint().port();
  const NetLimits& L = opts.limits;
  // Room for the connection cap's sockets, their upload files and the store's files: the soft limit on open
  // files is raised to the hard one (often 1024 and 4096 or more). When it stays below the cap, accept
  // fails with EMFILE for a while rather than the cap refusing with 503.
  if (rlimit fds{}; getrlimit(RLIMIT_NOFILE, &fds) == 0 && fds.rlim_cur < fds.rlim_max) {
    fds.rlim_cur = fds.rlim_max;
    setrlimit(RLIMIT_NOFILE, &fds);
  }
  // Declared after the io_context, so destroyed before it: the pool's threads post into it.
  Server server{router,
                hub,
                upload_dir,
                replays,
                streams,
                L,
                OriginPolicy(opts.host, port, opts.server_names, opts.allowed_origins),
                TokenBuckets(L.per_address_rate, L.per_address_burst),
                TokenBuckets(L.per_token_rate, L.per_token_burst),
                ConnectionCounter(L.max_connections_per_address, L.max_connections),
                ComputePool(L.compute_workers, L.max_queued_compute)};

  net::signal_set signals(ioc, SIGINT, SIGTERM);
  signals.async_wait([&](const beast::error_code&, int) {
    acceptor.close();
    ioc.stop();
  });
  // Reported once the signal handler is in place, so that a SIGTERM right after it stops the server.
  on_listening(port);
  net::co_spawn(ioc, listen(acceptor, server), net::detached);
  std::vector<std::thread> threads;
  for (unsigned i = 1; i < std::max(1u, opts.threads); ++i) threads.emplace_back([&] { ioc.run(); });
  ioc.run();
  for (auto& t : threads) t.join();
}

}  // namespace trailscope::server
