// Segmentation from the stacked DMD layers (dmd.hpp, Segment): the component tree of the nested
// sets {layer_of >= i}, built level by level with connected components, then collapsed so that a
// component with a single child joins its child's segment, unless the step swallows at least as much
// again as the child already is (a growth of kMaxChainGrowth or more from a child of kMinChainArea
// pixels or more). Such a jump is a peak running into a plateau that never became a leaf of its own
// (a noisy summit whose top layers were all islands): the plateau then starts its own segment
// instead of being claimed by whichever peak touched it first. Small children (a tip's first few
// pixels grow by large factors) never cut.
#include <algorithm>
#include <limits>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "dmd/box.hpp"
#include "dmd/stages.hpp"

namespace trailscope::dmd::detail {
namespace {

constexpr double kMaxChainGrowth = 2.0;
constexpr std::int64_t kMinChainArea = 16;

struct Node {
  int level = 0;
  std::int64_t area = 0;
  int parent = -1;
  int children = 0;
  int only_child = -1;  // valid when children == 1
  int segment = -1;
};

}  // namespace

void segment_layers(const std::vector<std::uint8_t>& layer_of, const GreyImage& image,
                    const std::vector<int>& levels, std::int64_t min_area, std::vector<std::int32_t>& labels,
                    std::vector<Segment>& segments) {
  const int w = image.width, h = image.height;
  const std::size_t n = layer_of.size();
  const int top = static_cast<int>(levels.size()) - 1;
  // Each level's components lie in the bounding box of {layer_of >= level}. The levels' connected
  // components are independent and computed in parallel; linking them into a tree is then one pass
  // over the components and one over the pixels.
  const std::vector<Box> boxes = suffix_boxes(layer_of, w, h, top + 1);
  int present = 0;
  while (present < top && !boxes[present + 1].empty()) ++present;
  struct Level {
    cv::Mat cc, stats;
    int count = 1;
    std::vector<std::size_t> first;  // a pixel (image index) of each component
  };
  std::vector<Level> lv(present + 1);
  tbb::parallel_for(1, present + 1, [&](int level) {
    const Box& box = boxes[level];
    Level& l = lv[level];
    cv::Mat mask(box.height(), box.width(), CV_8UC1), centroids;
    for (int y = 0; y < box.height(); ++y)
      for (int x = 0; x < box.width(); ++x)
        mask.at<std::uint8_t>(y, x) =
            layer_of[static_cast<std::size_t>(y + box.y0) * w + x + box.x0] >= level;
    l.count = cv::connectedComponentsWithStats(mask, l.cc, l.stats, centroids, 8, CV_32S);
    l.first.assign(l.count, n);
    for (int y = 0; y < box.height(); ++y)
      for (int x = 0; x < box.width(); ++x) {
        const int c = l.cc.at<int>(y, x);
        if (c > 0 && l.first[c] == n) l.first[c] = static_cast<std::size_t>(y + box.y0) * w + x + box.x0;
      }
  });
  // The label of image pixel i at a level (0 outside its components).
  auto label_at = [&](int level, std::size_t i) {
    const Box& box = boxes[level];
    return lv[level].cc.at<int>(static_cast<int>(i / w) - box.y0, static_cast<int>(i % w) - box.x0);
  };
  std::vector<int> base(present + 1, 0);  // node id of component 1 of each level
  std::vector<Node> nodes{Node{}};        // node 0: the canvas, level 0, the whole image
  for (int level = 1; level <= present; ++level) {
    const Level& l = lv[level];
    base[level] = static_cast<int>(nodes.size());
    nodes.resize(base[level] + l.count - 1);
    for (int c = 1; c < l.count; ++c) {
      Node& node = nodes[base[level] + c - 1];
      node.level = level;
      node.area = l.stats.at<int>(c, cv::CC_STAT_AREA);
      // the parent is the component of the level below holding any of its pixels (levels are nested)
      node.parent = level == 1 ? 0 : base[level - 1] + label_at(level - 1, l.first[c]) - 1;
      Node& parent = nodes[node.parent];
      parent.only_child = base[level] + c - 1;
      ++parent.children;
    }
  }
  std::vector<std::int32_t> deepest(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (layer_of[i] > 0) deepest[i] = base[layer_of[i]] + label_at(layer_of[i], i) - 1;

  // Segments, children before parents (nodes were created level by level).
  int next_segment = 0;
  for (int id = static_cast<int>(nodes.size()) - 1; id >= 0; --id) {
    Node& node = nodes[id];
    bool joins = id != 0 && node.children == 1;
    if (joins) {
      const Node& child = nodes[node.only_child];
      joins = child.area < std::max(kMinChainArea, min_area) ||
              double(node.area) < kMaxChainGrowth * double(child.area);
    }
    node.segment = joins ? nodes[node.only_child].segment : next_segment++;
  }
  std::vector<SegmentKind> kind(next_segment, SegmentKind::junction);
  std::vector<int> top_level(next_segment, 0), base_level(next_segment, 256);
  for (int id = 0; id < static_cast<int>(nodes.size()); ++id) {
    const Node& node = nodes[id];
    const int s = node.segment;
    if (id == 0)
      kind[s] = SegmentKind::canvas;
    else if (node.children == 0)
      kind[s] = SegmentKind::peak;  // a cut chain's upper part keeps the leaf; its lower part is a junction
    top_level[s] = std::max(top_level[s], levels[node.level]);
    base_level[s] = std::min(base_level[s], levels[node.level]);
  }

  // Labels in raster order of first appearance, statistics over the pixels.
  std::vector<int> label_of(next_segment, 0);
  segments.clear();
  labels.assign(n, 0);
  std::vector<double> sx, sy, sv;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      const int s = nodes[deepest[i]].segment;
      if (label_of[s] == 0) {
        Segment seg;
        seg.label = static_cast<int>(segments.size()) + 1;
        seg.kind = kind[s];
        seg.x0 = seg.x1 = x;
        seg.y0 = seg.y1 = y;
        seg.top_level = top_level[s];
        seg.base_level = base_level[s];
        segments.push_back(seg);
        sx.push_back(0);
        sy.push_back(0);
        sv.push_back(0);
        label_of[s] = seg.label;
      }
      const int l = label_of[s];
      labels[i] = l;
      Segment& seg = segments[l - 1];
      ++seg.area;
      seg.x0 = std::min(seg.x0, x);
      seg.x1 = std::max(seg.x1, x);
      seg.y0 = std::min(seg.y0, y);
      seg.y1 = std::max(seg.y1, y);
      sx[l - 1] += x;
      sy[l - 1] += y;
      sv[l - 1] += image.pixels[i];
    }
  }
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const double a = double(segments[k].area);
    segments[k].cx = sx[k] / a;
    segments[k].cy = sy[k] / a;
    segments[k].mean_value = sv[k] / a;
  }
}

}  // namespace trailscope::dmd::detail
