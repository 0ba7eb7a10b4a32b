#include <fstream>
#include <limits>
#include <optional>
#include <iostream>

#include "trailscope/core/json_text.hpp"
#include "cli/commands.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/congestion/congestion_map.hpp"
#include "trailscope/density/renderer.hpp"

namespace trailscope::cli {

namespace {

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw Error(Error::Kind::internal, "output", "cannot write " + path);
}

// `trailscope tile --congestion`: the density-only options must keep their defaults.
template <typename Opts>
void congestion_tile(const Opts& o, const server::Dataset& ds, const Query& q) {
  if (o.value != "count") throw invalid_argument("value", "--value does not apply to --congestion");
  if (o.kernel != 0) throw invalid_argument("kernel", "--kernel does not apply to --congestion");
  if (!o.backend.empty()) throw invalid_argument("backend", "--backend does not apply to --congestion");
  if (o.min_level) throw invalid_argument("min_level", "--min-level does not apply to --congestion");
  congestion::CongestionTileRequest req;
  req.tile = geo::TileId{o.z, o.x, o.y};
  req.size = o.size;
  if (!o.t.empty()) req.t = parse_time(o.t, "t");
  req.threshold = o.threshold;
  req.vmax = o.vmax;
  req.how = density::parse_how(o.how.empty() ? "linear" : o.how, "how");
  req.cmap = o.cmap;
  const congestion::CongestionTile r = congestion::render_congestion_tile(*ds.trails, q, req);
  write_file(o.out, r.png);
  const nlohmann::json j = {{"output", o.out},
                            {"bytes", r.png.size()},
                            {"max_value", r.max_value},
                            {"pixels_above", r.pixels_above},
                            {"threshold", req.threshold}};
  if (o.json)
    std::cout << json_text(j, 2) << std::endl;
  else
    std::cout << "wrote " << o.out << " (" << r.png.size() << " bytes, " << r.pixels_above
              << " pixels at or above " << req.threshold << " aircraft, largest " << r.max_value << ")\n";
}

}  // namespace

void add_tile(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "tile",
      "Render one density tile (XYZ, Web Mercator) of a dataset to PNG; with --congestion, the "
      "congestion map of simultaneous aircraft (at --t, or averaged over --t0/--t1), thresholded");
  struct Opts {
    std::string data_dir = default_data_dir(), dataset, out, value = "count", how, cmap = "fire", backend, t;
    int z = 0, x = 0, y = 0, size = 256, kernel = 0;
    bool json = false, congestion = false;
    double threshold = 1.0;
    std::optional<double> vmax, min_level;
    QueryFlags flags;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("DATASET", o->dataset, "dataset id")->required();
  cmd->add_option("Z", o->z, "zoom")->required();
  cmd->add_option("X", o->x, "tile column")->required();
  cmd->add_option("Y", o->y, "tile row (0 = north)")->required();
  cmd->add_option("-o,--output", o->out, "PNG file to write")->required();
  cmd->add_option("--data-dir", o->data_dir, "store folder")->capture_default_str();
  cmd->add_option("--value", o->value, "count | altitude | speed")->capture_default_str();
  cmd->add_option("--how", o->how,
                  "linear | log | eq_hist (default eq_hist; --congestion: linear | log, default linear)");
  cmd->add_option("--cmap", o->cmap, "fire | viridis | inferno | magma | gray")->capture_default_str();
  cmd->add_option("--size", o->size, "256 or 512")->capture_default_str();
  cmd->add_option("--kernel", o->kernel, "KDE kernel radius in pixels (0 = none)")->capture_default_str();
  cmd->add_option(
      "--min-level", o->min_level,
      "colormap position [0, 1) of the lowest non-empty pixel (default 0.25 for count, 0 otherwise)");
  cmd->add_option("--backend", o->backend, "cpu | opencl | auto");
  cmd->add_flag("--json", o->json, "print what was rendered as JSON");
  cmd->add_flag("--congestion", o->congestion,
                "the congestion map (simultaneous aircraft per pixel) instead of line density");
  cmd->add_option("--t", o->t, "--congestion: the instant (Unix seconds or ISO 8601), or give --t0 and --t1");
  cmd->add_option("--threshold", o->threshold,
                  "--congestion: aircraft per pixel below which it is transparent")
      ->capture_default_str();
  cmd->add_option("--vmax", o->vmax,
                  "--congestion: aircraft per pixel of the last colour (default 4 x threshold)");
  o->flags.add_to(*cmd);
  cmd->callback([o] {
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    const Query q = parse_query(o->flags.params);
    if (o->congestion) return congestion_tile(*o, *ds, q);
    if (!o->t.empty()) throw invalid_argument("t", "--t applies to --congestion only");
    density::TileRequest req;
    req.tile = geo::TileId{o->z, o->x, o->y};
    req.size = o->size;
    req.value = density::parse_density_value(o->value, "value");
    req.how = density::parse_how(o->how.empty() ? "eq_hist" : o->how, "how");
    req.cmap = o->cmap;
    req.kernel_radius = o->kernel;
    req.min_level = o->min_level;
    req.max_gap_seconds =
        std::numeric_limits<double>::infinity();  // as the tile route: flights are split at ingest
    req.backend = o->backend.empty() ? default_backend() : parse_backend(o->backend, "backend");
    density::DensityRenderer renderer;
    const density::TileResult r = renderer.render_tile(*ds->trails, ds->id + "@" + ds->created, q, req);
    write_file(o->out, r.png);
    const nlohmann::json j = {{"output", o->out},         {"bytes", r.png.size()}, {"empty", r.empty},
                              {"max_count", r.max_count}, {"backend", r.path},     {"ms", r.ms}};
    if (o->json)
      std::cout << json_text(j, 2) << std::endl;
    else
      std::cout << "wrote " << o->out << " (" << r.png.size() << " bytes, " << r.path << ", " << r.ms
                << " ms)\n";
  });
}

}  // namespace trailscope::cli
