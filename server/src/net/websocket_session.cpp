#include "net/websocket_session.hpp"

#include <boost/asio/post.hpp>

#include "net/ws_hub.hpp"

namespace trailscope::server {
namespace beast = boost::beast;
namespace websocket = beast::websocket;

void WsHub::join(WebSocketSession* s) {
  std::lock_guard lock(mu_);
  sessions_.insert(s);
}
void WsHub::leave(WebSocketSession* s) {
  std::lock_guard lock(mu_);
  sessions_.erase(s);
}
std::size_t WsHub::size() const {
  std::lock_guard lock(mu_);
  return sessions_.size();
}
void WsHub::broadcast(std::string message) {
  auto shared = std::make_shared<const std::string>(std::move(message));
  std::vector<std::weak_ptr<WebSocketSession>> targets;
  {
    std::lock_guard lock(mu_);
    for (auto* s : sessions_) targets.push_back(s->weak_from_this());
  }
  for (auto& w : targets)
    if (auto s = w.lock()) s->send(shared);
}

WebSocketSession::WebSocketSession(beast::tcp_stream&& stream, WsHub& hub)
    : ws_(std::move(stream)), hub_(hub) {}

WebSocketSession::~WebSocketSession() {
  if (joined_) hub_.leave(this);
}

void WebSocketSession::run(beast::http::request<beast::http::empty_body> req) {
  set_server_options(ws_);
  ws_.async_accept(req, beast::bind_front_handler(&WebSocketSession::on_accept, shared_from_this()));
}

void WebSocketSession::on_accept(beast::error_code ec) {
  if (ec) return;
  hub_.join(this);
  joined_ = true;
  send(std::make_shared<const std::string>(R"({"type":"hello","version":")" TRAILSCOPE_VERSION R"("})"));
  do_read();
}

void WebSocketSession::do_read() {
  ws_.async_read(buffer_, beast::bind_front_handler(&WebSocketSession::on_read, shared_from_this()));
}

void WebSocketSession::on_read(beast::error_code ec, std::size_t) {
  if (ec) return;  // closed or failed: the session ends when the last handler lets go
  const std::string text = beast::buffers_to_string(buffer_.data());
  buffer_.consume(buffer_.size());
  if (text == R"({"type":"ping"})")
    send(std::make_shared<const std::string>(R"({"type":"pong"})"));
  else
    send(std::make_shared<const std::string>(
        R"({"type":"error","error":"invalid_argument","detail":"unknown message; the server only sends events","param":"type"})"));
  do_read();
}

void WebSocketSession::send(std::shared_ptr<const std::string> message) {
  boost::asio::post(ws_.get_executor(), [self = shared_from_this(), message = std::move(message)]() mutable {
    self->out_.push({std::move(message), false}, self);
  });
}

}  // namespace trailscope::server
