// `trailscope metrics`: TrackEval-exact MOT metrics (HOTA, CLEAR, Identity) of one tracker run against
// ground truth, as TrackEval's tables or as JSON with per-frame and per-target detail.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/metrics/evaluate.hpp"
#include "trailscope/metrics/mot_text.hpp"

namespace trailscope::cli {

void add_metrics(CLI::App& app) {
  auto* cmd = app.add_subcommand("metrics",
                                 "Tracking metrics of a run against ground truth, exactly as TrackEval "
                                 "computes them (HOTA, CLEAR, Identity)");
  cmd->footer(
      "Files: MOTChallenge text. --sim iou (default): GT 'frame,id,x,y,w,h,consider,class[,visibility]' and "
      "run\n"
      "'frame,id,x,y,w,h[,conf,x,y,z]', with MOTChallenge preprocessing (pedestrians, distractors removed).\n"
      "--sim distance: 3D points 'frame,id,x,y,z' in mm in both files, similarity max(0, 1 - d/d_max).\n"
      "Bad files print the offending lines and exit 2.");
  struct Opts {
    std::string gt, run, sim = "iou";
    double d_max = metrics::kDefaultDistanceMax;
    std::int64_t frames = 0;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("--gt", o->gt, "ground-truth file")->required();
  cmd->add_option("--run", o->run, "tracker output file")->required();
  cmd->add_option("--sim", o->sim, "similarity: iou (boxes) | distance (3D points)")->capture_default_str();
  cmd->add_option("--d-max", o->d_max,
                  "distance of zero similarity for --sim distance (mm); a match needs d <= d_max/2")
      ->capture_default_str();
  cmd->add_option("--frames", o->frames,
                  "sequence length (seqLength of seqinfo.ini); 0 = last frame in the files")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "print JSON with per-frame and per-target detail instead of tables");
  cmd->callback([o] {
    metrics::MetricsOptions options;
    if (o->sim == "iou")
      options.kind = metrics::SimilarityKind::iou;
    else if (o->sim == "distance")
      options.kind = metrics::SimilarityKind::distance;
    else
      throw invalid_argument("sim", "sim must be iou or distance, not '" + o->sim + "'");
    options.d_max = o->d_max;
    options.frames = o->frames;
    const std::string gt = metrics::read_text_file(o->gt, "gt");
    const std::string run = metrics::read_text_file(o->run, "run");
    const metrics::MetricsReport report = metrics::evaluate_text(gt, run, options);
    if (o->json)
      std::cout << json_text(metrics::to_json(report, true), 2) << std::endl;
    else
      std::cout << metrics::to_table(report, std::filesystem::path(o->run).stem().string());
  });
}

}  // namespace trailscope::cli
