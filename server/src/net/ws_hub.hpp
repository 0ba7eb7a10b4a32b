#pragma once
// The set of connected WebSocket clients. Broadcasts copy weak references under the lock and send one
// shared, immutable buffer outside it (as Beast's chat-multi example does).
#include <memory>
#include <mutex>
#include <string>
#include <unordered_set>
#include <vector>

namespace trailscope::server {

class WebSocketSession;

class WsHub {
 public:
  void join(WebSocketSession* s);
  void leave(WebSocketSession* s);
  /// Sends `message` (a JSON text) to every connected client.
  void broadcast(std::string message);
  std::size_t size() const;

 private:
  mutable std::mutex mu_;
  std::unordered_set<WebSocketSession*> sessions_;
};

}  // namespace trailscope::server
