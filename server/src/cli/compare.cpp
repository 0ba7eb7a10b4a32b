// `trailscope compare`: tracker logs of one video side by side — parameter and result differences and the
// frames where the runs disagree most (what POST /api/v1/compare returns, from files).
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "trailscope/analysis/run_compare.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::cli {
namespace {

void print_rows(const char* title, const std::vector<analysis::ValueRow>& rows, bool differing_only) {
  std::cout << title << "\n";
  for (const analysis::ValueRow& r : rows) {
    if (differing_only && !r.differs) continue;
    std::cout << "  " << (r.differs ? "* " : "  ") << std::left << std::setw(28) << r.name << std::right;
    for (double v : r.values) std::cout << std::setw(12) << std::setprecision(4) << v;
    std::cout << "\n";
  }
}

}  // namespace

void add_compare(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("compare", "compare tracker runs of one video: differences and disagreements");
  cmd->footer(
      "RUN: a tracker log (.tslog or .json, `trailscope track -o`), 2 to " +
      std::to_string(limits::kMaxCompareRuns) +
      " of one video. Runs are compared on the frames they share. A frame's disagreement is the mean "
      "over the\nfour teats of the largest distance between two runs' estimates, plus --miss-mm × the "
      "share of runs\nthat miss a teat others report. Parameters marked * differ.");
  struct Opts {
    std::vector<std::string> runs;
    analysis::CompareOptions options;
    bool json = false, all_params = false;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("RUN", o->runs, "tracker logs")->required();
  cmd->add_option("--top", o->options.top, "disagreement frames listed")->capture_default_str();
  cmd->add_option("--miss-mm", o->options.miss_mm,
                  "added to a teat's spread, times the share of runs that miss it, mm")
      ->capture_default_str();
  cmd->add_option("--within-mm", o->options.within_mm, "radius of the accuracy figures, mm")
      ->capture_default_str();
  cmd->add_flag("--all-params", o->all_params, "list every parameter, not only those that differ");
  cmd->add_flag("--json", o->json,
                "print the comparison as POST /api/v1/compare returns it (without run rows)");
  cmd->callback([o] {
    std::vector<tracker::TrackerLog> logs;
    for (const std::string& path : o->runs) logs.push_back(tracker::read_log(path));
    std::vector<const tracker::TrackerLog*> runs;
    for (const auto& l : logs) runs.push_back(&l);
    const analysis::Comparison c = analysis::compare_runs(runs, o->options);
    if (o->json) {
      nlohmann::json j = analysis::to_json(c);
      for (std::size_t r = 0; r < o->runs.size(); ++r) j["series"][r]["id"] = o->runs[r];
      std::cout << json_text(j, 2) << std::endl;
      return;
    }
    std::cout << o->runs.size() << " runs of video '" << c.video << "', frames " << c.first_frame << ".."
              << c.first_frame + c.frames - 1 << "\n";
    for (std::size_t r = 0; r < o->runs.size(); ++r)
      std::cout << "  run " << r + 1 << ": " << o->runs[r] << "\n";
    print_rows("parameters", c.params, !o->all_params);
    print_rows("results", c.results, false);
    std::cout << "frames where the runs disagree most (score mm, worst teat, states)\n";
    for (const analysis::Disagreement& d : c.disagreements) {
      std::cout << "  frame " << std::setw(6) << d.frame << std::setw(10) << std::fixed
                << std::setprecision(1) << d.score_mm << "  "
                << tof::kTeatNames[static_cast<std::size_t>(d.worst_teat)] << " ";
      for (int s : d.states) std::cout << ' ' << tracker::to_string(static_cast<tracker::State>(s));
      std::cout << std::defaultfloat << "\n";
    }
    if (c.disagreements.empty()) std::cout << "  (none: the runs agree on every shared frame)\n";
  });
}

}  // namespace trailscope::cli
