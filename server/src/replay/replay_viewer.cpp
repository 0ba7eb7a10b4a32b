#include "replay/replay_viewer.hpp"

#include <algorithm>
#include <cmath>

#include <boost/asio/post.hpp>

#include "errors/error_table.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::server {
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using Clock = std::chrono::steady_clock;

namespace {
// How often a viewer looks again for a frame the tracker has not computed yet.
constexpr auto kPollInterval = std::chrono::milliseconds(10);

/// An error body (errors/error_table.hpp) as a WebSocket message.
nlohmann::json error_message(nlohmann::json body) {
  body["type"] = "error";
  return body;
}

}  // namespace

ReplayViewer::ReplayViewer(beast::tcp_stream&& stream, std::shared_ptr<Replay> replay)
    : ws_(std::move(stream)),
      timer_(ws_.get_executor()),
      replay_(std::move(replay)),
      out_(ws_, {.written =
                     [this](const WsWriteQueue::Message& m) {
                       if (m.binary) --frames_in_flight_;
                     },
                 .drained =
                     [this] {
                       if (closed_) {  // a close was asked for while writing: now the stream is free for it
                         ws_.async_close(websocket::close_code::going_away,
                                         [self = shared_from_this()](beast::error_code) {});
                         return;
                       }
                       pump();
                     },
                 .failed = [this] { closed_ = true; }}) {}

ReplayViewer::~ReplayViewer() {
  if (attached_) replay_->detach(this);
}

void ReplayViewer::run(beast::http::request<beast::http::empty_body> req) {
  set_server_options(ws_);
  ws_.async_accept(req, beast::bind_front_handler(&ReplayViewer::on_accept, shared_from_this()));
}

void ReplayViewer::on_accept(beast::error_code ec) {
  if (ec) return;
  try {
    replay_->attach(shared_from_this());
    attached_ = true;
  } catch (const Error& e) {
    send_text(error_message(error_body(e).body));
    on_close();
    return;
  }
  send_text({{"type", "hello"},
             {"replay", replay_->to_json()},
             {"header", replay_->header_json()},
             {"state", {{"playing", pb_.playing}, {"frame", pb_.cursor}, {"speed", pb_.speed}}}});
  pb_.want = 0;  // the first picture without asking
  tick();
  do_read();
}

void ReplayViewer::do_read() {
  ws_.async_read(buffer_, beast::bind_front_handler(&ReplayViewer::on_read, shared_from_this()));
}

void ReplayViewer::on_read(beast::error_code ec, std::size_t) {
  if (ec) {
    closed_ = true;
    timer_.cancel();
    return;  // closed or failed: the viewer ends when the last handler lets go
  }
  std::optional<nlohmann::json> err;
  if (!ws_.got_text())
    err = error_message(
        error_json("invalid_argument", "op", "messages to a replay are JSON text such as {\"op\":\"play\"}"));
  else
    err = apply(beast::buffers_to_string(buffer_.data()));
  buffer_.consume(buffer_.size());
  if (err) send_text(*err);
  do_read();
}

std::optional<nlohmann::json> ReplayViewer::apply(const std::string& text) {
  if (auto err = apply_replay_control(text, replay_->frame_count(), pb_)) return err;
  send_state();
  tick();
  return std::nullopt;
}

void ReplayViewer::send_state() {
  send_text({{"type", "state"},
             {"playing", pb_.playing},
             {"frame", pb_.cursor},
             {"speed", pb_.speed},
             {"computed", replay_->computed()},
             {"done", replay_->done()}});
}

void ReplayViewer::send_text(const nlohmann::json& j) {
  enqueue({std::make_shared<const std::string>(json_text(j)), false});
}

void ReplayViewer::enqueue(WsWriteQueue::Message out) {
  if (closed_) return;
  const bool binary = out.binary;
  if (!out_.push(std::move(out), shared_from_this())) {
    closed_ = true;
    return;
  }
  if (binary) ++frames_in_flight_;
}

void ReplayViewer::pump() {
  if (closed_ || !pb_.want || frames_in_flight_ >= kMaxFramesInFlight) return;
  try {
    auto msg = replay_->frame_message(*pb_.want);
    if (!msg) return;  // not computed yet: tick() polls
    pb_.want.reset();
    enqueue({std::make_shared<const std::string>(std::move(*msg)), true});
  } catch (const std::exception& e) {
    // The video went away under the replay (deleted): say so, stop playing, keep the connection.
    nlohmann::json body = error_body(e).body;
    body["param"] = "frame";
    pb_.want.reset();
    pb_.playing = false;
    send_text(error_message(std::move(body)));
  }
}

void ReplayViewer::tick() {
  if (closed_) return;
  const auto now = Clock::now();
  std::optional<Clock::duration> next;
  bool ended = false;
  if (pb_.playing) {
    const std::size_t total = replay_->frame_count(), computed = replay_->computed();
    if (!pb_.anchored) {
      if (auto ts = replay_->timestamp(pb_.cursor)) anchor_wall_ = now, anchor_ts_ = *ts, pb_.anchored = true;
    }
    if (!pb_.anchored) {
      next = kPollInterval;  // the cursor's frame is not computed yet
    } else {
      const double target =
          anchor_ts_ + std::chrono::duration<double>(now - anchor_wall_).count() * pb_.speed;
      bool moved = false;
      // Frames whose time has passed are skipped, not queued: only the newest is sent.
      while (pb_.cursor + 1 < computed && *replay_->timestamp(pb_.cursor + 1) <= target)
        ++pb_.cursor, moved = true;
      if (moved) pb_.want = pb_.cursor;
      if (pb_.cursor + 1 >= total) {
        ended = true;
      } else if (pb_.cursor + 1 < computed) {
        const double dt = (*replay_->timestamp(pb_.cursor + 1) - anchor_ts_) / pb_.speed;
        const auto due =
            anchor_wall_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dt));
        next = std::max<Clock::duration>(due - now, Clock::duration::zero());
      } else if (replay_->done()) {
        ended = true;  // tracking stopped early: play what there is
      } else {
        // Waiting for the tracker: restart the clock at the cursor so playback resumes at its pace.
        anchor_wall_ = now, anchor_ts_ = *replay_->timestamp(pb_.cursor);
        next = kPollInterval;
      }
    }
  }
  pump();
  if (ended) {
    pb_.playing = false;
    send_state();
  }
  if (pb_.want && !replay_->timestamp(*pb_.want))
    next = next ? std::min<Clock::duration>(*next, kPollInterval) : kPollInterval;
  if (next) schedule(*next);
}

void ReplayViewer::schedule(Clock::duration after) {
  timer_.expires_after(after);  // cancels the previous wait: one tick pending at a time
  timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (!ec) self->tick();
  });
}

void ReplayViewer::on_run(const std::string& run) {
  boost::asio::post(ws_.get_executor(), [self = shared_from_this(), run] {
    self->send_text({{"type", "run"}, {"run", run}});
  });
}

void ReplayViewer::on_close() {
  boost::asio::post(ws_.get_executor(), [self = shared_from_this()] {
    if (self->closed_) return;
    self->closed_ = true;
    self->pb_.playing = false;
    self->timer_.cancel();
    if (self->out_.empty())
      self->ws_.async_close(websocket::close_code::going_away, [self](beast::error_code) {});
    // else on_write closes once the write in progress completes
  });
}

}  // namespace trailscope::server
