#include "routes/bundle_body.hpp"

#include <algorithm>
#include <cmath>

#include "routes/params.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/query.hpp"

namespace trailscope::server {

namespace {
/// A JSON scalar as the text BundleParams::set and parse_query read ("32", "0.5", "true", "hourglass").
std::string scalar_text(const nlohmann::json& v, const std::string& name) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) {
    // dump() prints 32.0 for a whole float; the parameter parsers take either, but 32 reads better.
    const double d = v.get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 1e15) return std::to_string(std::int64_t(d));
    return v.dump();
  }
  throw invalid_argument(name, name + ": must be a string, a number or a boolean");
}

void reject_unknown_fields(const nlohmann::json& obj, std::initializer_list<const char*> allowed,
                           const std::string& where) {
  for (const auto& [k, v] : obj.items())
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return k == a; }))
      throw invalid_argument(k, "unknown field '" + k + "' in " + where);
}
}  // namespace

BundleRequest parse_bundle_request(const std::string& body) {
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw invalid_argument("body", "body: a JSON object {\"source\": ..., \"params\": ...} is required");
  reject_unknown_fields(j, {"source", "params", "backend"}, "the body");
  BundleRequest r;
  const auto src = j.find("source");
  if (src == j.end() || !src->is_object())
    throw invalid_argument(
        "source", "source: an object {\"dataset\": ..., \"query\": ...} or {\"graph\": ...} is required");
  reject_unknown_fields(*src, {"dataset", "query", "max_gap", "graph"}, "source");
  const bool has_dataset = src->contains("dataset"), has_graph = src->contains("graph");
  if (has_dataset == has_graph)
    throw invalid_argument("source", "source: give either \"dataset\" or \"graph\", not both or neither");
  if (has_graph) {
    if (!src->at("graph").is_string() || src->at("graph").get<std::string>().empty())
      throw invalid_argument("graph", "graph: must be a graph id (a string)");
    if (src->contains("query") || src->contains("max_gap"))
      throw invalid_argument("source", "source: query and max_gap apply to a dataset, not to a graph");
    r.graph = src->at("graph").get<std::string>();
  } else {
    if (!src->at("dataset").is_string() || src->at("dataset").get<std::string>().empty())
      throw invalid_argument("dataset", "dataset: must be a dataset id (a string)");
    r.dataset = src->at("dataset").get<std::string>();
    if (const auto q = src->find("query"); q != src->end()) {
      if (!q->is_object()) throw invalid_argument("query", "query: must be an object of window filters");
      const auto& keys = params::query_keys();
      for (const auto& [k, v] : q->items()) {
        if (std::find(keys.begin(), keys.end(), k) == keys.end())
          throw invalid_argument(k, "unknown query parameter '" + k + "'");
        r.query[k] = scalar_text(v, k);
      }
      parse_query(r.query);  // fail now, naming the filter, not in the job
    }
    if (const auto g = src->find("max_gap"); g != src->end() && !g->is_null()) {
      if (!g->is_number() || !(g->get<double>() > 0))
        throw invalid_argument("max_gap", "max_gap: must be a positive number of seconds");
      r.max_gap = g->get<double>();
    }
  }
  if (const auto p = j.find("params"); p != j.end()) {
    if (!p->is_object()) throw invalid_argument("params", "params: must be an object of bundling parameters");
    for (const auto& [k, v] : p->items()) r.params.set(k, scalar_text(v, k));
    r.params.validate();
  }
  if (const auto b = j.find("backend"); b != j.end()) {
    if (!b->is_string()) throw invalid_argument("backend", "backend: must be cpu, opencl or auto");
    r.backend = parse_backend(b->get<std::string>(), "backend");
  }
  return r;
}

}  // namespace trailscope::server
