#pragma once
// Depth and amplitude frames as pictures, for the video routes and the live replay: depth colour-mapped
// over a millimetre range with one of the density colormaps (density/colormap.hpp), amplitude as
// log-scaled grey. Also the ground truth of a frame as JSON in the manifest's shape (proto/depth_video.md),
// so that every wire format that carries truth uses the same object.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/density/colormap.hpp"
#include "trailscope/density/shade.hpp"
#include "trailscope/tof/depth_video.hpp"

namespace trailscope::tof {

/// A depth range in mm, min < max.
struct DepthRange {
  double min_mm = 0, max_mm = 0;
};

/// The `lo`-th and `hi`-th quantiles (0 <= lo < hi <= 1, e.g. 0.02 and 0.98) of the valid (non-NaN) depth
/// values, widened to at least 1 mm. A frame without valid pixels gives {0, 1000}: there is nothing to
/// show, and any range draws it all transparent. Throws Error(invalid_argument, "quantile") for bad lo/hi.
DepthRange depth_quantile_range(const std::vector<float>& depth_mm, double lo = 0.02, double hi = 0.98);

/// The quantile range over several frames' pixels together (the replay fixes one range per video from its
/// first frames, so that colours do not flicker from frame to frame).
DepthRange depth_quantile_range(const std::vector<const std::vector<float>*>& frames, double lo = 0.02,
                                double hi = 0.98);

class DepthVideoReader;
/// Frames video_depth_range reads.
inline constexpr std::size_t kDepthRangeFrames = 10;
/// One colour range for a whole video: depth_quantile_range over its first kDepthRangeFrames frames'
/// pixels together, so that colours do not flicker from frame to frame (the live replay and the stored
/// video's "depth_range_mm" use it). Throws as DepthVideoReader::read_frame.
DepthRange video_depth_range(const DepthVideoReader& reader);

/// Depth as RGBA, width * height values row-major: NEAR IS THE BRIGHT END of the colormap (index 255 at
/// range.min_mm, 0 at range.max_mm; values beyond clamp), since what a tracker looks for (teat tips) is
/// nearest the camera. Holes (NaN) are transparent black. Throws Error(invalid_argument, "min") when
/// !(min < max) or either is not finite, Error(invalid_argument, "depth") when the size does not match.
density::Image render_depth(const std::vector<float>& depth_mm, int width, int height,
                            const DepthRange& range, const density::Colormap& cmap);

/// Amplitude as opaque grey: log1p(a) / log1p(a_max) with a_max the frame's largest value (black when all
/// are 0). An empty vector (a video without amplitude) gives an all-black image. Throws
/// Error(invalid_argument, "amplitude") when a non-empty vector's size does not match.
density::Image render_amplitude(const std::vector<float>& amplitude, int width, int height);

/// {"teats": [{name, tip_mm, tip_px, visible, visible_fraction, box_px, cup_attached} x 4]}: the object
/// manifest.json holds per frame (box_px = [x, y, w, h] px or null, tip_px = [u, v] px or null).
nlohmann::json truth_to_json(const FrameTruth& truth);

}  // namespace trailscope::tof
