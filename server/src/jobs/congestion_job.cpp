#include "jobs/congestion_job.hpp"

#include <algorithm>
#include <future>
#include <sstream>

#include "limits.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

namespace {
/// Share of the progress bar the counts take when separation follows (the all-pairs search costs about
/// as much as the counts on the Europe day).
constexpr double kCountsShare = 0.5;
}  // namespace

const std::vector<std::string>& congestion_tables() {
  static const std::vector<std::string> tables = {"series", "hotspots", "complexity", "separation"};
  return tables;
}

nlohmann::json CongestionOutput::to_json() const {
  return {{"dataset", dataset},
          {"volumes", volumes},
          {"compute", compute},
          {"counts", counts ? counts->to_json() : nlohmann::json(nullptr)},
          {"separation", separation ? separation->to_json() : nlohmann::json(nullptr)}};
}

std::string CongestionOutput::csv(const std::string& table) const {
  const auto& tables = congestion_tables();
  if (std::find(tables.begin(), tables.end(), table) == tables.end())
    throw invalid_argument("table",
                           "table must be series, hotspots, complexity or separation, got '" + table + "'");
  const auto has = [&](const char* part) {
    return std::find(compute.begin(), compute.end(), part) != compute.end();
  };
  const auto missing = [&](const std::string& what) {
    return invalid_argument("table", "table " + table + ": this result did not compute " + what);
  };
  if (table == "separation") {
    if (!separation) throw missing("separation");
    return separation->to_csv();
  }
  std::ostringstream out;
  if (table == "series") {
    if (!counts || !(has("occupancy") || has("entries"))) throw missing("occupancy or entries");
    counts->write_csv(out);
  } else if (table == "hotspots") {
    if (!counts || !has("hotspots")) throw missing("hotspots");
    counts->write_hotspots_csv(out);
  } else {
    if (!counts || !counts->has_complexity) throw missing("complexity");
    counts->write_complexity_csv(out);
  }
  return out.str();
}

nlohmann::json CongestionOutput::summary() const {
  nlohmann::json j = {{"dataset", dataset}, {"compute", compute}};
  if (!sectors.empty()) j["sectors"] = sectors;
  if (counts) {
    j["flights"] = counts->flights;
    j["volumes"] = counts->volumes.size();
    j["steps"] = counts->steps;
    j["hotspots"] = counts->hotspots_total;
  }
  if (separation) {
    if (!counts) j["flights"] = separation->flights;
    j["separation_events"] = separation->events.size();
  }
  return j;
}

std::shared_ptr<CongestionOutput> run_congestion(const TrailSet& set, const CongestionRequest& r,
                                                 const ProgressFn& progress, const CancelToken* cancel) {
  auto out = std::make_shared<CongestionOutput>();
  out->dataset = r.dataset;
  out->sectors = r.sectors;
  out->volumes = r.volumes;
  out->compute = r.compute();
  // The counts report their stages with fractions of their own; the job's progress is one monotonic
  // bar, counts first, then separation.
  double shown = 0;
  const auto part = [&](double base, double share) -> ProgressFn {
    return [&, base, share](double f, std::string_view stage) {
      shown = std::max(shown, base + share * std::clamp(f, 0.0, 1.0));
      if (progress) progress(shown, stage);
    };
  };
  const double counts_share = !r.runs_counts() ? 0.0 : r.separation ? kCountsShare : 1.0;
  if (r.runs_counts()) {
    congestion::CountsResult c = congestion::count(set, r.counts, part(0, counts_share), cancel);
    // The parts left out of `compute` are left out of the answer too (they cost nothing extra to count,
    // but a client that did not ask for them should not have to download them).
    for (auto& v : c.volumes) {
      if (!r.occupancy) v.occupancy = {};
      if (!r.entries) v.entries = {};
    }
    if (!r.hotspots) c.hotspots.clear(), c.hotspots_total = 0;
    out->counts = std::move(c);
  }
  if (r.separation)
    out->separation = congestion::losses_of_separation(set, r.counts.query, {},
                                                       part(counts_share, 1 - counts_share), cancel);
  if (cancel) cancel->throw_if_cancelled();
  return out;
}

void CongestionResults::put(const std::string& job, std::shared_ptr<const CongestionOutput> out) {
  std::lock_guard lock(mu_);
  if (!results_.count(job)) order_.push_back(job);
  results_[job] = std::move(out);
  while (order_.size() > limits::kMaxCongestionResults) {
    results_.erase(order_.front());
    order_.pop_front();
  }
}

std::shared_ptr<const CongestionOutput> CongestionResults::get(const std::string& job) const {
  std::lock_guard lock(mu_);
  const auto it = results_.find(job);
  return it == results_.end() ? nullptr : it->second;
}

JobState submit_congestion(JobManager& jobs, std::shared_ptr<CongestionResults> results,
                           std::shared_ptr<const Dataset> ds, CongestionRequest r, const std::string& owner) {
  // The job's id is known only once it is queued; the work waits for it (set right below) before it
  // files its result under it.
  auto id = std::make_shared<std::promise<std::string>>();
  std::shared_future<std::string> job_id = id->get_future().share();
  auto request = std::make_shared<const CongestionRequest>(std::move(r));
  const std::string dataset = ds->id;
  const JobState job = jobs.submit(
      "congestion", dataset,
      [results, ds, request, job_id](const ProgressFn& progress, const CancelToken& cancel) {
        const auto out = run_congestion(*ds->trails, *request, progress, &cancel);
        const std::string id = job_id.get();
        results->put(id, out);
        nlohmann::json summary = out->summary();
        summary["congestion"] = "/api/v1/congestion/" + id;
        return summary;
      },
      owner);
  id->set_value(job.id);
  return job;
}

}  // namespace trailscope::server
