// MOTChallenge text files (ground truth, tracker results, 3D points) and TrackEval-exact metrics of one
// stored result against one stored ground truth.
#include "routes/handlers.hpp"
#include "params/json_fields.hpp"
#include "params/upload_body.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"
#include "trailscope/metrics/evaluate.hpp"

namespace trailscope::server::handlers {

namespace {
const std::string kTooLarge =
    "MOT file upload exceeds the limit of " + std::to_string(limits::kMaxRunBytes >> 20) + " MiB";

/// The stored file named by body field `field`, which must be of one of `kinds` for the similarity.
std::string mot_text(MotStore& store, const nlohmann::json& body, const std::string& field,
                     const std::string& kind, const std::string& similarity) {
  const std::string id = string_field(body, field);
  const nlohmann::json row = store.meta(id, field);
  if (row.at("kind") != kind)
    throw invalid_argument(field, field + ": MOT file '" + id + "' is of kind " +
                                      row.at("kind").get<std::string>() + ", similarity " + similarity +
                                      " needs kind " + kind);
  return store.text(id, field);
}
}  // namespace

// The query of a MOT upload (kind required): checked on the header and again by the handler.
void create_mot_check(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {"kind", "name"});
  need(app.mot, "a MOT store");
  const auto k = req.query.find("kind");
  if (k == req.query.end()) throw invalid_argument("kind", "kind: required (gt, result or points)");
  if (k->second != "gt" && k->second != "result" && k->second != "points")
    throw invalid_argument("kind", "kind must be gt, result or points, got '" + k->second + "'");
}

Response create_mot(App& app, const Request& req, const PathParams& p) {
  create_mot_check(app, req, p);
  MotStore& store = *app.mot;
  const auto k = req.query.find("kind");
  const auto n = req.query.find("name");
  const nlohmann::json row =
      store.put(n == req.query.end() ? "" : n->second, k->second,
                upload_bytes(req, limits::kMaxRunBytes, kTooLarge), req.principal.owner);
  return Response::json_at(201, row, "/api/v1/mot/" + row.at("id").get<std::string>());
}

Response compute_metrics(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  const nlohmann::json j =
      parse_body_object(req.body, {"gt", "run", "similarity", "d_max", "frames", "per_frame"});
  metrics::MetricsOptions options;
  const std::string similarity = j.contains("similarity") ? string_field(j, "similarity") : "iou";
  if (similarity == "iou")
    options.kind = metrics::SimilarityKind::iou;
  else if (similarity == "distance")
    options.kind = metrics::SimilarityKind::distance;
  else
    throw invalid_argument("similarity", "similarity must be iou or distance, got '" + similarity + "'");
  options.d_max = number_field(j, "d_max", options.d_max);
  options.frames = integer_field(j, "frames", options.frames);
  const bool per_frame = bool_field(j, "per_frame", false);
  MotStore& store = need(app.mot, "a MOT store");
  // The rows evaluated, from the stored rows (404 first), bounded before any text is read or parsed.
  const std::uint64_t rows = store.meta(string_field(j, "gt"), "gt").value("rows", std::uint64_t{0}) +
                             store.meta(string_field(j, "run"), "run").value("rows", std::uint64_t{0});
  if (rows > limits::kMaxMetricsRows)
    throw Error(Error::Kind::payload_too_large, "run",
                "gt and run hold " + std::to_string(rows) +
                    " rows together, more than one evaluation may read: " +
                    std::to_string(limits::kMaxMetricsRows) + " (kMaxMetricsRows)");
  const bool iou = options.kind == metrics::SimilarityKind::iou;
  const std::string gt = mot_text(store, j, "gt", iou ? "gt" : "points", similarity);
  const std::string run = mot_text(store, j, "run", iou ? "result" : "points", similarity);
  return Response::json(200, metrics::to_json(metrics::evaluate_text(gt, run, options), per_frame));
}

}  // namespace trailscope::server::handlers
