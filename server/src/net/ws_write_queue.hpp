#pragma once
// The server side of one WebSocket connection, shared by every kind of session (events, replay viewers):
// the options it is accepted with, and its write side:
// messages go out one at a time and in order, each as text or binary, and a client that cannot keep up
// is dropped (its socket closed) once limits::kMaxQueuedWebSocketMessages wait, rather than letting its
// queue grow without bound. Used on the connection's strand only.
#include <deque>
#include <functional>
#include <memory>
#include <string>

#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

namespace trailscope::server {

class WsWriteQueue {
 public:
  using Stream = boost::beast::websocket::stream<boost::beast::tcp_stream>;
  struct Message {
    std::shared_ptr<const std::string> bytes;
    bool binary = false;
  };
  /// What the session learns of its writes (each optional): `written` after a message went out, `drained`
  /// when that left the queue empty, `failed` when a write failed (the queue then stops writing).
  struct Hooks {
    std::function<void(const Message&)> written;
    std::function<void()> drained;
    std::function<void()> failed;
  };

  explicit WsWriteQueue(Stream& ws, Hooks hooks = {}) : ws_(ws), hooks_(std::move(hooks)) {}

  /// Queues `message` and starts writing when idle; `owner` (the session) is kept alive by the write in
  /// flight. Returns false, having closed the socket, when the queue is full.
  bool push(Message message, std::shared_ptr<void> owner);
  bool empty() const { return queue_.empty(); }

 private:
  void write_front(std::shared_ptr<void> owner);
  void on_write(boost::beast::error_code ec, std::shared_ptr<void> owner);

  Stream& ws_;
  Hooks hooks_;
  std::deque<Message> queue_;
};

/// Sets the server's options on a connection about to be accepted: Beast's suggested server timeouts,
/// messages from the client of at most limits::kMaxWebSocketMessageBytes, and the Server header.
void set_server_options(WsWriteQueue::Stream& ws);

}  // namespace trailscope::server
