#pragma once
// Uploaded graphs (and trail sets) to bundle, persisted under <root>/graphs/<id>/ (a FolderStore,
// folder_store.hpp): the parsed polylines as column files and a manifest written last. The parsed form is
// stored rather than the upload, so a bundle request never re-parses a file and a graph that was accepted
// once stays readable.
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/folder_store.hpp"
#include "trailscope/bundling/graph_io.hpp"

namespace trailscope::server {

struct StoredGraph {
  std::string id;           ///< "g1", "g2", ... (never reused while the store is open)
  std::string name;         ///< display name (?name= of the upload)
  std::string created;      ///< ISO 8601 UTC
  std::uint64_t bytes = 0;  ///< size of the upload
  std::string owner;        ///< the owner name of its creator ("" for graphs made before owners)
  bundling::Graph graph;

  /// The API's Graph object: id, name, format, created, bytes, edges, points, nodes, skipped, geographic,
  /// y_up, bbox (source units), owner.
  nlohmann::json to_json() const;
};

class GraphStore {
 public:
  static constexpr const char* kNoun = "graph";  ///< in messages
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
  FolderStore folders_;
  mutable std::mutex mu_;  ///< guards loaded_ and reads of graph folders (a delete cannot move one mid-read)
  /// The loaded graphs (a few: an upload may hold millions of edges).
  mutable RecentItems<StoredGraph> loaded_;
};

}  // namespace trailscope::server
