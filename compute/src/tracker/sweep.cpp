#include "trailscope/tracker/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/rng.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::tracker {
namespace {

const ParamInfo& info_of(const std::string& name) {
  for (const auto& i : parameter_infos())
    if (i.name == name) return i;
  throw invalid_argument("axes", "unknown tracker parameter '" + name + "' in axes");
}

// splitmix64 (core/rng.hpp), as everywhere a seeded stream must give the same points on every machine.
using Rng = rng::SplitMix64;

bool valid(const TrackerParams& p) {
  try {
    validate(p);
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

std::vector<TrackerParams> sweep_points(const SweepSpec& spec) {
  if (spec.axes.empty()) throw invalid_argument("axes", "a sweep needs at least one axis");
  std::set<std::string> seen;
  for (const auto& a : spec.axes) {
    const ParamInfo& in = info_of(a.param);
    if (!seen.insert(a.param).second)
      throw invalid_argument("axes", "parameter '" + a.param + "' appears twice in axes");
    if (!(a.min <= a.max) || a.min < in.min || a.max > in.max)
      throw invalid_argument("axes", "axis " + a.param + " must lie within [" + format_double(in.min) + ", " +
                                         format_double(in.max) + "] with min <= max, got [" +
                                         format_double(a.min) + ", " + format_double(a.max) + "]");
    if (spec.mode == SweepMode::grid && (a.steps < 2 || a.steps > 100))
      throw invalid_argument("axes",
                             "axis " + a.param + " needs 2..100 steps, got " + std::to_string(a.steps));
  }
  validate(spec.base);
  const auto set = [](TrackerParams& p, const SweepAxis& a, double v) {
    if (info_of(a.param).integer) v = std::round(v);
    set_param(p, a.param, std::clamp(v, a.min, a.max));
  };
  std::vector<TrackerParams> out;
  if (spec.mode == SweepMode::grid) {
    double total = 1;
    for (const auto& a : spec.axes) total *= a.steps;
    if (total > double(limits::kMaxSweepRuns))
      throw Error(Error::Kind::payload_too_large, "axes",
                  "the grid has " + format_double(total) + " points, at most " +
                      std::to_string(limits::kMaxSweepRuns));
    std::vector<int> at(spec.axes.size(), 0);
    std::set<std::vector<double>> kept;
    for (std::size_t n = 0; n < static_cast<std::size_t>(total); ++n) {
      TrackerParams p = spec.base;
      for (std::size_t k = 0; k < spec.axes.size(); ++k) {
        const auto& a = spec.axes[k];
        set(p, a, a.min + (a.max - a.min) * at[k] / (a.steps - 1));
      }
      if (!valid(p))
        throw Error(Error::Kind::unprocessable, "axes",
                    "a grid point breaks a parameter constraint (e.g. r_min_mm < r_max_mm)");
      if (kept.insert(to_vector(p)).second) out.push_back(p);
      for (std::size_t k = spec.axes.size(); k-- > 0;) {  // odometer: the last axis varies fastest
        if (++at[k] < spec.axes[k].steps) break;
        at[k] = 0;
      }
    }
    return out;
  }
  if (spec.samples < 1 || spec.samples > limits::kMaxSweepRuns)
    throw invalid_argument("samples", "samples must be in [1, " + std::to_string(limits::kMaxSweepRuns) +
                                          "], got " + std::to_string(spec.samples));
  Rng rng{spec.seed};
  for (std::size_t n = 0; n < spec.samples; ++n) {
    TrackerParams p;
    int tries = 0;
    do {
      if (++tries > 100)
        throw Error(Error::Kind::unprocessable, "axes",
                    "no random point satisfies the parameter constraints");
      p = spec.base;
      for (const auto& a : spec.axes) {
        // Integers: every whole value in [min, max] equally likely.
        const double lo = info_of(a.param).integer ? a.min - 0.5 : a.min,
                     hi = info_of(a.param).integer ? a.max + 0.5 : a.max;
        set(p, a, lo + (hi - lo) * rng.uniform());
      }
    } while (!valid(p));
    out.push_back(p);
  }
  return out;
}

SweepSpec parse_sweep(const nlohmann::json& j) {
  if (!j.is_object()) throw invalid_argument("body", "a sweep is a JSON object");
  SweepSpec s;
  const auto number = [&](const nlohmann::json& v, const std::string& field) {
    if (!v.is_number()) throw invalid_argument(field, field + " must be a number");
    return v.get<double>();
  };
  if (j.contains("mode")) {
    const auto m = j["mode"].is_string() ? j["mode"].get<std::string>() : "";
    if (m == "grid")
      s.mode = SweepMode::grid;
    else if (m == "random")
      s.mode = SweepMode::random;
    else
      throw invalid_argument("mode", "mode must be \"grid\" or \"random\"");
  }
  if (j.contains("samples")) {
    const double v = number(j["samples"], "samples");
    if (v < 1 || v != std::floor(v))
      throw invalid_argument("samples", "samples must be a positive whole number");
    s.samples = static_cast<std::size_t>(v);
  }
  if (j.contains("seed")) {
    const double v = number(j["seed"], "seed");
    if (v < 0 || v != std::floor(v))
      throw invalid_argument("seed", "seed must be a non-negative whole number");
    s.seed = static_cast<std::uint64_t>(v);
  }
  if (j.contains("base")) {
    if (!j["base"].is_object()) throw invalid_argument("base", "base must be an object of parameter values");
    for (const auto& [name, v] : j["base"].items()) set_param(s.base, name, number(v, name));
  }
  if (!j.contains("axes") || !j["axes"].is_array()) throw invalid_argument("axes", "axes must be an array");
  for (const auto& a : j["axes"]) {
    if (!a.is_object() || !a.contains("param") || !a["param"].is_string())
      throw invalid_argument("axes", "each axis needs a \"param\" name");
    SweepAxis ax;
    ax.param = a["param"].get<std::string>();
    const ParamInfo& in = info_of(ax.param);
    ax.min = a.contains("min") ? number(a["min"], "axes") : in.min;
    ax.max = a.contains("max") ? number(a["max"], "axes") : in.max;
    if (a.contains("steps")) ax.steps = static_cast<int>(number(a["steps"], "axes"));
    s.axes.push_back(ax);
  }
  return s;
}

nlohmann::json to_json(const SweepSpec& s) {
  nlohmann::json axes = nlohmann::json::array();
  for (const auto& a : s.axes)
    axes.push_back({{"param", a.param}, {"min", a.min}, {"max", a.max}, {"steps", a.steps}});
  nlohmann::json base = nlohmann::json::object();
  const auto v = to_vector(s.base);
  for (std::size_t i = 0; i < v.size(); ++i) base[parameter_infos()[i].name] = v[i];
  return {{"mode", s.mode == SweepMode::grid ? "grid" : "random"},
          {"samples", s.samples},
          {"seed", s.seed},
          {"base", base},
          {"axes", axes}};
}

void run_sweep(const std::vector<TrackerParams>& points, const std::vector<SweepVideo>& videos,
               const RunOptions& range, const std::function<void(TrackerLog&&)>& on_run,
               const ProgressFn& progress, const CancelToken* cancel) {
  const double total = static_cast<double>(points.size() * videos.size());
  std::size_t done = 0;
  const auto report = [&](double fraction) {
    if (progress) progress(fraction / total, "sweep");
  };
  for (const auto& params : points)
    for (const SweepVideo& video : videos) {
      if (cancel) cancel->throw_if_cancelled();
      RunOptions ro;
      ro.video_id = video.id;
      ro.first_frame = range.first_frame;
      ro.frame_count = range.frame_count;
      const ProgressFn run_progress = [&](double f, std::string_view) {
        if (cancel)
          cancel->throw_if_cancelled();  // run_tracker stops at the throw; that run is not handed on
        report(static_cast<double>(done) + f);
      };
      on_run(run_tracker(video.path, params, ro, run_progress));
      report(static_cast<double>(++done));
    }
}

}  // namespace trailscope::tracker
