#pragma once
// One binary layer of the DMD: island removal, the medial axis transform (MAT) with its salience,
// simplification and reconstruction by inflating the MAT's disks. The grey pipeline (dmd.hpp) runs
// these per threshold layer; they are public so that each step can be checked on its own.
//
// Geometry. Outside the image counts as outside the shape. The distance of an inside pixel p is
// D(p) = squared Euclidean distance to the nearest outside pixel centre (exact, integer), and its
// disk is {x : |x - p|^2 < D(p)}: every such disk lies inside the shape, and each inside pixel lies
// in its own disk, so the union of all disks is the shape.
//
// Medial axis. p is on the MAT unless an 8-neighbour q has a disk containing p's disk, tested
// exactly on the lattice disks (not on the continuous disks, whose test fails off the grid
// directions). Containment is transitive and D strictly grows along such a chain, so the MAT's disks
// still cover the shape exactly: the reconstruction from the full MAT is the shape. (Looking at 8
// neighbours only, a few non-maximal pixels stay on the MAT; simplification removes them.)
//
// Salience (the simplification measure; the method of the AFMM "boundary collapse" importance
// [Telea & van Wijk 2002] on an exact feature transform, normalised as in saliency skeletons
// [Telea 2012]): each inside pixel gets its feature point, the nearest outside pixel, and that
// point's arc-length position along the traced boundary of the shape. The importance rho(p) is the
// largest boundary distance (the shorter way round the contour) between p's feature point and an
// 8-neighbour's: the length of boundary that collapses onto p. Feature points on different contours
// (the two sides of a loop around a hole) give rho = +infinity. The salience is rho(p) / sqrt(D(p)):
// about 2 along the branch of a right-angled corner, pi at the centre of a disk, and small on the
// spurious MAT pixels of discretisation and on boundary noise, whose collapsed boundary is short for
// their depth. Thresholding salience at sigma keeps the MAT pixels with salience >= sigma, so raising
// sigma only removes pixels and sigma = 0 keeps the whole MAT.
#include <cstdint>
#include <vector>

#include "trailscope/dmd/image.hpp"

namespace trailscope::dmd {

/// What remove_islands() changed.
struct IslandStats {
  int islands_removed = 0;  ///< inside components (8-connected) cleared
  int holes_filled = 0;     ///< outside components (4-connected, border ones included) filled
  std::int64_t pixels_cleared = 0;
  std::int64_t pixels_filled = 0;
};

/// Clears every 8-connected inside component with fewer than `min_area` pixels, then fills every
/// 4-connected outside component with fewer than `min_area` pixels (of the cleared layer; outside
/// components touching the image border count too, as in DMD, which removes background islands
/// alike). 8/4 is the usual pair that keeps inside and outside topologies dual. `min_area` <= 1 does
/// nothing. Throws invalid_argument("layer") for a malformed image, ("min_area") for min_area < 0.
IslandStats remove_islands(BinaryImage& layer, std::int64_t min_area);

/// The MAT of one binary layer. `squared_radius[i]` is D of pixel i if it is on the MAT, else 0;
/// `salience[i]` is that pixel's salience (+infinity on loops, 0 off the MAT).
struct MedialAxis {
  int width = 0;
  int height = 0;
  std::vector<std::int32_t> squared_radius;
  std::vector<float> salience;
  std::int64_t pixels() const;  ///< pixels on the (simplified) axis
};

/// The full MAT with salience (see the header comment). Throws invalid_argument("layer") for a
/// malformed image.
MedialAxis medial_axis(const BinaryImage& layer);

/// Keeps the MAT pixels with salience >= sigma (sigma = 0 keeps all). Throws invalid_argument("saliency")
/// unless sigma is finite and >= 0.
MedialAxis simplify(const MedialAxis& axis, double sigma);

/// The union of the disks of `axis` (an exact reverse distance transform, linear in the pixels).
BinaryImage inflate(const MedialAxis& axis);

}  // namespace trailscope::dmd
