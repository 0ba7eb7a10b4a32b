#include "store/clickhouse_store.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>

#include "store/clickhouse_tile_sql.hpp"
#include "store/failpoint.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/aggregate.hpp"
#include "trailscope/density/tile_parts.hpp"
#include "trailscope/trails/partial_reads.hpp"
#include "trailscope/trails/quality.hpp"

namespace trailscope::server {

namespace {

/// Appends values in ClickHouse's RowBinary encoding: little-endian fixed-size numbers, strings as a
/// LEB128 length and the bytes.
struct RowBinary {
  std::string buf;
  template <class T>
  void num(T v) {
    static_assert(std::is_arithmetic_v<T>);
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // x86-64 and aarch64 are little-endian, as RowBinary is
    buf.append(b, sizeof(T));
  }
  void str(std::string_view s) {
    std::uint64_t n = s.size();
    do {
      std::uint8_t byte = n & 0x7f;
      n >>= 7;
      if (n) byte |= 0x80;
      buf.push_back(static_cast<char>(byte));
    } while (n);
    buf.append(s);
  }
};

/// Reads RowBinary values; throws Error(internal) at the end of the data.
struct RowReader {
  std::string_view data;
  std::size_t pos = 0;
  bool done() const { return pos == data.size(); }
  void need(std::size_t n) const {
    if (data.size() - pos < n) throw Error(Error::Kind::internal, "store", "ClickHouse: a truncated answer");
  }
  template <class T>
  T num() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, data.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  /// An Array(T): its LEB128 length, then the values.
  template <class T>
  std::vector<T> array() {
    const std::uint64_t n = length();
    if (n > (data.size() - pos) / sizeof(T))
      throw Error(Error::Kind::internal, "store", "ClickHouse: a truncated answer");
    std::vector<T> v(n);
    for (auto& x : v) x = num<T>();
    return v;
  }
  std::uint64_t length() {
    std::uint64_t n = 0;
    for (int shift = 0;; shift += 7) {
      need(1);
      const auto byte = static_cast<std::uint8_t>(data[pos++]);
      n |= std::uint64_t(byte & 0x7f) << shift;
      if (!(byte & 0x80)) break;
      if (shift > 56) throw Error(Error::Kind::internal, "store", "ClickHouse: a malformed string length");
    }
    return n;
  }
  std::string str() {
    const std::uint64_t n = length();
    need(n);
    std::string s(data.substr(pos, n));
    pos += n;
    return s;
  }
};

/// The hour of a time (floor(t / 3600)); 0 for a time that is not finite.
std::int32_t hour_of(double t) {
  if (!std::isfinite(t)) return 0;
  const double h = std::floor(t / 3600.0);
  return h < -2147483648.0 ? INT32_MIN : h > 2147483647.0 ? INT32_MAX : static_cast<std::int32_t>(h);
}

/// A double as an SQL literal that reads back as the same double (17 significant digits; ClickHouse parses
/// number literals with strtod, correctly rounded), in parentheses when negative.
std::string sql_double(double v) {
  if (!std::isfinite(v))
    throw Error(Error::Kind::internal, "store", "ClickHouse: a bound that is not finite");
  char b[40];
  std::snprintf(b, sizeof b, v < 0 ? "(%.17g)" : "%.17g", v);
  return b;
}

/// Whether `e` is ClickHouse refusing an insert over its quorum: UNKNOWN_STATUS_OF_INSERT (319; the quorum
/// timed out, a replica did not confirm) or UNSATISFIED_QUORUM_FOR_PREVIOUS_WRITE (286).
bool quorum_unconfirmed(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const ClickHouseError& c) {
    return c.code() == 319 || c.code() == 286;
  } catch (...) {
  }
  return false;
}

std::uint64_t now_version() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
}

}  // namespace

std::uint64_t ClickHouseStore::morton(std::uint32_t x, std::uint32_t y) {
  // Spreads the 32 bits of v over the even bits of a 64-bit word (the "magic bits" method of Morton codes,
  // Sean Eron Anderson, Bit Twiddling Hacks, "Interleave bits by Binary Magic Numbers").
  auto spread = [](std::uint64_t v) {
    v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
    v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
    v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
    return v;
  };
  return spread(x) | (spread(y) << 1);
}

ClickHouseStore::ClickHouseStore(const ClickHouseUrl& url, bool leftovers,
                                 ClickHouseClient::Timeouts timeouts)
    : client_(url.hosts, timeouts), db_(url.database), cluster_(url.cluster) {
  const std::string replicas = client_.query(
      "SELECT count() FROM system.clusters WHERE cluster = " + ClickHouseClient::quote(cluster_) +
      " GROUP BY shard_num ORDER BY count() LIMIT 1 FORMAT TSV");
  if (replicas.empty())
    throw invalid_argument("--store", "--store: the ClickHouse nodes know no cluster '" + cluster_ + "'");
  quorum_ = std::max(1, std::atoi(replicas.c_str()));
  create_tables();
  // The catalogue: the highest version of each id, visible unless deleted.
  const std::string rows = client_.query(
      "SELECT id, name, format, created, owner, ingest, points FROM (SELECT id, argMax(deleted, version) AS "
      "del, "
      "argMax(name, version) AS name, argMax(format, version) AS format, argMax(created, version) AS "
      "created, "
      "argMax(owner, version) AS owner, argMax(ingest, version) AS ingest, argMax(points, version) AS "
      "points FROM " +
      db_ + ".catalogue GROUP BY id) WHERE del = 0 FORMAT RowBinary");
  RowReader r{rows};
  while (!r.done()) {
    const std::string id = r.str();
    Meta m;
    m.name = r.str(), m.format = r.str(), m.created = r.str(), m.owner = r.str();
    m.ingest = nlohmann::json::parse(r.str(), nullptr, false);
    if (m.ingest.is_discarded()) m.ingest = nlohmann::json::object();
    m.points = r.num<std::uint64_t>();
    catalogue_[id] = std::move(m);
  }
  if (leftovers) remove_leftovers();
}

void ClickHouseStore::create_tables() {
  const std::string on = " ON CLUSTER " + cluster_;
  auto replicated = [&](const std::string& table) {
    return "ReplicatedMergeTree('/clickhouse/tables/{shard}/" + db_ + "/" + table + "', '{replica}')";
  };
  auto distributed = [&](const std::string& table) {
    return "CREATE TABLE IF NOT EXISTS " + db_ + "." + table + on + " AS " + db_ + "." + table +
           "_local ENGINE = Distributed(" + cluster_ + ", " + db_ + ", " + table +
           "_local, intHash32(flight))";
  };
  // ON CLUSTER waits for every node: skipped when the answering node has every table already, so that a
  // server starts while a replica is down.
  const std::string have = client_.query(
      "SELECT count() FROM system.tables WHERE database = " + ClickHouseClient::quote(db_) +
      " AND name IN ('points_local', 'segments_local', 'flights_local', 'points', 'segments', 'flights', "
      "'catalogue') FORMAT TSV");
  // Flight extents, prev_t and the segments' point attributes came later: a database made before them is
  // read without (describe() and the tiles that need them fetch the copy).
  auto check_extents = [&] {
    segment_prev_t_ =
        client_.query("SELECT count() FROM system.columns WHERE database = " + ClickHouseClient::quote(db_) +
                      " AND table = 'segments_local' AND name = 'prev_t' FORMAT TSV") == "1\n";
    segment_attrs_ =
        client_.query("SELECT count() FROM system.columns WHERE database = " + ClickHouseClient::quote(db_) +
                      " AND table = 'segments_local' AND name = 'v_flags' FORMAT TSV") == "1\n";
    flight_extents_ =
        client_.query("SELECT count() FROM system.columns WHERE database = " + ClickHouseClient::quote(db_) +
                      " AND table = 'flights_local' AND name = 'crosses' FORMAT TSV") == "1\n";
    quality_events_ =
        client_.query("SELECT count() FROM system.tables WHERE database = " + ClickHouseClient::quote(db_) +
                      " AND name IN ('events_local', 'events') FORMAT TSV") == "2\n";
  };
  if (have == "7\n") return check_extents();
  client_.query("CREATE DATABASE IF NOT EXISTS " + db_ + on);
  client_.query(
      "CREATE TABLE IF NOT EXISTS " + db_ + ".points_local" + on +
      " (dataset String, idx UInt32, flight UInt32, t Float64, lat Float32, lon Float32, alt Float32, "
      "speed Float32, track Float32, vrate Float32, on_ground UInt8, mx UInt32, my UInt32, "
      "morton UInt64, hour Int32) ENGINE = " +
      replicated("points_local") + " PARTITION BY dataset ORDER BY (hour, morton)");
  client_.query(
      "CREATE TABLE IF NOT EXISTS " + db_ + ".segments_local" + on +
      " (dataset String, idx UInt32, flight UInt32, t0 Float64, t1 Float64, x0 UInt32, y0 UInt32, "
      "x1 UInt32, y1 UInt32, morton UInt64, hour Int32, prev_t Float64, alt0 Float32, alt1 Float32, "
      "lat0 Float32, lat1 Float32, lon0 Float32, lon1 Float32, g0 UInt8, g1 UInt8, prev_alt Float32, "
      "prev_lat Float32, prev_lon Float32, prev_ground UInt8, v_alt Int32, v_speed Int32, v_flags "
      "UInt8) ENGINE = " +
      replicated("segments_local") + " PARTITION BY dataset ORDER BY (hour, morton)");
  client_.query("CREATE TABLE IF NOT EXISTS " + db_ + ".flights_local" + on +
                " (dataset String, flight UInt32, begin UInt32, end UInt32, icao24 String, callsign String, "
                "t_min Float64, t_max Float64, lat_min Float32, lat_max Float32, lon_min Float32, lon_max "
                "Float32, alt_min Float32, alt_max Float32, crosses UInt8) ENGINE = " +
                replicated("flights_local") + " PARTITION BY dataset ORDER BY flight");
  client_.query("CREATE TABLE IF NOT EXISTS " + db_ + ".events_local" + on +
                " (dataset String, flight UInt32, kind UInt8, t Float64, value Float64, alt Float32, lat "
                "Float32, lon Float32, on_ground UInt8, prev_t Float64, prev_alt Float32, prev_lat Float32, "
                "prev_lon Float32, prev_ground UInt8, hour Int32) ENGINE = " +
                replicated("events_local") + " PARTITION BY dataset ORDER BY (hour, flight)");
  for (const char* t : {"points", "segments", "flights", "events"}) client_.query(distributed(t));
  // Replicated on every node (one replica set for the whole cluster): any node answers list().
  client_.query("CREATE TABLE IF NOT EXISTS " + db_ + ".catalogue" + on +
                " (id String, version UInt64, deleted UInt8, name String, format String, created String, "
                "owner String, ingest String, points UInt64, flights UInt64) ENGINE = "
                "ReplicatedMergeTree('/clickhouse/tables/all/" +
                db_ + "/catalogue', '{shard}-{replica}') ORDER BY (id, version)");
  check_extents();
}

bool ClickHouseStore::has_rows(const std::string& id) const {
  return client_.query(
             "SELECT count() FROM cluster(" + ClickHouseClient::quote(cluster_) +
             ", system, parts) WHERE database = " + ClickHouseClient::quote(db_) +
             " AND table IN ('points_local', 'segments_local', 'flights_local', 'events_local') AND "
             "active AND "
             "partition = " +
             ClickHouseClient::quote(id) + " FORMAT TSV") != "0\n";
}

void ClickHouseStore::drop_partitions(const std::string& id) {
  // Every table's drop is issued even when one fails: a drop that outlives distributed_ddl_task_timeout
  // (ClickHouse's TIMEOUT_EXCEEDED: a node slow under load, down, or just restarted) stays in ZooKeeper's DDL
  // queue and still runs on every node, so stopping at the first error would leave the later tables' rows
  // behind for good. After one such timeout the others are only queued (a timeout of 0 answers at once), so
  // that a node that is down costs one timeout, not one per table.
  constexpr int kTimeoutExceeded = 159;
  std::exception_ptr first;
  ClickHouseClient::Settings settings;
  for (const char* t : {"points_local", "segments_local", "flights_local", "events_local"})
    if (quality_events_ || std::string_view(t) != "events_local") try {
        client_.query("ALTER TABLE " + db_ + "." + t + " ON CLUSTER " + cluster_ + " DROP PARTITION " +
                          ClickHouseClient::quote(id),
                      settings);
      } catch (const ClickHouseError& e) {
        if (e.code() == kTimeoutExceeded) settings["distributed_ddl_task_timeout"] = "0";
        if (!first) first = std::current_exception();
      } catch (const std::exception&) {
        if (!first) first = std::current_exception();
      }
  if (first) std::rethrow_exception(first);
}

void ClickHouseStore::clear_rows(const std::string& id) {
  try {
    drop_partitions(id);
  } catch (const std::exception&) {
    // A drop that outlived the DDL timeout still runs from the queue: new rows under `id` must wait for it,
    // or it would drop them too.
    const auto until = std::chrono::steady_clock::now() + kDropWait;
    while (has_rows(id)) {
      if (std::chrono::steady_clock::now() > until) throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
  }
}

void ClickHouseStore::remove_leftovers() {
  // One replica of each shard answers (the parts of replicas are the same).
  const std::string rows = client_.query(
      "SELECT DISTINCT partition FROM cluster(" + ClickHouseClient::quote(cluster_) +
      ", system, parts) WHERE database = " + ClickHouseClient::quote(db_) +
      " AND table IN ('points_local', 'segments_local', 'flights_local', 'events_local') AND active FORMAT "
      "RowBinary");
  RowReader r{rows};
  std::set<std::string> orphans;
  while (!r.done()) {
    std::string id = r.str();
    if (!catalogue_.count(id)) orphans.insert(std::move(id));
  }
  for (const auto& id : orphans) {
    std::cerr << "store: removing the rows of dataset '" << id
              << "', not in the catalogue (an interrupted ingest or delete)\n";
    // Best effort, as in remove(): rows outside the catalogue are never read, and put() drops them before
    // it writes that id again. A replica that is down or has just restarted (its DDL queue not yet
    // active) must not keep the store from opening.
    try {
      drop_partitions(id);
    } catch (const std::exception& ex) {
      std::cerr << "store: the rows of '" << id << "' stay until the next start: " << ex.what() << "\n";
    }
  }
}

std::vector<std::shared_ptr<const Dataset>> ClickHouseStore::list() const {
  std::vector<std::string> ids;
  {
    std::lock_guard lock(mu_);
    for (const auto& [id, m] : catalogue_) ids.push_back(id);
  }
  std::vector<std::shared_ptr<const Dataset>> out;
  for (const auto& id : ids) try {
      out.push_back(describe(id));
    } catch (const Error& e) {
      if (e.kind() != Error::Kind::not_found) throw;  // deleted meanwhile
    }
  return out;
}

bool ClickHouseStore::contains(const std::string& id) const {
  std::lock_guard lock(mu_);
  return catalogue_.count(id) > 0;
}

std::shared_ptr<const Dataset> ClickHouseStore::get(const std::string& id) const {
  Meta meta;
  auto kept = [&]() -> std::shared_ptr<const Dataset> {
    for (auto it = loaded_.begin(); it != loaded_.end(); ++it)
      if ((*it)->id == id) {
        auto ds = *it;
        loaded_.erase(it);
        loaded_.insert(loaded_.begin(), ds);
        return ds;
      }
    return nullptr;
  };
  {
    std::lock_guard lock(mu_);
    auto it = catalogue_.find(id);
    if (it == catalogue_.end()) throw not_found("dataset", "dataset '" + id + "' does not exist");
    if (auto ds = kept()) return ds;
    meta = it->second;
  }
  std::lock_guard load_lock(load_mu_);
  {
    std::lock_guard lock(mu_);
    if (auto ds = kept()) return ds;
  }
  auto ds = load(id, meta);
  ++fetches_;
  std::lock_guard lock(mu_);
  if (!catalogue_.count(id)) throw not_found("dataset", "dataset '" + id + "' does not exist");
  loaded_.insert(loaded_.begin(), ds);
  if (loaded_.size() > kKeptCopies) loaded_.resize(kKeptCopies);
  if (!outlines_.count(id)) outlines_[id] = outline_of(*ds);
  return ds;
}

std::shared_ptr<const Dataset> ClickHouseStore::outline_of(const Dataset& full) {
  auto d = std::make_shared<Dataset>();
  d->id = full.id, d->name = full.name, d->format = full.format, d->created = full.created;
  d->ingest = full.ingest, d->owner = full.owner;
  d->outline = std::make_shared<const TrailSet>(PointColumns{}, full.flights());
  d->outline_points = full.num_points();
  return d;
}

std::shared_ptr<const Dataset> ClickHouseStore::describe(const std::string& id) const {
  Meta meta;
  {
    std::lock_guard lock(mu_);
    auto it = catalogue_.find(id);
    if (it == catalogue_.end()) throw not_found("dataset", "dataset '" + id + "' does not exist");
    if (auto o = outlines_.find(id); o != outlines_.end()) return o->second;
    meta = it->second;
  }
  // Without the extent columns the flights' extents need the points.
  if (!flight_extents_) return outline_of(*get(id));
  auto d = std::make_shared<Dataset>();
  d->id = id, d->name = meta.name, d->format = meta.format, d->created = meta.created;
  d->ingest = meta.ingest, d->owner = meta.owner;
  d->outline = std::make_shared<const TrailSet>(PointColumns{}, load_flights(id));
  d->outline_points = meta.points;
  for (const Flight& f : d->outline->flights())
    if (f.begin > f.end || f.end > meta.points)
      throw Error(Error::Kind::internal, "store",
                  "ClickHouse: dataset '" + id + "' has a flight range outside its points");
  std::lock_guard lock(mu_);
  if (!catalogue_.count(id)) throw not_found("dataset", "dataset '" + id + "' does not exist");
  return outlines_.emplace(id, std::move(d)).first->second;
}

std::vector<Flight> ClickHouseStore::load_flights(const std::string& id) const {
  const std::string frows = client_.query(
      "SELECT flight, begin, end, icao24, callsign" +
      std::string(flight_extents_
                      ? ", t_min, t_max, lat_min, lat_max, lon_min, lon_max, alt_min, alt_max, crosses"
                      : "") +
      " FROM " + db_ + ".flights WHERE dataset = " + ClickHouseClient::quote(id) + " FORMAT RowBinary");
  RowReader fr{frows};
  std::vector<std::pair<std::uint32_t, Flight>> rows;
  while (!fr.done()) {
    std::pair<std::uint32_t, Flight> row;
    Flight& f = row.second;
    row.first = fr.num<std::uint32_t>();
    f.begin = fr.num<std::uint32_t>(), f.end = fr.num<std::uint32_t>();
    f.icao24 = fr.str(), f.callsign = fr.str();
    if (flight_extents_) {
      f.t_min = fr.num<double>(), f.t_max = fr.num<double>();
      f.lat_min = fr.num<float>(), f.lat_max = fr.num<float>(), f.lon_min = fr.num<float>();
      f.lon_max = fr.num<float>(), f.alt_min = fr.num<float>(), f.alt_max = fr.num<float>();
      f.crosses_antimeridian = fr.num<std::uint8_t>() != 0;
    }
    rows.push_back(std::move(row));
  }
  std::vector<Flight> flights(rows.size());
  std::vector<bool> seen(rows.size(), false);
  for (auto& [i, f] : rows) {
    if (i >= flights.size() || seen[i])
      throw Error(Error::Kind::internal, "store",
                  "ClickHouse: dataset '" + id + "' has an inconsistent flight table");
    seen[i] = true;
    flights[i] = std::move(f);
  }
  return flights;
}

std::shared_ptr<const Dataset> ClickHouseStore::load(const std::string& id, const Meta& meta) const {
  const std::string where = " WHERE dataset = " + ClickHouseClient::quote(id);
  std::vector<Flight> flights = load_flights(id);
  auto corrupt = [&](const std::string& what) {
    return Error(Error::Kind::internal, "store", "ClickHouse: dataset '" + id + "' " + what);
  };

  const std::string prows =
      client_.query("SELECT idx, t, lat, lon, alt, speed, track, vrate, on_ground FROM " + db_ + ".points" +
                    where + " FORMAT RowBinary");
  constexpr std::size_t kRow = 4 + 8 + 6 * 4 + 1;
  if (prows.size() % kRow) throw corrupt("has a truncated point table");
  const std::size_t n = prows.size() / kRow;
  PointColumns p;
  p.resize(n);
  std::vector<bool> seen(n, false);
  RowReader pr{prows};
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = pr.num<std::uint32_t>();
    if (i >= n || seen[i]) throw corrupt("has an inconsistent point table");
    seen[i] = true;
    p.t[i] = pr.num<double>();
    p.lat[i] = pr.num<float>(), p.lon[i] = pr.num<float>(), p.alt[i] = pr.num<float>();
    p.speed[i] = pr.num<float>(), p.track[i] = pr.num<float>(), p.vrate[i] = pr.num<float>();
    p.on_ground[i] = pr.num<std::uint8_t>();
  }
  for (Flight& f : flights) {
    if (f.begin > f.end || f.end > n) throw corrupt("has a flight range outside its points");
    compute_extents(f, p);
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = id;
  ds->name = meta.name;
  ds->format = meta.format;
  ds->created = meta.created;
  ds->ingest = meta.ingest;
  ds->owner = meta.owner;
  ds->trails = std::make_shared<const TrailSet>(std::move(p), std::move(flights));
  return ds;
}

void ClickHouseStore::put(std::shared_ptr<const Dataset> ds, const ProgressFn& progress) {
  validate_dataset_id(ds->id);
  if (contains(ds->id)) throw Error(Error::Kind::conflict, "name", "dataset '" + ds->id + "' already exists");
  const TrailSet& t = *ds->trails;
  const PointColumns& p = t.points();
  const std::size_t n = p.size(), nf = t.num_flights();
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw invalid_argument("name", "a dataset of more than 2^32 - 1 points");
  // Each point's flight (the sharding key); points outside every flight go to flight 0's shard.
  std::vector<std::uint32_t> flight_of(n, 0);
  for (std::size_t f = 0; f < nf; ++f)
    for (std::uint32_t i = t.flights()[f].begin; i < t.flights()[f].end; ++i)
      flight_of[i] = static_cast<std::uint32_t>(f);
  // Rows every replica of its shard has acknowledged (so that any replica serves the whole dataset).
  // No deduplication: a dataset put again after a delete has the same blocks, which replicated tables
  // would otherwise skip as already inserted.
  // A replica that is down makes the quorum fail after kQuorumTimeoutMs (ClickHouse's default waits 10
  // minutes): the ingest is refused, not hung.
  const ClickHouseClient::Settings ins = {
      {"insert_distributed_sync", "1"},
      {"insert_distributed_timeout", std::to_string(kQuorumTimeoutMs / 1000)},
      {"insert_quorum", std::to_string(quorum_)},
      {"insert_quorum_timeout", std::to_string(kQuorumTimeoutMs)},
      {"insert_deduplicate", "0"}};
  const std::size_t segments = [&] {
    std::size_t s = 0;
    for (const Flight& f : t.flights()) s += f.size() > 1 ? f.size() - 1 : 0;
    return s;
  }();
  const std::vector<QualityEvent> events = quality_events_ ? quality_events(t) : std::vector<QualityEvent>{};
  const double total = static_cast<double>(nf + n + segments + events.size()) + 1;
  double done = 0;
  auto report = [&](std::size_t rows) {
    done += static_cast<double>(rows);
    if (progress) progress(done / total, "store");
  };
  try {
    // Rows of an earlier attempt at this id that never reached the catalogue (a killed CLI ingest).
    if (has_rows(ds->id)) clear_rows(ds->id);
    RowBinary rb;
    auto flush = [&](const std::string& table, const std::string& cols, std::size_t rows) {
      if (rows == 0) return;
      client_.query("INSERT INTO " + db_ + "." + table + " (" + cols + ") FORMAT RowBinary", ins, rb.buf);
      rb.buf.clear();
      report(rows);
      failpoint("clickhouse.insert.batch");
    };
    std::size_t rows = 0;
    const std::string fcols =
        std::string("dataset, flight, begin, end, icao24, callsign") +
        (flight_extents_ ? ", t_min, t_max, lat_min, lat_max, lon_min, lon_max, alt_min, alt_max, crosses"
                         : "");
    for (std::size_t f = 0; f < nf; ++f) {
      const Flight& fl = t.flights()[f];
      rb.str(ds->id), rb.num<std::uint32_t>(f), rb.num(fl.begin), rb.num(fl.end), rb.str(fl.icao24),
          rb.str(fl.callsign);
      if (flight_extents_) {
        rb.num(fl.t_min), rb.num(fl.t_max), rb.num(fl.lat_min), rb.num(fl.lat_max), rb.num(fl.lon_min),
            rb.num(fl.lon_max), rb.num(fl.alt_min), rb.num(fl.alt_max);
        rb.num<std::uint8_t>(fl.crosses_antimeridian ? 1 : 0);
      }
      if (++rows == kBatchRows) flush("flights", fcols, rows), rows = 0;
    }
    flush("flights", fcols, rows), rows = 0;
    const auto& mx = t.merc_x();
    const auto& my = t.merc_y();
    const std::string pcols =
        "dataset, idx, flight, t, lat, lon, alt, speed, track, vrate, on_ground, mx, my, morton, hour";
    for (std::size_t i = 0; i < n; ++i) {
      rb.str(ds->id), rb.num<std::uint32_t>(i), rb.num(flight_of[i]), rb.num(p.t[i]);
      rb.num(p.lat[i]), rb.num(p.lon[i]), rb.num(p.alt[i]), rb.num(p.speed[i]), rb.num(p.track[i]),
          rb.num(p.vrate[i]), rb.num(p.on_ground[i]);
      rb.num(mx[i]), rb.num(my[i]), rb.num(morton(mx[i], my[i])), rb.num(hour_of(p.t[i]));
      if (++rows == kBatchRows) flush("points", pcols, rows), rows = 0;
    }
    flush("points", pcols, rows), rows = 0;
    const std::string scols =
        std::string("dataset, idx, flight, t0, t1, x0, y0, x1, y1, morton, hour") +
        (segment_prev_t_ ? ", prev_t" : "") +
        (segment_attrs_ ? ", alt0, alt1, lat0, lat1, lon0, lon1, g0, g1, prev_alt, prev_lat, prev_lon, "
                          "prev_ground, v_alt, v_speed, v_flags"
                        : "");
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t f = 0; f < nf; ++f) {
      const Flight& fl = t.flights()[f];
      for (std::uint32_t i = fl.begin; i + 1 < fl.end; ++i) {
        rb.str(ds->id), rb.num<std::uint32_t>(i), rb.num<std::uint32_t>(f), rb.num(p.t[i]),
            rb.num(p.t[i + 1]);
        rb.num(mx[i]), rb.num(my[i]), rb.num(mx[i + 1]), rb.num(my[i + 1]);
        rb.num(morton(mx[i], my[i])), rb.num(hour_of(p.t[i]));
        if (segment_prev_t_) rb.num(i > fl.begin ? p.t[i - 1] : std::numeric_limits<double>::quiet_NaN());
        if (segment_attrs_) {
          // Both points' and the previous point's filter attributes (none before a flight's first), and
          // the segment's values exactly as density_lines() computes them.
          const bool first = i == fl.begin;
          rb.num(p.alt[i]), rb.num(p.alt[i + 1]), rb.num(p.lat[i]), rb.num(p.lat[i + 1]), rb.num(p.lon[i]),
              rb.num(p.lon[i + 1]), rb.num(p.on_ground[i]), rb.num(p.on_ground[i + 1]);
          rb.num(first ? kNaN : p.alt[i - 1]), rb.num(first ? kNaN : p.lat[i - 1]),
              rb.num(first ? kNaN : p.lon[i - 1]), rb.num<std::uint8_t>(first ? 0 : p.on_ground[i - 1]);
          const double va = density::segment_value(p.alt[i], p.alt[i + 1]),
                       vs = density::segment_value(p.speed[i], p.speed[i + 1]);
          rb.num<std::int32_t>(std::isnan(va) ? 0 : density::to_fixed(va));
          rb.num<std::int32_t>(std::isnan(vs) ? 0 : density::to_fixed(vs));
          rb.num<std::uint8_t>((std::isnan(va) ? 0 : 1) | (std::isnan(vs) ? 0 : 2));
        }
        if (++rows == kBatchRows) flush("segments", scols, rows), rows = 0;
      }
    }
    flush("segments", scols, rows), rows = 0;
    if (quality_events_) {
      // The implausible values with the attributes PointFilter reads of their sample and, for a jump, of
      // the sample before it: the summary's quality block under any query (see summarize()).
      const std::string ecols =
          "dataset, flight, kind, t, value, alt, lat, lon, on_ground, prev_t, prev_alt, prev_lat, prev_lon, "
          "prev_ground, hour";
      for (const QualityEvent& e : events) {
        const std::uint32_t i = e.point, j = e.kind == 2 ? e.point - 1 : e.point;
        const bool jump = e.kind == 2;
        rb.str(ds->id), rb.num(e.flight), rb.num(e.kind), rb.num(p.t[i]), rb.num(e.value);
        rb.num(p.alt[i]), rb.num(p.lat[i]), rb.num(p.lon[i]), rb.num(p.on_ground[i]);
        rb.num(jump ? p.t[j] : std::numeric_limits<double>::quiet_NaN());
        rb.num(jump ? p.alt[j] : kNaN), rb.num(jump ? p.lat[j] : kNaN), rb.num(jump ? p.lon[j] : kNaN);
        rb.num<std::uint8_t>(jump ? p.on_ground[j] : 0), rb.num(hour_of(p.t[i]));
        if (++rows == kBatchRows) flush("events", ecols, rows), rows = 0;
      }
      flush("events", ecols, rows), rows = 0;
    }
    failpoint("clickhouse.before_catalogue");
    // The catalogue row, last: from now on the dataset is visible.
    write_catalogue_row(ds->id, false, Meta{ds->name, ds->format, ds->created, ds->owner, ds->ingest, n}, n,
                        nf);
    report(1);
  } catch (...) {
    // Not in the catalogue: invisible; its rows go now or, if the cluster cannot be reached, at the next
    // start. Not now when a replica did not confirm the quorum insert: ClickHouse 18.16 keeps waiting for
    // that part until the replica has fetched it, and a partition dropped before then leaves it waiting for
    // a part that no longer exists, refusing every later quorum insert into the table (code 286).
    if (quorum_unconfirmed(std::current_exception()))
      std::cerr << "store: the rows of the failed ingest of '" << ds->id
                << "' stay until the next start (a replica did not confirm them)\n";
    else
      try {
        if (has_rows(ds->id)) drop_partitions(ds->id);
      } catch (const std::exception& ex) {
        std::cerr << "store: the rows of the failed ingest of '" << ds->id
                  << "' stay until the next start: " << ex.what() << "\n";
      }
    throw;
  }
  std::lock_guard lock(mu_);
  catalogue_[ds->id] = Meta{ds->name, ds->format, ds->created, ds->owner, ds->ingest, n};
  outlines_[ds->id] = outline_of(*ds);
}

// ---- push-down ------------------------------------------------------------------------------------------

bool ClickHouseStore::pushable(const Dataset& ds) {
  std::size_t covered = 0;
  std::uint32_t next = 0;
  for (const Flight& f : ds.flights()) {
    if (f.begin != next) return false;
    covered += f.size(), next = f.end;
  }
  return covered == ds.num_points();
}

std::string ClickHouseStore::read(const std::string& sql) const {
  // A flight-id list of every flight of a large dataset stays within the parser's limit (default 256 KiB).
  // A dead replica is skipped after 200 ms instead of ClickHouse's 50 ms default, which a loaded machine
  // can miss for a live one.
  static const ClickHouseClient::Settings settings = {{"max_query_size", std::to_string(64u << 20)},
                                                      {"connect_timeout_with_failover_ms", "200"}};
  for (int attempt = 1;; ++attempt) {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      std::string out = client_.query(sql, settings);
      ++reads_;
      if (observer_)
        observer_(sql,
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      return out;
    } catch (const ClickHouseError& e) {
      const int c = e.code();
      const bool network = c == 32 || c == 209 || c == 210 || c == 279;
      if (!network || attempt == kReadAttempts) throw;
      std::cerr << "store: a read failed on a replica that went away, again (" << attempt << "): " << e.what()
                << "\n";
      std::this_thread::sleep_for(std::chrono::milliseconds(200 * attempt));
    }
  }
}

std::string ClickHouseStore::point_condition(const Query& q, const std::string& t, const std::string& alt,
                                             const std::string& lat, const std::string& lon,
                                             const std::string& ground) {
  // PointFilter (trails/point_filter.hpp) as SQL: Float32 columns compare as doubles, as there; NaN fails
  // every comparison, as there.
  std::string w;
  if (q.t0) w += " AND " + t + " >= " + sql_double(*q.t0);
  if (q.t1) w += " AND " + t + " < " + sql_double(*q.t1);
  if (q.alt_min) w += " AND " + alt + " >= " + sql_double(*q.alt_min);
  if (q.alt_max) w += " AND " + alt + " <= " + sql_double(*q.alt_max);
  if ((q.alt_min || q.alt_max) && !(q.alt_min && q.alt_max)) w += " AND NOT isNaN(" + alt + ")";
  if (q.bbox) {
    const BBox& b = *q.bbox;
    w += " AND " + lat + " >= " + sql_double(b.south) + " AND " + lat + " <= " + sql_double(b.north);
    w += b.west > b.east
             ? " AND (" + lon + " >= " + sql_double(b.west) + " OR " + lon + " <= " + sql_double(b.east) + ")"
             : " AND " + lon + " >= " + sql_double(b.west) + " AND " + lon + " <= " + sql_double(b.east);
  }
  if (q.on_ground) w += " AND " + ground + (*q.on_ground ? " = 1" : " = 0");
  return w;
}

namespace {
// The ids of the flights passing q's flight filters (icao24, callsign), comma-separated for an SQL IN list:
// callsign_matches()' patterns are not LIKE's, so they are matched here against the flight table.
std::string matching_flights(const Dataset& ds, const Query& q) {
  std::string ids;
  const auto& flights = ds.flights();
  for (std::size_t f = 0; f < flights.size(); ++f)
    if (q.matches_flight_ids(flights[f])) ids += (ids.empty() ? "" : ",") + std::to_string(f);
  return ids;
}
}  // namespace

std::string ClickHouseStore::point_where(const Dataset& ds, const Query& q) const {
  std::string w = "dataset = " + ClickHouseClient::quote(ds.id);
  if (q.t0) w += " AND hour >= " + std::to_string(hour_of(*q.t0));
  if (q.t1) w += " AND hour <= " + std::to_string(hour_of(*q.t1));
  w += point_condition(q, "t", "alt", "lat", "lon", "on_ground");
  if (!q.icao24.empty() || !q.callsign.empty()) {
    const std::string ids = matching_flights(ds, q);
    if (ids.empty()) return "";
    w += " AND flight IN (" + ids + ")";
  }
  return w;
}

Summary ClickHouseStore::summarize(const Dataset& ds, const Query& q, const SummaryOptions& opts) const {
  if (!pushable(ds)) return LocalReads{}.summarize(*whole(ds), q, opts);
  const TrailSet& set = ds.shape();
  double top_alt = 0;
  for (const Flight& f : set.flights())
    if (!std::isnan(f.alt_max)) top_alt = std::max<double>(top_alt, f.alt_max);
  const SummaryLayout l = summary_layout(q, opts, set.t_min(), set.t_max(), top_alt);
  SummaryCounts c(l, set.num_flights());
  const std::string where = point_where(ds, q);
  if (!where.empty()) {
    // The bins exactly as summarize() computes them (SummaryCounts): the same double operations, on
    // constants that read back bit for bit.
    const std::string O = sql_double(l.t_origin), B = sql_double(l.bin_seconds),
                      IB = sql_double(1.0 / l.bin_seconds), NT = std::to_string(l.time_bins),
                      NA = std::to_string(l.alt_bins), NS = std::to_string(SummaryLayout::kSpeedBins);
    // The last bin of each histogram, as UInt64 (least() takes no mix of signed and unsigned types).
    auto last_bin = [](std::size_t n) { return "toUInt64(" + std::to_string(n - 1) + ")"; };
    const std::string tb0 =
        "least(toUInt64(greatest(0., (t - " + O + ") * " + IB + ")), " + last_bin(l.time_bins) + ")";
    const std::string tb = "if(" + tb0 + " + 1 < " + NT + " AND t >= " + O + " + (" + tb0 + " + 1) * " + B +
                           ", " + tb0 + " + 1, " + tb0 + ")";
    const std::string ab = "(toFloat64(alt) * " + sql_double(l.alt_scale) + " + " +
                           sql_double(SummaryLayout::kAltEdgeNudge) + ")";
    // Unknown altitudes and speeds go to the key one past the last bin, dropped below.
    const std::string akey = "if(isNaN(alt), " + NA + ", if(" + ab + " <= 0, 0, least(toUInt64(" + ab +
                             "), " + last_bin(l.alt_bins) + ")))";
    const std::string sb = "(toFloat64(speed) * 4)";
    static_assert(SummaryLayout::kSpeedBin == 0.25);
    const std::string skey = "if(isNaN(speed), " + NS + ", if(" + sb + " <= 0, 0, least(toUInt64(" + sb +
                             "), " + last_bin(SummaryLayout::kSpeedBins) + ")))";
    const std::string one = "[toUInt64(1)]";
    const std::string sql =
        "SELECT count(), min(t), max(t), countIf(NOT isNaN(speed)), sumIf(toFloat64(speed), NOT "
        "isNaN(speed)), "
        "minIf(speed, NOT isNaN(speed)), maxIf(speed, NOT isNaN(speed)), sumMap([toUInt32(" +
        tb + ")], " + one + "), sumMap([toUInt32(" + akey + ")], " + one + "), sumMap([toUInt32(" + skey +
        ")], " + one + "), sumMap([flight], " + one + ") FROM " + db_ + ".points WHERE " + where +
        " FORMAT RowBinary";
    const std::string body = read(sql);
    RowReader r{body};
    c.points = r.num<std::uint64_t>();
    c.t_min = r.num<double>(), c.t_max = r.num<double>();
    c.speed_n = r.num<std::uint64_t>();
    c.speed_sum = r.num<double>();
    c.speed_min = r.num<float>(), c.speed_max = r.num<float>();
    auto histogram = [&](std::vector<std::uint64_t>& h) {
      const auto keys = r.array<std::uint32_t>();
      const auto counts = r.array<std::uint64_t>();
      if (keys.size() != counts.size())
        throw Error(Error::Kind::internal, "store", "ClickHouse: a malformed map");
      for (std::size_t i = 0; i < keys.size(); ++i)
        if (keys[i] < h.size()) h[keys[i]] += counts[i];
    };
    histogram(c.time), histogram(c.alt), histogram(c.speed);
    const auto fl = r.array<std::uint32_t>();
    const auto fc = r.array<std::uint64_t>();
    if (fl.size() != fc.size()) throw Error(Error::Kind::internal, "store", "ClickHouse: a malformed map");
    for (std::size_t i = 0; i < fl.size(); ++i)
      if (fl[i] < c.matched.size()) c.matched[fl[i]] = static_cast<std::uint32_t>(fc[i]);
  }
  return finish_summary(l, opts, std::move(c), set.flights(),
                        quality_events_ ? shard_quality(ds, q) : check_quality(*whole(ds)->trails, q));
}

QualityReport ClickHouseStore::shard_quality(const Dataset& ds, const Query& q) const {
  // check_quality() over the events stored at ingest (quality_events(): every implausible value with
  // every point passing): those of the query's flights whose sample, and for a jump the sample before
  // it, pass its point filter. Counts per kind, and each kind's largest values (LIMIT BY on each shard,
  // then cut again here, with check_quality()'s order: value descending, then flight id, then time).
  QualityReport out;
  const std::string where = point_where(ds, q);
  if (where.empty()) return out;
  const std::string prev = point_condition(q, "prev_t", "prev_alt", "prev_lat", "prev_lon", "prev_ground");
  const std::string w = where + (prev.empty() ? "" : " AND (kind != 2 OR (1" + prev + "))");
  QualityCount* counts[3] = {&out.speed, &out.altitude, &out.jumps};
  {
    const std::string body =
        read("SELECT kind, count() FROM " + db_ + ".events WHERE " + w + " GROUP BY kind FORMAT RowBinary");
    RowReader r{body};
    while (!r.done()) {
      const auto kind = r.num<std::uint8_t>();
      const auto n = r.num<std::uint64_t>();
      if (kind > 2) throw Error(Error::Kind::internal, "store", "ClickHouse: an unknown quality event");
      counts[kind]->count = n;
    }
  }
  if (!out.speed.count && !out.altitude.count && !out.jumps.count) return out;
  const std::string body = read("SELECT kind, flight, t, value FROM " + db_ + ".events WHERE " + w +
                                " ORDER BY kind, value DESC, flight, t LIMIT " +
                                std::to_string(kQualityExamples) + " BY kind FORMAT RowBinary");
  RowReader r{body};
  const auto& flights = ds.flights();
  while (!r.done()) {
    const auto kind = r.num<std::uint8_t>();
    QualityExample e;
    e.flight_id = r.num<std::uint32_t>();
    e.t = r.num<double>(), e.value = r.num<double>();
    if (kind > 2 || e.flight_id >= flights.size())
      throw Error(Error::Kind::internal, "store", "ClickHouse: a quality event out of range");
    e.callsign = flights[e.flight_id].callsign;
    counts[kind]->examples.push_back(std::move(e));
  }
  for (QualityCount* c : counts) keep_largest_examples(c->examples);
  return out;
}

FlightPage ClickHouseStore::list_flights(const Dataset& ds, const Query& q, std::size_t page,
                                         std::size_t page_size, const FlightSort& sort) const {
  if (!pushable(ds)) return LocalReads{}.list_flights(*whole(ds), q, page, page_size, sort);
  if (page_size < 1 || page_size > limits::kMaxPageSize)
    throw invalid_argument("page_size", "page_size must lie in 1..1000");
  const auto& flights = ds.flights();
  std::vector<FlightRow> rows;
  const std::string where = point_where(ds, q);
  if (!where.empty()) {
    const std::string body = read(
        "SELECT flight, count(), min(t), max(t), maxIf(alt, NOT isNaN(alt)), countIf(NOT isNaN(alt)) FROM " +
        db_ + ".points WHERE " + where + " GROUP BY flight FORMAT RowBinary");
    RowReader r{body};
    while (!r.done()) {
      FlightRow row;
      row.id = r.num<std::uint32_t>();
      row.points = r.num<std::uint64_t>();
      row.t_start = r.num<double>(), row.t_end = r.num<double>();
      const float alt = r.num<float>();
      row.alt_max_m = r.num<std::uint64_t>() ? alt : std::numeric_limits<double>::quiet_NaN();
      if (row.id >= flights.size())
        throw Error(Error::Kind::internal, "store", "ClickHouse: a flight out of range");
      const Flight& f = flights[row.id];
      row.duration_s = row.t_end - row.t_start;
      row.flight_t_start = f.t_min, row.flight_t_end = f.t_max;
      row.flight_duration_s = f.t_max - f.t_min;
      row.flight_points = f.size();
      rows.push_back(std::move(row));
    }
  }
  return page_flights(std::move(rows), flights, page, page_size, sort);
}

Positions ClickHouseStore::positions_at(const Dataset& ds, double t, const Query& q,
                                        std::size_t max_positions) const {
  validate_positions_query(t, q);
  if (!pushable(ds)) return LocalReads{}.positions_at(*whole(ds), t, q, max_positions);
  // The flights present at t that the query may match, by their extents (as positions_at() skips them);
  // their samples around t lie within the hours of their extents.
  const auto& flights = ds.flights();
  std::string ids;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t f = 0; f < flights.size(); ++f) {
    const Flight& fl = flights[f];
    if (!(fl.t_min <= t && t <= fl.t_max) || fl.begin == fl.end || !q.may_match(fl)) continue;
    ids += (ids.empty() ? "" : ",") + std::to_string(f);
    lo = std::min(lo, fl.t_min), hi = std::max(hi, fl.t_max);
  }
  std::vector<Position> hits;
  if (!ids.empty()) {
    // Per flight: the first sample at exactly t, the last one before t and the first one after (by index,
    // the flight's time order: lower_bound's choice among equal times).
    const std::string T = sql_double(t);
    const std::string row = "tuple(t, lat, lon, alt, speed, track, vrate, on_ground)";
    const std::string body =
        read("SELECT flight, countIf(t = " + T + "), argMinIf(" + row + ", idx, t = " + T + "), argMaxIf(" +
             row + ", idx, t < " + T + "), argMinIf(" + row + ", idx, t > " + T + ") FROM " + db_ +
             ".points WHERE dataset = " + ClickHouseClient::quote(ds.id) +
             " AND hour >= " + std::to_string(hour_of(lo)) + " AND hour <= " + std::to_string(hour_of(hi)) +
             " AND flight IN (" + ids + ") GROUP BY flight FORMAT RowBinary");
    RowReader r{body};
    auto sample = [&] {
      PositionSample p;
      p.t = r.num<double>();
      p.lat = r.num<float>(), p.lon = r.num<float>(), p.alt = r.num<float>();
      p.speed = r.num<float>(), p.track = r.num<float>(), p.vrate = r.num<float>();
      p.on_ground = r.num<std::uint8_t>();
      return p;
    };
    while (!r.done()) {
      const auto flight = r.num<std::uint32_t>();
      const auto exact = r.num<std::uint64_t>();
      const PositionSample e = sample(), a = sample(), b = sample();
      if (flight >= flights.size())
        throw Error(Error::Kind::internal, "store", "ClickHouse: a flight out of range");
      Position p;
      if (position_from_samples(flight, exact ? &e : nullptr, a, b, t, q, p)) hits.push_back(std::move(p));
    }
  }
  return finish_positions(t, std::move(hits), flights, max_positions);
}

std::optional<density::Aggregate> ClickHouseStore::shard_aggregate(const Dataset& ds, const Query& q,
                                                                   const density::Canvas& work,
                                                                   density::DensityValue value,
                                                                   double max_gap_seconds) const {
  namespace den = trailscope::density;
  // On the shards: datasets without a flight across 180° (whose segments' wrapped copies the SQL does
  // not draw), on a canvas within a world of the world's x range. A time window needs prev_t; point
  // filters, values and a gap limit need the segments' point attributes (a database made before them
  // draws from the copy).
  const bool point_filter = q.alt_min || q.alt_max || q.bbox || q.on_ground;
  const bool window = q.t0 || q.t1;
  const bool valued = value != den::DensityValue::count;
  const bool gap = std::isfinite(max_gap_seconds);
  bool wraps = false;
  for (const Flight& f : ds.flights()) wraps = wraps || f.crosses_antimeridian;
  if (wraps || (window && !segment_prev_t_) || ((point_filter || valued || gap) && !segment_attrs_) ||
      !pushable(ds))
    return std::nullopt;
  // Beyond the world's x range (a canvas across 180°, or a kernel's margin at the world's edge) the
  // canvas also shows the segments' copies one world east or west, as density_lines() draws them: the
  // canvas and the three copies move one world east, so that every coordinate stays non-negative (intDiv
  // truncates) and on the same pixel grid (the pixel divides 2^32).
  constexpr std::int64_t W = std::int64_t{1} << 32;
  const std::int64_t P = work.pixel_units();
  const bool beyond = work.origin_x() < 0 || work.end_x() > W;
  if (beyond && (work.origin_x() < -W || work.end_x() > 2 * W || W % P != 0)) return std::nullopt;
  den::Aggregate agg = den::Aggregate::zeros(work.width(), work.height(), valued);

  // The pixels of each segment as density_lines() walks them on `work`, counted on the shards: the SQL
  // of clickhouse_tile_sql.hpp (the tile benchmark's ClickHouse peer runs the same builder). A segment is
  // drawn when both its points pass the query's point filter and t1 − t0 <= the gap; it continues a
  // drawn run (leaving out the pixel of its first endpoint) when the segment before it was drawn: its
  // first point, which passes, and the point before it pass, and that step is within the gap (prev_*:
  // NaN prev_t for a flight's first point, which no comparison passes). These are exactly the run breaks
  // density_lines() makes, since a flight's samples are in time order.
  const std::int64_t shift = beyond ? W : 0, x0 = work.origin_x() + shift, x_end = work.end_x() + shift,
                     y0 = work.origin_y();
  const LineTileGrid grid{P, x0 / P, y0 / P, work.width(), work.height()};
  const std::string meets_x = " AND greatest(x0, x1)" + std::string(beyond ? " + sh_" : "") +
                              " >= " + std::to_string(x0) + " AND least(x0, x1)" + (beyond ? " + sh_" : "") +
                              " < " + std::to_string(x_end);
  std::string where = "dataset = " + ClickHouseClient::quote(ds.id) + (beyond ? "" : meets_x) +
                      " AND greatest(y0, y1) >= " + std::to_string(y0) + " AND least(y0, y1) < " +
                      std::to_string(work.end_y());
  // `hour` (the first point's) bounds the table's prefix.
  if (q.t0) where += " AND hour >= " + std::to_string(hour_of(*q.t0));
  if (q.t1) where += " AND hour <= " + std::to_string(hour_of(*q.t1));
  where += point_condition(q, "t0", "alt0", "lat0", "lon0", "g0") +
           point_condition(q, "t1", "alt1", "lat1", "lon1", "g1");
  std::string cont;
  if (segment_prev_t_) {
    cont =
        "NOT isNaN(prev_t)" + point_condition(q, "prev_t", "prev_alt", "prev_lat", "prev_lon", "prev_ground");
    if (gap) {
      where += " AND t1 - t0 <= " + sql_double(max_gap_seconds);
      cont += " AND t0 - prev_t <= " + sql_double(max_gap_seconds);
    }
  } else {
    std::string begins;
    for (const Flight& f : ds.flights()) begins += (begins.empty() ? "" : ",") + std::to_string(f.begin);
    cont = "NOT (idx IN (" + begins + "))";
  }
  if (!q.icao24.empty() || !q.callsign.empty()) {
    const std::string ids = matching_flights(ds, q);
    where += " AND flight IN (" + (ids.empty() ? std::string("4294967295") : ids) + ")";
  }
  const bool alt = value == den::DensityValue::altitude;
  const std::string sql =
      line_tile_sql(grid, cont, beyond ? "toInt64(x0) + sh_" : "toInt64(x0)", "toInt64(y0)",
                    beyond ? "toInt64(x1) + sh_" : "toInt64(x1)", "toInt64(y1)",
                    beyond ? "FROM (SELECT *, arrayJoin([toInt64(0), toInt64(" + std::to_string(W) +
                                 "), toInt64(" + std::to_string(2 * W) + ")]) AS sh_ FROM " + db_ +
                                 ".segments WHERE " + where + ") WHERE 1" + meets_x
                           : "FROM " + db_ + ".segments WHERE " + where,
                    valued ? (alt ? "toInt64(v_alt)" : "toInt64(v_speed)") : "",
                    valued ? (alt ? "bitAnd(v_flags, 1) != 0" : "bitAnd(v_flags, 2) != 0") : "") +
      " FORMAT RowBinary";
  const std::string body = read(sql);
  RowReader r{body};
  while (!r.done()) {
    const auto pos = r.num<std::uint32_t>();
    const auto n = r.num<std::uint32_t>();
    if (pos >= agg.count.size())
      throw Error(Error::Kind::internal, "store", "ClickHouse: a pixel outside the tile");
    agg.count[pos] = static_cast<std::int32_t>(n);
    if (valued) {
      agg.value_sum[pos] = r.num<std::int64_t>();
      agg.value_count[pos] = static_cast<std::int32_t>(r.num<std::uint32_t>());
    }
  }
  return agg;
}

std::string ClickHouseStore::density_tile(const Dataset& ds, density::DensityRenderer& renderer,
                                          const std::string& dataset_key, const Query& q,
                                          const density::TileRequest& request) const {
  namespace den = trailscope::density;
  // Pushed down as shard_aggregate() says: the tile's aggregate on the work canvas (the tile plus the
  // kernel's margin), and the level's shared span, whose coarse aggregate the same SQL counts on the
  // coarse canvas (computed once per zoom and cached by the renderer); the server smooths and shades
  // through finish_aggregate() and shade_tile(), the code render_tile() finishes with.
  den::validate(request);
  const int grow = static_cast<int>(std::ceil(request.kernel_radius));
  const den::Canvas canvas = den::Canvas::for_tile(request.tile, request.size);
  const den::Canvas work = grow > 0 ? canvas.with_margin(grow) : canvas;
  std::optional<den::Aggregate> agg = shard_aggregate(ds, q, work, request.value, request.max_gap_seconds);
  if (!agg) return LocalReads{}.density_tile(*whole(ds), renderer, dataset_key, q, request);
  const std::shared_ptr<const den::SpanStats> span =
      renderer.span_for(ds.shape(), dataset_key, q, request, coarse_counter(ds, q, request.backend));
  den::AggregateOptions options;
  options.value = request.value;
  options.kernel_radius = request.kernel_radius;
  options.max_gap_seconds = request.max_gap_seconds;
  return std::move(den::shade_tile(den::finish_aggregate(*agg, work, options), *span, request).png);
}

density::CoarseAggregateFn ClickHouseStore::coarse_counter(const Dataset& ds, const Query& q,
                                                           Backend backend) const {
  // A coarse canvas may lie beyond the world's x range (a margin at its edge), or the dataset may need
  // what shard_aggregate() cannot draw: that aggregate is then drawn from the copy.
  return [this, &ds, q, backend](const density::Canvas& c, density::DensityValue value, double gap) {
    if (auto a = shard_aggregate(ds, q, c, value, gap)) return std::move(*a);
    return density::aggregate_lines(*whole(ds)->trails, q, c, value, gap, backend);
  };
}

density::Legend ClickHouseStore::density_legend(const Dataset& ds, density::DensityRenderer& renderer,
                                                const std::string& dataset_key, const Query& q,
                                                const density::TileRequest& request, int stops) const {
  // The span the tiles are shaded with, counted as density_tile() counts it.
  return renderer.legend(ds.shape(), dataset_key, q, request, stops, coarse_counter(ds, q, request.backend));
}

void ClickHouseStore::write_catalogue_row(const std::string& id, bool deleted, const Meta& meta,
                                          std::uint64_t points, std::uint64_t flights) {
  RowBinary rb;
  rb.str(id), rb.num(now_version()), rb.num<std::uint8_t>(deleted ? 1 : 0), rb.str(meta.name),
      rb.str(meta.format), rb.str(meta.created), rb.str(meta.owner), rb.str(meta.ingest.dump()),
      rb.num<std::uint64_t>(points), rb.num<std::uint64_t>(flights);
  client_.query(
      "INSERT INTO " + db_ +
          ".catalogue (id, version, deleted, name, format, created, owner, ingest, points, flights) "
          "FORMAT RowBinary",
      {{"insert_quorum", std::to_string(quorum_)},
       {"insert_quorum_timeout", std::to_string(kQuorumTimeoutMs)}},
      rb.buf);
}

void ClickHouseStore::remove(const std::string& id) {
  Meta meta;
  {
    std::lock_guard lock(mu_);
    auto it = catalogue_.find(id);
    if (it == catalogue_.end()) throw not_found("dataset", "dataset '" + id + "' does not exist");
    meta = it->second;
  }
  // The tombstone is one row, written at once: the dataset disappears whole.
  write_catalogue_row(id, true, meta, 0, 0);
  {
    std::lock_guard lock(mu_);
    catalogue_.erase(id);
    outlines_.erase(id);
    std::erase_if(loaded_, [&](const auto& d) { return d->id == id; });
  }
  try {
    drop_partitions(id);
  } catch (const std::exception& ex) {
    std::cerr << "store: the rows of deleted dataset '" << id << "' stay until the next start: " << ex.what()
              << "\n";
  }
}

}  // namespace trailscope::server

namespace trailscope::server {

std::shared_ptr<DatasetStore> open_dataset_store(const std::string& store,
                                                 const std::filesystem::path& data_dir,
                                                 EmbeddedStore::Leftovers leftovers) {
  if (store.empty() || store == "embedded") return std::make_shared<EmbeddedStore>(data_dir, leftovers);
  if (store.rfind("clickhouse://", 0) == 0)
    return std::make_shared<ClickHouseStore>(ClickHouseUrl::parse(store, "--store"),
                                             leftovers == EmbeddedStore::Leftovers::remove);
  throw invalid_argument(
      "--store",
      "--store: '" + store + "' is neither 'embedded' nor clickhouse://HOST:PORT[,...]/DB?cluster=NAME");
}

}  // namespace trailscope::server
