// Gaze views on the Lund 2013 data (Andersson, Larsson, Holmqvist, Stridh and Nystrom, Behav Res Methods
// 2017): the 4 recordings of the Europe image (1024 x 768 px, 38 x 30 cm at 67 cm), read into memory first.
//  - a stimulus-space density tile (gazeview::render_stimulus_tile: binning, the zoom's exact span, shading,
//    PNG) of every valid sample, tile 1/0/0, without and with a 4 px kernel;
//  - an AOI query (gazeview::view_events with I-VT, then aoi_statistics) with a 3 x 2 grid of rectangles
//    under a polygon of 64 vertices.
//
//   gaze_views_bench --gaze-dir DIR [--reps 10]      (DIR: the gaze folder of the shared data, data/gaze)
//     {"bench":"gaze_views", "op":"tile", "kernel", "points", "ms_p50", "points_per_s_p50", "reps"}
//     {"bench":"gaze_views", "op":"aoi", "aois", "vertices", "samples", "fixations", "ms_p50", "reps",
//      "aoi_only_ms_p50"}
#include <cmath>
#include <filesystem>
#include <limits>

#include "bench_util.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/gazeview/aoi.hpp"
#include "trailscope/gazeview/tiles.hpp"

using namespace bench;
namespace fs = std::filesystem;
namespace gv = trailscope::gazeview;
namespace gz = trailscope::gaze;

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const fs::path dir = a.get("gaze-dir");
    if (dir.empty()) throw std::invalid_argument("--gaze-dir DIR (the data/gaze folder) is required");
    const int reps = static_cast<int>(a.num("reps", 10));
    gz::GazeIngestOptions o;
    o.geometry.width_px = 1024, o.geometry.height_px = 768;
    o.geometry.width_cm = 38, o.geometry.height_cm = 30, o.geometry.distance_cm = 67;
    gz::GazeDataset ds;
    for (const char* name : {"TH34", "UH29", "UH47", "UL23"}) {
      auto one = gz::read_gaze_file(
          (dir / "andersson2017_lund" / "tsv" / (std::string(name) + "_img_Europe.tsv")).string(), o);
      for (auto& r : one.recordings) ds.recordings.push_back(std::move(r));
    }
    const std::size_t all = std::numeric_limits<std::size_t>::max();
    const gv::Stimulus st{1024, 768};

    const gv::GazePoints points = gv::gaze_points(ds, {}, {}, gv::TileWhat::samples, all);
    for (double kernel : {0.0, 4.0}) {
      gv::StimulusTileRequest req;
      req.tile = {1, 0, 0};
      req.kernel_radius = kernel;
      gv::render_stimulus_tile(points, st, req);  // untimed warm-up
      std::vector<double> ms;
      for (int r = 0; r < reps; ++r) {
        const auto t0 = Clock::now();
        const gv::StimulusTile t = gv::render_stimulus_tile(points, st, req);
        ms.push_back(ms_since(t0));
        if (t.empty) throw std::runtime_error("the Lund tile is empty");
      }
      const Stats s = Stats::of(ms);
      json j = {{"bench", "gaze_views"},
                {"op", "tile"},
                {"kernel", kernel},
                {"points", points.size()},
                {"reps", reps}};
      s.put(j, "ms_");
      j["points_per_s_p50"] = std::llround(double(points.size()) / (s.p50 / 1000.0));
      emit(j);
    }

    std::vector<gv::Aoi> aois;
    std::vector<double> px, py;
    for (int k = 0; k < 64; ++k) {
      const double t = 2 * M_PI * k / 64;
      px.push_back(512 + 200 * std::cos(t)), py.push_back(384 + 150 * std::sin(t));
    }
    aois.push_back(gv::Aoi::polygon("centre", px, py));
    for (int gx = 0; gx < 3; ++gx)
      for (int gy = 0; gy < 2; ++gy)
        aois.push_back(gv::Aoi::rect("g" + std::to_string(gx) + std::to_string(gy), gx * 1024.0 / 3,
                                     gy * 384.0, (gx + 1) * 1024.0 / 3, (gy + 1) * 384.0));
    std::vector<double> ms, aoi_ms;
    std::size_t fixations = 0;
    for (int r = 0; r < reps; ++r) {
      const auto t0 = Clock::now();
      const gv::ViewEvents ev = gv::view_events(ds, {}, {}, all);
      const auto t1 = Clock::now();
      const gv::AoiReport rep = gv::aoi_statistics(aois, ev.fixations);
      ms.push_back(ms_since(t0));
      aoi_ms.push_back(ms_since(t1));
      fixations = rep.fixations;
    }
    json j = {{"bench", "gaze_views"},
              {"op", "aoi"},
              {"aois", aois.size()},
              {"vertices", 64 + 6 * 4},
              {"samples", ds.total_samples()},
              {"fixations", fixations},
              {"reps", reps}};
    Stats::of(ms).put(j, "ms_");
    j["aoi_only_ms_p50"] = Stats::of(aoi_ms).p50;
    emit(j);
    return 0;
  } catch (const std::exception& e) {
    log(std::string("gaze_views_bench: ") + e.what());
    return 1;
  }
}
