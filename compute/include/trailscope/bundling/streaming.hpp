#pragma once
// Streaming CUBu bundling: the trails of a sliding time window [t − W, t] kept bundled while a clock
// moves, after Hurter, Ersoy, Telea, "Smooth bundling of large streaming and sequence graphs"
// (PacificVis 2013): KDEEB's advection runs continuously, trails are dropped into the density as they
// arrive and taken out as they expire. The steps are CUBu's (van der Zwan, Codreanu, Telea, IEEE TVCG
// 22(12), 2016; bundle.hpp, THE LOOP), run on the same C++ reference and OpenCL kernels as bundle():
//
//   - A trail ENTERS the window when its first sample is at or before t (t0 <= t) and LEAVES when its
//     last sample falls out of it (t1 < t − W): it is present for clock times t in [t0, t1 + W]. An
//     entering trail is mapped into the frame's pixels, resampled ONCE at arc-length step spl (the
//     resampling of bundle.hpp, with jitter and profile weights; its jitter seeded by (seed, id), so a
//     trail's samples do not depend on what else is in the window) and added unbundled; a persistent
//     trail keeps its bundled points from one update to the next (same point count, so the points
//     correspond); a leaving trail is removed.
//   - Each update runs `iterations` CUBu iterations (splat, convolve, advect, smooth; no resampling)
//     with a FIXED kernel radius h and advection step eps · h px, instead of bundle()'s decay from h
//     to 2 px: the bundles hold their scale while the window slides, and advection moves a point at
//     most eps · h · iterations px per update (then the Laplacian smoothing and the anchor, below, pull
//     it), which bounds the frame-to-frame drift by construction. Then the anchor (ANCHOR below).
//   - Every trail's splat weight is its density weight (weighted: min(1, arc length / size), a trail
//     as long as the image is wide counting fully — fixed against the frame rather than against the
//     longest trail present, so that weights do not jump when the longest trail leaves; count: 1)
//     times its OPACITY, the fade ramp over its life in the window:
//       opacity(t) = clamp(min(t − t0, t1 + W − t) / fade, 0, 1)      (1 when fade = 0)
//     so that a trail grows into the density over `fade` seconds after it enters and shrinks out of it
//     over the `fade` seconds before it leaves: bundles do not pop. The same opacity is reported for
//     drawing.
//
// WHAT A TRAIL IS for flights (flight_stream_source()): a stored flight's WHOLE path (the store splits
// flights at the gap limit), present while its time extent overlaps the window. Its geometry never
// changes while it is present, so its bundled points can persist and move only by bundling; the
// fragment inside the window would change shape at every update (growing at the head, shrinking at the
// tail), need resampling every time and lose the point correspondence that makes the motion smooth.
// The window then shows the route network flown in the last W, and the moving aircraft are drawn over
// it by the animation layer.
//
// ANCHOR. KDEEB with a fixed kernel never stops contracting: every point moves eps · h along the
// normalised gradient at every iteration, so bundles keep merging for as long as trails stay (hundreds of
// updates), and what a trail looks like would depend on how long it has been in the window. After each
// update every point is pulled back a fraction `anchor` of the way to where it entered (its resampled
// input position), as CUBu's relaxation blends toward the original (bundle.hpp, relax()): a point then
// settles where the pull balances the advection, about iterations · eps · h · (1 − anchor) / anchor px
// from its input (12.8 px with the defaults, under half the kernel radius), and the settled state depends
// little on the order in which trails entered, which makes a stream comparable with a from-scratch
// bundling of its window (the measure and its tolerance: tests/compute/bundling/stream_bundle_test.cpp).
//
// THE FRAME is a Frame (bundle.hpp) from source units (flights: 32-bit Web Mercator units) to the
// size × size bundling image: the client's view (Frame::view of its bbox) or the data extent. A new
// frame (the view moved) maps the held points through the old frame back to source units and into the
// new one, so bundles carry over a pan or zoom instead of restarting.
//
// DRIFT. update() reports the mean displacement, in pixels of the frame, of the points of the trails
// present in both this update and the previous one (at the same frame), between the two updates.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "trailscope/bundling/bundle.hpp"
#include "trailscope/bundling/params.hpp"
#include "trailscope/bundling/polylines.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::bundling {

/// Parameters of a streaming bundler. Lengths are pixels of the size × size image.
struct StreamParams {
  int size = 512;               ///< density image edge, px; 64..4096
  double h = 32;                ///< the FIXED kernel radius, px; 2..128 (CUBu's initial radius)
  double eps = 0.05;            ///< advection step as a fraction of h (1.6 px with h = 32); (0, 2]
  int iterations = 2;           ///< CUBu iterations per update; 1..limits::kMaxStreamIterations
  double lambda = 0.2;          ///< Laplacian smoothing strength; 0..1
  double smooth_kernel = 0.05;  ///< Laplacian half-window as a fraction of `size`; 0..0.5
  int smooth_iterations = 1;    ///< Laplacian passes; odd, 1..15
  double spl = 15;              ///< resampling step when a trail enters, px; 1..256
  double jitter = 0.25;         ///< sample jitter as a fraction of spl; 0..1
  std::uint64_t seed = 1;       ///< jitter seed (combined with each trail's id)
  DensityMode density = DensityMode::weighted;
  Profile profile = Profile::uniform;
  bool block_endpoints = true;  ///< trail ends never move
  double anchor = 0.2;          ///< after each update, every point moves back this fraction of the way to
                                ///< its entry position; 0..1 (see ANCHOR at the top)
  double window_s = 3600;       ///< W, seconds; 60..limits::kMaxStreamWindowSeconds
  double fade_s = 300;          ///< fade ramp, seconds; 0..W

  /// Throws invalid_argument naming the first parameter out of range (the field's name).
  void validate() const;
};

/// One trail a stream may hold: a caller's id (unique within a source) and its time extent, Unix
/// seconds, t0 <= t1.
struct StreamTrail {
  std::uint64_t id = 0;
  double t0 = 0, t1 = 0;
};

/// Everything a stream may show, with geometry on demand: `geometry(i, x, y)` fills the points of
/// trails[i] (source units, at least 2, finite) into the cleared vectors x and y. Only entering trails
/// are asked for their geometry.
struct StreamSource {
  std::vector<StreamTrail> trails;
  std::function<void(std::size_t index, std::vector<double>& x, std::vector<double>& y)> geometry;
};

/// Time per phase of one update, milliseconds: wall time on the reference, device time on OpenCL
/// (bundle.hpp, PhaseTimes); total_ms is wall time of the whole update.
struct StreamTimes {
  double select_ms = 0;  ///< finding the present trails, removing the leaving ones, adding (and
                         ///< resampling) the entering ones
  double splat_ms = 0, convolve_ms = 0, advect_ms = 0, smooth_ms = 0;
  double output_ms = 0;  ///< drift and the output polylines
  double total_ms = 0;
};

/// The state after one update.
struct StreamUpdate {
  double t = 0;                   ///< the clock, Unix seconds
  std::uint64_t sequence = 0;     ///< 1 for the first update, then +1
  std::vector<std::uint64_t> id;  ///< per trail held, its id (in the order of `lines`)
  std::vector<float> opacity;     ///< per trail, its fade ramp at t, (0, 1]
  Polylines lines;                ///< per trail, its current points, pixels of the frame
  std::size_t added = 0, removed = 0, persistent = 0;
  double drift_px = 0;      ///< mean displacement of the points of persistent trails since the previous
                            ///< update (0 when there are none, or after a frame change)
  double max_drift_px = 0;  ///< the largest such displacement
  std::string path;         ///< "opencl" or "cpu": where the iterations ran
  StreamTimes times;
};

/// A streaming bundler. Not thread-safe: one owner calls update() at a time.
class StreamingBundler {
 public:
  /// Throws what StreamParams::validate() throws, and invalid_argument(`size`) when frame.size ≠
  /// params.size.
  StreamingBundler(const Frame& frame, const StreamParams& params, Backend backend = default_backend());

  /// Moves the clock to `t` (any direction; a jump simply changes which trails are present) and runs
  /// one update over `source`'s trails present at t. Throws invalid_argument(`t`) for a non-finite t,
  /// Error(payload_too_large, `window`) when more than limits::kMaxStreamTrails trails would be present
  /// or their points would exceed limits::kMaxStreamPoints (checked before any geometry is read; the
  /// state is left as it was), Error(unprocessable, `geometry`) for a trail whose geometry has fewer
  /// than 2 points or a non-finite one, and Error(backend) under opencl_strict() when OpenCL was chosen
  /// and could not run. The source must keep the same id → trail mapping between updates (a new
  /// source: reset()).
  StreamUpdate update(double t, const StreamSource& source);

  /// Changes W (and fade, clamped to the new W): takes effect at the next update. Throws
  /// invalid_argument(`window_s` / `fade_s`).
  void set_window(double window_s, double fade_s);
  /// A new frame (same size): the held points are mapped through the old frame into the new one.
  /// Throws invalid_argument(`size`) when frame.size ≠ params().size.
  void set_frame(const Frame& frame);
  /// Forgets every trail (the next update starts unbundled).
  void reset();

  const Frame& frame() const { return frame_; }
  const StreamParams& params() const { return params_; }
  std::size_t trails() const { return ids_.size(); }

 private:
  Frame frame_;
  StreamParams params_;
  Backend backend_;
  std::uint64_t sequence_ = 0;
  bool frame_changed_ = false;
  // The held trails, in the flat layout of the CUBu steps (pixels).
  std::vector<std::uint64_t> ids_;
  std::vector<double> t0_, t1_;
  std::vector<float> base_weight_;  ///< the density weight before the fade
  std::vector<float> x_, y_, z_;
  std::vector<float> ox_, oy_;  ///< per point, its position when its trail entered (the anchor)
  std::vector<std::uint32_t> offsets_{0};
};

/// The opacity of a trail [t0, t1] at clock t under window W and fade F (see the top).
double stream_opacity(double t, double t0, double t1, double window_s, double fade_s);

/// The stored flights of `trails` as a stream source: one trail per flight that passes the query's
/// flight-level filters (Query::matches_flight_ids: icao24, callsign) and whose position extent meets
/// the query's bbox when it has one (other filters of the query are not used), id = the flight's index
/// in the TrailSet, [t0, t1] = its time extent, geometry = its points in 32-bit Web Mercator units
/// (TrailSet::merc_x/merc_y, x unwrapped along the path as flight_trails() does). `trails` must outlive
/// the source.
StreamSource flight_stream_source(const TrailSet& trails, const Query& filters);

}  // namespace trailscope::bundling
