#include "net/websocket_session.hpp"

#include <boost/asio/post.hpp>

#include "net/ws_hub.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::server {
namespace beast = boost::beast;
namespace websocket = beast::websocket;

namespace {
// A client that cannot keep up is dropped rather than letting its queue grow without bound.
constexpr std::size_t kMaxQueuedMessages = 1024;
}  // namespace

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
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.read_message_max(limits::kMaxWebSocketMessageBytes);
  ws_.set_option(websocket::stream_base::decorator(
      [](websocket::response_type& res) { res.set(beast::http::field::server, "trailscope"); }));
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
  boost::asio::post(ws_.get_executor(), beast::bind_front_handler(&WebSocketSession::on_send,
                                                                  shared_from_this(), std::move(message)));
}

void WebSocketSession::on_send(std::shared_ptr<const std::string> message) {
  if (queue_.size() >= kMaxQueuedMessages) {
    beast::get_lowest_layer(ws_).close();
    return;
  }
  queue_.push_back(std::move(message));
  if (queue_.size() > 1) return;  // a write is in flight
  ws_.text(true);
  ws_.async_write(boost::asio::buffer(*queue_.front()),
                  beast::bind_front_handler(&WebSocketSession::on_write, shared_from_this()));
}

void WebSocketSession::on_write(beast::error_code ec, std::size_t) {
  if (ec) return;
  queue_.pop_front();
  if (queue_.empty()) return;
  ws_.async_write(boost::asio::buffer(*queue_.front()),
                  beast::bind_front_handler(&WebSocketSession::on_write, shared_from_this()));
}

}  // namespace trailscope::server
