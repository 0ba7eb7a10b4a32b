// Gaze density tiles on the stimulus grid (tiles.hpp): the flight density stages, fed with points.
#include "trailscope/gazeview/tiles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/kde.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::gazeview {

namespace {
constexpr double kWorld = 4294967296.0;  // 2^32 grid units across the square
constexpr int kTilePx = 256;
constexpr std::int64_t kInt32Max = std::numeric_limits<std::int32_t>::max();

double tile_min_level(const StimulusTileRequest& r) {
  return r.min_level ? *r.min_level : density::kDefaultCountMinLevel;
}

/// NaN for every pixel of `raster` (the inner area of `canvas`) whose centre is outside the stimulus.
void mask_outside(density::Raster& raster, const density::Canvas& inner, const Stimulus& stim) {
  const double side = stim.side();
  for (int j = 0; j < raster.height; ++j) {
    const double cy = (double(inner.origin_y()) + (j + 0.5) * double(inner.pixel_units())) / kWorld * side;
    for (int i = 0; i < raster.width; ++i) {
      const double cx = (double(inner.origin_x()) + (i + 0.5) * double(inner.pixel_units())) / kWorld * side;
      if (cx >= stim.width_px || cy >= stim.height_px)
        raster.values[std::size_t(j) * raster.width + i] = std::numeric_limits<float>::quiet_NaN();
    }
  }
}

void check_points(const GazePoints& p) {
  if (p.y.size() != p.x.size() || p.weight.size() != p.x.size())
    throw invalid_argument("points", "x, y and weight arrays differ in length");
}

bool inside(double x, double y, const Stimulus& stim) {
  return x >= 0 && x < stim.width_px && y >= 0 && y < stim.height_px;  // false for NaN
}
}  // namespace

void validate(const Stimulus& s) {
  if (!std::isfinite(s.width_px) || s.width_px <= 0 || s.width_px > 1e6)
    throw invalid_argument("width_px",
                           "stimulus width must be in (0, 1e6] px, not " + format_double(s.width_px));
  if (!std::isfinite(s.height_px) || s.height_px <= 0 || s.height_px > 1e6)
    throw invalid_argument("height_px",
                           "stimulus height must be in (0, 1e6] px, not " + format_double(s.height_px));
}

Stimulus stimulus_of(const gaze::GazeDataset& ds, const std::vector<std::size_t>& recordings) {
  if (recordings.empty())
    throw Error(Error::Kind::unprocessable, "recording", "the filters select no recording");
  const gaze::ScreenGeometry& g = ds.recordings.at(recordings.front()).geometry;
  if (!g.has_pixels())
    throw Error(Error::Kind::unprocessable, "width_px",
                "recording " + std::to_string(recordings.front()) +
                    " gives no screen size in px (width_px, height_px)");
  const Stimulus s{g.width_px, g.height_px};
  validate(s);
  return s;
}

TileWhat parse_tile_what(std::string_view text, const std::string& param) {
  if (text == "samples") return TileWhat::samples;
  if (text == "fixations") return TileWhat::fixations;
  throw invalid_argument(param, "'" + std::string(text) + "' is not samples or fixations");
}

const char* to_string(TileWhat w) noexcept {
  return w == TileWhat::samples ? "samples" : "fixations";
}

GazePoints gaze_points(const gaze::GazeDataset& ds, const gaze::GazeFilter& f, const gaze::EventParams& p,
                       TileWhat what, std::size_t max_events) {
  GazePoints out;
  if (what == TileWhat::fixations) {
    for (const Fixation& x : view_events(ds, f, p, max_events).fixations) {
      out.x.push_back(x.x), out.y.push_back(x.y), out.weight.push_back(x.duration_ms);
    }
    return out;
  }
  for (std::size_t i : pixel_recordings(ds, f)) {
    const gaze::Recording& r = ds.recordings[i];
    const auto [a, b] = gaze::window_samples(r, f);
    for (std::size_t s = a; s < b; ++s)
      if (r.valid[s] && std::isfinite(r.x[s]) && std::isfinite(r.y[s])) {
        out.x.push_back(r.x[s]), out.y.push_back(r.y[s]), out.weight.push_back(1.0);
      }
  }
  return out;
}

std::int32_t point_weight(double weight) {
  if (!(weight >= 1)) return 1;  // NaN, 0 and fractions of a ms
  return weight >= double(kInt32Max) ? std::int32_t(kInt32Max) : std::int32_t(std::llround(weight));
}

density::Canvas tile_canvas(const geo::TileId& tile, int margin_px) {
  return density::Canvas::for_tile(tile, kTilePx, margin_px);
}

std::int64_t grid_unit(double v, double side) {
  return std::int64_t(std::floor(v / side * kWorld));
}

density::Aggregate aggregate_points(const GazePoints& points, const Stimulus& stim,
                                    const density::Canvas& canvas) {
  check_points(points);
  const double side = stim.side();
  const int w = canvas.width(), h = canvas.height();
  std::vector<std::int64_t> sums(std::size_t(w) * h, 0);
  const std::int64_t p = canvas.pixel_units();
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!inside(points.x[k], points.y[k], stim)) continue;
    const std::int64_t ux = grid_unit(points.x[k], side) - canvas.origin_x();
    const std::int64_t uy = grid_unit(points.y[k], side) - canvas.origin_y();
    if (ux < 0 || uy < 0) continue;
    const std::int64_t i = ux / p, j = uy / p;
    if (i >= w || j >= h) continue;
    sums[std::size_t(j) * w + std::size_t(i)] += point_weight(points.weight[k]);
  }
  density::Aggregate a = density::Aggregate::zeros(w, h, false);
  for (std::size_t k = 0; k < sums.size(); ++k) a.count[k] = std::int32_t(std::min(sums[k], kInt32Max));
  return a;
}

void validate(const StimulusTileRequest& r) {
  geo::validate_tile(r.tile);
  density::colormap(r.cmap, "cmap");
  if (!(r.kernel_radius >= 0) || r.kernel_radius > limits::kMaxKernelRadiusPx)
    throw invalid_argument(
        "kernel_radius", "kernel radius must be in 0.." + std::to_string(limits::kMaxKernelRadiusPx) + " px");
  const double level = tile_min_level(r);
  if (!(level >= 0 && level < 1))
    throw invalid_argument("min_level", "min_level must lie in [0, 1), got " + format_double(level));
}

density::Raster tile_raster(const GazePoints& points, const Stimulus& stim, const StimulusTileRequest& r) {
  validate(stim);
  validate(r);
  const int grow = int(std::ceil(r.kernel_radius));
  const density::Canvas canvas = tile_canvas(r.tile, grow);
  const density::Aggregate agg = aggregate_points(points, stim, canvas);
  density::Raster raster = density::crop(
      r.kernel_radius > 0 ? density::kde_smooth(agg, density::DensityValue::count, r.kernel_radius)
                          : density::to_raster(agg, density::DensityValue::count),
      grow);
  mask_outside(raster, canvas.inner(), stim);
  return raster;
}

density::SpanStats zoom_span(const GazePoints& points, const Stimulus& stim, int z, double kernel_radius) {
  validate(stim);
  check_points(points);
  geo::validate_tile({z, 0, 0});
  const double side = stim.side();
  if (kernel_radius > 0) {
    const int ls = std::min(z, 2);
    const int px = kTilePx << ls;
    const density::Canvas whole(0, 0, std::int64_t{1} << (32 - 8 - ls), px, px, 0);
    const density::Aggregate agg = aggregate_points(points, stim, whole);
    density::Raster raster =
        density::kde_smooth(agg, density::DensityValue::count, std::ldexp(kernel_radius, ls - z));
    mask_outside(raster, whole, stim);
    return density::compute_span(raster, std::ldexp(1.0, 2 * (ls - z)));
  }
  // Exact: every non-empty pixel of the zoom's grid, from the points' pixel keys.
  const int shift = 32 - 8 - z;
  std::vector<std::pair<std::uint64_t, std::int64_t>> keyed;
  keyed.reserve(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!inside(points.x[k], points.y[k], stim)) continue;
    const std::uint64_t i = std::uint64_t(grid_unit(points.x[k], side)) >> shift;
    const std::uint64_t j = std::uint64_t(grid_unit(points.y[k], side)) >> shift;
    keyed.emplace_back((i << 32) | j, point_weight(points.weight[k]));
  }
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  density::Raster sums;
  for (std::size_t a = 0; a < keyed.size();) {
    std::int64_t s = 0;
    std::size_t b = a;
    for (; b < keyed.size() && keyed[b].first == keyed[a].first; ++b) s += keyed[b].second;
    sums.values.push_back(float(std::min(s, kInt32Max)));
    a = b;
  }
  sums.width = int(sums.values.size());
  sums.height = sums.values.empty() ? 0 : 1;
  return density::compute_span(sums);
}

StimulusTile render_stimulus_tile(const GazePoints& points, const Stimulus& stim,
                                  const StimulusTileRequest& r) {
  const density::Raster raster = tile_raster(points, stim, r);
  const density::SpanStats span = zoom_span(points, stim, r.tile.z, r.kernel_radius);
  density::ShadeOptions shade;
  shade.how = r.how;
  shade.cmap = r.cmap;
  shade.min_level = tile_min_level(r);
  StimulusTile out;
  out.image = density::shade(raster, span, shade);
  for (float v : raster.values)
    if (!std::isnan(v)) out.empty = false, out.max_value = std::max(out.max_value, double(v));
  out.png = density::encode_png(out.image);
  return out;
}

density::Legend stimulus_legend(const GazePoints& points, const Stimulus& stim, const StimulusTileRequest& r,
                                int stops) {
  validate(stim);
  validate(r);
  return density::legend(zoom_span(points, stim, r.tile.z, r.kernel_radius), r.how, r.cmap, tile_min_level(r),
                         stops);
}

}  // namespace trailscope::gazeview
