#pragma once
// One viewer of a live replay: a WebSocket connection with its own playback cursor (proto/replay_ws.md).
// Everything of a viewer runs on its connection's strand; the replay reaches it only through
// ReplayListener, which posts there.
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "net/ws_write_queue.hpp"
#include "replay/replay.hpp"
#include "replay/replay_control.hpp"

namespace trailscope::server {

class ReplayViewer : public ReplayListener, public std::enable_shared_from_this<ReplayViewer> {
 public:
  /// Binary frame messages queued or being written at once; later frames are dropped while playing
  /// (a seek or step is kept and sent when one completes), so a slow client never builds a queue.
  static constexpr int kMaxFramesInFlight = 2;

  ReplayViewer(boost::beast::tcp_stream&& stream, std::shared_ptr<Replay> replay);
  ~ReplayViewer() override;
  /// Accepts the upgrade, sends hello and frame 0, and starts reading ops.
  void run(boost::beast::http::request<boost::beast::http::empty_body> req);

  void on_run(const std::string& run) override;
  void on_close() override;

 private:
  void on_accept(boost::beast::error_code ec);
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t);
  /// Applies one client message; returns the error message to send, or nothing.
  std::optional<nlohmann::json> apply(const std::string& text);
  void send_text(const nlohmann::json& j);
  void send_state();
  void enqueue(WsWriteQueue::Message out);
  /// Sends the wanted frame when it is computed and the in-flight limit allows.
  void pump();
  /// One playback step: advances the cursor to the video time that wall time has reached.
  void tick();
  void schedule(std::chrono::steady_clock::duration after);

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
  boost::asio::steady_timer timer_;
  std::shared_ptr<Replay> replay_;
  WsWriteQueue out_;
  int frames_in_flight_ = 0;
  bool closed_ = false;
  bool attached_ = false;

  // playback state (strand only)
  ReplayPlayback pb_;
  std::chrono::steady_clock::time_point anchor_wall_;
  double anchor_ts_ = 0;
};

}  // namespace trailscope::server
