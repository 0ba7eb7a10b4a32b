// CUBu trail text (the original CUBu code's GraphDrawing::readTrails): whitespace-separated
// tokens, line breaks (LF or CRLF) insignificant. A token ending in ':' ("12:") starts a polyline, then
// come x y pairs; tokens starting with '(' or '<' (a bundled file's "(7)" and "<0.000000>" annotations)
// are skipped. A label followed by a single number is a header field ("maxv: 1.000000") and, like every
// polyline of fewer than 2 points, counts as skipped. Anything else that is not a finite number, a
// coordinate before the first label, or an x without its y in a longer polyline is an error naming the
// line.
#include <cctype>
#include <string>

#include "bundling/io/graph_parse.hpp"

namespace trailscope::bundling::detail {
namespace {

constexpr const char* kFormat = "trl";

struct Open {
  std::string label;
  std::size_t line = 0;
  std::vector<double> xy;
};

}  // namespace

Graph parse_trl(std::string_view bytes) {
  Graph g;
  g.format = GraphFormat::trl;
  Open cur;
  bool open = false;
  std::vector<double> xs, ys;
  auto close = [&] {
    if (!open) return;
    if (cur.xy.size() % 2 == 1 && cur.xy.size() > 1)
      fail(kFormat, cur.line,
           "polyline " + quote(cur.label) + " has an odd number of coordinates (" +
               std::to_string(cur.xy.size()) + ")");
    const std::size_t n = cur.xy.size() / 2;
    if (n < 2) {
      ++g.skipped;
    } else {
      xs.resize(n), ys.resize(n);
      for (std::size_t k = 0; k < n; ++k) xs[k] = cur.xy[2 * k], ys[k] = cur.xy[2 * k + 1];
      g.edges.add(xs, ys);
      check_limits(g.edges.size(), g.edges.points());
    }
    cur.xy.clear();
  };

  std::size_t line = 1, i = 0;
  while (i < bytes.size()) {
    const char c = bytes[i];
    if (c == '\n') ++line;
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[j]))) ++j;
    const std::string_view token = bytes.substr(i, j - i);
    i = j;
    if (token.back() == ':') {
      close();
      open = true;
      cur.label = std::string(token.substr(0, token.size() - 1));
      cur.line = line;
      continue;
    }
    if (token.front() == '(' || token.front() == '<') continue;
    double v = 0;
    if (!parse_double(token, v)) fail(kFormat, line, quote(token) + " is not a finite number");
    if (!open)
      fail(kFormat, line, "coordinate " + quote(token) + " before the first polyline label (\"0:\")");
    cur.xy.push_back(v);
  }
  close();
  if (g.edges.size() == 0)
    fail(kFormat, 0, "no polyline with at least 2 points (" + std::to_string(g.skipped) + " skipped)");
  g.weight.assign(g.edges.size(), 1.0);
  return g;
}

}  // namespace trailscope::bundling::detail
