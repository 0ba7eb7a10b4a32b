// Frame: the affine map between source coordinates and bundle pixels (bundle.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "trailscope/bundling/bundle.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::bundling {
namespace {

void check_size(int size) {
  if (size < 1) throw invalid_argument("size", "size must be >= 1 px (got " + std::to_string(size) + ")");
}

}  // namespace

Frame Frame::fit(const Polylines& lines, int size, double border, bool flip_y) {
  check_size(size);
  if (!(border >= 0 && border < 0.5))
    throw invalid_argument("border", "border must be in [0, 0.5) (got " + std::to_string(border) + ")");
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
  for (std::size_t i = 0; i < lines.points(); ++i) {
    const double x = lines.x[i], y = lines.y[i];
    if (!std::isfinite(x) || !std::isfinite(y))
      throw Error(Error::Kind::unprocessable, "input", "point " + std::to_string(i) + " is not finite");
    lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x), lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
  }
  if (lines.points() == 0)
    throw Error(Error::Kind::unprocessable, "input", "nothing to fit: the input has no points");
  const double w = hi_x - lo_x, h = hi_y - lo_y, extent = std::max(w, h);
  if (!(extent > 0))
    throw Error(Error::Kind::unprocessable, "input", "nothing to fit: every point of the input is the same");
  Frame f;
  f.size = size;
  f.x0 = lo_x;
  f.y0 = lo_y;
  f.flip_y = flip_y;
  f.scale = (1 - 2 * border) * size / extent;
  // Centred: the shorter side gets the slack on both sides.
  f.offset_x = (size - w * f.scale) / 2;
  f.offset_y = (size - h * f.scale) / 2;
  return f;
}

Frame Frame::view(double x0, double y0, double x1, double y1, int size, bool flip_y) {
  check_size(size);
  if (!(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(x1) && std::isfinite(y1) && x1 > x0 &&
        y1 > y0))
    throw invalid_argument("bbox", "the view box must be finite with x1 > x0 and y1 > y0");
  Frame f;
  f.size = size;
  f.x0 = x0;
  f.y0 = y0;
  f.flip_y = flip_y;
  const double w = x1 - x0, h = y1 - y0;
  f.scale = size / std::max(w, h);
  f.offset_x = (size - w * f.scale) / 2;
  f.offset_y = (size - h * f.scale) / 2;
  return f;
}

double Frame::to_px_x(double x) const {
  return (x - x0) * scale + offset_x;
}
double Frame::to_px_y(double y) const {
  const double v = (y - y0) * scale + offset_y;
  return flip_y ? size - v : v;
}
double Frame::from_px_x(double px) const {
  return (px - offset_x) / scale + x0;
}
double Frame::from_px_y(double py) const {
  const double v = flip_y ? size - py : py;
  return (v - offset_y) / scale + y0;
}

Polylines Frame::to_pixels(const Polylines& lines) const {
  Polylines out;
  out.offsets = lines.offsets;
  out.x.resize(lines.points());
  out.y.resize(lines.points());
  for (std::size_t i = 0; i < lines.points(); ++i)
    out.x[i] = to_px_x(lines.x[i]), out.y[i] = to_px_y(lines.y[i]);
  return out;
}

Polylines Frame::from_pixels(const Polylines& px) const {
  Polylines out;
  out.offsets = px.offsets;
  out.x.resize(px.points());
  out.y.resize(px.points());
  for (std::size_t i = 0; i < px.points(); ++i) out.x[i] = from_px_x(px.x[i]), out.y[i] = from_px_y(px.y[i]);
  return out;
}

}  // namespace trailscope::bundling
