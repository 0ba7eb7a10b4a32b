// The public one-layer operations of medial.hpp on top of the transforms in mat.cpp and edt.cpp.
#include "trailscope/dmd/medial.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "dmd/edt.hpp"
#include "dmd/mat.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::dmd {

std::int64_t MedialAxis::pixels() const {
  std::int64_t n = 0;
  for (const auto r2 : squared_radius) n += r2 > 0;
  return n;
}

MedialAxis medial_axis(const BinaryImage& layer) {
  detail::MatWork work = detail::compute_mat(layer);
  MedialAxis axis;
  axis.width = work.w;
  axis.height = work.h;
  axis.squared_radius = std::move(work.mat_r2);
  axis.salience = std::move(work.salience);
  return axis;
}

MedialAxis simplify(const MedialAxis& axis, double sigma) {
  if (!std::isfinite(sigma) || sigma < 0)
    throw invalid_argument("saliency",
                           "saliency must be finite and >= 0 (got " + std::to_string(sigma) + ")");
  MedialAxis out = axis;
  for (std::size_t i = 0; i < out.squared_radius.size(); ++i)
    if (out.squared_radius[i] > 0 && !(out.salience[i] >= sigma)) {
      out.squared_radius[i] = 0;
      out.salience[i] = 0;
    }
  return out;
}

BinaryImage inflate(const MedialAxis& axis) {
  BinaryImage out;
  out.width = axis.width;
  out.height = axis.height;
  if (axis.width < 1 || axis.height < 1) return out;
  detail::union_of_disks(axis.squared_radius.data(), axis.width, axis.height, out.pixels);
  return out;
}

}  // namespace trailscope::dmd
