// POST /api/v1/compare: stored runs of one video side by side (compute/analysis/run_compare): aligned
// series, the frames where they disagree most, parameter and result differences.
#include "routes/handlers.hpp"
#include "params/json_fields.hpp"
#include "store/run_store.hpp"
#include "trailscope/analysis/run_compare.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"

namespace trailscope::server::handlers {

Response compare_runs(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  need(app.runs, "a run store");
  const nlohmann::json j = parse_body_object(req.body, {"runs", "top", "miss_mm", "within_mm"});
  if (!j.contains("runs") || !j["runs"].is_array())
    throw invalid_argument(
        "runs", "runs: required, an array of 2 to " + std::to_string(limits::kMaxCompareRuns) + " run ids");
  std::vector<std::string> ids;
  for (const auto& id : j["runs"]) {
    if (!id.is_string()) throw invalid_argument("runs", "runs: must be an array of run ids");
    ids.push_back(id.get<std::string>());
  }
  if (ids.size() < 2 || ids.size() > limits::kMaxCompareRuns)
    throw invalid_argument("runs", "runs: compare 2 to " + std::to_string(limits::kMaxCompareRuns) +
                                       " runs, got " + std::to_string(ids.size()));
  analysis::CompareOptions o;
  const std::int64_t top = integer_field(j, "top", static_cast<std::int64_t>(o.top));
  if (top < 1 || top > static_cast<std::int64_t>(limits::kMaxCompareTop))
    throw invalid_argument("top", "top: must be in [1, " + std::to_string(limits::kMaxCompareTop) + "]");
  o.top = static_cast<std::size_t>(top);
  o.miss_mm = number_field(j, "miss_mm", o.miss_mm);
  o.within_mm = number_field(j, "within_mm", o.within_mm);

  std::vector<std::shared_ptr<const tracker::TrackerLog>> logs;
  std::vector<const tracker::TrackerLog*> runs;
  nlohmann::json rows = nlohmann::json::array();
  // The frames compared, from the stored rows (404 "run" first), bounded before any log is read.
  std::uint64_t frames = 0;
  for (const std::string& id : ids) {
    rows.push_back(app.runs->meta(id));  // 404 "run"
    frames += rows.back().at("summary").value("frames", std::uint64_t{0});
  }
  if (frames > limits::kMaxCompareReadFrames)
    throw Error(Error::Kind::payload_too_large, "runs",
                "runs: the " + std::to_string(ids.size()) + " runs hold " + std::to_string(frames) +
                    " frames together, more than one comparison may read: " +
                    std::to_string(limits::kMaxCompareReadFrames) + " (kMaxCompareReadFrames)");
  for (const std::string& id : ids) {
    logs.push_back(app.runs->get(id));
    runs.push_back(logs.back().get());
  }
  nlohmann::json out = analysis::to_json(analysis::compare_runs(runs, o));
  for (std::size_t r = 0; r < ids.size(); ++r) out["series"][r]["id"] = ids[r];
  out["runs"] = std::move(rows);
  return Response::json(200, out);
}

}  // namespace trailscope::server::handlers
