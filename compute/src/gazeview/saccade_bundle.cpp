// Saccades bundled with CUBu in stimulus pixel space (saccade_bundle.hpp).
#include "trailscope/gazeview/saccade_bundle.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"

namespace trailscope::gazeview {

SaccadeLines saccade_lines(const std::vector<Saccade>& saccades, const Stimulus& stim,
                           const bundling::BundleParams& params) {
  validate(stim);
  params.validate();
  SaccadeLines out;
  out.frame = bundling::Frame::view(0, 0, stim.width_px, stim.height_px, params.size);
  for (const Saccade& s : saccades) {
    if (!std::isfinite(s.x0) || !std::isfinite(s.y0) || !std::isfinite(s.x1) || !std::isfinite(s.y1))
      continue;
    out.px.add_edge(out.frame.to_px_x(s.x0), out.frame.to_px_y(s.y0), out.frame.to_px_x(s.x1),
                    out.frame.to_px_y(s.y1));
  }
  if (out.px.size() == 0)
    throw Error(Error::Kind::unprocessable, "stimulus", "no saccade to bundle in the selected recordings");
  return out;
}

bundling::Bundled bundle_saccades(const std::vector<Saccade>& saccades, const Stimulus& stim,
                                  const bundling::BundleParams& params, Backend backend,
                                  const ProgressFn& progress, const CancelToken* cancel) {
  const SaccadeLines in = saccade_lines(saccades, stim, params);
  return bundling::bundle(in.px, in.frame, params, backend, progress, cancel);
}

}  // namespace trailscope::gazeview
