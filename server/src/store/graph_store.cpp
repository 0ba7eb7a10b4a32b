#include "store/graph_store.hpp"

#include <algorithm>
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
  g->owner = m.value("owner", "");
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
          {"bbox", e.points() ? nlohmann::json{x0, y0, x1, y1} : nlohmann::json(nullptr)},
          {"owner", owner}};
}

GraphStore::GraphStore(fs::path root)
    : folders_(std::move(root), {"graph", "graphs", 'g', "manifest.json"},
               manifest_meta(kMagic, kFormatVersion)),
      loaded_(kLoadedGraphs) {}

std::vector<nlohmann::json> GraphStore::list() const {
  return folders_.list();
}

nlohmann::json GraphStore::meta(const std::string& id) const {
  return folders_.meta(id);
}

std::shared_ptr<const StoredGraph> GraphStore::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  folders_.check(id);
  // Read under the lock: a delete cannot move the folder away mid-read.
  return loaded_.get(id, [&] { return read_graph_dir(folders_.dir(id)); });
}

std::shared_ptr<const StoredGraph> GraphStore::put(StoredGraph g) {
  g.id = folders_.next_id();
  if (g.name.empty()) g.name = g.id;
  auto stored = std::make_shared<const StoredGraph>(std::move(g));
  const fs::path tmp = folders_.stage(stored->id);
  try {
    write_graph(*stored, tmp);
    std::lock_guard lock(mu_);
    folders_.publish(stored->id, tmp, stored->to_json());
    loaded_.put(stored->id, stored);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
  return stored;
}

void GraphStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  folders_.remove(id);
  loaded_.erase(id);
}

}  // namespace trailscope::server
