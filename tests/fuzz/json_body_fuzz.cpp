// libFuzzer harness: the one parser of JSON request bodies (server/src/params/json_fields.cpp) as the POST
// routes use it: parse_body_object() with a route's allowed fields, then the typed field readers. The
// fields are those of POST /api/v1/runs and /replays (video, params: the tracker parameters, read by
// parse_tracker_params and tracker::set_param / validate) and of /videos/synth (frames, seed, width,
// height: unsigned; fps: number; noise_free: bool; scenario, name: strings).
#include "fuzz_support.hpp"
#include "params/json_fields.hpp"

using namespace trailscope;
using namespace trailscope::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json j;
  try {
    j = parse_body_object(std::string(fuzz::bytes_of(data, size)),
                          {"video", "params", "colormap", "scenario", "frames", "seed", "width", "height",
                           "fps", "noise_free", "name"});
  } catch (const Error& e) {
    fuzz::refuse(e);
    return 0;
  }
  try {
    (void)parse_tracker_params(j.value("params", nlohmann::json()));
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    std::uint32_t frames = 0, width = 0, height = 0;
    std::uint64_t seed = 0;
    unsigned_field(j, "frames", frames);
    unsigned_field(j, "seed", seed);
    unsigned_field(j, "width", width);
    unsigned_field(j, "height", height);
    (void)number_field(j, "fps", 30);
    (void)integer_field(j, "seed", 0);
    (void)bool_field(j, "noise_free", false);
    if (j.contains("video")) (void)string_field(j, "video");
    if (j.contains("name")) (void)scalar_text(j["name"], "name");
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
