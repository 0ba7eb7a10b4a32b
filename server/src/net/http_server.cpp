#include "net/http_server.hpp"

#include <atomic>
#include <iostream>
#include <random>
#include <thread>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/http/span_body.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/url/parse.hpp>

#include "errors/error_table.hpp"
#include "net/websocket_session.hpp"
#include "net/ws_hub.hpp"
#include "replay/replay_manager.hpp"
#include "replay/replay_viewer.hpp"
#include "bundle_stream/bundle_stream_session.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"

namespace trailscope::server {
namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;
namespace fs = std::filesystem;

namespace {

// "2 GiB", "256 MiB": the limit as the error detail names it.
std::string size_text(std::uint64_t bytes) {
  if (bytes >= (1ull << 30) && bytes % (1ull << 30) == 0) return std::to_string(bytes >> 30) + " GiB";
  return std::to_string(bytes >> 20) + " MiB";
}

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
  for (const auto& f : h) {
    std::string name(f.name_string());
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    req.headers[name] = std::string(f.value());
  }
  req.body = std::move(body);
  req.body_file = std::move(body_file);
  return req;
}

// Status, headers and keep-alive of any Beast response from the router's Response.
template <typename Body>
void set_head(http::response<Body>& out, const Response& res, bool keep_alive) {
  out.set(http::field::server, "trailscope/" TRAILSCOPE_VERSION);
  if (!res.content_type.empty()) out.set(http::field::content_type, res.content_type);
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
  if (res.head_only) {
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

// The body rule of the route the request reaches (the default rule for a malformed target, which the
// router then refuses).
BodyRule body_rule(const Router& router, const http::request_header<>& h) {
  auto parsed = boost::urls::parse_origin_form(h.target());
  if (!parsed) return {};
  return router.body_rule(std::string(h.method_string()), parsed->path());
}

fs::path upload_path(const fs::path& dir) {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  return dir / ("upload-" + std::to_string(rd()) + "-" + std::to_string(counter++));
}

net::awaitable<void> session(beast::tcp_stream stream, const Router& router, WsHub& hub, fs::path upload_dir,
                             ReplayManager* replays, BundleStreams* streams) {
  beast::flat_buffer buffer;
  beast::error_code ec;
  const std::string remote = [&] {
    auto ep = stream.socket().remote_endpoint(ec);
    return ec ? std::string() : ep.address().to_string();
  }();
  for (;;) {
    http::request_parser<http::empty_body> head;
    head.header_limit(16 * 1024);
    // The body limit depends on the route, so it is checked below, not by this header-only parser
    // (whose default 1 MB limit would otherwise reject every large upload while reading the header).
    head.body_limit(boost::none);
    stream.expires_after(std::chrono::seconds(limits::kRequestTimeoutSeconds));
    co_await http::async_read_header(stream, buffer, head, net::redirect_error(net::use_awaitable, ec));
    if (ec) break;  // closed, timed out, or not HTTP: nothing useful to answer
    const auto& h = head.get();
    const unsigned version = h.version();

    if (beast::websocket::is_upgrade(h)) {
      // The route table decides: an unknown endpoint, an unknown replay or a full one is answered before
      // upgrading.
      Router::Upgrade up;
      std::shared_ptr<Replay> replay;
      try {
        up = router.upgrade(to_request(h, {}, {}, remote));
        if (up.route && up.route->websocket == WebSocketKind::replay) {
          if (!replays) throw not_found("replay", "replay '" + up.params.at("replay") + "' does not exist");
          replay = replays->get(up.params.at("replay"));
        }
        if (up.route && up.route->websocket == WebSocketKind::bundle_stream && !streams)
          throw Error(Error::Kind::internal, "", "this server was started without bundle streams");
      } catch (const std::exception& e) {
        up.route = nullptr;
        up.refusal = error_response(e);
      }
      if (!up.route) {
        auto res = to_beast(std::move(up.refusal), version, false);
        co_await http::async_write(stream, res, net::redirect_error(net::use_awaitable, ec));
        break;
      }
      stream.expires_never();
      if (up.route->websocket == WebSocketKind::bundle_stream)
        streams->open(std::move(stream), head.release(), up.params.at("dataset"));
      else if (replay)
        std::make_shared<ReplayViewer>(std::move(stream), replay)->run(head.release());
      else
        std::make_shared<WebSocketSession>(std::move(stream), hub)->run(head.release());
      co_return;
    }

    Response res;
    bool keep_alive = h.keep_alive();
    fs::path file;
    try {
      const BodyRule rule = body_rule(router, h);
      const bool upload = rule.to_file;
      const std::uint64_t limit = rule.limit;
      const std::string too_large = rule.name + " exceeds the limit of " + size_text(limit);
      if (head.content_length() && *head.content_length() > limit)
        throw Error(Error::Kind::payload_too_large, "body", too_large);
      if (upload) {
        // Uploads stream to disk with their own limit and timeout; memory stays flat.
        file = upload_path(upload_dir);
        http::request_parser<http::file_body> p{std::move(head)};
        p.body_limit(limit);
        p.get().body().open(file.c_str(), beast::file_mode::write, ec);
        if (ec) throw Error(Error::Kind::internal, "", "cannot open upload file: " + ec.message());
        stream.expires_after(std::chrono::seconds(limits::kUploadTimeoutSeconds));
        co_await http::async_read(stream, buffer, p, net::redirect_error(net::use_awaitable, ec));
        p.get().body().close();
        if (ec == http::error::body_limit) throw Error(Error::Kind::payload_too_large, "body", too_large);
        if (ec) throw beast::system_error(ec);
        res = router.handle(to_request(p.get(), {}, file, remote));
        if (res.status >= 400) fs::remove(file, ec);  // the handler did not take it
        keep_alive = p.get().keep_alive();
      } else {
        http::request_parser<http::string_body> p{std::move(head)};
        p.body_limit(limit);
        co_await http::async_read(stream, buffer, p, net::redirect_error(net::use_awaitable, ec));
        if (ec == http::error::body_limit) throw Error(Error::Kind::payload_too_large, "body", too_large);
        if (ec) throw beast::system_error(ec);
        auto msg = p.release();
        res = router.handle(to_request(msg, std::move(msg.body()), {}, remote));
      }
    } catch (const beast::system_error& e) {
      if (!file.empty()) fs::remove(file, ec);
      std::cerr << "connection dropped mid-request: " << e.code().message() << "\n";
      break;  // the connection failed mid-request; nobody to answer
    } catch (const std::exception& e) {
      if (!file.empty()) fs::remove(file, ec);
      res = error_response(e);
      keep_alive = false;  // the rest of the body is unread: do not reuse the connection
    }
    stream.expires_after(std::chrono::seconds(limits::kRequestTimeoutSeconds));
    co_await write_response(stream, std::move(res), version, keep_alive, ec);
    if (ec || !keep_alive) break;
  }
  stream.socket().shutdown(tcp::socket::shutdown_send, ec);
}

net::awaitable<void> listen(tcp::acceptor& acceptor, const Router& router, WsHub& hub, fs::path upload_dir,
                            ReplayManager* replays, BundleStreams* streams) {
  for (;;) {
    beast::error_code ec;
    auto socket = co_await acceptor.async_accept(net::make_strand(acceptor.get_executor()),
                                                 net::redirect_error(net::use_awaitable, ec));
    if (ec) {
      if (ec == net::error::operation_aborted) co_return;
      continue;  // e.g. too many open files: keep serving the others
    }
    auto ex = socket.get_executor();
    net::co_spawn(ex,
                  session(beast::tcp_stream(std::move(socket)), router, hub, upload_dir, replays, streams),
                  net::detached);
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
  on_listening(acceptor.local_endpoint().port());

  net::signal_set signals(ioc, SIGINT, SIGTERM);
  signals.async_wait([&](const beast::error_code&, int) {
    acceptor.close();
    ioc.stop();
  });
  net::co_spawn(ioc, listen(acceptor, router, hub, upload_dir, replays, streams), net::detached);
  std::vector<std::thread> threads;
  for (unsigned i = 1; i < std::max(1u, opts.threads); ++i) threads.emplace_back([&] { ioc.run(); });
  ioc.run();
  for (auto& t : threads) t.join();
}

}  // namespace trailscope::server
