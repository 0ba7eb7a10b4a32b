#include "net/ws_write_queue.hpp"

#include <boost/beast/http.hpp>

#include "limits.hpp"

namespace trailscope::server {

bool WsWriteQueue::push(Message message, std::shared_ptr<void> owner) {
  if (queue_.size() >= limits::kMaxQueuedWebSocketMessages) {
    boost::beast::get_lowest_layer(ws_).close();
    return false;
  }
  queue_.push_back(std::move(message));
  if (queue_.size() == 1) write_front(std::move(owner));  // else a write is in flight
  return true;
}

void WsWriteQueue::write_front(std::shared_ptr<void> owner) {
  ws_.binary(queue_.front().binary);
  ws_.async_write(boost::asio::buffer(*queue_.front().bytes),
                  [this, owner = std::move(owner)](boost::beast::error_code ec, std::size_t) mutable {
                    on_write(ec, std::move(owner));
                  });
}

void WsWriteQueue::on_write(boost::beast::error_code ec, std::shared_ptr<void> owner) {
  if (ec) {
    if (hooks_.failed) hooks_.failed();
    return;
  }
  if (hooks_.written) hooks_.written(queue_.front());
  queue_.pop_front();
  if (!queue_.empty()) {
    write_front(std::move(owner));
    return;
  }
  if (hooks_.drained) hooks_.drained();
}

void set_server_options(WsWriteQueue::Stream& ws) {
  namespace websocket = boost::beast::websocket;
  ws.set_option(websocket::stream_base::timeout::suggested(boost::beast::role_type::server));
  ws.read_message_max(limits::kMaxWebSocketMessageBytes);
  ws.set_option(websocket::stream_base::decorator(
      [](websocket::response_type& res) { res.set(boost::beast::http::field::server, "trailscope"); }));
}

}  // namespace trailscope::server
