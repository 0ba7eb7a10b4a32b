#pragma once
// Bundles that follow a client's clock (proto/bundle_stream.md): one WebSocket connection per client on
// GET /api/v1/datasets/{dataset}/bundles/stream, one streaming bundler (trailscope/bundling/streaming.hpp)
// per connection. The client sends its clock and view as JSON control messages; the server updates at
// most every limits::kBundleStreamMinIntervalMs, on a small worker pool (never on the network threads),
// and sends each update as one binary TSBS frame through the connection's write queue. At most one frame
// is queued or being written: an update that completes while one is still going out replaces any frame
// waiting behind it, so a slow client gets the newest state and the server never builds a backlog.
// While the clock stands still the bundler keeps updating (the bundles settle) until an update adds no
// trail and its mean drift falls below kSettledDriftPx, or limits::kBundleStreamSettleUpdates updates
// have run.
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <boost/asio/steady_timer.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "bundle_stream/stream_control.hpp"
#include "net/ws_write_queue.hpp"
#include "store/dataset_store.hpp"
#include "trailscope/bundling/streaming.hpp"

namespace trailscope::server {

/// The server's bundle streams: the worker pool their updates run on and the count of open streams
/// (at most limits::kMaxBundleStreams). Outlives its sessions' work (its destructor joins the pool).
class BundleStreams {
 public:
  explicit BundleStreams(std::shared_ptr<DatasetStore> store);
  ~BundleStreams();
  /// Throws Error(not_found, `dataset`) for an unknown dataset and Error(conflict, `stream`) when
  /// limits::kMaxBundleStreams streams are open: the check before the upgrade.
  void check(const std::string& dataset) const;
  /// Opens a stream on an upgraded connection (the check is repeated; a refusal then is sent as an error
  /// message and the connection closed).
  void open(boost::beast::tcp_stream&& stream,
            boost::beast::http::request<boost::beast::http::empty_body> req, const std::string& dataset);
  std::size_t open_streams() const { return open_.load(); }

 private:
  friend class BundleStreamSession;
  std::shared_ptr<DatasetStore> store_;
  boost::asio::thread_pool pool_;
  std::atomic<std::size_t> open_{0};
};

/// The bundling side of one stream: what its updates run on the pool with. A task on the pool holds this,
/// never the session (whose socket belongs to the network's io_context, which may be gone when a task
/// ends); the session polls for the result on its own strand.
struct BundleStreamWorker {
  struct Result {
    std::shared_ptr<const std::string> frame;  ///< the TSBS frame, or null with `error`
    std::optional<nlohmann::json> error;       ///< an error message to send
    bool settled = false;                      ///< no trail added and drift < kSettledDriftPx
    double t = 0;                              ///< the update's clock
  };
  /// One update for `c` (on the pool; one at a time per worker), leaving its result for take().
  void run(const StreamControl& c);
  /// The result of the last run(), once (thread-safe).
  std::optional<Result> take();

  std::shared_ptr<const Dataset> dataset;
  std::unique_ptr<bundling::StreamingBundler> bundler;
  bundling::StreamSource source;
  std::uint64_t source_generation = ~std::uint64_t{0};
  std::mutex mutex;
  std::optional<Result> done;  ///< guarded by `mutex`
};

class BundleStreamSession : public std::enable_shared_from_this<BundleStreamSession> {
 public:
  /// An update that added no trail and whose mean drift is below this (px) counts as settled: with the
  /// clock standing still, no more updates until the client sends a control message.
  static constexpr double kSettledDriftPx = 0.05;

  BundleStreamSession(boost::beast::tcp_stream&& stream, BundleStreams& owner,
                      std::shared_ptr<const Dataset> dataset, bool counted);
  ~BundleStreamSession();
  void run(boost::beast::http::request<boost::beast::http::empty_body> req,
           std::optional<nlohmann::json> refusal);

 private:
  void on_accept(boost::beast::error_code ec, std::optional<nlohmann::json> refusal);
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t);
  void send_text(const nlohmann::json& j);
  void enqueue(WsWriteQueue::Message m);
  void send_frame(std::shared_ptr<const std::string> frame);
  /// Starts an update when one is wanted, none is running and the rate allows.
  void maybe_update();
  /// Waits (polling every kPollInterval on the strand) for the worker's result.
  void poll();
  static constexpr auto kPollInterval = std::chrono::milliseconds(5);
  void on_computed(std::shared_ptr<const std::string> frame, std::optional<nlohmann::json> error,
                   bool settled, double t);

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
  boost::asio::steady_timer timer_;
  BundleStreams& owner_;
  std::shared_ptr<const Dataset> dataset_;
  std::shared_ptr<BundleStreamWorker> worker_;
  boost::asio::steady_timer poll_timer_;
  bool counted_;
  WsWriteQueue out_;
  bool closed_ = false;
  int frames_in_flight_ = 0;
  std::shared_ptr<const std::string> pending_frame_;  ///< the newest frame waiting for the one in flight

  // strand state
  StreamControl control_;
  bool computing_ = false;
  bool timer_armed_ = false;
  bool dirty_ = false;            ///< a control message arrived since the last update started
  std::optional<double> last_t_;  ///< clock of the last update
  bool settled_ = false;          ///< the last update added no trail and drifted < kSettledDriftPx
  int settle_left_ = 0;           ///< updates still allowed with the clock standing still
  bool failed_ = false;           ///< the last update failed; wait for the next control message
  std::chrono::steady_clock::time_point last_start_{};
};

}  // namespace trailscope::server
