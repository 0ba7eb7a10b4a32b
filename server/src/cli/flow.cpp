// `trailscope flow DATASET [window filters] -o OUT.png [--level L] [--json]`: the flow map of a dataset's
// traffic (trailscope/flow/render.hpp, flow_image), or of an uploaded vector field with --field FILE.
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/flow/render.hpp"

namespace trailscope::cli {

void add_flow(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "flow",
      "Draw the flow map of a dataset's traffic (a velocity field per heading sector, evenly spaced "
      "streamlines, CUBu bundling) at an abstraction level 0 (density) .. 1 (streamlines) .. 2 (bundled); "
      "or of an uploaded vector field (--field, proto/flow_field.md)");
  struct Opts {
    std::string data_dir = default_data_dir(), dataset, field, out, backend, level;
    bool json = false, quiet = false;
    std::vector<std::string> params;
    QueryFlags flags;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("DATASET", o->dataset, "dataset id (or give --field)");
  cmd->add_option("--field", o->field, "a vector field file (proto/flow_field.md) instead of a dataset");
  cmd->add_option("-o,--output", o->out, "PNG file to write");
  cmd->add_option("--level", o->level, "abstraction level in [0, 2] (default 2: bundled)");
  cmd->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
  cmd->add_option("--backend", o->backend, "cpu | opencl | auto (the bundling)");
  cmd->add_option("--param", o->params,
                  "NAME=VALUE, repeatable: grid, sectors, smooth, max_gap, d_sep, d_test, step, integrator, "
                  "min_length, min_traffic, min_coherence, max_line_points, cell_px, line_width, halo_px, "
                  "background, cmap, bundle.<CUBu parameter> (the route's query parameters)");
  cmd->add_flag("--json", o->json, "print the streamlines at the level and the timings as JSON");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  o->flags.add_to(*cmd);
  cmd->callback([o] {
    if (o->out.empty() && !o->json) throw invalid_argument("output", "output: give -o OUT.png and/or --json");
    if (o->dataset.empty() == o->field.empty())
      throw invalid_argument("field", "give either DATASET or --field FILE, not both");
    flow::FlowParams params;
    flow::FlowRenderParams render;
    if (!o->level.empty()) flow::set_flow_option(params, render, "level", o->level);
    for (const std::string& kv : o->params) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0)
        throw invalid_argument("param", "--param takes NAME=VALUE, got '" + kv + "'");
      flow::set_flow_option(params, render, kv.substr(0, eq), kv.substr(eq + 1));
    }
    const Backend backend = o->backend.empty() ? default_backend() : parse_backend(o->backend, "backend");
    flow::FlowImage r;
    {
      ProgressBar bar("flow", !o->quiet);
      if (!o->field.empty()) {
        if (!o->flags.params.empty())
          throw invalid_argument(o->flags.params.begin()->first,
                                 "the window filters (--bbox, --t0, ...) apply to a dataset only");
        std::ifstream in(o->field, std::ios::binary);
        if (!in) throw not_found("field", "cannot open " + o->field);
        std::string text;
        in.seekg(0, std::ios::end);
        const auto bytes = static_cast<std::uint64_t>(std::max<std::streamoff>(0, in.tellg()));
        if (bytes > limits::kMaxFlowFieldBytes)
          throw Error(Error::Kind::payload_too_large, "field",
                      "a vector field file may have at most " + std::to_string(limits::kMaxFlowFieldBytes) +
                          " bytes (limits::kMaxFlowFieldBytes)");
        in.seekg(0);
        text.assign(std::istreambuf_iterator<char>(in), {});
        r = flow::flow_image(flow::parse_field(text), params, render, backend, bar.fn());
      } else {
        server::EmbeddedStore store(o->data_dir);
        const auto ds = store.get(o->dataset);
        const Query q = parse_query(o->flags.params);
        r = flow::flow_image(*ds->trails, q, params, render, backend, bar.fn());
      }
    }
    if (!o->out.empty()) density::write_png(r.image, o->out);
    const double total = r.map.field_ms + r.map.lines_ms + r.map.bundle_ms + r.render_ms;
    if (o->json) {
      nlohmann::json j = flow::flow_json(r.map, render.level);
      j["times"]["render_ms"] = r.render_ms;
      j["times"]["total_ms"] = total;
      j["width"] = r.image.width, j["height"] = r.image.height;
      if (!o->out.empty()) j["output"] = o->out;
      std::cout << json_text(j, 2) << std::endl;
    } else {
      std::cout << "wrote " << o->out << " (" << r.image.width << " x " << r.image.height << " px, "
                << r.map.lines.size() << " streamlines, level " << render.level << ", " << total << " ms)\n";
    }
  });
}

}  // namespace trailscope::cli
