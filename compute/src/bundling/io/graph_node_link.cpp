// networkx node-link JSON (networkx.readwrite.json_graph.node_link_data): {"nodes": [{"id", "x", "y"}],
// "links": [{"source", "target"[, "weight"|"value"]}]}. networkx writes the node ids in source/target;
// other writers (d3) use indices into "nodes", so an endpoint that is no node's id but an integer in
// range is read as an index.
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "bundling/io/graph_parse.hpp"

namespace trailscope::bundling::detail {
namespace {

constexpr const char* kFormat = "node_link";

/// A node id or link endpoint as text: strings as they are, integers in decimal; "" for anything else.
std::string id_text(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  if (v.is_number_unsigned()) return std::to_string(v.get<unsigned long long>());
  return {};
}

double number(const nlohmann::json& obj, const char* field, const std::string& where) {
  const auto it = obj.find(field);
  if (it == obj.end()) fail(kFormat, 0, where + " has no " + field);
  double v = 0;
  if (it->is_number())
    v = it->get<double>();
  else if (!(it->is_string() && parse_double(it->get<std::string>(), v)))
    fail(kFormat, 0, where + ": " + field + " is not a number");
  if (!std::isfinite(v)) fail(kFormat, 0, where + ": " + field + " is not finite");
  return v;
}

}  // namespace

Graph parse_node_link(std::string_view bytes) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(bytes.begin(), bytes.end());
  } catch (const nlohmann::json::parse_error& e) {
    fail(kFormat, line_of(bytes, e.byte > 0 ? e.byte - 1 : 0), std::string("JSON error: ") + e.what());
  } catch (const nlohmann::json::exception& e) {
    // A number beyond double's range ("1e999") is out_of_range, not a parse_error, and carries no position.
    fail(kFormat, 0, std::string("JSON error: ") + e.what());
  }
  if (!doc.is_object()) fail(kFormat, 0, "the document is not a JSON object");
  const auto nodes = doc.find("nodes");
  if (nodes == doc.end() || !nodes->is_array()) fail(kFormat, 0, "no \"nodes\" array");
  auto links = doc.find("links");
  if (links == doc.end()) links = doc.find("edges");
  if (links == doc.end() || !links->is_array()) fail(kFormat, 0, "no \"links\" (or \"edges\") array");

  GraphBuilder builder(GraphFormat::node_link);
  const std::size_t n = nodes->size();
  std::vector<std::string> ids(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& node = (*nodes)[i];
    const std::string where = "nodes[" + std::to_string(i) + "]";
    if (!node.is_object()) fail(kFormat, 0, where + " is not an object");
    const auto id = node.find("id");
    ids[i] = id == node.end() ? std::to_string(i) : id_text(*id);
    if (ids[i].empty()) fail(kFormat, 0, where + ": id is neither a string nor an integer");
    builder.add_node(ids[i], number(node, "x", where), number(node, "y", where));
  }
  auto endpoint = [&](const nlohmann::json& v) {
    std::string id = id_text(v);
    if (!builder.has_node(id) && v.is_number_integer()) {
      const long long k = v.get<long long>();
      if (k >= 0 && static_cast<std::size_t>(k) < n) id = ids[static_cast<std::size_t>(k)];
    }
    return id;
  };
  for (std::size_t i = 0; i < links->size(); ++i) {
    const auto& link = (*links)[i];
    const std::string where = "links[" + std::to_string(i) + "]";
    if (!link.is_object()) fail(kFormat, 0, where + " is not an object");
    const auto s = link.find("source"), t = link.find("target");
    if (s == link.end() || t == link.end()) fail(kFormat, 0, where + " has no source or target");
    double weight = 1;
    if (link.contains("weight"))
      weight = number(link, "weight", where);
    else if (link.contains("value"))
      weight = number(link, "value", where);
    builder.add_edge(endpoint(*s), endpoint(*t), weight);
  }
  return builder.finish(false, false);
}

}  // namespace trailscope::bundling::detail
