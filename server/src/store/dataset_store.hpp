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
  std::shared_ptr<const TrailSet> trails;

  /// The API's Dataset object (id, name, format, flights, points, t_min, t_max, bbox, owner, ...).
  nlohmann::json to_json() const;
};

class DatasetStore {
 public:
  virtual ~DatasetStore() = default;
  virtual std::vector<std::shared_ptr<const Dataset>> list() const = 0;
  /// Throws not_found("dataset") when absent.
  virtual std::shared_ptr<const Dataset> get(const std::string& id) const = 0;
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
