#pragma once
// Evenly spaced streamlines (Jobard and Lefer, "Creating evenly-spaced streamlines of arbitrary
// density", Eurographics Workshop on Visualization in Scientific Computing, 1997) traced through one
// sector field (field.hpp), in cell coordinates.
//
// THE FIELD BETWEEN CELLS. (sx, sy, w) are sampled at the cell centres (i + 0.5, j + 0.5) and
// interpolated bilinearly; the DOMAIN is the square spanned by the centres, [0.5, nx − 0.5] ×
// [0.5, ny − 0.5] (inside it the interpolation is exact for a linear field). A line moves along the
// unit direction d = (sx, sy)/|(sx, sy)|, so its step is arc length.
//
// THE ALGORITHM (Jobard & Lefer, section 3). A line is traced from its seed forward along d and
// backward along −d, with a classical Runge–Kutta step of `step` cells (RK2: midpoint; RK4), and stops
// where the next point
//   - leaves the domain;
//   - has w < min_traffic, or coherence |(sx, sy)|/w < min_coherence (flows that cancel: no direction);
//   - is closer than d_test to a point of another line (of the same field), or closer than d_test to a
//     point of its own line more than 3·d_test of arc length back (a closed or spiralling line);
//   - turns back (its step direction and the previous one have a negative dot product);
//   - or the line reached max_line_points.
// The points then run in the direction of the flow (the backward half reversed, then the forward half).
// A line shorter than min_length is dropped. Seeds: the first line starts at the cell centre of highest
// w (ties: lowest index); every accepted line is queued, and for each of its points the two candidates
// at distance d_sep on either side (along the normal of its local direction) become the seeds of new
// lines when they are in the domain, pass the traffic and coherence thresholds and are at least d_sep
// from every point of every line. When the queue is empty, the cell centres in order of decreasing w
// (ties: lower index first) that pass those tests seed new lines in turn (disconnected parts of the
// traffic), until none is left. Deterministic: the same field and parameters give the same lines.
//
// GUARANTEE (tested): any point of a line is at least d_test from every point of every other line.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/bundling/polylines.hpp"
#include "trailscope/core/params.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/flow/field.hpp"

namespace trailscope::flow {

enum class Integrator { rk2, rk4 };

struct StreamlineParams {
  double d_sep = 3;     ///< seed separation, cells; 0.5..64
  double d_test = 0.5;  ///< stop distance as a fraction of d_sep (Jobard & Lefer's 0.5); 0.1..1
  double step = 0.5;    ///< integration step, cells of arc length; 0.05..d_sep
  Integrator integrator = Integrator::rk4;
  double min_length = 6;       ///< shorter lines are dropped, cells; 0..1000
  double min_traffic = 2;      ///< w below which there is no flow (≈ flights crossing a cell); >= 0
  double min_coherence = 0.3;  ///< |(sx, sy)|/w below which directions cancel; 0..1
  int max_line_points = 4000;  ///< points per line at most; 2..100000
  /// Throws invalid_argument naming the first bad field (its name as above; `integrator`).
  void validate() const;
  /// Sets field `name` from text; throws invalid_argument(name) for an unknown name or a bad value.
  void set(std::string_view name, std::string_view value);
  /// An upper bound on the points of all lines in an nx × ny field: lines keep d_test apart, so their
  /// points (step apart along a line) pack at most ~ area / (d_test · step), plus one line's worth per
  /// seed cell on the border. Used to refuse a request before tracing (limits::kMaxFlowLinePoints).
  double max_points(int nx, int ny) const;
};

/// The parameter table (the CLI's --help and the route's documentation).
const std::vector<ParamInfo>& streamline_parameter_infos();
Integrator parse_integrator(std::string_view text, const std::string& param = "integrator");
const char* to_string(Integrator i) noexcept;

struct Streamlines {
  bundling::Polylines lines;   ///< cell coordinates, each in the direction of the flow
  std::vector<float> traffic;  ///< per point, the interpolated w
};

/// Traces the evenly spaced streamlines of `field` on an nx × ny grid. Throws invalid_argument as
/// validate(), Error(payload_too_large, `d_sep`) when the lines would pass `max_points` points (checked
/// while tracing; callers check max_points() first), Error(cancelled) when `cancel` is set.
Streamlines evenly_spaced_streamlines(const SectorField& field, int nx, int ny,
                                      const StreamlineParams& params,
                                      std::size_t max_points = limits::kMaxFlowLinePoints,
                                      const CancelToken* cancel = nullptr);

}  // namespace trailscope::flow
