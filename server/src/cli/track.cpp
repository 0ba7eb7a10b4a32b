// `trailscope track`: runs the teat tracker over a depth video and writes the run as a tracker log
// (proto/tracker_log.md), then prints what the run achieved and, when the video has ground truth, how
// accurate it was.
#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/tracker/run_counts.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::cli {
namespace {

std::string flag_of(const std::string& param) {
  if (param == "first_frame") return "--first";
  if (param == "frame_count") return "--frames";
  std::string f = "--" + param;
  for (char& c : f)
    if (c == '_') c = '-';
  return f;
}

std::string number_text(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

/// "[mm, 0..5000, default 80]": what --help shows for every tracker parameter.
std::string range_text(const ParamInfo& info) {
  return "[" + (info.unit.empty() ? std::string() : info.unit + ", ") + number_text(info.min) + ".." +
         number_text(info.max) + (info.integer ? ", whole" : "") + ", default " +
         number_text(info.default_number) + "]";
}

/// Runs `f`, turning an invalid_argument about a tracker parameter or the frame range into one that names
/// the CLI flag, since the user typed the flag, not the library's parameter name.
template <typename F>
auto naming_flags(F&& f) {
  try {
    return f();
  } catch (const Error& e) {
    bool ours = e.param() == "first_frame" || e.param() == "frame_count";
    for (const auto& info : tracker::parameter_infos()) ours = ours || info.name == e.param();
    if (e.kind() != Error::Kind::invalid_argument || !ours) throw;
    throw Error(e.kind(), e.param(), flag_of(e.param()) + ": " + e.what());
  }
}

double parse_number(const std::string& name, const std::string& text) {
  double v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || ptr != end || text.empty())
    throw invalid_argument(name, "'" + text + "' is not a number");  // naming_flags adds the flag
  return v;
}

nlohmann::json run_summary(const tracker::TrackerLog& log, double wall_s) {
  const tracker::StateCounts c = tracker::count_states(log.frames);
  const double tracker_us = c.tracker_us;
  const double n = static_cast<double>(log.frames.size());
  nlohmann::json j = {
      {"run_id", log.header.run_id},
      {"video_id", log.header.video_id},
      {"frames", log.frames.size()},
      {"first_frame", log.frames.empty() ? 0 : log.frames.front().index},
      {"seconds", wall_s},
      {"tracker_seconds", tracker_us * 1e-6},
      // Frames per second of the tracker itself (its stage times), without reading and decoding PNGs.
      {"fps", tracker_us > 0 ? n / (tracker_us * 1e-6) : 0.0},
      {"states", {{"SEARCH", c.search}, {"TRACK", c.track}, {"LOST", c.lost}}},
      {"track_share", n > 0 ? static_cast<double>(c.track) / n : 0.0},
      {"lost_episodes", c.lost_episodes},
      {"accuracy", nullptr}};
  if (!log.truth.empty()) {
    nlohmann::json a = tracker::to_json(tracker::evaluate_accuracy(log));
    a.erase("frame_max_error_mm");  // per frame: in the log's consumers, not in a summary
    j["accuracy"] = a;
  }
  return j;
}

std::string mm(const nlohmann::json& v) {
  if (!v.is_number()) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.2f mm", v.get<double>());
  return b;
}

void print_text(const nlohmann::json& s) {
  std::printf("tracked %zu frames of %s from frame %zu: %.1f fps (tracker only), %.2f s in all\n",
              s["frames"].get<std::size_t>(), s["video_id"].get<std::string>().c_str(),
              s["first_frame"].get<std::size_t>(), s["fps"].get<double>(), s["seconds"].get<double>());
  std::printf("states    SEARCH %zu, TRACK %zu, LOST %zu (TRACK %.1f %%, %zu lost episodes)\n",
              s["states"]["SEARCH"].get<std::size_t>(), s["states"]["TRACK"].get<std::size_t>(),
              s["states"]["LOST"].get<std::size_t>(), 100.0 * s["track_share"].get<double>(),
              s["lost_episodes"].get<std::size_t>());
  const auto& a = s["accuracy"];
  if (a.is_null()) {
    std::printf("accuracy  (the video has no ground truth)\n");
  } else {
    std::printf("accuracy  tip error median %s, mean %s, p95 %s; %zu of %zu visible teats reported\n",
                mm(a["median_error_mm"]).c_str(), mm(a["mean_error_mm"]).c_str(),
                mm(a["p95_error_mm"]).c_str(), a["reported_pairs"].get<std::size_t>(),
                a["visible_pairs"].get<std::size_t>());
    if (a["frames_all_within"].is_number())
      std::printf("          every visible teat within %g mm in %.1f %% of frames\n",
                  a["within_mm"].get<double>(), 100.0 * a["frames_all_within"].get<double>());
    for (const auto& t : a["teats"])
      std::printf("          %s  median %s, p95 %s, %zu of %zu visible frames reported\n",
                  t["name"].get<std::string>().c_str(), mm(t["median_error_mm"]).c_str(),
                  mm(t["p95_error_mm"]).c_str(), t["reported"].get<std::size_t>(),
                  t["visible_frames"].get<std::size_t>());
  }
  std::printf("run       %s\nwrote     %s\n", s["run_id"].get<std::string>().c_str(),
              s["output"].get<std::string>().c_str());
}

}  // namespace

void add_track(CLI::App& app) {
  auto* cmd = app.add_subcommand("track", "Run the teat tracker over a depth video and write the run's log");
  cmd->footer(
      "VIDEO: a video folder, a .tsdv pack, or 16-bit depth PNGs (trailscope video info VIDEO).\n"
      "Output: RUN.json (protobuf JSON mapping) or any other name for binary protobuf (RUN.tslog); the\n"
      "format is proto/tracker_log.md. Summary: frames, tracker fps, states, lost episodes and, when the\n"
      "video has ground truth, the 3D tip errors. Bad values name the flag and exit 2.");
  struct Opts {
    std::string video, output, run_id;
    std::size_t first = 0, frames = 0;
    bool force = false, json = false, quiet = false;
    std::map<std::string, std::string> params;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("VIDEO", o->video, "depth video")->required();
  cmd->add_option("-o,--output", o->output, "log file to write: RUN.tslog (binary) or RUN.json")->required();
  cmd->add_option("--first", o->first, "first frame to track (0-based)")->capture_default_str();
  cmd->add_option("--frames", o->frames, "frames to track; 0 = to the end")->capture_default_str();
  cmd->add_option("--run-id", o->run_id, "run id (default: run-YYYYMMDD-HHMMSS-xxxx)");
  cmd->add_flag("--force", o->force, "replace an existing output");
  cmd->add_flag("--json", o->json, "print the summary as JSON on stdout");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  // One flag per tracker parameter, from the table the API and the logs use, so they cannot drift
  // apart; values are checked by set_param/validate, whose errors are re-worded to name the flag.
  for (const auto& info : tracker::parameter_infos()) {
    const std::string name = info.name;
    cmd->add_option_function<std::string>(
           flag_of(name), [o, name](const std::string& v) { o->params[name] = v; },
           info.help + " " + range_text(info))
        ->type_name(info.integer ? "INT" : "NUM");
  }
  cmd->callback([o] {
    tracker::TrackerParams params;
    naming_flags([&] {
      for (const auto& [name, text] : o->params) tracker::set_param(params, name, parse_number(name, text));
      tracker::validate(params);
      return 0;
    });
    if (!o->force && std::filesystem::exists(o->output))
      throw Error(Error::Kind::conflict, "output", "output: " + o->output + " exists (--force replaces it)");
    tracker::RunOptions options;
    options.run_id = o->run_id;
    options.first_frame = o->first;
    options.frame_count = o->frames;
    const auto t0 = std::chrono::steady_clock::now();
    const tracker::TrackerLog log = naming_flags([&] {
      std::filesystem::path name = std::filesystem::path(o->video).lexically_normal();
      if (name.filename().empty()) name = name.parent_path();  // "clip/" is the folder clip
      ProgressBar bar("tracking " + name.filename().string(), !o->quiet);
      return tracker::run_tracker(o->video, params, options, bar.fn());
    });
    tracker::write_log(log, o->output, o->force);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json summary = run_summary(log, seconds);
    summary["output"] = o->output;
    if (o->json)
      std::cout << json_text(summary, 2) << std::endl;
    else
      print_text(summary);
  });
}

}  // namespace trailscope::cli
