#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "formats/bundle_export.hpp"
#include "jobs/bundle_job.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/bundling/graph_io.hpp"
#include "trailscope/bundling/render.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::cli {
namespace fs = std::filesystem;

namespace {
/// The RenderParams fields the CLI sets by name (RenderParams::set), with their help. `relaxation` is
/// left out: --relaxation is the bundling parameter, which the image follows.
struct RenderFlag {
  const char* name;
  const char* help;
};
constexpr RenderFlag kRenderFlags[] = {
    {"width", "image width, px (16..8192; default 1024)"},
    {"height", "image height, px (0 = width · the frame's aspect)"},
    {"style", "lines | shaded | tube (default shaded)"},
    {"color", "length | direction | density | displacement | flat (default length)"},
    {"alpha_mode", "constant | value | inverse (default constant)"},
    {"alpha", "global alpha, 0..1 (default 0.6)"},
    {"alpha_by_density", "modulate alpha by the local density: true | false"},
    {"shading_radius", "density smoothing for shading, px, 0..32 (default 3)"},
    {"local_max_radius", "radius of the local-maximum normalisation, px, 1..256 (default 16)"},
    {"line_width", "line width, px, 0.5..8 (default 1)"},
    {"cmap", "colour map for density/displacement colouring (default viridis)"},
    {"background", "black | white | transparent (default black)"},
};

std::string flag_name(const std::string& param) {
  std::string f = "--" + param;
  for (char& c : f)
    if (c == '_') c = '-';
  return f;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void write_file(const std::string& path, const std::string& bytes, const std::string& param) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw Error(Error::Kind::internal, param, "cannot write " + path);
}

void print_text(const nlohmann::json& j) {
  const auto& q = j["quality"];
  const auto& t = j["times_ms"];
  std::printf("bundled %llu polylines (%llu input points, %llu after resampling) on %s%s%s\n",
              j["polylines"].get<unsigned long long>(), j["input_points"].get<unsigned long long>(),
              j["points"].get<unsigned long long>(), j["path"].get<std::string>().c_str(),
              j["device"].get<std::string>().empty() ? "" : " · ", j["device"].get<std::string>().c_str());
  std::printf("ink reduction  %.1f %% (%llu px raw, %llu px bundled)\n",
              100.0 * q["ink_reduction"].get<double>(), q["ink_raw_px"].get<unsigned long long>(),
              q["ink_bundled_px"].get<unsigned long long>());
  std::printf("displacement   mean %.2f px, max %.2f px\n", q["mean_displacement_px"].get<double>(),
              q["max_displacement_px"].get<double>());
  std::printf(
      "time (ms)      resample %.1f, splat %.1f, convolve %.1f, advect %.1f, smooth %.1f, endpoints %.1f, "
      "post %.1f; total %.1f\n",
      t["resample"].get<double>(), t["splat"].get<double>(), t["convolve"].get<double>(),
      t["advect"].get<double>(), t["smooth"].get<double>(), t["endpoints"].get<double>(),
      t["post"].get<double>(), t["total"].get<double>());
  for (const char* k : {"output", "polylines_file"})
    if (j.contains(k)) std::printf("wrote          %s\n", j[k].get<std::string>().c_str());
}
}  // namespace

void add_bundle(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "bundle",
      "Bundle a graph or trail set (GraphML, node-link JSON, OD CSV, CUBu .trl) or the flight trails of a "
      "dataset window (INPUT = dataset:NAME) with CUBu, and draw it");
  struct Opts {
    std::string input, out, nodes, format, polylines, backend, data_dir = default_data_dir();
    double max_gap = std::numeric_limits<double>::infinity();
    bool json = false, quiet = false;
    std::map<std::string, std::string> params, render;
    QueryFlags flags;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("INPUT", o->input, "graph or trail file, or dataset:NAME for a dataset's flight trails")
      ->required();
  cmd->add_option("-o,--output", o->out, "PNG file to write");
  cmd->add_option("--nodes", o->nodes, "nodes CSV of an OD CSV that names its nodes (airports.csv)");
  cmd->add_option("--format", o->format, "graphml | node_link | od_csv | trl (default: detected)");
  cmd->add_option("--polylines", o->polylines,
                  "also write the bundled polylines: .json (source coordinates), .bin (TSBL) or .trl");
  cmd->add_option("--backend", o->backend, "cpu | opencl | auto");
  cmd->add_option("--data-dir", o->data_dir, "store folder (for dataset:NAME)")->capture_default_str();
  cmd->add_option("--max-gap", o->max_gap,
                  "dataset trails: split where samples are more than this many s apart");
  cmd->add_flag("--json", o->json, "print the result (the API's Bundle object) as JSON");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  // One flag per bundling parameter, from the same table as the API's parameter list, so that the two
  // cannot drift apart; values are checked by BundleParams::set, which names the parameter.
  for (const auto& info : bundling::parameter_infos()) {
    const std::string name = info.name;
    cmd->add_option_function<std::string>(
        flag_name(name), [o, name](const std::string& v) { o->params[name] = v; },
        info.help + " [" + info.type + ", " + info.range + ", default " + info.default_value + "]");
  }
  for (const auto& f : kRenderFlags) {
    const std::string name = f.name;
    cmd->add_option_function<std::string>(
        flag_name(name), [o, name](const std::string& v) { o->render[name] = v; }, f.help);
  }
  o->flags.add_to(*cmd);
  cmd->callback([o] {
    if (o->out.empty() && o->polylines.empty())
      throw invalid_argument("output", "output: give -o OUT.png and/or --polylines FILE");
    if (!o->polylines.empty() && !ends_with(o->polylines, ".json") && !ends_with(o->polylines, ".bin") &&
        !ends_with(o->polylines, ".trl"))
      throw invalid_argument("polylines", "--polylines: the file must end in .json, .bin or .trl");
    bundling::BundleParams params;
    for (const auto& [k, v] : o->params) params.set(k, v);
    params.validate();
    bundling::RenderParams rp;
    for (const auto& [k, v] : o->render) rp.set(k, v);
    rp.validate();
    const Backend backend = o->backend.empty() ? default_backend() : parse_backend(o->backend, "backend");
    if (!(o->max_gap > 0))
      throw invalid_argument("max-gap", "--max-gap must be a positive number of seconds");

    server::BundleInput in;
    const std::string prefix = "dataset:";
    if (o->input.rfind(prefix, 0) == 0) {
      server::EmbeddedStore store(o->data_dir);
      const auto ds = store.get(o->input.substr(prefix.size()));
      in = server::input_from_dataset(*ds, o->flags.params, o->max_gap, params);
    } else {
      if (!o->flags.params.empty())
        throw invalid_argument(o->flags.params.begin()->first,
                               "the window filters (--bbox, --t0, ...) apply to INPUT = dataset:NAME only");
      std::optional<bundling::GraphFormat> format;
      if (!o->format.empty() && o->format != "auto")
        format = bundling::parse_graph_format(o->format, "format");
      const bundling::Graph g = bundling::read_graph(o->input, o->nodes, format ? &*format : nullptr);
      in = server::input_from_graph(
          g, params,
          {{"file", o->input}, {"format", bundling::to_string(g.format)}, {"edges", g.edges.size()}});
    }
    std::shared_ptr<server::StoredBundle> b;
    {
      ProgressBar bar("bundle", !o->quiet);
      b = server::run_bundle(std::move(in), "", params, backend, bar.fn(), nullptr);
    }
    nlohmann::json j = b->to_json();
    j.erase("id");
    j.erase("created");
    if (!o->out.empty()) {
      density::write_png(bundling::render_bundle(b->bundled, rp), o->out);
      j["output"] = o->out;
    }
    if (!o->polylines.empty()) {
      const double relaxation = -1;  // the bundle's own --relaxation
      if (ends_with(o->polylines, ".json"))
        write_file(
            o->polylines,
            json_text(server::polylines_json(*b, relaxation, std::numeric_limits<std::size_t>::max())) + "\n",
            "polylines");
      else if (ends_with(o->polylines, ".bin"))
        write_file(o->polylines, server::polylines_binary(*b, relaxation), "polylines");
      else
        write_file(o->polylines, server::polylines_trl(*b, relaxation), "polylines");
      j["polylines_file"] = o->polylines;
    }
    if (o->json)
      std::cout << json_text(j, 2) << std::endl;
    else
      print_text(j);
  });
}

}  // namespace trailscope::cli
