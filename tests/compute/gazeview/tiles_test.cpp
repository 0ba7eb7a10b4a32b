// Gaze density tiles on the stimulus grid (gazeview/tiles.hpp) against brute-force binning done here with
// floating-point pixel sizes, and the raw Lund TSV read here line by line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/kde.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/gazeview/tiles.hpp"

using namespace trailscope;
using namespace trailscope::gazeview;
using trailscope::test::shared_data;

namespace {

// Brute force: pixel (i, j) of tile (z, tx, ty) holds the weights of the points in
// [ (tx·256 + i)·s, (tx·256 + i + 1)·s ) x ..., s = side / (256·2^z) stimulus px.
std::map<std::pair<int, int>, double> binned(const GazePoints& p, const Stimulus& st, int z, int tx, int ty) {
  std::map<std::pair<int, int>, double> out;
  const double s = st.side() / (256.0 * std::pow(2.0, z));
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (!(p.x[k] >= 0 && p.x[k] < st.width_px && p.y[k] >= 0 && p.y[k] < st.height_px)) continue;
    const int i = int(std::floor(p.x[k] / s)) - tx * 256, j = int(std::floor(p.y[k] / s)) - ty * 256;
    if (i < 0 || j < 0 || i >= 256 || j >= 256) continue;
    out[{i, j}] += std::max(1.0, std::round(p.weight[k]));
  }
  return out;
}

GazePoints some_points() {
  // Points at pixel-centre-ish positions (never on a pixel edge at zooms 0..2 of a 1000 x 600 stimulus,
  // whose pixels at zoom z are 1000/256/2^z px), a few off the stimulus, some fixation-like weights.
  GazePoints p;
  std::uint64_t h = 12345;
  for (int k = 0; k < 3000; ++k) {
    h = h * 6364136223846793005ull + 1442695040888963407ull;
    const double u = double(h >> 11) / 9007199254740992.0;
    h = h * 6364136223846793005ull + 1442695040888963407ull;
    const double v = double(h >> 11) / 9007199254740992.0;
    const double cell = 1000.0 / 1024;  // zoom 2 pixel
    const double x = (std::floor(u * 1100 / cell) + 0.37) * cell - 50;
    const double y = (std::floor(v * 700 / cell) + 0.61) * cell - 50;
    p.x.push_back(x), p.y.push_back(y), p.weight.push_back(k % 3 == 0 ? 1.0 : 20.0 + k % 200);
  }
  return p;
}

}  // namespace

TEST(GazeTiles, RasterEqualsBruteForceBinning) {
  const Stimulus st{1000, 600};
  const GazePoints p = some_points();
  for (int z = 0; z <= 2; ++z)
    for (int tx = 0; tx < (1 << z); ++tx)
      for (int ty = 0; ty < (1 << z); ++ty) {
        SCOPED_TRACE(std::to_string(z) + "/" + std::to_string(tx) + "/" + std::to_string(ty));
        StimulusTileRequest r;
        r.tile = {z, tx, ty};
        const density::Raster got = tile_raster(p, st, r);
        ASSERT_EQ(got.width, 256);
        ASSERT_EQ(got.height, 256);
        const auto want = binned(p, st, z, tx, ty);
        const double s = 1000.0 / (256 * std::pow(2.0, z));
        std::size_t data = 0;
        for (int j = 0; j < 256; ++j)
          for (int i = 0; i < 256; ++i) {
            const float v = got.at(i, j);
            const auto it = want.find({i, j});
            const bool outside = (tx * 256 + i + 0.5) * s >= 1000 || (ty * 256 + j + 0.5) * s >= 600;
            if (it == want.end() || outside) {
              ASSERT_TRUE(std::isnan(v)) << i << "," << j;
            } else {
              ASSERT_EQ(double(v), it->second) << i << "," << j;
              ++data;
            }
          }
        if (z == 0) EXPECT_GT(data, 1000u);
      }
}

TEST(GazeTiles, ExactSpanIsTheZoomsPixels) {
  const Stimulus st{1000, 600};
  const GazePoints p = some_points();
  // The span of zoom 1 = the span of its 4 tiles' pixels together.
  density::Raster all;
  for (int tx = 0; tx < 2; ++tx)
    for (int ty = 0; ty < 2; ++ty) {
      StimulusTileRequest r;
      r.tile = {1, tx, ty};
      const density::Raster t = tile_raster(p, st, r);
      all.values.insert(all.values.end(), t.values.begin(), t.values.end());
    }
  all.width = int(all.values.size()), all.height = 1;
  const density::SpanStats want = density::compute_span(all), got = zoom_span(p, st, 1, 0);
  EXPECT_EQ(got.samples, want.samples);
  EXPECT_EQ(got.lo, want.lo);
  EXPECT_EQ(got.hi, want.hi);
  EXPECT_EQ(got.cdf_values, want.cdf_values);
  EXPECT_EQ(got.cdf, want.cdf);
}

TEST(GazeTiles, SmoothedTilesAreSeamless) {
  // Two neighbouring zoom-1 tiles with a kernel equal the matching halves of one 512 x 256 canvas binned
  // here and smoothed by the density stage's own kde_smooth.
  const Stimulus st{1000, 600};
  const GazePoints p = some_points();
  const double radius = 5;
  const int m = 5;
  const double s = 1000.0 / 512;
  density::Aggregate big = density::Aggregate::zeros(512 + 2 * m, 256 + 2 * m, false);
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (!(p.x[k] >= 0 && p.x[k] < 1000 && p.y[k] >= 0 && p.y[k] < 600)) continue;
    const int i = int(std::floor(p.x[k] / s)) + m, j = int(std::floor(p.y[k] / s)) + m;
    if (j < big.height) big.count[std::size_t(j) * big.width + i] += point_weight(p.weight[k]);
  }
  const density::Raster smooth = density::kde_smooth(big, density::DensityValue::count, radius);
  for (int tx = 0; tx < 2; ++tx) {
    StimulusTileRequest r;
    r.tile = {1, tx, 0};
    r.kernel_radius = radius;
    const density::Raster t = tile_raster(p, st, r);
    for (int j = 0; j < 256; ++j)
      for (int i = 0; i < 256; ++i) {
        const float want = smooth.at(tx * 256 + i + m, j + m);
        const float got = t.at(i, j);
        if ((tx * 256 + i + 0.5) * s >= 1000) {
          ASSERT_TRUE(std::isnan(got));
        } else if (std::isnan(want)) {
          ASSERT_TRUE(std::isnan(got)) << tx << ": " << i << "," << j;
        } else {
          ASSERT_FLOAT_EQ(got, want) << tx << ": " << i << "," << j;
        }
      }
  }
}

TEST(GazeTiles, PngIsTransparentOutsideTheStimulus) {
  const Stimulus st{1000, 600};
  StimulusTileRequest r;
  r.tile = {0, 0, 0};
  const StimulusTile t = render_stimulus_tile(some_points(), st, r);
  EXPECT_FALSE(t.empty);
  const density::Image img = density::decode_png(t.png);
  ASSERT_EQ(img.width, 256);
  EXPECT_EQ(img.rgba, t.image.rgba);
  // Row 200 is below the stimulus (600 / (1000/256) = 153.6 rows).
  for (int i = 0; i < 256; ++i) EXPECT_EQ(img.pixel(i, 200)[3], 0);
  const density::Raster raster = tile_raster(some_points(), st, r);
  int opaque = 0;
  for (int j = 0; j < 256; ++j)
    for (int i = 0; i < 256; ++i) opaque += !std::isnan(raster.at(i, j)) && img.pixel(i, j)[3] == 255;
  EXPECT_EQ(std::size_t(opaque), raster.valid_count());
  EXPECT_EQ(t.max_value, zoom_span(some_points(), st, 0, 0).hi);
}

TEST(GazeTiles, BadRequests) {
  const Stimulus st{1000, 600};
  StimulusTileRequest r;
  r.tile = {1, 2, 0};
  try {
    render_stimulus_tile({}, st, r);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "x");
  }
  r.tile = {0, 0, 0};
  r.kernel_radius = 40;
  try {
    render_stimulus_tile({}, st, r);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "kernel_radius");
  }
  r.kernel_radius = 0;
  try {
    render_stimulus_tile({}, {0, 10}, r);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "width_px");
  }
  EXPECT_TRUE(render_stimulus_tile({}, st, r).empty);
  EXPECT_THROW(parse_tile_what("saccades"), Error);
}

// Real data: every valid sample of a Lund recording drawn on tile 0/0/0 (1024 x 768 image, 4 px per tile
// pixel); the total equals the sample rows counted from the raw TSV (x = y = 0 marks a lost sample).
TEST(GazeTiles, LundSamplesTotal) {
  const auto path = shared_data("gaze/andersson2017_lund/tsv/UL23_img_Europe.tsv");
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header: time_us pupil pupil x_px y_px ...
  std::size_t want = 0;
  std::map<std::pair<int, int>, int> per;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    double t, a, b, x, y;
    ss >> t >> a >> b >> x >> y;
    if (x == 0 && y == 0) continue;
    if (x >= 0 && x < 1024 && y >= 0 && y < 768)
      ++want, ++per[{int(std::floor(x / 4)), int(std::floor(y / 4))}];
  }
  gaze::GazeIngestOptions o;
  const gaze::GazeDataset ds = gaze::read_gaze_file(path.string(), o);
  const GazePoints p = gaze_points(ds, {}, {}, TileWhat::samples, SIZE_MAX);
  StimulusTileRequest r;
  const density::Raster raster = tile_raster(p, {1024, 768}, r);
  double total = 0;
  std::size_t pixels = 0;
  for (float v : raster.values)
    if (!std::isnan(v)) total += v, ++pixels;
  EXPECT_EQ(total, double(want));
  EXPECT_EQ(pixels, per.size());
  for (const auto& [ij, n] : per) ASSERT_EQ(raster.at(ij.first, ij.second), float(n));
}
