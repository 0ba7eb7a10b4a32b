// Graph input: format names and detection, the shared builder, reading files, and .trl output. The
// readers of each format are in graph_graphml.cpp, graph_node_link.cpp, graph_od_csv.cpp, graph_trl.cpp.
#include "trailscope/bundling/graph_io.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <utility>

#include "bundling/io/graph_parse.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::bundling {
namespace detail {

void fail(const char* format, std::size_t line, const std::string& what, const std::string& param) {
  std::string msg = format;
  if (line > 0) msg += " line " + std::to_string(line);
  throw Error(Error::Kind::unprocessable, param, msg + ": " + what);
}

std::size_t line_of(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
}

std::string quote(std::string_view s, std::size_t max) {
  std::string out = "'";
  for (std::size_t i = 0; i < s.size() && i < max; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    out += (c < 32 || c >= 127) ? '?' : static_cast<char>(c);  // messages end up in JSON: ASCII only
  }
  if (s.size() > max) out += "...";
  return out + "'";
}

bool parse_double(std::string_view s, double& out) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars refuses a leading '+'
  if (s.empty()) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && std::isfinite(out);
}

void check_limits(std::size_t edges, std::size_t points) {
  if (edges > limits::kMaxBundleEdges)
    throw Error(Error::Kind::payload_too_large, "input",
                "the input has more than " + std::to_string(limits::kMaxBundleEdges) +
                    " edges/trails (limits::kMaxBundleEdges)");
  if (points > limits::kMaxBundleInputPoints)
    throw Error(Error::Kind::payload_too_large, "input",
                "the input has more than " + std::to_string(limits::kMaxBundleInputPoints) +
                    " points (limits::kMaxBundleInputPoints)");
}

void GraphBuilder::add_edge(const std::string& source, const std::string& target, double weight) {
  const auto a = pos_.find(source), b = pos_.find(target);
  if (a == pos_.end() || b == pos_.end()) return skip();
  add_edge(a->second.x, a->second.y, b->second.x, b->second.y, weight);
}

void GraphBuilder::add_edge(double x0, double y0, double x1, double y1, double weight) {
  // A self-loop, or an edge between two records of one position (migrations.xml repeats nodes per
  // position), has no direction and no length to bundle.
  if (x0 == x1 && y0 == y1) return skip();
  graph_.edges.add_edge(x0, y0, x1, y1);
  graph_.weight.push_back(weight);
  check_limits(graph_.edges.size(), graph_.edges.points());
}

Graph GraphBuilder::finish(bool geographic, bool y_up) {
  if (graph_.edges.size() == 0)
    fail(to_string(graph_.format), 0,
         "no edge remains (" + std::to_string(graph_.skipped) + " skipped: self-loops or unknown nodes)");
  std::vector<std::pair<double, double>> ends;
  ends.reserve(graph_.edges.points());
  for (std::size_t i = 0; i < graph_.edges.points(); ++i)
    ends.emplace_back(graph_.edges.x[i], graph_.edges.y[i]);
  std::sort(ends.begin(), ends.end());
  graph_.nodes = static_cast<std::size_t>(std::unique(ends.begin(), ends.end()) - ends.begin());
  graph_.geographic = geographic;
  graph_.y_up = y_up;
  return std::move(graph_);
}

}  // namespace detail

GraphFormat parse_graph_format(std::string_view text, const std::string& param) {
  if (text == "graphml") return GraphFormat::graphml;
  if (text == "node_link") return GraphFormat::node_link;
  if (text == "od_csv") return GraphFormat::od_csv;
  if (text == "trl") return GraphFormat::trl;
  throw invalid_argument(
      param, param + " " + detail::quote(text) + " is not a graph format (graphml, node_link, od_csv, trl)");
}

const char* to_string(GraphFormat f) noexcept {
  switch (f) {
    case GraphFormat::graphml:
      return "graphml";
    case GraphFormat::node_link:
      return "node_link";
    case GraphFormat::od_csv:
      return "od_csv";
    case GraphFormat::trl:
      return "trl";
  }
  return "?";
}

namespace {

std::string_view skip_bom_and_space(std::string_view s) {
  if (s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

GraphFormat detect_graph_format(std::string_view bytes) {
  const std::string_view s = skip_bom_and_space(bytes);
  auto unsupported = [] {
    return Error(Error::Kind::unsupported_format, "input",
                 "the input is not a graph or trail file: expected GraphML, node-link JSON, an "
                 "origin-destination CSV or CUBu trail text (.trl)");
  };
  if (s.empty()) throw unsupported();
  if (s.front() == '<') {
    // An XML prolog and comments may come first; the root element is within the first few KiB.
    if (lower(s.substr(0, 65536)).find("<graphml") != std::string::npos) return GraphFormat::graphml;
    throw unsupported();
  }
  if (s.front() == '{') return GraphFormat::node_link;
  const std::size_t token_end = s.find_first_of(" \t\r\n");
  const std::string_view token = s.substr(0, token_end);
  if (token.size() > 1 && token.back() == ':') return GraphFormat::trl;
  // A CSV header names its columns: accept it when it has a comma and a column this reader knows.
  std::string_view line = s.substr(0, s.find('\n'));
  if (line.find(',') != std::string_view::npos) {
    const std::string head = lower(line);
    for (const char* known : {"x1", "origin", "source", "from", "lon1", "src_lon"})
      if (head.find(known) != std::string::npos) return GraphFormat::od_csv;
  }
  throw unsupported();
}

Graph parse_graph(std::string_view bytes, std::string_view nodes_csv, const GraphFormat* format) {
  const GraphFormat f = format ? *format : detect_graph_format(bytes);
  switch (f) {
    case GraphFormat::graphml:
      return detail::parse_graphml(bytes);
    case GraphFormat::node_link:
      return detail::parse_node_link(bytes);
    case GraphFormat::od_csv:
      return detail::parse_od_csv(bytes, nodes_csv);
    case GraphFormat::trl:
      return detail::parse_trl(bytes);
  }
  throw Error(Error::Kind::internal, "format", "unknown graph format");
}

namespace {

std::string read_all(const std::filesystem::path& path, const std::string& param) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  if (!in || std::filesystem::is_directory(path, ec))
    throw not_found(param, "cannot read " + param + " file " + path.string());
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > limits::kMaxGraphUploadBytes)
    throw Error(Error::Kind::payload_too_large, param,
                path.string() + " is larger than " + std::to_string(limits::kMaxGraphUploadBytes) +
                    " bytes (limits::kMaxGraphUploadBytes)");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

Graph read_graph(const std::filesystem::path& path, const std::filesystem::path& nodes_path,
                 const GraphFormat* format) {
  const std::string bytes = read_all(path, "input");
  const std::string nodes = nodes_path.empty() ? std::string() : read_all(nodes_path, "nodes");
  return parse_graph(bytes, nodes, format);
}

std::string write_trl(const Polylines& lines) {
  std::string out;
  out.reserve(lines.points() * 24 + lines.size() * 8);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    out += std::to_string(i);
    out += ':';
    for (std::size_t k = lines.begin(i); k < lines.end(i); ++k) {
      // Shortest round-trip text: parsing it back gives the same doubles.
      for (double v : {lines.x[k], lines.y[k]}) {
        out += ' ';
        append_shortest(out, v);
      }
    }
    out += '\n';
  }
  return out;
}

}  // namespace trailscope::bundling
