#pragma once
// Where datasets live. The interface keeps the rest of the server independent of the backend that holds
// them: the embedded store (embedded_store.hpp: this machine, files + memory) implements it, and a backend
// for data beyond one machine (a database server) implements the same interface.
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/core/progress.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::server {

/// A stored, immutable dataset: its trails and what is known about where they came from.
struct Dataset {
  std::string id;         ///< [a-z0-9_-], 1..64 chars; unique in the store
  std::string name;       ///< display name
  std::string format;     ///< source format ("so6", "opensky_csv", "demo", ...)
  std::string created;    ///< ISO 8601 UTC
  nlohmann::json ingest;  ///< the ingest report
  std::string owner;      ///< the owner name of its creator ("" for datasets made before owners, the CLI's)
  /// Every point and flight. Null in a described view (DatasetStore::describe(), list()) of a store that
  /// fetches points on demand: then `outline` and `outline_points` stand for it.
  std::shared_ptr<const TrailSet> trails;
  /// With `trails` null: the flights with their extents (begin/end index points that are not there) in a
  /// TrailSet without points, whose overall extents (t_min() .. lon_max()) are those of the full set.
  std::shared_ptr<const TrailSet> outline;
  std::size_t outline_points = 0;  ///< with `trails` null: the number of points

  /// The flights, with their extents: of `trails`, else of `outline`.
  const std::vector<Flight>& flights() const { return shape().flights(); }
  std::size_t num_points() const { return trails ? trails->num_points() : outline_points; }
  /// The set whose flights and overall extents (t_min() .. lon_max()) describe the dataset: `trails`, or
  /// `outline` in a described view. Never read its points (an outline has none).
  const TrailSet& shape() const { return trails ? *trails : *outline; }

  /// The API's Dataset object (id, name, format, flights, points, t_min, t_max, bbox, owner, ...).
  nlohmann::json to_json() const;
};

class DatasetStore {
 public:
  virtual ~DatasetStore() = default;
  /// Every dataset, as describe() answers it.
  virtual std::vector<std::shared_ptr<const Dataset>> list() const = 0;
  /// The dataset with every point (Dataset::trails set). Throws not_found("dataset") when absent.
  virtual std::shared_ptr<const Dataset> get(const std::string& id) const = 0;
  /// The dataset as far as it is known without reading its points: a store that fetches points on demand
  /// (the ClickHouse store) answers with `trails` null and `outline` set, which is enough for to_json()
  /// and for its own DatasetReads (dataset_reads.hpp); any other store answers get(). Routes that read no
  /// point themselves call this. Throws not_found("dataset") when absent.
  virtual std::shared_ptr<const Dataset> describe(const std::string& id) const { return get(id); }
  virtual bool contains(const std::string& id) const = 0;
  /// Stores a dataset whole or not at all. Throws Error(conflict, "name") when the id exists and
  /// invalid_argument("name") when the id is malformed. `progress` (0..1) is told how far the writing is,
  /// when the backend writes over a network (the ClickHouse store); the embedded store does not call it.
  virtual void put(std::shared_ptr<const Dataset> ds, const ProgressFn& progress = {}) = 0;
  /// Throws not_found("dataset") when absent.
  virtual void remove(const std::string& id) = 0;
};

/// Checks a dataset id: 1..64 chars of [a-z0-9_-]; throws invalid_argument(param) otherwise.
void validate_dataset_id(const std::string& id, const std::string& param = "name");

/// Derives a valid id from a free name (lower-cased, other chars → '-', trimmed to 64).
std::string dataset_id_from_name(const std::string& name);

}  // namespace trailscope::server
