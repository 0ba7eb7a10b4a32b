#pragma once
// Drawing bundles (research note §1.5; CUBu gdrawing.cpp): the same canvas → aggregate → shade shape as
// the density path. Lines are drawn into a per-pixel colour accumulation (shortest edges first, each
// point with its colour, alpha and cushion) and into a line density; the style then shades:
//  - lines:  the accumulated colours, alpha-composited;
//  - shaded: the colours lit as a height field: the line density, smoothed with radius shading_radius and
//            normalised by its maximum within local_max_radius, gives normals (∂ρ/∂x, ∂ρ/∂y, −1) and
//            Phong lighting (light (0.4, 0.4, −1), ambient 0.1, diffuse 0.7, specular 10, highlight 8);
//  - tube:   the colours times the locally max-normalised density as luminance.
// Local-maximum normalisation is what makes shading work at all: raw bundle density is close to Dirac.
#include <string>
#include <string_view>

#include "trailscope/bundling/bundle.hpp"
#include "trailscope/density/shade.hpp"

namespace trailscope::bundling {

enum class Style { lines, shaded, tube };
enum class ColorBy {
  length,        ///< rainbow by edge length (CUBu's default RAINBOW)
  direction,     ///< hue = angle(end − start)/2π, saturation = (relative length)^0.3
  density,       ///< colour map of the locally normalised density
  displacement,  ///< colour map of the normalised displacement from the original edge
  flat,          ///< grey 0.9
};
enum class AlphaMode {
  constant,  ///< every line `alpha`
  value,     ///< alpha · the colouring value (long edges / dense / displaced are opaque)
  inverse,   ///< alpha · (1 − the colouring value)
};

struct RenderParams {
  int width = 1024;   ///< output pixels; 16..8192
  int height = 0;     ///< 0 = width · the frame's aspect (a square for a fitted graph)
  Style style = Style::shaded;
  ColorBy color = ColorBy::length;
  AlphaMode alpha_mode = AlphaMode::constant;
  double alpha = 0.6;           ///< global alpha, 0..1
  bool alpha_by_density = false;  ///< modulate alpha by the local density
  double shading_radius = 3;    ///< density smoothing for shading, output px; 0..32
  double local_max_radius = 16;  ///< radius of the local-maximum normalisation, output px; 1..256
  double line_width = 1;        ///< px; 0.5..8
  std::string cmap = "viridis";  ///< for density / displacement (density/colormap.hpp names)
  std::string background = "black";  ///< black | white | transparent
  double relaxation = -1;       ///< < 0: the bundle's own params.relaxation; else 0..1
  /// Throws invalid_argument naming the first bad field.
  void validate() const;
  /// Sets field `name` ("style", "color", "alpha_mode", ...) from text; throws invalid_argument(name).
  void set(std::string_view name, std::string_view value);
};

Style parse_style(std::string_view text, const std::string& param = "style");
ColorBy parse_color_by(std::string_view text, const std::string& param = "color");
AlphaMode parse_alpha_mode(std::string_view text, const std::string& param = "alpha_mode");
const char* to_string(Style s) noexcept;
const char* to_string(ColorBy c) noexcept;
const char* to_string(AlphaMode a) noexcept;

/// The part of the bundle's pixel plane an image shows: bundle pixel (bx, by) lands on output pixel
/// ((bx − x0) · scale, (by − y0) · scale).
struct Viewport {
  double x0 = 0, y0 = 0, scale = 1;
  int width = 0, height = 0;
  /// The whole bundle image at params.width × params.height.
  static Viewport whole(const Bundled& b, const RenderParams& params);
};

/// Renders `bundled` through `view` in `params`' style. Deterministic (same bytes on every run).
/// Throws invalid_argument naming a bad field of params.
density::Image render_bundle(const Bundled& bundled, const RenderParams& params);
density::Image render_bundle(const Bundled& bundled, const RenderParams& params, const Viewport& view);

/// An XYZ map tile of a bundle of flight trails (its frame in 32-bit Web Mercator units): the tile's
/// area with a margin of the shading radii, rendered and cropped, so neighbouring tiles have no seams.
density::Image render_bundle_tile(const Bundled& bundled, const RenderParams& params, int z, int x, int y,
                                  int tile_size);

}  // namespace trailscope::bundling
