#pragma once
// Saccade bundling: every saccade is a straight 2-point trail from its start to its end (fixations.hpp) in
// stimulus pixels, bundled by the project's one CUBu implementation (bundling::bundle, bundling/bundle.hpp:
// van der Zwan, Codreanu, Telea, IEEE TVCG 2016), which resamples each trail at `spl` and moves the
// interior samples; the ends stay where they are (block_endpoints, the default) unless endpoint clustering
// (ms_iterations > 0) is asked for. CUBu's own examples include eye-tracking saccades.
//
// THE FRAME. Bundling runs in the pixels of a `size` x `size` image onto which the stimulus box
// [0, width_px] x [0, height_px] is mapped (bundling::Frame::view: the longer side fills the image, y down
// as in the stimulus), so the kernel radii and steps of BundleParams mean the same on every stimulus of
// one aspect. Saccades that leave the stimulus are kept (the frame maps them beyond the image, where
// they take part in the advection only where the density image reaches).
#include <vector>

#include "trailscope/bundling/bundle.hpp"
#include "trailscope/bundling/params.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/gazeview/fixations.hpp"
#include "trailscope/gazeview/tiles.hpp"

namespace trailscope::gazeview {

struct SaccadeLines {
  bundling::Polylines px;  ///< one 2-point polyline per saccade, in bundle pixels
  bundling::Frame frame;   ///< stimulus px <-> bundle px
};

/// The saccades as bundle input for `params.size`. Saccades with a non-finite end are skipped. Throws
/// what validate(stim) throws and Error(unprocessable, "stimulus", ...) when there is no saccade.
SaccadeLines saccade_lines(const std::vector<Saccade>& saccades, const Stimulus& stim,
                           const bundling::BundleParams& params);

/// saccade_lines, then bundling::bundle (its checks and limits: limits::kMaxBundleEdges and the point
/// limits, Error(payload_too_large, "input", ...); invalid_argument naming a bad parameter; progress and
/// cancel as there). The result's frame maps back to stimulus px (Frame::from_pixels).
bundling::Bundled bundle_saccades(const std::vector<Saccade>& saccades, const Stimulus& stim,
                                  const bundling::BundleParams& params, Backend backend = default_backend(),
                                  const ProgressFn& progress = {}, const CancelToken* cancel = nullptr);

}  // namespace trailscope::gazeview
