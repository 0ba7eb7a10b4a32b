#pragma once
// Dense medial descriptor (DMD) of a grey image: van der Zwan, Meiburg, Telea, "A Dense Medial
// Descriptor for Image Analysis", VISAPP 2013.
//
// Pipeline of run_dmd():
//  1. layer selection: `layers` grey levels v_0 < v_1 < ... chosen from the histogram (v_0 is the
//     image minimum); every pixel is quantised to its nearest level, and layer i is the threshold set
//     T_i = {x : quantised(x) >= v_i}. T_0 is the whole image, the canvas the others are drawn on;
//  2. island removal per layer i >= 1 (medial.hpp, remove_islands), islands and holes smaller than
//     `island` x image area;
//  3. medial axis transform of each layer with its salience (medial.hpp, medial_axis);
//  4. simplification: keep the MAT pixels of salience >= `saliency` (medial.hpp, simplify);
//  5. reconstruction of each layer as the union of its MAT's disks (medial.hpp, inflate);
//  6. stacking: a pixel's layer index is the highest i whose reconstruction covers it, its value v_i,
//     or with `interpolate` a ramp across the band between consecutive layers by the distances to the
//     layer below and above (DMD's interpolation "in the Hausdorff sense", see stack.cpp);
//  7. segmentation from the component tree of the stacked layers (see Segment).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/core/params.hpp"
#include "trailscope/dmd/image.hpp"
#include "trailscope/dmd/medial.hpp"

namespace trailscope::dmd {

/// How the grey levels of the layers are chosen from the image histogram.
enum class LayerSelection {
  cumulative,    ///< equal pixel counts between levels: level k at the k/layers quantile
  local_maxima,  ///< the most populated histogram peaks (a level is a local maximum within min_gap)
};

/// Every DMD parameter, with its default and range. Defaults follow the DMD code's recommendations
/// (the successor DMD code, github.com/rmast/SSDMD-code: 20–40 layers, islands 0.001–0.02 of the area,
/// 5 grey levels apart, saliency thresholds 0.2–2).
struct DmdParams {
  int layers = 20;  ///< number of threshold layers including the canvas v_0; [2, 256]. Fewer are
                    ///< used when the image has fewer distinct levels or min_gap forbids more
  LayerSelection selection = LayerSelection::cumulative;
  int min_gap = 5;          ///< smallest grey-level difference between two selected levels (DMD's
                            ///< distinguishable interval); [1, 128]
  double island = 0.001;    ///< epsilon: islands and holes below this fraction of the image area are
                            ///< removed from every layer; [0, 0.1] (0 keeps all)
  double saliency = 0.5;    ///< sigma: salience threshold of the skeleton (dimensionless, see
                            ///< medial.hpp); [0, 100] (0 keeps the full MAT: exact reconstruction)
  bool interpolate = true;  ///< ramp between consecutive layers instead of flat bands

  /// Throws invalid_argument(name) naming the first parameter out of range, with the message
  /// "<name> must be in [lo, hi] (got v)".
  void validate() const;
};

/// Every parameter of DmdParams, in a stable order (type, default and range as text; numeric ones also
/// with default_number, min, max and integer).
const std::vector<ParamInfo>& parameter_infos();

const char* to_string(LayerSelection s) noexcept;
/// "cumulative" or "local_maxima"; throws invalid_argument(param) otherwise.
LayerSelection parse_layer_selection(std::string_view text, const std::string& param = "selection");

/// What happened to one threshold layer (i >= 1; the canvas has none).
struct LayerInfo {
  int level = 0;                        ///< grey level v_i
  std::int64_t threshold_pixels = 0;    ///< |T_i| before island removal
  IslandStats islands;                  ///< islands and holes removed
  std::int64_t medial_axis_pixels = 0;  ///< full MAT
  std::int64_t skeleton_pixels = 0;     ///< simplified MAT (salience >= saliency)
  std::int64_t reconstructed_pixels = 0;
};

/// Kind of a segment in the component tree of the stacked layers.
enum class SegmentKind {
  canvas,    ///< the pixels of the canvas layer covered by no other layer's reconstruction
  peak,      ///< a branch of the tree ending in a leaf: a local maximum region (e.g. a teat seen
             ///< from below in a near = bright depth image) down to where it meets another branch
  junction,  ///< a region where two or more branches meet, down to where it meets another
};
const char* to_string(SegmentKind k) noexcept;

/// One segment. Label l of the label image is segments[l - 1]; every pixel has a label.
/// Segmentation: the components (8-connected) of the nested sets {layer index >= i} of the stacked
/// reconstruction form a tree. A component with exactly one child component belongs to its child's
/// segment; a leaf or a component with two or more children starts a segment; the canvas is its own
/// segment. So a peak segment is a bright blob down to the level where it merges with a neighbour,
/// the shapes DMD simplification has kept, and noise already removed as islands cannot split it.
/// One exception keeps peaks from swallowing plateaus: a single-child component at least twice the
/// area of its child (a child of at least max(16, island area) px) starts a segment of its own.
struct Segment {
  int label = 0;
  SegmentKind kind = SegmentKind::canvas;
  std::int64_t area = 0;               ///< pixels
  double cx = 0, cy = 0;               ///< centroid, pixel centres at integer coordinates
  double mean_value = 0;               ///< mean input grey over the segment
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< bounding box, inclusive
  int top_level = 0;                   ///< grey level v of the segment's highest layer
  int base_level = 0;                  ///< grey level v of its lowest layer
};

/// Milliseconds per stage. Layers run in parallel (oneTBB), so the per-layer stages (threshold,
/// islands, skeleton = distance/feature transform, medial axis and salience, simplify, reconstruct) are
/// the sums of the layers' wall-clock times, i.e. CPU time; select, stack, segment and total are
/// wall-clock.
struct StageTimes {
  double select_ms = 0, threshold_ms = 0, islands_ms = 0, skeleton_ms = 0, simplify_ms = 0,
         reconstruct_ms = 0, stack_ms = 0, segment_ms = 0, total_ms = 0;
};

struct DmdResult {
  GreyImage reconstruction;
  std::vector<int> levels;              ///< v_0 < v_1 < ... (levels.size() = layers used)
  std::vector<LayerInfo> layers;        ///< layers 1 .. levels.size() - 1
  std::int64_t skeleton_pixels = 0;     ///< simplified MAT pixels over all layers
  std::int64_t medial_axis_pixels = 0;  ///< full MAT pixels over all layers
  std::vector<std::int32_t> labels;     ///< width * height, 1 .. segments.size()
  std::vector<Segment> segments;
  StageTimes times;
};

/// Runs the pipeline above. Throws invalid_argument("image") for an empty or malformed image, or as
/// DmdParams::validate().
DmdResult run_dmd(const GreyImage& image, const DmdParams& params = {});

}  // namespace trailscope::dmd
