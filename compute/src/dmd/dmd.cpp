// run_dmd(): the DMD pipeline of dmd.hpp, one threshold layer at a time, with per-stage timings.
#include "trailscope/dmd/dmd.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "dmd/box.hpp"
#include "dmd/edt.hpp"
#include "dmd/islands.hpp"
#include "dmd/mat.hpp"
#include "dmd/stages.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::dmd {
namespace {

using Clock = std::chrono::steady_clock;

// Adds the milliseconds since `t` to `acc` and restarts `t`.
void lap(Clock::time_point& t, double& acc) {
  const auto now = Clock::now();
  acc += std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
}

// What one layer leaves for the stacking: its reconstruction inside `box`.
struct LayerOutput {
  LayerInfo info;
  detail::Box box;
  std::vector<std::uint8_t> covered;  // box-sized
  StageTimes times;                   // this layer's share of the per-layer stages
};

// Threshold, islands, MAT, simplification and reconstruction of layer li (>= 1).
LayerOutput process_layer(int li, const std::vector<std::uint8_t>& quantised, int width, int height,
                          const detail::Box& layer_box, int level, std::int64_t min_area, double saliency) {
  LayerOutput out;
  StageTimes& times = out.times;
  auto t = Clock::now();
  LayerInfo& info = out.info;
  info.level = level;
  const std::int64_t n = std::int64_t(width) * height;
  // The layer is processed in its bounding box plus a one-pixel outside margin: inside components lie
  // in the box, and everything beyond the margin is one outside component whose size is known. Where
  // the margin does not fit in the image, or that component could itself be an island, the whole
  // image is used, so the result is the same either way.
  detail::Box box = layer_box.grown(1, width, height);
  const std::int64_t beyond = n - std::int64_t(box.width()) * box.height();
  const bool cropped = layer_box.inside_with_margin(1, width, height) && beyond >= min_area;
  if (!cropped) box = detail::Box{0, 0, width - 1, height - 1};
  out.box = box;
  BinaryImage mask{box.width(), box.height(),
                   std::vector<std::uint8_t>(std::size_t(box.width()) * box.height())};
  for (int y = 0; y < mask.height; ++y) {
    const std::uint8_t* q = &quantised[static_cast<std::size_t>(y + box.y0) * width + box.x0];
    std::uint8_t* m = &mask.pixels[static_cast<std::size_t>(y) * mask.width];
    for (int x = 0; x < mask.width; ++x) info.threshold_pixels += m[x] = q[x] >= li;
  }
  lap(t, times.threshold_ms);
  info.islands = detail::remove_islands_in(mask, min_area, cropped ? beyond : 0);
  lap(t, times.islands_ms);
  detail::MatWork work = detail::compute_mat(mask);
  info.medial_axis_pixels = work.mat_pixels;
  lap(t, times.skeleton_ms);
  for (std::size_t i = 0; i < work.mat_r2.size(); ++i)
    if (work.mat_r2[i] > 0 && !(work.salience[i] >= saliency)) work.mat_r2[i] = 0;
  for (const auto r2 : work.mat_r2) info.skeleton_pixels += r2 > 0;
  lap(t, times.simplify_ms);
  detail::union_of_disks(work.mat_r2.data(), mask.width, mask.height, out.covered);
  for (const auto c : out.covered) info.reconstructed_pixels += c;
  lap(t, times.reconstruct_ms);
  return out;
}

}  // namespace

DmdResult run_dmd(const GreyImage& image, const DmdParams& params) {
  if (image.width < 1 || image.height < 1 || image.width > 32765 || image.height > 32765 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
    throw invalid_argument("image",
                           "image must be non-empty, at most 32765 px a side, with width * height "
                           "pixels");
  params.validate();
  const auto start = Clock::now();
  auto t = start;
  DmdResult r;
  StageTimes& times = r.times;
  const std::size_t n = image.pixels.size();

  r.levels = detail::select_levels(image, params);
  const auto index = detail::nearest_level_index(r.levels);
  std::vector<std::uint8_t> quantised(n);
  for (std::size_t i = 0; i < n; ++i) quantised[i] = index[image.pixels[i]];
  lap(t, times.select_ms);

  // Islands strictly smaller than island * area go: area < ceil(island * area) in integers.
  const auto min_area = static_cast<std::int64_t>(std::ceil(params.island * double(n)));
  const int levels = static_cast<int>(r.levels.size());
  const std::vector<detail::Box> boxes = detail::suffix_boxes(quantised, image.width, image.height, levels);
  lap(t, times.select_ms);
  // Layers are independent until they are stacked: they run in parallel, and are stacked in order.
  std::vector<LayerOutput> outputs(levels);
  tbb::parallel_for(1, levels, [&](int li) {
    outputs[li] = process_layer(li, quantised, image.width, image.height, boxes[li], r.levels[li], min_area,
                                params.saliency);
  });
  t = Clock::now();  // the parallel section's wall time is in total_ms; its stages are summed below
  std::vector<std::uint8_t> layer_of(n, 0);  // the highest layer whose reconstruction covers a pixel
  for (int li = 1; li < levels; ++li) {
    const LayerOutput& o = outputs[li];
    for (int y = 0; y < o.box.height(); ++y)
      for (int x = 0; x < o.box.width(); ++x)
        if (o.covered[static_cast<std::size_t>(y) * o.box.width() + x])
          layer_of[static_cast<std::size_t>(y + o.box.y0) * image.width + x + o.box.x0] =
              static_cast<std::uint8_t>(li);
    r.skeleton_pixels += o.info.skeleton_pixels;
    r.medial_axis_pixels += o.info.medial_axis_pixels;
    r.layers.push_back(o.info);
    times.threshold_ms += o.times.threshold_ms;
    times.islands_ms += o.times.islands_ms;
    times.skeleton_ms += o.times.skeleton_ms;
    times.simplify_ms += o.times.simplify_ms;
    times.reconstruct_ms += o.times.reconstruct_ms;
  }
  lap(t, times.reconstruct_ms);  // pasting the layers into the stack; the layers' own share is above

  r.reconstruction = detail::stack_layers(layer_of, image.width, image.height, r.levels, params.interpolate);
  lap(t, times.stack_ms);
  detail::segment_layers(layer_of, image, r.levels, min_area, r.labels, r.segments);
  lap(t, times.segment_ms);
  times.total_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return r;
}

}  // namespace trailscope::dmd
