#include "bundle_stream/bundle_stream_session.hpp"

#include <algorithm>
#include <thread>

#include <boost/asio/post.hpp>

#include "errors/error_table.hpp"
#include "formats/bundle_stream_frame.hpp"
#include "limits.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::server {
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using Clock = std::chrono::steady_clock;

namespace {

nlohmann::json error_message(nlohmann::json body) {
  body["type"] = "error";
  return body;
}

// The stream's bundling parameters: StreamParams' defaults (streaming.hpp), the window from the client.
bundling::StreamParams stream_params(const StreamControl& c) {
  bundling::StreamParams p;
  p.window_s = c.window_s;
  p.fade_s = c.fade_s;
  return p;
}

}  // namespace

BundleStreams::BundleStreams(std::shared_ptr<DatasetStore> store)
    : store_(std::move(store)), pool_(limits::kBundleStreamWorkers) {}

BundleStreams::~BundleStreams() {
  pool_.join();
}

void BundleStreams::check(const std::string& dataset) const {
  store_->get(dataset);  // throws not_found
  if (open_.load() >= limits::kMaxBundleStreams)
    throw Error(Error::Kind::conflict, "stream",
                "at most " + std::to_string(limits::kMaxBundleStreams) +
                    " bundle streams are open at once (kMaxBundleStreams); close one first");
}

void BundleStreams::open(beast::tcp_stream&& stream, beast::http::request<beast::http::empty_body> req,
                         const std::string& dataset) {
  std::shared_ptr<const Dataset> ds;
  std::optional<nlohmann::json> refusal;
  bool counted = false;
  try {
    ds = store_->get(dataset);
    std::size_t n = open_.load();
    do {
      if (n >= limits::kMaxBundleStreams) check(dataset);  // throws the conflict
    } while (!open_.compare_exchange_weak(n, n + 1));
    counted = true;
  } catch (const std::exception& e) {
    refusal = error_message(error_body(e).body);
  }
  std::make_shared<BundleStreamSession>(std::move(stream), *this, std::move(ds), counted)
      ->run(std::move(req), std::move(refusal));
}

BundleStreamSession::BundleStreamSession(beast::tcp_stream&& stream, BundleStreams& owner,
                                         std::shared_ptr<const Dataset> dataset, bool counted)
    : ws_(std::move(stream)),
      timer_(ws_.get_executor()),
      owner_(owner),
      dataset_(dataset),
      worker_(std::make_shared<BundleStreamWorker>()),
      poll_timer_(ws_.get_executor()),
      counted_(counted),
      out_(ws_, {.written =
                     [this](const WsWriteQueue::Message& m) {
                       if (!m.binary) return;
                       --frames_in_flight_;
                       if (pending_frame_ && !closed_) send_frame(std::exchange(pending_frame_, nullptr));
                     },
                 .drained =
                     [this] {
                       if (closed_)
                         ws_.async_close(websocket::close_code::policy_error,
                                         [self = shared_from_this()](beast::error_code) {});
                     },
                 .failed = [this] { closed_ = true; }}) {
  worker_->dataset = std::move(dataset);
}

BundleStreamSession::~BundleStreamSession() {
  if (counted_) --owner_.open_;
}

void BundleStreamSession::run(beast::http::request<beast::http::empty_body> req,
                              std::optional<nlohmann::json> refusal) {
  set_server_options(ws_);
  ws_.async_accept(req, [self = shared_from_this(), refusal = std::move(refusal)](
                            beast::error_code ec) mutable { self->on_accept(ec, std::move(refusal)); });
}

void BundleStreamSession::on_accept(beast::error_code ec, std::optional<nlohmann::json> refusal) {
  if (ec) return;
  if (refusal) {
    send_text(*refusal);
    closed_ = true;  // the close follows the error message (drained)
    return;
  }
  const bundling::StreamParams p;
  send_text({{"type", "hello"},
             {"dataset", dataset_->id},
             {"format", "TSBS 1"},
             {"t_min", dataset_->trails->t_min()},
             {"t_max", dataset_->trails->t_max()},
             {"params",
              {{"window_s", control_.window_s},
               {"fade_s", control_.fade_s},
               {"size", p.size},
               {"h", p.h},
               {"eps", p.eps},
               {"iterations", p.iterations},
               {"spl", p.spl}}},
             {"limits",
              {{"min_interval_ms", limits::kBundleStreamMinIntervalMs},
               {"settle_updates", limits::kBundleStreamSettleUpdates},
               {"max_trails", limits::kMaxStreamTrails},
               {"max_points", limits::kMaxStreamPoints},
               {"max_window_s", limits::kMaxStreamWindowSeconds}}}});
  do_read();
}

void BundleStreamSession::do_read() {
  ws_.async_read(buffer_, beast::bind_front_handler(&BundleStreamSession::on_read, shared_from_this()));
}

void BundleStreamSession::on_read(beast::error_code ec, std::size_t) {
  if (ec) {
    closed_ = true;
    timer_.cancel();
    poll_timer_.cancel();
    return;  // closed or failed: the session ends when the last handler lets go
  }
  if (!ws_.got_text()) {
    send_text(error_message(error_json("invalid_argument", "message",
                                       "control messages are JSON text such as {\"t\": 1514800000}")));
  } else {
    try {
      apply_control(beast::buffers_to_string(buffer_.data()), control_);
      failed_ = false;
      dirty_ = true;
      settle_left_ = limits::kBundleStreamSettleUpdates;
      maybe_update();
    } catch (const std::exception& e) {
      send_text(error_message(error_body(e).body));
    }
  }
  buffer_.consume(buffer_.size());
  do_read();
}

void BundleStreamSession::send_text(const nlohmann::json& j) {
  enqueue({std::make_shared<const std::string>(json_text(j)), false});
}

void BundleStreamSession::enqueue(WsWriteQueue::Message m) {
  if (closed_) return;
  if (!out_.push(std::move(m), shared_from_this())) closed_ = true;
}

void BundleStreamSession::send_frame(std::shared_ptr<const std::string> frame) {
  if (frames_in_flight_ >= 1) {
    pending_frame_ = std::move(frame);  // replaces an older one: only the newest state is worth sending
    return;
  }
  ++frames_in_flight_;
  enqueue({std::move(frame), true});
}

void BundleStreamSession::maybe_update() {
  if (closed_ || computing_ || failed_ || !control_.t) return;
  const bool settling = settle_left_ > 0 && !settled_;
  if (!dirty_ && !settling) return;
  const auto now = Clock::now();
  const auto due = last_start_ + std::chrono::milliseconds(limits::kBundleStreamMinIntervalMs);
  if (now < due) {
    if (!timer_armed_) {
      timer_armed_ = true;
      timer_.expires_at(due);
      timer_.async_wait([self = shared_from_this()](beast::error_code e) {
        self->timer_armed_ = false;
        if (!e) self->maybe_update();
      });
    }
    return;
  }
  computing_ = true;
  last_start_ = now;
  if (!dirty_) --settle_left_;
  dirty_ = false;
  // The task holds the worker only, never the session: the session's socket belongs to the network's
  // io_context, which may be gone (server stopping) by the time an update ends.
  boost::asio::post(owner_.pool_, [w = worker_, c = control_] { w->run(c); });
  poll();
}

void BundleStreamWorker::run(const StreamControl& c) {
  Result r;
  r.t = *c.t;
  try {
    const TrailSet& trails = *dataset->trails;
    if (source_generation != c.view_generation) {
      // Flight ids are TrailSet indices whatever the filters, so held trails that pass the new filters
      // stay bundled; the new frame carries their points over.
      source = bundling::flight_stream_source(trails, c.filters);
      const bundling::StreamParams p = stream_params(c);
      const bundling::Frame frame_now = stream_frame(trails, c, p.size);
      if (!bundler)
        bundler = std::make_unique<bundling::StreamingBundler>(frame_now, p);
      else
        bundler->set_frame(frame_now);
      source_generation = c.view_generation;
    }
    bundler->set_window(c.window_s, c.fade_s);
    const bundling::StreamUpdate u = bundler->update(*c.t, source);
    // Settled: nothing entered (entering trails are not in the drift yet) and the rest barely moved.
    r.settled = u.added == 0 && u.drift_px < BundleStreamSession::kSettledDriftPx;
    r.frame = std::make_shared<const std::string>(encode_stream_frame(u, bundler->frame(), c.window_s));
  } catch (const std::exception& e) {
    r.error = error_message(error_body(e).body);
  }
  const std::lock_guard lock(mutex);
  done = std::move(r);
}

std::optional<BundleStreamWorker::Result> BundleStreamWorker::take() {
  const std::lock_guard lock(mutex);
  return std::exchange(done, std::nullopt);
}

void BundleStreamSession::poll() {
  poll_timer_.expires_after(kPollInterval);
  poll_timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (ec || self->closed_) return;
    auto r = self->worker_->take();
    if (!r) return self->poll();
    self->on_computed(std::move(r->frame), std::move(r->error), r->settled, r->t);
  });
}

void BundleStreamSession::on_computed(std::shared_ptr<const std::string> frame,
                                      std::optional<nlohmann::json> error, bool settled, double t) {
  computing_ = false;
  if (error) {
    failed_ = true;  // the same control would fail again: wait for the client's next message
    send_text(*error);
    return;
  }
  last_t_ = t;
  settled_ = settled;
  send_frame(std::move(frame));
  maybe_update();
}

}  // namespace trailscope::server
