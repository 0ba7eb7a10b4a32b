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
//                   x0, y0, x1, y1 (UInt32 Web Mercator), the first point's morton and hour; same layout.
//   flights_local   one row per flight: its index, point range [begin, end), icao24, callsign.
//   points, segments, flights   Distributed over the *_local tables, sharded by intHash32(flight).
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
// Reads: get() fetches a dataset's rows back into a TrailSet (kept in memory until the dataset is deleted),
// identical to what was put, so every route answers from it as from the embedded store.
#include <map>
#include <mutex>

#include "store/clickhouse_client.hpp"
#include "store/dataset_store.hpp"
#include "store/embedded_store.hpp"

namespace trailscope::server {

class ClickHouseStore final : public DatasetStore {
 public:
  /// Connects to the cluster of `url`, creates the database and tables when absent (ON CLUSTER), reads the
  /// catalogue and, with `remove_leftovers` (`serve`, the one owner of the database; not the CLI verbs,
  /// which may run beside a server mid-ingest), drops the leftover partitions. Throws Error(unavailable)
  /// when no node answers, ClickHouseError when the cluster refuses (an unknown cluster name, ZooKeeper
  /// unreachable, ...), invalid_argument("--store") when the nodes know no such cluster.
  explicit ClickHouseStore(const ClickHouseUrl& url, bool remove_leftovers = false,
                           ClickHouseClient::Timeouts timeouts = {});

  std::vector<std::shared_ptr<const Dataset>> list() const override;
  std::shared_ptr<const Dataset> get(const std::string& id) const override;
  bool contains(const std::string& id) const override;
  /// Inserts the dataset's rows in batches of kBatchRows, reporting progress per batch, then its catalogue
  /// row. On any failure the partitions written so far are dropped (or at the next start) and the dataset
  /// stays invisible. Also throws what the client throws.
  void put(std::shared_ptr<const Dataset> ds, const ProgressFn& progress = {}) override;
  void remove(const std::string& id) override;

  static constexpr std::size_t kBatchRows = 1u << 20;
  /// How long an insert waits for every replica of its shard (insert_quorum_timeout) before it fails.
  static constexpr int kQuorumTimeoutMs = 30000;
  /// The Morton code of (x, y): bit i of x at bit 2i, bit i of y at bit 2i+1.
  static std::uint64_t morton(std::uint32_t x, std::uint32_t y);

  ClickHouseClient& client() { return client_; }
  const std::string& database() const { return db_; }
  const std::string& cluster() const { return cluster_; }

 private:
  struct Meta {
    std::string name, format, created, owner;
    nlohmann::json ingest;
  };
  std::shared_ptr<const Dataset> load(const std::string& id, const Meta& meta) const;
  void drop_partitions(const std::string& id);
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
  mutable std::map<std::string, std::shared_ptr<const Dataset>> loaded_;
  mutable std::mutex load_mu_;  ///< one dataset fetched at a time
};

/// The store a `--store` option names: "" or "embedded" → the embedded store at `data_dir`;
/// clickhouse://... → a ClickHouseStore (leftovers removed when `leftovers` is remove). Throws
/// invalid_argument("--store") for anything else, and what the stores' constructors throw.
std::shared_ptr<DatasetStore> open_dataset_store(const std::string& store,
                                                 const std::filesystem::path& data_dir,
                                                 EmbeddedStore::Leftovers leftovers);

}  // namespace trailscope::server
