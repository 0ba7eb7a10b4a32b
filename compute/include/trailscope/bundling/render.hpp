#pragma once
// Drawing bundles (CUBu, IEEE TVCG 2016, and its code's gdrawing.cpp): the same canvas → aggregate → shade
// shape as the density path. Lines are drawn into a per-pixel colour accumulation (shortest edges first, each
// point with its colour, alpha and cushion) and into a line density; the style then shades:
//  - lines:  the accumulated colours, alpha-composited;
//  - shaded: the colours lit as a height field: the line density, smoothed with radius shading_radius and
//            normalised by its maximum within local_max_radius, gives normals (∂ρ/∂x, ∂ρ/∂y, −1) and
//            Phong lighting (light (0.4, 0.4, −1), ambient 0.1, diffuse 0.7, specular 10, highlight 8);
//  - tube:   the colours times the locally max-normalised density as luminance.
// Local-maximum normalisation is what makes shading work at all: raw bundle density is close to Dirac.
//
// EXACTLY WHAT IS COMPUTED (all lengths in output pixels; pixel (i, j) is [i, i+1) × [j, j+1)):
//  1. Geometry: relax(bundled, relaxation, params.max_displacement), mapped through the Viewport.
//  2. Line density ρ: every polyline is one run of the exact integer walk of density_lines.hpp (1 px,
//     vertices at 1/256 px), so ρ(p) = the number of polylines passing pixel p.
//  3. ρs = ρ smoothed by density::kde_smooth (Gaussian σ = r/3 cut at r = shading_radius; none at 0).
//  4. ρn = ρs / M with M = the maximum of ρs over the SQUARE |dx|, |dy| <= floor(local_max_radius)
//     (separable, hence cheap; a disc would differ only in its corners), 0 where M = 0.
//  5. Per polyline, its normalised length len = (L − Lmin)/(Lmax − Lmin) over ALL polylines of the
//     bundle (Bundled::length; 1 when all are equal), so a tile colours like the whole image. Per point
//     (arc-length fraction t), the cushion c = 0.2 + 0.8·(1 − 2|t − 0.5|)^0.5, luminance
//     lum = len + (1 − len)·0.5·c and alpha factor ta = (1 − len) + len·0.5·c (cushion()).
//  6. Colour per point: length → rainbow(len); direction → hsv(angle/2π mod 1, len^0.3, 1); flat → 0.9
//     grey; displacement → cmap(d), d = |relaxed − original| / (max_displacement · L) clamped to [0, 1];
//     density → cmap(ρn(p)) per pixel with lum = 1 (CUBu sets it so: the map is the colour). The
//     colouring value v is len (length, direction, flat), d or ρn(p).
//  7. Alpha per point: alpha · {1, v, 1 − v}[alpha_mode] · ta, times ρn(p)^0.3 with alpha_by_density.
//  8. Lines are anti-aliased with a coverage of clamp(line_width/2 + 0.5 − dist, 0, 1), dist from the
//     pixel centre to the segment; colour and alpha are interpolated along each segment (Gouraud, as
//     GL_LINE_STRIP does). A polyline covers a pixel once (with its segment nearest to the pixel centre), so
//     joints and hairpins do not darken; polylines are composited "over" in order of increasing L (ties:
//     input order), fragment colour:
//        lines:  rgb·lum
//        shaded: c = rgb·lum·(0.1 + 0.7·s + 10·s^8), s = max(0, n·l) (light()) with n from the
//                central-difference gradient (edge-clamped) of the height kRelief·max(1, r)·ρn, then c /
//                max(c) where max(c) > 1: the specular highlight is tinted by the line colour (metallic) and
//                the result kept in range by its largest channel (hue and saturation kept), since a thin
//                line lies on its own density ridge where the surface is flat (s ≈ 0.87, 10·s^8 ≈ 3.3)
//                and a white highlight or a per-channel clamp would turn every isolated line white
//        tube:   rgb·lum·ρn(p)
//  9. The result goes over the background (black, white: opaque; transparent: straight alpha).
// Everything is a fixed-order sum over deterministic inputs: the same bytes on every run. Every step
// depends only on the global output pixel grid, not on the viewport's window, which is what lets
// render_bundle_tile cut a seamless map into tiles.
#include <array>
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
  int width = 1024;  ///< output pixels; 16..8192
  int height = 0;    ///< 0 = width · the frame's aspect (a square for a fitted graph)
  Style style = Style::shaded;
  ColorBy color = ColorBy::length;
  AlphaMode alpha_mode = AlphaMode::constant;
  double alpha = 0.6;                ///< global alpha, 0..1
  bool alpha_by_density = false;     ///< multiply alpha by ρn^0.3 (the locally normalised density)
  double shading_radius = 3;         ///< density smoothing for shading, output px; 0..32
  double local_max_radius = 16;      ///< radius of the local-maximum normalisation, output px; 1..256
  double line_width = 1;             ///< px; 0.5..8
  std::string cmap = "viridis";      ///< for density / displacement (density/colormap.hpp names)
  std::string background = "black";  ///< black | white | transparent
  double relaxation = -1;            ///< < 0: the bundle's own params.relaxation; else 0..1
  /// Throws invalid_argument naming the first bad field.
  void validate() const;
  /// Sets field `name` ("style", "color", "alpha_mode", ...) from text; throws invalid_argument(name)
  /// for an unknown name or a bad value, leaving the params unchanged.
  void set(std::string_view name, std::string_view value);

 private:
  void assign(std::string_view name, std::string_view value);
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
  /// The whole bundle image at params.width × params.height. "Whole" is the size × size bundle plane
  /// for a fitted frame (both offsets > 0: Frame::fit's border), and the view's box for a Frame::view
  /// (one offset 0: the box fills one axis; the other axis is cropped to the box, and height 0 follows
  /// the box's aspect). An explicit height is centred on the same area (scale from the width).
  static Viewport whole(const Bundled& b, const RenderParams& params);
};

/// Renders `bundled` through `view` in `params`' style. Deterministic (same bytes on every run).
/// Throws invalid_argument naming a bad field of params (the viewport's size is checked against 1..
/// limits::kMaxBundleImagePx as `width`/`height`, its scale as `scale`), and Error(unprocessable,
/// `bundle`) when the bundle's per-point / per-polyline arrays do not match its lines. Single-threaded
/// except for the density walk; working memory peaks near 40 bytes per output pixel (2.7 GB at 8192²).
density::Image render_bundle(const Bundled& bundled, const RenderParams& params);
density::Image render_bundle(const Bundled& bundled, const RenderParams& params, const Viewport& view);

/// An XYZ map tile of a bundle of flight trails (its frame in 32-bit Web Mercator units): the tile's
/// area with a margin of the shading radii, rendered and cropped, so neighbouring tiles have no seams.
/// params.width/height are ignored (the tile is tile_size²). Throws invalid_argument naming `z`, `x`,
/// `y` (geo::validate_tile), `tile_size` (16..4096) or a field of params, and Error(unprocessable,
/// `frame`) for a frame with flip_y (Mercator y already points down).
density::Image render_bundle_tile(const Bundled& bundled, const RenderParams& params, int z, int x, int y,
                                  int tile_size);

/// The margin (output px) render_bundle_tile draws around a tile: what the smoothing, the local maximum,
/// the gradient and the line width can carry across a tile edge.
int tile_margin_px(const RenderParams& params);
/// The viewport of the tiles_x × tiles_y block of XYZ tiles whose north-west tile is (z, x, y), each
/// tile_size px, grown by margin_px on every side (Mercator frames only, as render_bundle_tile).
Viewport tile_viewport(const Bundled& bundled, int z, int x, int y, int tile_size, int tiles_x = 1,
                       int tiles_y = 1, int margin_px = 0);

// --- the per-point and per-pixel formulas (exposed for tests) ------------------------------------------
using Rgb = std::array<double, 3>;  ///< 0..1
/// CUBu's RAINBOW of v in [0, 1] (clamped): blue (short) → cyan → green → yellow → red (long), Telea's
/// piecewise-linear rainbow with v' = 4.4·v + 0.8: r = (3 − |v'−4| − |v'−5|)/2, g = (4 − |v'−2| −
/// |v'−4|)/2, b = (3 − |v'−1| − |v'−2|)/2, each at least 0 (and at most 1).
Rgb rainbow(double v);
/// HSV → RGB, h in [0, 1) (wrapped), s and v in [0, 1].
Rgb hsv_to_rgb(double h, double s, double v);
struct Cushion {
  double luminance, alpha;
};
/// Step 5 above: len in [0, 1] (normalised length), t in [0, 1] (arc-length fraction).
Cushion cushion(double len, double t);
struct Lighting {
  double diffuse, specular;  ///< 0.1 + 0.7·s and 10·s^8, s = max(0, n·l)
};
/// Phong-like lighting of the height field at a point of gradient (gx, gy) (∂ρ/∂x, ∂ρ/∂y per output px,
/// x right, y down): n = (gx, gy, −1)/|…|, l = (0.4, 0.4, −1)/|…|. Light comes from the upper left:
/// a slope rising toward the lower right (gx, gy > 0) faces it.
Lighting light(double gx, double gy);
/// The gradient scale of the shaded style: the height field is kRelief·max(1, shading_radius)·ρn, so a
/// bundle's flank (about shading_radius wide, ρn rising by ~1) slopes by ~kRelief whatever the radius.
inline constexpr double kRelief = 1.0;

}  // namespace trailscope::bundling
