// The demo's synthetic depth videos (`trailscope serve --demo`), so the replay has something to play.
#include <iostream>

#include "cli/demo_dataset.hpp"

namespace trailscope::cli {

void create_demo_videos(server::VideoStore& videos) {
  struct Demo {
    const char* name;
    tof::Scenario scenario;
    std::uint64_t seed;
  };
  for (const Demo& d : {Demo{"demo-standard", tof::Scenario::standard, 1},
                        Demo{"demo-cups-attached", tof::Scenario::cups_attached, 2}}) {
    if (!videos.find_by_name(d.name).empty()) continue;
    tof::SynthOptions o;
    o.scenario = d.scenario, o.frames = 500, o.seed = d.seed;
    const nlohmann::json meta = videos.commit_synthetic(videos.reserve(), o, d.name);
    std::cerr << "stored video '" << meta.at("id").get<std::string>() << "' (" << d.name
              << "): " << meta.at("frame_count") << " frames\n";
  }
}

}  // namespace trailscope::cli
