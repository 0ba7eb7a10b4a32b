#pragma once
#include <memory>
#include <string>

#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "net/ws_write_queue.hpp"

namespace trailscope::server {

class WsHub;

/// One WebSocket client. The server pushes events ({"type":"job",...}); client messages are read (so
/// pings and closes work) and answered with {"type":"error"} for anything it does not understand.
class WebSocketSession : public std::enable_shared_from_this<WebSocketSession> {
 public:
  WebSocketSession(boost::beast::tcp_stream&& stream, WsHub& hub);
  ~WebSocketSession();
  /// Accepts the upgrade request and starts reading.
  void run(boost::beast::http::request<boost::beast::http::empty_body> req);
  /// Keeps `h` (the connection's slot of the connection caps, net/rate_limit.hpp) as long as the session.
  void hold(std::shared_ptr<void> h) { hold_ = std::move(h); }
  /// Queues a text message; thread-safe.
  void send(std::shared_ptr<const std::string> message);

 private:
  void on_accept(boost::beast::error_code ec);
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t);

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
  WsWriteQueue out_{ws_};
  WsHub& hub_;
  bool joined_ = false;
  std::shared_ptr<void> hold_;
};

}  // namespace trailscope::server
