// `trailscope synth`: a synthetic ToF depth video with exact ground truth (compute/.../tof/synth.hpp),
// written as a video folder or pack (proto/depth_video.md).
#include <chrono>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::cli {

void add_synth(CLI::App& app) {
  auto* cmd = app.add_subcommand("synth",
                                 "Render a synthetic time-of-flight depth video of an udder with exact "
                                 "teat ground truth");
  cmd->footer(
      "Scenarios: standard, noisy, occluded, cups-attached, fast-motion, plane (a calibration wall, no "
      "truth).\n"
      "Camera: 176x144 px by default, fx = fy = 150 px * width / 176. Output: a folder with manifest.json "
      "and\n"
      "16-bit PNGs (depth mm, 0 = no return; amplitude / 0.5), or with --pack one .tsdv file.");
  struct Opts {
    std::string scenario = "standard", output;
    std::size_t frames = 250;
    std::uint64_t seed = 1;
    int width = 176, height = 144;
    double fps = 25;
    bool noise_free = false, pack = false, force = false, json = false;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("--scenario", o->scenario, "scenario preset")->capture_default_str();
  cmd->add_option("--frames", o->frames,
                  "number of frames (1.." + std::to_string(limits::kMaxVideoFrames) + ")")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "random seed (same seed, same bytes)")->capture_default_str();
  cmd->add_option("--width", o->width, "image width, px")->capture_default_str();
  cmd->add_option("--height", o->height, "image height, px")->capture_default_str();
  cmd->add_option("--fps", o->fps, "frame rate, Hz")->capture_default_str();
  cmd->add_flag("--noise-free", o->noise_free, "ideal sensor: exact depth, no noise, flying pixels or holes");
  cmd->add_flag("--pack", o->pack, "write one pack file instead of a folder");
  cmd->add_flag("--force", o->force, "replace an existing output");
  cmd->add_option("-o,--output", o->output, "output folder (or pack file with --pack)")->required();
  cmd->add_flag("--json", o->json, "print a JSON summary on stdout");
  cmd->callback([o] {
    tof::SynthOptions s;
    s.scenario = tof::parse_scenario(o->scenario);
    s.frames = o->frames;
    s.seed = o->seed;
    s.width = o->width;
    s.height = o->height;
    s.fps = o->fps;
    s.noise_free = o->noise_free;
    tof::WriteOptions w;
    w.layout = o->pack ? tof::VideoLayout::pack : tof::VideoLayout::folder;
    w.overwrite = o->force;
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<tof::ToFSynth> synth;
    {
      ProgressBar bar("synthesising " + o->scenario);
      synth = std::make_unique<tof::ToFSynth>(tof::write_synthetic_video(s, o->output, w, bar.fn()));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json teats = nlohmann::json::array();
    for (int t = 0; t < tof::kTeatCount; ++t) {
      const auto& shape = synth->teat_shapes()[t];
      const auto& cup = synth->cup_intervals()[t];
      teats.push_back({{"name", std::string(tof::kTeatNames[t])},
                       {"length_mm", shape.length_mm},
                       {"diameter_mm", shape.diameter_mm},
                       {"tilt_deg", shape.tilt_deg},
                       {"cup_frames", cup.empty() ? nlohmann::json(nullptr)
                                                  : nlohmann::json::array({cup.begin, cup.end})}});
    }
    const nlohmann::json summary = {{"output", o->output},
                                    {"layout", o->pack ? "pack" : "folder"},
                                    {"scenario", o->scenario},
                                    {"frames", o->frames},
                                    {"seed", o->seed},
                                    {"width", o->width},
                                    {"height", o->height},
                                    {"fps", o->fps},
                                    {"noise_free", o->noise_free},
                                    {"seconds", seconds},
                                    {"teats", teats}};
    if (o->json)
      std::cout << json_text(summary, 2) << std::endl;
    else
      std::cerr << "wrote " << o->frames << " frames (" << o->width << "x" << o->height << ", " << o->scenario
                << ", seed " << o->seed << ") to " << o->output << " in " << seconds << " s\n";
  });
}

}  // namespace trailscope::cli
