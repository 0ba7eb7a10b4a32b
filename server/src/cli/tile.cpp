#include <fstream>
#include <limits>
#include <iostream>

#include "trailscope/core/json_text.hpp"
#include "cli/commands.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/renderer.hpp"

namespace trailscope::cli {

void add_tile(CLI::App& app) {
  auto* cmd = app.add_subcommand("tile", "Render one density tile (XYZ, Web Mercator) of a dataset to PNG");
  struct Opts {
    std::string data_dir = default_data_dir(), dataset, out, value = "count", how = "eq_hist", cmap = "fire",
                backend;
    int z = 0, x = 0, y = 0, size = 256, kernel = 0;
    bool json = false;
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
  cmd->add_option("--how", o->how, "linear | log | eq_hist")->capture_default_str();
  cmd->add_option("--cmap", o->cmap, "fire | viridis | inferno | magma | gray")->capture_default_str();
  cmd->add_option("--size", o->size, "256 or 512")->capture_default_str();
  cmd->add_option("--kernel", o->kernel, "KDE kernel radius in pixels (0 = none)")->capture_default_str();
  cmd->add_option("--backend", o->backend, "cpu | opencl | auto");
  cmd->add_flag("--json", o->json, "print what was rendered as JSON");
  o->flags.add_to(*cmd);
  cmd->callback([o] {
    server::EmbeddedStore store(o->data_dir);
    const auto ds = store.get(o->dataset);
    const Query q = parse_query(o->flags.params);
    density::TileRequest req;
    req.tile = geo::TileId{o->z, o->x, o->y};
    req.size = o->size;
    req.value = density::parse_density_value(o->value, "value");
    req.how = density::parse_how(o->how, "how");
    req.cmap = o->cmap;
    req.kernel_radius = o->kernel;
    req.max_gap_seconds =
        std::numeric_limits<double>::infinity();  // as the tile route: flights are split at ingest
    req.backend = o->backend.empty() ? default_backend() : parse_backend(o->backend, "backend");
    density::DensityRenderer renderer;
    const density::TileResult r = renderer.render_tile(*ds->trails, ds->id + "@" + ds->created, q, req);
    std::ofstream out(o->out, std::ios::binary);
    out.write(r.png.data(), static_cast<std::streamsize>(r.png.size()));
    if (!out) throw Error(Error::Kind::internal, "output", "cannot write " + o->out);
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
