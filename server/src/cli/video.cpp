// `trailscope video info`: what a depth video is (folder, pack, or 16-bit PNGs), from its manifest.
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::cli {

void add_video(CLI::App& app) {
  auto* video = app.add_subcommand("video", "Depth videos (proto/depth_video.md)");
  video->require_subcommand(1);
  auto* info =
      video->add_subcommand("info", "Describe a depth video: size, intrinsics, frames, truth, source");
  struct Opts {
    std::string path;
    bool json = false;
    double depth_unit_mm = 1.0;
  };
  auto o = std::make_shared<Opts>();
  info->add_option("VIDEO", o->path, "video folder, .tsdv pack, folder of 16-bit PNGs, or one PNG")
      ->required();
  info->add_option("--depth-unit", o->depth_unit_mm, "mm per count of manifest-less PNGs (TUM: 0.2)")
      ->capture_default_str();
  info->add_flag("--json", o->json, "print the manifest header as JSON");
  info->callback([o] {
    tof::ImportOptions import;
    import.depth_unit_mm = o->depth_unit_mm;
    const tof::DepthVideoReader reader(o->path, import);
    const tof::VideoInfo& v = reader.info();
    if (o->json) {
      std::cout << json_text(tof::describe_video(reader), 2) << std::endl;
      return;
    }
    const tof::Intrinsics& k = v.intrinsics;
    std::cout << o->path << "\n"
              << "  size        " << k.width << " x " << k.height << " px\n"
              << "  intrinsics  fx " << k.fx << ", fy " << k.fy << ", cx " << k.cx << ", cy " << k.cy
              << (k.defaulted ? " (defaulted)" : "") << "\n"
              << "  frames      " << v.frame_count << " at " << v.fps << " fps"
              << (v.timestamps_defaulted ? " (timestamps defaulted)" : "") << "\n"
              << "  amplitude   "
              << (v.has_amplitude ? "yes, " + std::to_string(v.amplitude_scale) + " per count" : "no") << "\n"
              << "  truth       " << (v.has_truth ? "yes (4 teats: FL FR RL RR)" : "no") << "\n"
              << "  source      " << json_text(v.source) << "\n";
  });
}

}  // namespace trailscope::cli
