#include "store/graph_store.hpp"

#include <algorithm>
#include <iostream>
#include <list>
#include <limits>

#include "store/column_io.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
constexpr char kMagic[] = "TRAILSCOPE-GRAPH-1";
constexpr int kFormatVersion = 1;
/// Graphs whose polylines stay in memory after use (an upload can hold millions of edges).
constexpr std::size_t kLoadedGraphs = 4;

void write_graph(const StoredGraph& g, const fs::path& dir) {
  write_column(dir, "x", g.graph.edges.x);
  write_column(dir, "y", g.graph.edges.y);
  write_column(dir, "offsets", g.graph.edges.offsets);
  write_column(dir, "weight", g.graph.weight);
  nlohmann::json m = g.to_json();
  m["magic"] = kMagic, m["version"] = kFormatVersion;
  write_manifest(dir, m);
}

std::shared_ptr<StoredGraph> read_graph_dir(const fs::path& dir) {
  const nlohmann::json m = read_manifest(dir);
  if (m.value("magic", "") != kMagic || m.value("version", 0) != kFormatVersion)
    throw io_error(dir, "recognise the format of");
  auto g = std::make_shared<StoredGraph>();
  g->id = m.at("id").get<std::string>();
  g->name = m.value("name", g->id);
  g->created = m.value("created", "");
  g->bytes = m.value("bytes", std::uint64_t{0});
  bundling::Graph& gr = g->graph;
  const std::size_t n = m.at("edges").get<std::size_t>(), pts = m.at("points").get<std::size_t>();
  read_column(dir, "x", gr.edges.x, pts);
  read_column(dir, "y", gr.edges.y, pts);
  read_column(dir, "offsets", gr.edges.offsets, n + 1);
  read_column(dir, "weight", gr.weight, n);
  if (gr.edges.offsets.front() != 0 || gr.edges.offsets.back() != pts ||
      !std::is_sorted(gr.edges.offsets.begin(), gr.edges.offsets.end()))
    throw io_error(dir, "validate the offsets of");
  gr.format = bundling::parse_graph_format(m.at("format").get<std::string>());
  gr.nodes = m.value("nodes", std::size_t{0});
  gr.skipped = m.value("skipped", std::size_t{0});
  gr.geographic = m.value("geographic", false);
  gr.y_up = m.value("y_up", false);
  return g;
}
}  // namespace

std::uint64_t store_id_number(const std::string& id, char prefix) {
  if (id.size() < 2 || id.size() > 20 || id[0] != prefix) return 0;
  std::uint64_t n = 0;
  for (std::size_t i = 1; i < id.size(); ++i) {
    if (id[i] < '0' || id[i] > '9') return 0;
    n = n * 10 + static_cast<std::uint64_t>(id[i] - '0');
  }
  return n;
}

std::string store_id(char prefix, std::uint64_t n) {
  std::string id(1, prefix);
  id += std::to_string(n);  // appended, not `prefix + to_string(n)`: GCC 12 warns falsely on that form
  return id;
}

nlohmann::json StoredGraph::to_json() const {
  const auto& e = graph.edges;
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (std::size_t i = 0; i < e.points(); ++i) {
    x0 = std::min(x0, e.x[i]), x1 = std::max(x1, e.x[i]);
    y0 = std::min(y0, e.y[i]), y1 = std::max(y1, e.y[i]);
  }
  return {{"id", id},
          {"name", name},
          {"created", created},
          {"bytes", bytes},
          {"format", bundling::to_string(graph.format)},
          {"edges", e.size()},
          {"points", e.points()},
          {"nodes", graph.nodes},
          {"skipped", graph.skipped},
          {"geographic", graph.geographic},
          {"y_up", graph.y_up},
          {"units", graph.geographic ? "epsg3857" : "source"},
          {"bbox", e.points() ? nlohmann::json{x0, y0, x1, y1} : nlohmann::json(nullptr)}};
}

GraphStore::GraphStore(fs::path root) : root_(std::move(root)) {
  std::error_code ec;
  for (const char* sub : {"graphs", "tmp"}) {
    fs::create_directories(root_ / sub, ec);
    if (ec) throw io_error(root_ / sub, "create");
  }
  for (const auto& e : fs::directory_iterator(root_ / "tmp"))
    if (e.path().filename().string().rfind("graph.", 0) == 0) fs::remove_all(e.path(), ec);
  for (const auto& e : fs::directory_iterator(root_ / "graphs")) {
    const std::string id = e.path().filename().string();
    const std::uint64_t n = store_id_number(id, 'g');
    if (!e.is_directory() || n == 0 || !fs::exists(e.path() / "manifest.json", ec)) continue;
    try {
      nlohmann::json m = read_manifest(e.path());
      if (m.value("magic", "") != kMagic || m.value("version", 0) != kFormatVersion)
        throw io_error(e.path(), "recognise the format of");
      m.erase("magic"), m.erase("version");
      meta_[id] = std::move(m);
      ids_[n] = id;
      next_ = std::max(next_, n + 1);
    } catch (const std::exception& ex) {
      // Unreadable on disk: reported and skipped for this run, never deleted (as datasets).
      std::cerr << "store: skipping graph '" << id << "': " << ex.what() << "\n";
    }
  }
}

void GraphStore::touch_locked(const std::string& id, std::shared_ptr<const StoredGraph> g) const {
  loaded_.remove_if([&](const auto& e) { return e.first == id; });
  loaded_.emplace_front(id, std::move(g));
  while (loaded_.size() > kLoadedGraphs) loaded_.pop_back();
}

std::vector<nlohmann::json> GraphStore::list() const {
  std::lock_guard lock(mu_);
  std::vector<nlohmann::json> out;
  for (const auto& [n, id] : ids_) out.push_back(meta_.at(id));
  return out;
}

nlohmann::json GraphStore::meta(const std::string& id) const {
  std::lock_guard lock(mu_);
  auto it = meta_.find(id);
  if (it == meta_.end()) throw not_found("graph", "graph '" + id + "' does not exist");
  return it->second;
}

std::shared_ptr<const StoredGraph> GraphStore::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("graph", "graph '" + id + "' does not exist");
  for (const auto& [lid, g] : loaded_)
    if (lid == id) {
      auto found = g;
      touch_locked(id, found);
      return found;
    }
  // Read under the lock: a delete cannot move the folder away mid-read.
  std::shared_ptr<const StoredGraph> g = read_graph_dir(root_ / "graphs" / id);
  touch_locked(id, g);
  return g;
}

std::shared_ptr<const StoredGraph> GraphStore::put(StoredGraph g) {
  std::uint64_t n = 0;
  {
    std::lock_guard lock(mu_);
    n = next_++;
  }
  g.id = store_id('g', n);
  if (g.name.empty()) g.name = g.id;
  auto stored = std::make_shared<const StoredGraph>(std::move(g));
  const fs::path tmp = root_ / "tmp" / ("graph." + stored->id + "." + random_suffix());
  std::error_code ec;
  fs::create_directories(tmp, ec);
  if (ec) throw io_error(tmp, "create");
  try {
    write_graph(*stored, tmp);
    const fs::path final_dir = root_ / "graphs" / stored->id;
    // rename(2) of a folder is atomic: after a crash the graph is there whole or not at all.
    fs::rename(tmp, final_dir, ec);
    if (ec) throw io_error(final_dir, "rename into");
    fsync_path(root_ / "graphs");
    std::lock_guard lock(mu_);
    ids_[n] = stored->id;
    meta_[stored->id] = stored->to_json();
    touch_locked(stored->id, stored);
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  return stored;
}

void GraphStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("graph", "graph '" + id + "' does not exist");
  // Out of graphs/ first (atomic), then deleted: a crash mid-delete leaves only tmp/.
  const fs::path gone = root_ / "tmp" / ("graph." + id + ".deleted." + random_suffix());
  std::error_code ec;
  fs::rename(root_ / "graphs" / id, gone, ec);
  if (ec) throw io_error(root_ / "graphs" / id, "remove");
  ids_.erase(store_id_number(id, 'g'));
  meta_.erase(id);
  loaded_.remove_if([&](const auto& e) { return e.first == id; });
  fs::remove_all(gone, ec);
}

}  // namespace trailscope::server
