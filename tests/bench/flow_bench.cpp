// The flow map of the Europe SO6 day end to end: trailscope::flow::flow_image() on the whole day at the
// defaults (256-cell grid, 8 heading sectors, evenly spaced streamlines, CUBu bundling, drawn at level 2)
// and the PNG encoded, repeated; the median run against the 2 s target on this machine's cores.
//
//   flow_bench --file PATH.so6.gz [--reps 5] [--level 2] [--backend cpu|opencl|auto]
//       one record {"bench":"flow", "label", "flights", "points", "grid", "sectors", "lines", "line_points",
//       "width", "height", "png_bytes", "field_ms", "lines_ms", "bundle_ms", "render_ms", "png_ms",
//       "s_min", "s_p50", "s_max", "reps", "threads", "bundle_path", "peak_rss_mib"}
#include <thread>

#include "bench_util.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/flow/render.hpp"
#include "trailscope/ingest/ingest.hpp"

using namespace bench;

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const std::string path = a.get("file");
    if (path.empty()) throw std::invalid_argument("--file PATH.so6.gz is required");
    const int reps = static_cast<int>(a.num("reps", 5));
    const std::string backend_text = a.get("backend");
    const trailscope::Backend backend = backend_text.empty()
                                            ? trailscope::default_backend()
                                            : trailscope::parse_backend(backend_text, "backend");
    const trailscope::TrailSet set = trailscope::ingest::ingest_file(path);
    const trailscope::Query q;  // the whole day
    trailscope::flow::FlowParams p;
    trailscope::flow::FlowRenderParams rp;
    rp.level = std::stod(a.get("level", "2"));
    std::vector<double> ms;
    trailscope::flow::FlowImage last;
    std::size_t png_bytes = 0;
    double png_ms = 0;
    for (int r = 0; r < reps; ++r) {
      const auto t0 = Clock::now();
      trailscope::flow::FlowImage img = trailscope::flow::flow_image(set, q, p, rp, backend);
      const auto t1 = Clock::now();
      const std::string png = trailscope::density::encode_png(img.image);
      png_ms = ms_since(t1);
      ms.push_back(ms_since(t0));
      if (r > 0 && img.map.lines.points() != last.map.lines.points())
        throw std::runtime_error("flow map not deterministic");
      png_bytes = png.size();
      last = std::move(img);
      log("flow run " + std::to_string(r + 1) + ": " + std::to_string(ms.back()) + " ms");
    }
    const Stats st = Stats::of(ms);
    emit({{"bench", "flow"},
          {"label", "so6_europe_day"},
          {"flights", set.num_flights()},
          {"points", set.num_points()},
          {"grid", p.field.grid},
          {"sectors", p.field.sectors},
          {"level", rp.level},
          {"lines", last.map.lines.size()},
          {"line_points", last.map.lines.points()},
          {"width", last.image.width},
          {"height", last.image.height},
          {"png_bytes", png_bytes},
          {"field_ms", last.map.field_ms},
          {"lines_ms", last.map.lines_ms},
          {"bundle_ms", last.map.bundle_ms},
          {"render_ms", last.render_ms},
          {"png_ms", png_ms},
          {"s_min", st.min / 1000.0},
          {"s_p50", st.p50 / 1000.0},
          {"s_max", st.max / 1000.0},
          {"reps", reps},
          {"threads", std::thread::hardware_concurrency()},
          {"bundle_path", last.map.bundled.path},
          {"peak_rss_mib", std::round(peak_rss_mib())}});
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "flow_bench: " << e.what() << "\n";
    return 1;
  }
}
