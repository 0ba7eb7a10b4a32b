#pragma once
// Shade: the last stage of the Datashader pipeline (datashader.transfer_functions.shade): numbers →
// colours. A value is first normalised to [0, 1] by `how` against a SpanStats (span.hpp), then looked up
// in a 256-entry colormap (colormap.hpp). Pixels without data (NaN) are fully transparent.
//  - linear: (v − lo) / (hi − lo);
//  - log: (log1p(v − o) − log1p(lo − o)) / (log1p(hi − o) − log1p(lo − o)) with o = min(lo, 0), i.e.
//    Datashader's log1p for non-negative data, shifted for data that goes below 0;
//  - eq_hist: histogram equalisation (Datashader's default): the fraction of the span's samples <= v,
//    interpolated between the span's distinct values and rescaled so that lo maps to 0 and hi to 1.
// Values beyond the span clamp to its ends. Output alpha is 255, or with `alpha_ramp` rises linearly
// from `min_alpha` at 0 to 255 at 1 (Datashader's min_alpha, default 40).
//
// MINIMUM LEVEL. The normalised value t in [0, 1] picks the colormap entry at min_level + t·(1 − min_level)
// instead of t: the lowest non-empty value gets the colour at `min_level`, not the map's first entry.
// Datashader's min_alpha keeps faint data visible on a light background by never letting its alpha reach
// 0; maps such as `fire` start at black instead, so on a dark basemap a single trail (the lowest
// eq_hist bin) is drawn black and disappears. A lightness floor is the same idea for dark backgrounds.
// Empty pixels stay transparent, so "no data" and "little data" still differ.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/density/raster.hpp"
#include "trailscope/density/span.hpp"

namespace trailscope::density {

/// An 8-bit RGBA image, row-major, straight (not premultiplied) alpha, as PNG stores it.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  ///< 4 bytes per pixel
  const std::uint8_t* pixel(int x, int y) const {
    return &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
  }
};

struct ShadeOptions {
  How how = How::eq_hist;
  std::string cmap = "fire";  ///< colormap name (colormap.hpp)
  bool alpha_ramp = false;
  int min_alpha = 40;    ///< 0..255, used with alpha_ramp
  double min_level = 0;  ///< [0, 1): colormap position of the lowest value (see MINIMUM LEVEL)
};

/// The density tiles' minimum level for counts (TileRequest::min_level): a quarter into the map, where
/// `fire` is a clear red (#8f0f00-ish) and `viridis`/`magma`/`inferno` have left their darkest blues.
inline constexpr double kDefaultCountMinLevel = 0.25;

/// Colours `raster` with `span`. Throws invalid_argument naming `cmap` (unknown colormap), `min_alpha`
/// (outside 0..255) or `min_level` (outside [0, 1)).
Image shade(const Raster& raster, const SpanStats& span, const ShadeOptions& options);

}  // namespace trailscope::density
