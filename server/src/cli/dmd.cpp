// `trailscope dmd`: the dense medial descriptor of one image (an 8-bit grey PNG, or a 16-bit depth
// PNG in mm mapped to grey with near = bright): reconstruction, optional segment labels, PSNR, layer
// and skeleton counts, per-stage times.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/dmd/dmd.hpp"
#include "trailscope/dmd/image_io.hpp"
#include "trailscope/dmd/report.hpp"

namespace trailscope::cli {

void add_dmd(CLI::App& app) {
  auto* cmd = app.add_subcommand("dmd",
                                 "Dense medial descriptor of an image: threshold layers, skeletons, "
                                 "reconstruction and segmentation (van der Zwan et al., VISAPP 2013)");
  cmd->footer(
      "IMAGE: an 8-bit grey PNG, or a 16-bit PNG of depth in mm (0 = hole), mapped to grey with near = 255,\n"
      "far = 1, holes and beyond-far = 0 (--near/--far default to the frame's valid depth range).\n"
      "The reconstruction is an 8-bit PNG; --segments writes a 16-bit PNG whose values are segment labels.");
  struct Opts {
    std::string image, out, segments, selection = "cumulative";
    std::optional<double> near_mm, far_mm;
    bool no_interpolate = false, json = false;
    dmd::DmdParams params;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("IMAGE", o->image, "8-bit grey or 16-bit depth (mm) PNG")->required();
  cmd->add_option("-o,--output", o->out, "reconstruction PNG to write")->required();
  cmd->add_option("--segments", o->segments, "label PNG (16-bit) to write");
  cmd->add_option("--layers", o->params.layers, "threshold layers incl. the canvas, 2..256")
      ->capture_default_str();
  cmd->add_option("--selection", o->selection, "layer levels: cumulative | local_maxima")
      ->capture_default_str();
  cmd->add_option("--min-gap", o->params.min_gap, "smallest grey difference between layer levels, 1..128")
      ->capture_default_str();
  cmd->add_option("--island", o->params.island, "islands/holes below this fraction of the area go, 0..0.1")
      ->capture_default_str();
  cmd->add_option("--saliency", o->params.saliency, "skeleton salience threshold, 0..100 (0 = exact)")
      ->capture_default_str();
  cmd->add_flag("--no-interpolate", o->no_interpolate, "flat bands instead of ramps between layers");
  cmd->add_option("--near", o->near_mm, "depth mapped to 255, mm (16-bit input only)");
  cmd->add_option("--far", o->far_mm, "depth mapped to 1, mm; deeper is 0 (16-bit input only)");
  cmd->add_flag("--json", o->json, "print the run as JSON (levels, layers, segments, times)");
  cmd->callback([o] {
    dmd::DmdParams params = o->params;
    params.selection = dmd::parse_layer_selection(o->selection, "selection");
    params.interpolate = !o->no_interpolate;
    params.validate();
    dmd::PngInput in = dmd::read_png_input(o->image);
    dmd::GreyImage grey;
    nlohmann::json input = {{"path", o->image}, {"bits", in.bits}};
    if (in.bits == 16) {
      dmd::DepthRange range{};
      if (!o->near_mm || !o->far_mm) range = dmd::valid_depth_range(in.depth);
      const double near_mm = o->near_mm.value_or(range.near_mm);
      // A frame of one depth has an empty range; one more mm keeps the map defined.
      const double far_mm = o->far_mm.value_or(std::max(range.far_mm, near_mm + 1));
      grey = dmd::depth_to_grey(in.depth, near_mm, far_mm);
      input["near_mm"] = near_mm;
      input["far_mm"] = far_mm;
    } else {
      if (o->near_mm) throw invalid_argument("near", "near applies to 16-bit depth input only");
      if (o->far_mm) throw invalid_argument("far", "far applies to 16-bit depth input only");
      grey = std::move(in.grey);
    }
    input["width"] = grey.width;
    input["height"] = grey.height;
    const dmd::DmdResult r = dmd::run_dmd(grey, params);
    dmd::write_grey_png(r.reconstruction, o->out);
    if (!o->segments.empty()) dmd::write_label_png(r.labels, grey.width, grey.height, o->segments);
    const double p = dmd::psnr(grey, r.reconstruction);
    if (o->json) {
      nlohmann::json j = dmd::to_json(r, params);
      j["input"] = input;
      j["psnr_db"] = std::isfinite(p) ? nlohmann::json(p) : nlohmann::json("inf");
      j["output"] = o->out;
      if (!o->segments.empty()) j["segments_output"] = o->segments;
      std::cout << json_text(j, 2) << std::endl;
      return;
    }
    const auto& t = r.times;
    std::size_t peaks = 0;
    for (const auto& s : r.segments) peaks += s.kind == dmd::SegmentKind::peak;
    std::cout << std::fixed << std::setprecision(2) << "input: " << o->image << " (" << grey.width << "x"
              << grey.height << ", " << in.bits << "-bit";
    if (in.bits == 16) std::cout << ", near " << input["near_mm"] << " mm, far " << input["far_mm"] << " mm";
    std::cout << ")\nlayers used: " << r.levels.size() << " of " << params.layers << "\nPSNR: " << p
              << " dB\nskeleton pixels: " << r.skeleton_pixels << " (medial axis " << r.medial_axis_pixels
              << ")\nsegments: " << r.segments.size() << " (" << peaks << " peaks)\ntimes (ms): select "
              << t.select_ms << ", threshold " << t.threshold_ms << ", islands " << t.islands_ms
              << ", skeleton " << t.skeleton_ms << ", simplify " << t.simplify_ms << ", reconstruct "
              << t.reconstruct_ms << ", stack " << t.stack_ms << ", segment " << t.segment_ms << ", total "
              << t.total_ms << "\nwrote " << o->out << (o->segments.empty() ? "" : " and " + o->segments)
              << "\n";
  });
}

}  // namespace trailscope::cli
