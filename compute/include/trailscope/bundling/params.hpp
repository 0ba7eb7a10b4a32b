#pragma once
// Every parameter of CUBu bundling (van der Zwan, Codreanu, Telea, "CUBu: Universal Real-Time Bundling
// for Large Graphs", IEEE TVCG 22(12), 2016) with its default and range. Names follow the paper's code
// (CPUBundling and its batch front-end) where it has one; lengths are in pixels of the
// bundling image (`size` × `size`), into which the input is fitted (bundle.hpp, Frame).
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/core/params.hpp"

namespace trailscope::bundling {

/// How points are splatted into the density image. Both are deterministic (integer atomics), unlike
/// the original FAST mode's racy float `+=`.
enum class DensityMode {
  weighted,  ///< each point adds its edge's length / the longest edge's length, in fixed point
             ///< (kSplatScale), the original FAST mode's weight
  count,     ///< each point adds 1, the original EXACT mode
};
/// How strongly each point along an edge moves (the edge profile, z in the original).
enum class Profile {
  uniform,    ///< 1 everywhere: classical (FDEB-like) bundles
  hourglass,  ///< ((1−x)/0.3)^4 on the outer 30 % at each end (x = distance from the midpoint / half
              ///< length), 1 elsewhere: the ends stay near the original edge (HEB-like)
};

struct BundleParams {
  int size = 512;               ///< density image edge, px (fboSize); 64..4096
  double h = 32;                ///< initial kernel radius, px; 2..128 (257 taps at most)
  int iterations = 15;          ///< niter; 1..100. The kernel shrinks by (2/h)^(1/iterations) each time
  double eps = 0.5;             ///< advection step as a fraction of the current kernel radius; (0, 2]
  double lambda = 0.2;          ///< Laplacian smoothing strength; 0..1
  double smooth_kernel = 0.05;  ///< Laplacian half-window as a fraction of `size`; 0..0.5
  int smooth_iterations = 1;    ///< Laplacian passes (liter); odd, 1..15
  double spl = 15;              ///< resampling step, px; 1..256
  double jitter = 0.25;         ///< sample jitter as a fraction of spl; 0..1
  std::uint64_t seed = 1;       ///< jitter seed: the same input, parameters and seed give the same bytes
  DensityMode density = DensityMode::weighted;
  Profile profile = Profile::uniform;
  bool block_endpoints = true;  ///< endpoints never move (profile 0 at both ends)
  bool polyline_style = false;  ///< resample only in the first iteration
  double border = 0.1;          ///< fraction of `size` left empty around a fitted drawing; 0..0.45
  // endpoint mean-shift clustering (off when ms_iterations = 0)
  int ms_iterations = 0;     ///< niter_ms; 0..50
  double ms_h = 32;          ///< initial mean-shift kernel radius, px; 2..128
  double lambda_ends = 0.5;  ///< smoothing of the end segments after clustering; 0..1
  // directional bundling: the direction of each point is kept in its own field
  bool directional = false;  ///< parallel edges attract, antiparallel ones repel (tangent)
  double repulsion = 1;      ///< strength of the repulsion of antiparallel edges (rep_strength); 0..10
  // post-processing (cheap; the client can also redo relaxation without recomputing)
  double relaxation = 0;          ///< 0 = fully bundled, 1 = the original edges; 0..1
  double max_displacement = 0.2;  ///< cap of a point's displacement, fraction of its edge's length; 0..10
  double dir_separation = 0;      ///< lane offset of the two directions of a bundle, px; 0..50

  /// Throws invalid_argument naming the first parameter out of range (its name as in parameter_names()).
  void validate() const;
  /// Sets parameter `name` from text ("32", "true", "hourglass"); throws invalid_argument(name) for an
  /// unknown name or a value that does not parse or is out of range.
  void set(std::string_view name, std::string_view value);
  /// name → value as text, every parameter (for results and the run header).
  std::map<std::string, std::string> to_map() const;
};

/// Every parameter of BundleParams, in a stable order (type, default and range as text; numeric ones
/// also with unit, default_number, min, max and integer).
const std::vector<ParamInfo>& parameter_infos();

const char* to_string(DensityMode m) noexcept;
const char* to_string(Profile p) noexcept;

/// Fixed-point scale of the weighted splat: a point of weight w adds round(w · kSplatScale) to a
/// 32-bit pixel counter, so 4 million full-weight points can meet on one pixel before it wraps.
inline constexpr double kSplatScale = 1024.0;

}  // namespace trailscope::bundling
