// Comparison of tracker runs on one video: aligned series, ranked disagreements, parameter and result
// differences (analysis/run_compare.hpp).
#include "trailscope/analysis/run_compare.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "trailscope/analysis/run_table.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tracker/run_counts.hpp"

namespace trailscope::analysis {
namespace {

using tracker::FrameLog;
using tracker::TrackerLog;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kTeats = tof::kTeatCount;

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

void check_options(const CompareOptions& o) {
  if (o.top < 1 || o.top > limits::kMaxCompareTop)
    throw invalid_argument("top", "top: must be in [1, " + std::to_string(limits::kMaxCompareTop) +
                                      "], got " + std::to_string(o.top));
  if (!(o.miss_mm > 0) || !std::isfinite(o.miss_mm))
    throw invalid_argument("miss_mm", "miss_mm: must be a finite distance > 0 mm");
  if (!(o.within_mm > 0) || !std::isfinite(o.within_mm))
    throw invalid_argument("within_mm", "within_mm: must be a finite distance > 0 mm");
}

/// The frame-index range every run covers, after checking that the runs are comparable.
std::pair<std::size_t, std::size_t> shared_range(const std::vector<const TrackerLog*>& runs) {
  std::size_t lo = 0, hi = std::numeric_limits<std::size_t>::max();
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const TrackerLog& log = *runs[r];
    if (log.header.video_id != runs[0]->header.video_id)
      throw Error(Error::Kind::unprocessable, "runs",
                  "runs: run " + std::to_string(r + 1) + " is of video '" + log.header.video_id +
                      "', run 1 of '" + runs[0]->header.video_id + "'; only runs of one video compare");
    if (log.frames.empty())
      throw Error(Error::Kind::unprocessable, "runs",
                  "runs: run " + std::to_string(r + 1) + " has no frames");
    // Consecutive frames make frame index → position a subtraction; the tracker writes them so.
    for (std::size_t i = 1; i < log.frames.size(); ++i)
      if (log.frames[i].index != log.frames[0].index + i)
        throw Error(Error::Kind::unprocessable, "runs",
                    "runs: run " + std::to_string(r + 1) + " skips from frame " +
                        std::to_string(log.frames[i - 1].index) + " to " +
                        std::to_string(log.frames[i].index));
    lo = std::max(lo, log.frames.front().index);
    hi = std::min(hi, log.frames.back().index);
  }
  if (lo > hi) throw Error(Error::Kind::unprocessable, "runs", "runs: the runs share no frame");
  if (hi - lo + 1 > limits::kMaxCompareFrames)
    throw Error(Error::Kind::payload_too_large, "runs",
                "runs: " + std::to_string(hi - lo + 1) + " shared frames, at most " +
                    std::to_string(limits::kMaxCompareFrames) + " compare at once");
  return {lo, hi - lo + 1};
}

/// The log restricted to `frames` frames from index `first` (the log itself when that is all of it).
const TrackerLog& restricted(const TrackerLog& log, std::size_t first, std::size_t frames,
                             TrackerLog& storage) {
  const std::size_t begin = first - log.frames.front().index;
  if (begin == 0 && frames == log.frames.size()) return log;
  storage.header = log.header;
  storage.frames.assign(log.frames.begin() + begin, log.frames.begin() + begin + frames);
  storage.header.frame_count = frames;
  if (!log.truth.empty()) storage.truth.assign(log.truth.begin() + begin, log.truth.begin() + begin + frames);
  return storage;
}

RunSeries series_of(const TrackerLog& log, const std::vector<double>& max_error) {
  RunSeries s;
  const std::size_t n = log.frames.size();
  s.state.reserve(n), s.matches.reserve(n), s.verified.reserve(n), s.teats_matched.reserve(n);
  s.model_cost.reserve(n), s.shape_cost.reserve(n);
  for (const FrameLog& f : log.frames) {
    s.state.push_back(static_cast<int>(f.state));
    s.matches.push_back(f.matches);
    s.verified.push_back(f.verified);
    s.teats_matched.push_back(f.model.teats_matched);
    s.model_cost.push_back(f.model.cost);
    s.shape_cost.push_back(f.model.shape_cost);
  }
  if (log.truth.empty()) return s;
  s.max_error_mm = max_error;
  s.teat_error_mm.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int t = 0; t < kTeats; ++t) {
      const auto& truth = log.truth[i];
      const auto& est = log.frames[i].teats[t];
      s.teat_error_mm[i][t] = truth && truth->teats[t].visible && est.visible
                                  ? distance(est.tip_mm, truth->teats[t].tip_mm)
                                  : kNaN;
    }
  return s;
}

std::vector<ValueRow> result_rows(const std::vector<const TrackerLog*>& logs, double within_mm) {
  std::vector<ValueRow> rows;
  for (const RunMetric& m : run_metrics()) rows.push_back({m.name, {}, false});
  for (const TrackerLog* log : logs) {
    const tracker::StateCounts counts = tracker::count_states(log->frames);
    const double total_us = counts.tracker_us;
    const double fps = total_us > 0 ? static_cast<double>(log->frames.size()) / (total_us * 1e-6) : kNaN;
    double median = kNaN, p95 = kNaN, within = kNaN;
    if (!log->truth.empty()) {
      const tracker::Accuracy a = tracker::evaluate_accuracy(*log, within_mm);
      median = a.median_error_mm, p95 = a.p95_error_mm, within = a.frames_all_within;
    }
    const double episodes = static_cast<double>(counts.lost_episodes);
    const double share = static_cast<double>(counts.track) / static_cast<double>(log->frames.size());
    const std::array<double, 6> figures = {share, episodes, fps, median, p95, within};  // run_metrics() order
    for (std::size_t k = 0; k < figures.size(); ++k) rows[k].values.push_back(figures[k]);
  }
  return rows;
}

bool all_equal(const std::vector<double>& v) {
  for (double x : v)
    if (!(x == v.front() || (std::isnan(x) && std::isnan(v.front())))) return false;
  return true;
}

std::vector<ValueRow> param_rows(const std::vector<const TrackerLog*>& logs) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> values;
  for (std::size_t r = 0; r < logs.size(); ++r)
    for (const tracker::NamedValue& p : logs[r]->header.params) {
      auto [it, fresh] = values.try_emplace(p.name, std::vector<double>(logs.size(), kNaN));
      if (fresh) order.push_back(p.name);
      it->second[r] = p.value;
    }
  std::vector<ValueRow> rows;
  for (const std::string& name : order) {
    ValueRow row{name, values[name], false};
    row.differs = !all_equal(row.values);
    rows.push_back(std::move(row));
  }
  std::stable_partition(rows.begin(), rows.end(), [](const ValueRow& r) { return r.differs; });
  return rows;
}

/// Score of one frame (see Disagreement::score_mm) and its worst teat; 0 when every run agrees.
std::pair<double, int> frame_disagreement(const std::vector<const FrameLog*>& frames, double miss_mm) {
  double sum = 0, worst = 0;
  int worst_teat = 0;
  for (int t = 0; t < kTeats; ++t) {
    std::size_t seen = 0;
    double spread = 0;
    for (std::size_t a = 0; a < frames.size(); ++a) {
      if (!frames[a]->teats[t].visible) continue;
      ++seen;
      for (std::size_t b = a + 1; b < frames.size(); ++b)
        if (frames[b]->teats[t].visible)
          spread = std::max(spread, distance(frames[a]->teats[t].tip_mm, frames[b]->teats[t].tip_mm));
    }
    // A miss adds in proportion to the runs that miss, so frames with the same pattern of misses still rank
    // by how far the reporting runs are apart (a run that never tracks would otherwise tie every frame).
    if (seen > 0 && seen < frames.size())
      spread += miss_mm * static_cast<double>(frames.size() - seen) / static_cast<double>(frames.size());
    sum += spread;
    if (spread > worst) worst = spread, worst_teat = t;
  }
  return {sum / kTeats, worst_teat};
}

}  // namespace

Comparison compare_runs(const std::vector<const TrackerLog*>& runs, const CompareOptions& options) {
  if (runs.size() < 2 || runs.size() > limits::kMaxCompareRuns)
    throw invalid_argument("runs", "runs: compare 2 to " + std::to_string(limits::kMaxCompareRuns) +
                                       " runs, got " + std::to_string(runs.size()));
  for (const TrackerLog* r : runs)
    if (r == nullptr) throw invalid_argument("runs", "runs: a null run");
  check_options(options);
  const auto [first, frames] = shared_range(runs);

  Comparison c;
  c.video = runs[0]->header.video_id;
  c.first_frame = first;
  c.frames = frames;
  std::vector<TrackerLog> storage(runs.size());
  std::vector<const TrackerLog*> logs;
  for (std::size_t r = 0; r < runs.size(); ++r)
    logs.push_back(&restricted(*runs[r], first, frames, storage[r]));

  for (const TrackerLog* log : logs) {
    std::vector<double> max_error;
    if (!log->truth.empty())
      max_error = tracker::evaluate_accuracy(*log, options.within_mm).frame_max_error_mm;
    c.series.push_back(series_of(*log, max_error));
  }

  std::vector<const FrameLog*> at(logs.size());
  for (std::size_t i = 0; i < frames; ++i) {
    for (std::size_t r = 0; r < logs.size(); ++r) at[r] = &logs[r]->frames[i];
    const auto [score, worst_teat] = frame_disagreement(at, options.miss_mm);
    if (score <= 0) continue;
    Disagreement d{first + i, score, {}, worst_teat};
    for (const FrameLog* f : at) d.states.push_back(static_cast<int>(f->state));
    c.disagreements.push_back(std::move(d));
  }
  const std::size_t keep = std::min(options.top, c.disagreements.size());
  std::partial_sort(c.disagreements.begin(), c.disagreements.begin() + static_cast<std::ptrdiff_t>(keep),
                    c.disagreements.end(), [](const Disagreement& a, const Disagreement& b) {
                      return a.score_mm != b.score_mm ? a.score_mm > b.score_mm : a.frame < b.frame;
                    });
  c.disagreements.resize(keep);

  c.params = param_rows(logs);
  c.results = result_rows(logs, options.within_mm);
  for (ValueRow& row : c.results) row.differs = !all_equal(row.values);
  return c;
}

namespace {

/// NaN → null, +inf → "Infinity" (a missed teat, as the tracker log's JSON writes it).
nlohmann::json number(double x) {
  if (std::isnan(x)) return nullptr;
  if (std::isinf(x)) return x > 0 ? "Infinity" : "-Infinity";
  return x;
}

nlohmann::json numbers(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(number(x));
  return a;
}

nlohmann::json value_rows(const std::vector<ValueRow>& rows) {
  nlohmann::json a = nlohmann::json::array();
  for (const ValueRow& r : rows)
    a.push_back({{"name", r.name}, {"values", numbers(r.values)}, {"differs", r.differs}});
  return a;
}

}  // namespace

nlohmann::json to_json(const Comparison& c) {
  nlohmann::json state_names = nlohmann::json::array();
  for (auto s : {tracker::State::search, tracker::State::track, tracker::State::lost})
    state_names.push_back(tracker::to_string(s));
  nlohmann::json series = nlohmann::json::array();
  for (const RunSeries& s : c.series) {
    nlohmann::json teat_error = nlohmann::json::array();
    for (const auto& e : s.teat_error_mm)
      teat_error.push_back({number(e[0]), number(e[1]), number(e[2]), number(e[3])});
    series.push_back({{"state", s.state},
                      {"matches", s.matches},
                      {"verified", s.verified},
                      {"teats_matched", s.teats_matched},
                      {"model_cost", numbers(s.model_cost)},
                      {"shape_cost", numbers(s.shape_cost)},
                      {"max_error_mm", numbers(s.max_error_mm)},
                      {"teat_error_mm", std::move(teat_error)}});
  }
  nlohmann::json disagreements = nlohmann::json::array();
  for (const Disagreement& d : c.disagreements)
    disagreements.push_back({{"frame", d.frame},
                             {"score_mm", d.score_mm},
                             {"states", d.states},
                             {"worst_teat", tof::kTeatNames[static_cast<std::size_t>(d.worst_teat)]}});
  return {{"video", c.video},
          {"first_frame", c.first_frame},
          {"frames", c.frames},
          {"state_names", state_names},
          {"teat_names", tof::kTeatNames},
          {"series", std::move(series)},
          {"disagreements", std::move(disagreements)},
          {"params", value_rows(c.params)},
          {"results", value_rows(c.results)}};
}

}  // namespace trailscope::analysis
