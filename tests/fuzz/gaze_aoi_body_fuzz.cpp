// libFuzzer harness: the body of POST /api/v1/gaze/{gaze}/aoi as the route reads it
// (server/src/routes/gaze_views.cpp): parse_body_object() with the route's fields, the AOI list
// (gazeview::aois_from_json, also the CLI's --aoi-file) and the gaze filters given as body fields
// (params::parse_gaze_filters). Besides a clean refusal, what a parsed list promises is checked: it passes
// validate_aois(), and contains() answers on the AOIs' own corners and centre (the even-odd test on the
// vertices the fuzzer chose).
#include "fuzz_support.hpp"
#include "params/gaze_filters.hpp"
#include "params/json_fields.hpp"
#include "trailscope/gazeview/aoi.hpp"

using namespace trailscope;
using namespace trailscope::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> allowed = params::gaze_filter_keys();
  allowed.push_back("aois");
  nlohmann::json body;
  try {
    body = parse_body_object(std::string(fuzz::bytes_of(data, size)), allowed);
  } catch (const Error& e) {
    fuzz::refuse(e);
    return 0;
  }
  if (body.contains("aois")) {
    try {
      const std::vector<gazeview::Aoi> aois = gazeview::aois_from_json(body["aois"]);
      gazeview::validate_aois(aois);  // a list aois_from_json returned is valid: throwing here is a bug
      for (const gazeview::Aoi& a : aois) {
        if (a.is_rect) {
          // Closed rectangles: corners and centre are inside.
          if (!a.contains(a.x0, a.y0) || !a.contains(a.x1, a.y1) ||
              !a.contains((a.x0 + a.x1) / 2, (a.y0 + a.y1) / 2))
            std::abort();
        } else {
          // The boundary is inside: every vertex is.
          for (std::size_t k = 0; k < a.xs.size(); ++k)
            if (!a.contains(a.xs[k], a.ys[k])) std::abort();
        }
      }
    } catch (const Error& e) {
      if (e.param() != "aois") std::abort();  // every AOI error names the body field
      fuzz::refuse(e);
    }
  }
  try {
    (void)params::parse_gaze_filters(body);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
