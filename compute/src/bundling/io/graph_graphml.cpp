// GraphML (graphml.graphdrawing.org) with node coordinates in <data> elements. A <data key="…"> refers to
// a <key id="…">; the key's attr.name says what it holds ("x", "y", "value", "weight"), so files whose
// key ids are "d0", "d1" read the same as the FDEB files whose ids equal the names. Nodes of nested
// graphs, ports and hyperedges are not used.
#include <pugixml.hpp>

#include <map>
#include <string>

#include "bundling/io/graph_parse.hpp"

namespace trailscope::bundling::detail {
namespace {

constexpr const char* kFormat = "graphml";

/// Key id → attr.name for one domain ("node" / "edge"; keys for "all" serve both). A key without
/// attr.name is known by its id.
std::map<std::string, std::string> key_names(const pugi::xml_node& root, const char* domain) {
  std::map<std::string, std::string> names;
  for (pugi::xml_node key : root.children("key")) {
    const std::string for_ = key.attribute("for").as_string("all");
    if (for_ != domain && for_ != "all") continue;
    const std::string id = key.attribute("id").as_string();
    const std::string name = key.attribute("attr.name").as_string(id.c_str());
    names[id] = name;
  }
  return names;
}

/// The text of the <data> child of `el` whose key is called `name`, or nullptr.
const char* data_named(const pugi::xml_node& el, const std::map<std::string, std::string>& keys,
                       const std::string& name) {
  for (pugi::xml_node d : el.children("data")) {
    const std::string key = d.attribute("key").as_string();
    const auto it = keys.find(key);
    if ((it != keys.end() ? it->second : key) == name) return d.child_value();
  }
  return nullptr;
}

}  // namespace

Graph parse_graphml(std::string_view bytes) {
  pugi::xml_document doc;
  const pugi::xml_parse_result ok = doc.load_buffer(bytes.data(), bytes.size(), pugi::parse_default);
  if (!ok)
    fail(kFormat, line_of(bytes, static_cast<std::size_t>(ok.offset)),
         std::string("XML error: ") + ok.description());
  const pugi::xml_node root = doc.child("graphml");
  if (!root) fail(kFormat, 0, "no <graphml> root element");
  const pugi::xml_node graph = root.child("graph");
  if (!graph) fail(kFormat, 0, "no <graph> element");
  const auto node_keys = key_names(root, "node");
  const auto edge_keys = key_names(root, "edge");
  auto line = [&](const pugi::xml_node& n) {
    return line_of(bytes, static_cast<std::size_t>(n.offset_debug()));
  };

  GraphBuilder builder(GraphFormat::graphml);
  for (pugi::xml_node node : graph.children("node")) {
    const std::string id = node.attribute("id").as_string();
    if (id.empty()) fail(kFormat, line(node), "<node> without an id");
    double xy[2];
    for (int axis = 0; axis < 2; ++axis) {
      const char* name = axis == 0 ? "x" : "y";
      const char* text = data_named(node, node_keys, name);
      if (!text)
        fail(kFormat, line(node),
             "node " + quote(id) + " has no " + name + " (no <data> for a key with attr.name=\"" + name +
                 "\")");
      if (!parse_double(text, xy[axis]))
        fail(kFormat, line(node),
             "node " + quote(id) + ": " + name + " " + quote(text) + " is not a finite number");
    }
    builder.add_node(id, xy[0], xy[1]);
  }
  for (pugi::xml_node edge : graph.children("edge")) {
    const std::string source = edge.attribute("source").as_string();
    const std::string target = edge.attribute("target").as_string();
    if (source.empty() || target.empty()) fail(kFormat, line(edge), "<edge> without source or target");
    double weight = 1;
    for (const char* name : {"weight", "value"}) {
      if (const char* text = data_named(edge, edge_keys, name)) {
        if (!parse_double(text, weight))
          fail(kFormat, line(edge),
               std::string("edge ") + name + " " + quote(text) + " is not a finite number");
        break;
      }
    }
    builder.add_edge(source, target, weight);
  }
  return builder.finish(false, false);
}

}  // namespace trailscope::bundling::detail
