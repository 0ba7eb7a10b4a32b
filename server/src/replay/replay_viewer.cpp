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

nlohmann::json error_message(const std::string& param, const std::string& detail) {
  return error_message(error_json("invalid_argument", param, detail));
}

/// An integer field of an op, or an error naming it.
std::optional<std::int64_t> integer_field(const nlohmann::json& j, const char* name) {
  auto it = j.find(name);
  if (it == j.end() || !it->is_number()) return std::nullopt;
  const double v = it->get<double>();
  if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e15) return std::nullopt;
  return static_cast<std::int64_t>(v);
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
             {"state", {{"playing", playing_}, {"frame", cursor_}, {"speed", speed_}}}});
  want_ = 0;  // the first picture without asking
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
    err = error_message("op", "messages to a replay are JSON text such as {\"op\":\"play\"}");
  else
    err = apply(beast::buffers_to_string(buffer_.data()));
  buffer_.consume(buffer_.size());
  if (err) send_text(*err);
  do_read();
}

std::optional<nlohmann::json> ReplayViewer::apply(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("op") || !j["op"].is_string())
    return error_message("op",
                         "a message must be a JSON object with a string \"op\": play, pause, seek, step "
                         "or speed");
  const std::string op = j["op"];
  const std::size_t total = replay_->frame_count();
  if (op == "play") {
    if (cursor_ + 1 >= total) cursor_ = 0, want_ = 0;  // play at the end starts over
    playing_ = true;
    anchored_ = false;
  } else if (op == "pause") {
    playing_ = false;
  } else if (op == "seek") {
    const auto f = integer_field(j, "frame");
    if (!f || *f < 0 || static_cast<std::uint64_t>(*f) >= total)
      return error_message("frame", "seek: frame must be an integer in 0.." + std::to_string(total - 1));
    cursor_ = static_cast<std::size_t>(*f);
    want_ = cursor_;
    anchored_ = false;
  } else if (op == "step") {
    const auto d = integer_field(j, "delta");
    if (!d) return error_message("delta", "step: delta must be an integer (frames, negative = back)");
    playing_ = false;  // stepping is for looking at single frames
    const std::int64_t to = std::clamp<std::int64_t>(static_cast<std::int64_t>(cursor_) + *d, 0,
                                                     static_cast<std::int64_t>(total) - 1);
    cursor_ = static_cast<std::size_t>(to);
    want_ = cursor_;
  } else if (op == "speed") {
    auto it = j.find("value");
    const double v = it != j.end() && it->is_number() ? it->get<double>() : std::nan("");
    if (!(v >= kMinSpeed && v <= kMaxSpeed))
      return error_message("value", "speed: value must be a number in 0.1..16 (times the video's rate)");
    speed_ = v;
    anchored_ = false;
  } else {
    return error_message("op", "unknown op '" + op + "': play, pause, seek, step or speed");
  }
  send_state();
  tick();
  return std::nullopt;
}

void ReplayViewer::send_state() {
  send_text({{"type", "state"},
             {"playing", playing_},
             {"frame", cursor_},
             {"speed", speed_},
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
  if (closed_ || !want_ || frames_in_flight_ >= kMaxFramesInFlight) return;
  try {
    auto msg = replay_->frame_message(*want_);
    if (!msg) return;  // not computed yet: tick() polls
    want_.reset();
    enqueue({std::make_shared<const std::string>(std::move(*msg)), true});
  } catch (const std::exception& e) {
    // The video went away under the replay (deleted): say so, stop playing, keep the connection.
    nlohmann::json body = error_body(e).body;
    body["param"] = "frame";
    want_.reset();
    playing_ = false;
    send_text(error_message(std::move(body)));
  }
}

void ReplayViewer::tick() {
  if (closed_) return;
  const auto now = Clock::now();
  std::optional<Clock::duration> next;
  bool ended = false;
  if (playing_) {
    const std::size_t total = replay_->frame_count(), computed = replay_->computed();
    if (!anchored_) {
      if (auto ts = replay_->timestamp(cursor_)) anchor_wall_ = now, anchor_ts_ = *ts, anchored_ = true;
    }
    if (!anchored_) {
      next = kPollInterval;  // the cursor's frame is not computed yet
    } else {
      const double target = anchor_ts_ + std::chrono::duration<double>(now - anchor_wall_).count() * speed_;
      bool moved = false;
      // Frames whose time has passed are skipped, not queued: only the newest is sent.
      while (cursor_ + 1 < computed && *replay_->timestamp(cursor_ + 1) <= target) ++cursor_, moved = true;
      if (moved) want_ = cursor_;
      if (cursor_ + 1 >= total) {
        ended = true;
      } else if (cursor_ + 1 < computed) {
        const double dt = (*replay_->timestamp(cursor_ + 1) - anchor_ts_) / speed_;
        const auto due =
            anchor_wall_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dt));
        next = std::max<Clock::duration>(due - now, Clock::duration::zero());
      } else if (replay_->done()) {
        ended = true;  // tracking stopped early: play what there is
      } else {
        // Waiting for the tracker: restart the clock at the cursor so playback resumes at its pace.
        anchor_wall_ = now, anchor_ts_ = *replay_->timestamp(cursor_);
        next = kPollInterval;
      }
    }
  }
  pump();
  if (ended) {
    playing_ = false;
    send_state();
  }
  if (want_ && !replay_->timestamp(*want_))
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
    self->playing_ = false;
    self->timer_.cancel();
    if (self->out_.empty())
      self->ws_.async_close(websocket::close_code::going_away, [self](beast::error_code) {});
    // else on_write closes once the write in progress completes
  });
}

}  // namespace trailscope::server
