#pragma once
// The ClickHouse store: datasets kept in a ClickHouse cluster (`serve --store clickhouse://...`), for data
// beyond one machine. The tables (all in the URL's database, created with ON CLUSTER when absent):
//
//   points_local    ReplicatedMergeTree, one row per point: the dataset's columns exactly as the embedded
//                   store holds them (t Float64; lat, lon, alt, speed, track, vrate Float32; on_ground
//                   UInt8), the point's index `idx` in the dataset and its flight's index `flight`, its Web
//                   Mercator position mx, my (UInt32, TrailSet::merc_x/merc_y), their Morton code `morton`
//                   (UInt64, x in the even bits, y in the odd bits; computed here, since ClickHouse 18.16 has
//                   no mortonEncode) and `hour` = floor(t / 3600). PARTITION BY dataset, ORDER BY (hour,
//                   morton): a time window reads only its hours, a tile only its Morton ranges within them.
//   segments_local  one row per pair of consecutive points of a flight: the first point's idx, t0, t1,
//                   x0, y0, x1, y1 (UInt32 Web Mercator), the first point's morton and hour, prev_t, the
//                   time of the point before the first (NaN for a flight's first segment); what PointFilter
//                   reads of both points and of the one before: alt0, alt1, prev_alt, lat0, lat1, prev_lat,
//                   lon0, lon1, prev_lon (Float32; NaN before a flight's first), g0, g1, prev_ground
//                   (UInt8); and the segment's fixed-point altitude and speed values exactly as
//                   density_lines() computes them (segment_value, to_fixed): v_alt, v_speed (Int32), v_flags
//                   (UInt8: bit 0 an altitude value, bit 1 a speed value). Same layout. A database made
//                   before prev_t draws windowed tiles from a fetched copy, one made before the point
//                   attributes its tiles with values, point filters or a gap limit.
//   events_local    one row per implausible value quality_events() finds (trails/quality.hpp): flight,
//                   kind (0 speed, 1 altitude, 2 jump), value, the sample's t, alt, lat, lon, on_ground and
//                   hour, and for a jump the sample before it (prev_t, prev_alt, prev_lat, prev_lon,
//                   prev_ground); same layout, ORDER BY (hour, flight). A database made before it computes
//                   the summary's quality block on a fetched copy.
//   flights_local   one row per flight: its index, point range [begin, end), icao24, callsign and the
//                   extents compute_extents() gives it (t_min, t_max, lat/lon/alt min and max, whether it
//                   crosses 180°). A database made before these columns existed is read as before: its
//                   datasets are described from a fetched copy.
//   points, segments, flights, events   Distributed over the *_local tables, sharded by
//                   intHash32(flight).
//   catalogue       ReplicatedMergeTree replicated on every node: one row per change of a dataset (id,
//                   version, deleted, name, format, created, owner, ingest report as JSON, points,
//                   flights); a dataset is the row of its highest version, visible unless `deleted`.
//
// Atomic visibility: every row of a dataset lies in the partition named by its id; the catalogue row is
// written last, after every insert was acknowledged by every replica of its shard (insert_quorum), so a
// dataset is visible whole or not at all. Opening the store drops every partition whose dataset is not in
// the catalogue (an ingest killed midway, a delete interrupted before its partitions were dropped). Delete
// writes a `deleted` row first (one atomic insert) and then drops the partitions. One server owns a
// database: a second server on the same database would remove the first one's ingest in flight.
//
// Reads: describe() and list() read only the catalogue and the flight table (each flight's point range,
// addresses and extents, written at ingest): the dataset object, the flight list and the positions need
// nothing more. get() fetches a dataset's rows back into a TrailSet identical to what was put, for the
// computations that follow every point (the routes without push-down below: flight GeoJSON, bundles,
// exports, animation, flow and congestion maps, and the tiles and legend of a dataset with a flight across
// 180°); the last kKeptCopies fetched are kept in memory, so the server holds at most that
// many copies beside the ones requests in flight still use.
//
// Push-down: the scans over points run on the shards, as SQL over the Distributed tables, and the server
// only merges their partial answers with compute/'s own finishing code, so the bytes equal the embedded
// store's (tests/cluster/clickhouse_store_test.cpp compares them on the Europe SO6 day and the demo day):
//  - summarize(): one query gives the counts, first/last time, the speed count/sum/min/max and, with
//    sumMap, the time, altitude and speed histograms (bins computed in SQL with the same IEEE double
//    operations as trails/summary.cpp: see SummaryCounts) and the matching points per flight; the server
//    finishes with finish_summary() (percentiles, mean, top callsigns). The data-quality block counts the
//    events stored at ingest (their position jumps follow each flight's samples in order from the time a
//    position was first reported, a running state ClickHouse 18.16 cannot keep without window functions)
//    whose sample, and for a jump the sample before it, pass the point filter, of the flights passing the
//    flight filters: one GROUP BY kind and the largest values per kind (LIMIT BY), exactly what
//    check_quality() reports. The speed mean is the SQL sum divided by the count: it equals the embedded
//    store's to the bit whenever the double sum is exact whatever the order (speeds of at least 2 m/s
//    summing below 2^31 m/s, as on real traffic days); otherwise the two differ in the last bits, as two runs
//    of the embedded store's parallel sum may.
//  - list_flights(): one GROUP BY flight gives each matching flight's points, first/last matching time and
//    highest known altitude; the server sorts and pages them with page_flights().
//  - positions_at(): the flights present at t and passing the flight filters are chosen by their extents
//    (the zone map positions_at() uses); one GROUP BY flight over the hours of their extents gives each
//    one's sample at exactly t, or the last sample before t and the first after; the server interpolates
//    them with position_from_samples() and filters the positions (bbox, altitude band, on_ground apply to
//    the interpolated position, which SQL cannot know before interpolating).
//  Summary and flight list push the point filter (time window with the hour prefix of the table order,
//  altitude band, bbox including one across 180°, on_ground) into WHERE; icao24 and callsign patterns are
//  matched on the server against the flight table (a list of flight ids in WHERE), since callsign_matches()'
//  patterns are not LIKE's. A dataset whose flights do not cover its points one to one (never made by the
//  ingest) falls back to the computation on the server's copy.
//  - density_tile(): every tile of a dataset without a flight across 180°, under any query (time window,
//    altitude band, bbox, on_ground, icao24/callsign), any value (count, altitude, speed), gap and
//    kernel: one query over the segment table gives each pixel's count (and the sum and count of the
//    segments' fixed-point values) on the work canvas (the tile plus the kernel's margin), the pixels of
//    each segment enumerated in exact integer arithmetic as density_lines() walks them (the SQL of
//    clickhouse_tile_sql.hpp, which the tile benchmark checks pixel for pixel against
//    density_lines_ref); the first pixel of a segment that continues a drawn run is left out. A flight
//    filter keeps or drops a flight whole (flight IN (...)); a segment is drawn when both its points pass
//    the point filter (their stored attributes) and t1 − t0 <= the gap, and continues a run when the
//    point before it passes too and that step is within the gap (prev_*), exactly the run breaks
//    density_lines() makes, since a flight's samples are in time order. The level's shared span comes
//    from the same query on the coarse canvas of the renderer's plan (DensityRenderer::span_for with a
//    CoarseAggregateFn; the data extent from the flight table's extents), computed once per zoom and
//    cached by the renderer; a canvas beyond the world's x range (a bbox across 180°, a margin at the
//    world's edge) sees the segments' copies one world east and west. The server smooths and shades
//    through finish_aggregate() and shade_tile(). Drawn from the copy: datasets with a flight across 180°
//    (its segments' wrapped copies: a segment's pixels then depend on which world copy meets the canvas,
//    which the SQL does not enumerate).
//  - density_legend(): the legend of those tiles, from the same span (the same coarse query and cache).
// Not pushed down: bundles, flight GeoJSON, exports, animation, picking,
// congestion and flow maps: they follow every sample of the flights they draw and read the copy get()
// fetches.
#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <mutex>
#include <optional>

#include "store/clickhouse_client.hpp"
#include "store/dataset_reads.hpp"
#include "store/dataset_store.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/trails/quality.hpp"

namespace trailscope::server {

class ClickHouseStore final : public DatasetStore, public DatasetReads {
 public:
  /// Connects to the cluster of `url`, creates the database and tables when absent (ON CLUSTER), reads the
  /// catalogue and, with `remove_leftovers` (`serve`, the one owner of the database; not the CLI verbs,
  /// which may run beside a server mid-ingest), drops the leftover partitions (best effort: a drop that
  /// fails now, a replica being down, is logged, and its rows stay unread until the next start). Throws
  /// Error(unavailable) when no node answers, ClickHouseError when the cluster refuses (an unknown cluster
  /// name, ZooKeeper unreachable, ...), invalid_argument("--store") when the nodes know no such cluster.
  explicit ClickHouseStore(const ClickHouseUrl& url, bool remove_leftovers = false,
                           ClickHouseClient::Timeouts timeouts = {});

  std::vector<std::shared_ptr<const Dataset>> list() const override;
  std::shared_ptr<const Dataset> get(const std::string& id) const override;
  /// The catalogue row and the flight table (no point): trails null, outline set. Cached per dataset.
  std::shared_ptr<const Dataset> describe(const std::string& id) const override;
  bool contains(const std::string& id) const override;
  /// Inserts the dataset's rows in batches of kBatchRows, reporting progress per batch, then its catalogue
  /// row. On any failure the partitions written so far are dropped (or at the next start) and the dataset
  /// stays invisible. Also throws what the client throws.
  void put(std::shared_ptr<const Dataset> ds, const ProgressFn& progress = {}) override;
  void remove(const std::string& id) override;
  // DatasetReads, run on the shards (see the header's "Push-down").
  Summary summarize(const Dataset& ds, const Query& q, const SummaryOptions& opts) const override;
  FlightPage list_flights(const Dataset& ds, const Query& q, std::size_t page, std::size_t page_size,
                          const FlightSort& sort) const override;
  Positions positions_at(const Dataset& ds, double t, const Query& q,
                         std::size_t max_positions) const override;
  std::string density_tile(const Dataset& ds, density::DensityRenderer& renderer,
                           const std::string& dataset_key, const Query& q,
                           const density::TileRequest& request) const override;
  density::Legend density_legend(const Dataset& ds, density::DensityRenderer& renderer,
                                 const std::string& dataset_key, const Query& q,
                                 const density::TileRequest& request, int stops) const override;

  static constexpr std::size_t kBatchRows = 1u << 20;
  /// Fetched copies (get()) kept in memory, most recently used first; older ones are released.
  static constexpr std::size_t kKeptCopies = 2;
  /// How long an insert waits for every replica of its shard (insert_quorum_timeout) before it fails.
  static constexpr int kQuorumTimeoutMs = 30000;
  /// The Morton code of (x, y): bit i of x at bit 2i, bit i of y at bit 2i+1.
  static std::uint64_t morton(std::uint32_t x, std::uint32_t y);

  ClickHouseClient& client() { return client_; }
  /// Pushed-down queries answered so far (read() calls that returned).
  std::uint64_t pushed_down_reads() const { return reads_; }
  /// Datasets fetched whole (get() calls that read the point table) so far.
  std::uint64_t fetched_copies() const { return fetches_; }
  /// Told the SQL and wall time (ms) of every pushed-down query that returned (the benchmark's view of
  /// what ClickHouse did for an answer). Set before the store is shared between threads.
  void on_read(std::function<void(const std::string& sql, double ms)> observer) {
    observer_ = std::move(observer);
  }
  const std::string& database() const { return db_; }
  const std::string& cluster() const { return cluster_; }

 private:
  struct Meta {
    std::string name, format, created, owner;
    nlohmann::json ingest;
    std::uint64_t points = 0;
  };
  std::shared_ptr<const Dataset> load(const std::string& id, const Meta& meta) const;
  /// The flight table of `id` (with its extents when the table has them), ordered by index. Throws
  /// Error(internal) when it is inconsistent.
  std::vector<Flight> load_flights(const std::string& id) const;
  /// The full copy of `full` without its points: the described view.
  static std::shared_ptr<const Dataset> outline_of(const Dataset& full);
  /// `ds` with its points: itself (not owned) when it has them, else get(ds.id).
  std::shared_ptr<const Dataset> whole(const Dataset& ds) const {
    return ds.trails ? std::shared_ptr<const Dataset>(std::shared_ptr<const Dataset>{}, &ds) : get(ds.id);
  }
  /// The SQL condition on the points table of `ds` for the point filter and flight filters of `q`; ""
  /// when no point can match (a flight filter no flight passes).
  std::string point_where(const Dataset& ds, const Query& q) const;
  /// PointFilter of `q` as SQL over the columns named (time, altitude, latitude, longitude, ground
  /// state): " AND ..." per condition, "" without a point filter.
  static std::string point_condition(const Query& q, const std::string& t, const std::string& alt,
                                     const std::string& lat, const std::string& lon,
                                     const std::string& ground);
  /// check_quality() of `q` over the quality events stored at ingest (needs quality_events_).
  QualityReport shard_quality(const Dataset& ds, const Query& q) const;
  /// The density_lines() aggregate of `q`'s segments of `ds` on `work` with `value` and the gap, counted
  /// on the shards; nullopt when they cannot count it (see the header's "Push-down").
  std::optional<density::Aggregate> shard_aggregate(const Dataset& ds, const Query& q,
                                                    const density::Canvas& work, density::DensityValue value,
                                                    double max_gap_seconds) const;
  /// The coarse aggregate of a tile level's span for DensityRenderer (span_for, legend): shard_aggregate(),
  /// else on the fetched copy. Holds `ds` by reference: call it while `ds` lives.
  density::CoarseAggregateFn coarse_counter(const Dataset& ds, const Query& q, Backend backend) const;
  /// Whether the queries can run on the shards for `ds` (its flights cover its points one to one).
  static bool pushable(const Dataset& ds);
  /// Runs a push-down SELECT. The client already moves to the next node of the URL when the one it asks
  /// cannot be reached or drops the connection; here a query that the node it reached could not finish
  /// because a replica it read from went away mid-query (ClickHouse's network errors: codes 32, 209, 210,
  /// 279) runs again, up to kReadAttempts times, and the Distributed tables pick a live replica of each
  /// shard (load_balancing, connect_timeout_with_failover_ms). Throws the last error after that.
  std::string read(const std::string& sql) const;
  static constexpr int kReadAttempts = 4;
  /// Drops the rows of `id` from every table on every node (ALTER ... ON CLUSTER DROP PARTITION). Tries
  /// every table, then throws the first failure; a drop that timed out is still queued and runs later.
  void drop_partitions(const std::string& id);
  /// drop_partitions(), and when a drop timed out, waits up to kDropWait until no node holds rows of `id`
  /// (the queued drop ran); throws the drop's error after that. Before rows are written under `id`.
  void clear_rows(const std::string& id);
  static constexpr std::chrono::seconds kDropWait{120};
  /// One catalogue row of `id` (a dataset, or with `deleted` its tombstone), written with the insert quorum:
  /// the row that makes a dataset visible, or invisible, at once.
  void write_catalogue_row(const std::string& id, bool deleted, const Meta& meta, std::uint64_t points,
                           std::uint64_t flights);
  /// Whether some replica of some shard holds rows of `id` (system.parts).
  bool has_rows(const std::string& id) const;
  void create_tables();
  /// Leftover partitions: datasets with rows but not live in the catalogue.
  void remove_leftovers();

  mutable ClickHouseClient client_;
  std::string db_, cluster_;
  int quorum_ = 1;  ///< replicas per shard (the fewest of any shard)
  mutable std::mutex mu_;
  std::map<std::string, Meta> catalogue_;  ///< the visible datasets
  bool flight_extents_ = true;             ///< flights_local has the extent columns
  bool segment_prev_t_ = true;             ///< segments_local has prev_t
  bool segment_attrs_ = true;              ///< segments_local has the point attributes and values
  bool quality_events_ = true;             ///< the events tables exist
  mutable std::map<std::string, std::shared_ptr<const Dataset>> outlines_;
  mutable std::vector<std::shared_ptr<const Dataset>> loaded_;  ///< kKeptCopies at most, newest first
  mutable std::atomic<std::uint64_t> fetches_{0};
  mutable std::mutex load_mu_;  ///< one dataset fetched at a time
  mutable std::atomic<std::uint64_t> reads_{0};
  std::function<void(const std::string&, double)> observer_;
};

/// The store a `--store` option names: "" or "embedded" → the embedded store at `data_dir`;
/// clickhouse://... → a ClickHouseStore (leftovers removed when `leftovers` is remove). Throws
/// invalid_argument("--store") for anything else, and what the stores' constructors throw.
std::shared_ptr<DatasetStore> open_dataset_store(const std::string& store,
                                                 const std::filesystem::path& data_dir,
                                                 EmbeddedStore::Leftovers leftovers);

}  // namespace trailscope::server
