#include "routes/handlers.hpp"
#include "params/upload_body.hpp"
#include "store/dataset_ingest.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::server::handlers {

namespace {
/// Longest display name of a graph (characters).
constexpr std::size_t kMaxGraphNameLength = 128;

const std::string kTooLarge =
    "graph upload exceeds the limit of " + std::to_string(limits::kMaxGraphUploadBytes >> 20) + " MiB";

}  // namespace

namespace {
// The query of a graph upload, checked: what the precheck runs on the header and the handler again.
struct GraphUpload {
  std::optional<bundling::GraphFormat> format;
  std::string name;
};
GraphUpload graph_upload(App& app, const Request& req) {
  reject_unknown_params(req, {"format", "name"});
  need(app.graphs, "a graph store");
  GraphUpload u;
  if (auto f = req.query.find("format"); f != req.query.end() && f->second != "auto")
    u.format = bundling::parse_graph_format(f->second, "format");
  if (auto n = req.query.find("name"); n != req.query.end()) {
    if (n->second.empty() || n->second.size() > kMaxGraphNameLength)
      throw invalid_argument("name", "name: 1 to " + std::to_string(kMaxGraphNameLength) + " characters");
    u.name = n->second;
  }
  return u;
}
}  // namespace

void create_graph_check(App& app, const Request& req, const PathParams&) {
  graph_upload(app, req);
}

Response create_graph(App& app, const Request& req, const PathParams&) {
  const auto [format, name] = graph_upload(app, req);
  GraphStore& graphs = *app.graphs;
  StoredGraph g;
  g.name = name;
  const std::string bytes = upload_bytes(req, limits::kMaxGraphUploadBytes, kTooLarge);
  g.bytes = bytes.size();
  // An OD CSV by node name needs its nodes table too: both travel in one JSON object.
  const bool json_body = req.header("content-type").rfind("application/json", 0) == 0;
  const nlohmann::json j = json_body ? nlohmann::json::parse(bytes, nullptr, false) : nlohmann::json();
  if (j.is_object() && j.contains("edges_csv")) {
    for (const auto& [k, v] : j.items())
      if (k != "edges_csv" && k != "nodes_csv")
        throw invalid_argument(k, "unknown field '" + k + "' (an OD upload has edges_csv and nodes_csv)");
    if (!j["edges_csv"].is_string()) throw invalid_argument("edges_csv", "edges_csv: must be CSV text");
    if (j.contains("nodes_csv") && !j["nodes_csv"].is_string())
      throw invalid_argument("nodes_csv", "nodes_csv: must be CSV text");
    if (format && *format != bundling::GraphFormat::od_csv)
      throw invalid_argument("format", "format: an edges_csv/nodes_csv upload is od_csv");
    const auto od = bundling::GraphFormat::od_csv;
    g.graph =
        bundling::parse_graph(j["edges_csv"].get<std::string>(), j.value("nodes_csv", std::string()), &od);
  } else {
    g.graph = bundling::parse_graph(bytes, {}, format ? &*format : nullptr);
  }
  g.created = utc_now_iso();
  g.owner = req.principal.owner;
  const auto stored = graphs.put(std::move(g));
  return Response::json_at(201, stored->to_json(), "/api/v1/graphs/" + stored->id);
}

}  // namespace trailscope::server::handlers
