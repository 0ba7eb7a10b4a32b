#pragma once
// Uploaded graphs (and trail sets) to bundle, persisted under <root>/graphs/<id>/ like datasets: the
// parsed polylines as column files and a manifest written last, into <root>/tmp/ first and renamed into
// place. The parsed form is stored rather than the upload, so a bundle request never re-parses a file
// and a graph that was accepted once stays readable.
#include <filesystem>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/bundling/graph_io.hpp"

namespace trailscope::server {

struct StoredGraph {
  std::string id;           ///< "g1", "g2", ... (never reused while the store is open)
  std::string name;         ///< display name (?name= of the upload)
  std::string created;      ///< ISO 8601 UTC
  std::uint64_t bytes = 0;  ///< size of the upload
  bundling::Graph graph;

  /// The API's Graph object: id, name, format, created, bytes, edges, points, nodes, skipped, geographic,
  /// y_up, bbox (source units).
  nlohmann::json to_json() const;
};

class GraphStore {
 public:
  /// Opens (creating if needed) <root>/graphs and notes every complete graph (its manifest now, its
  /// polylines on first get()). A folder that fails to load is reported on stderr and skipped.
  explicit GraphStore(std::filesystem::path root);

  /// Metadata of every graph (StoredGraph::to_json), oldest first: listing reads no geometry.
  std::vector<nlohmann::json> list() const;
  /// Throws not_found("graph").
  nlohmann::json meta(const std::string& id) const;
  /// The whole graph, read from disk when not loaded. Throws not_found("graph").
  std::shared_ptr<const StoredGraph> get(const std::string& id) const;
  /// Gives `g` the next id (and its name when it has none), writes it whole or not at all, and returns
  /// the stored graph.
  std::shared_ptr<const StoredGraph> put(StoredGraph g);
  /// Throws not_found("graph").
  void remove(const std::string& id);

 private:
  void touch_locked(const std::string& id, std::shared_ptr<const StoredGraph> g) const;

  std::filesystem::path root_;
  mutable std::mutex mu_;
  std::map<std::uint64_t, std::string> ids_;  ///< number → id, oldest first
  std::map<std::string, nlohmann::json> meta_;
  /// The loaded graphs, most recently used first (a few: an upload may hold millions of edges).
  mutable std::list<std::pair<std::string, std::shared_ptr<const StoredGraph>>> loaded_;
  std::uint64_t next_ = 1;
};

/// The number of a store id ("g12" → 12; 0 when it is not the prefix followed by digits).
std::uint64_t store_id_number(const std::string& id, char prefix);
/// The store id of a number ('g', 12 → "g12").
std::string store_id(char prefix, std::uint64_t n);

}  // namespace trailscope::server
