#include "params/bundle_body.hpp"

#include <algorithm>

#include "params/json_fields.hpp"
#include "params/query_params.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/query.hpp"

namespace trailscope::server {

BundleRequest parse_bundle_request(const std::string& body) {
  const nlohmann::json j =
      parse_json_object(body, "body: a JSON object {\"source\": ..., \"params\": ...} is required");
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
