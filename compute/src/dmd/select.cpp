// Layer selection from the histogram (DMD keeps only "relevant" threshold sets: van der Zwan, Meiburg, Telea,
// VISAPP 2013).
#include <algorithm>
#include <cstdint>
#include <cstdlib>

#include "dmd/stages.hpp"

namespace trailscope::dmd::detail {
namespace {

// Cumulative: level k at the k/layers quantile of the pixel values, so each band between levels
// holds about the same number of pixels. A quantile closer than min_gap to the previous level moves
// up to the next present value at least min_gap above it, so that a tall histogram spike (e.g. the
// holes of a depth frame) does not swallow levels.
std::vector<int> cumulative(const std::array<std::int64_t, 256>& hist, std::int64_t total, int first,
                            const DmdParams& p) {
  std::vector<int> levels{first};
  std::array<std::int64_t, 256> cum{};  // pixels <= g
  std::int64_t run = 0;
  for (int g = 0; g < 256; ++g) cum[g] = run += hist[g];
  for (int k = 1; k < p.layers; ++k) {
    const double target = double(k) * double(total) / p.layers;
    int q = 0;
    while (q < 255 && double(cum[q]) <= target) ++q;
    int g = std::max(q, levels.back() + p.min_gap);
    while (g < 256 && hist[g] == 0) ++g;
    if (g > 255) break;
    if (g > levels.back()) levels.push_back(g);
  }
  return levels;
}

// Local maxima: values whose count is the largest within +-min_gap, taken by decreasing count while
// they stay min_gap apart from each other and from the minimum.
std::vector<int> local_maxima(const std::array<std::int64_t, 256>& hist, int first, const DmdParams& p) {
  std::vector<int> peaks;
  for (int g = first + 1; g < 256; ++g) {
    if (hist[g] == 0) continue;
    bool peak = true;
    for (int o = std::max(0, g - p.min_gap); o <= std::min(255, g + p.min_gap) && peak; ++o)
      if (o != g && (hist[o] > hist[g] || (hist[o] == hist[g] && o < g))) peak = false;
    if (peak) peaks.push_back(g);
  }
  std::stable_sort(peaks.begin(), peaks.end(), [&](int a, int b) { return hist[a] > hist[b]; });
  std::vector<int> levels{first};
  for (const int g : peaks) {
    if (static_cast<int>(levels.size()) >= p.layers) break;
    bool apart = true;
    for (const int l : levels) apart = apart && std::abs(l - g) >= p.min_gap;
    if (apart) levels.push_back(g);
  }
  std::sort(levels.begin(), levels.end());
  return levels;
}

}  // namespace

std::vector<int> select_levels(const GreyImage& image, const DmdParams& params) {
  std::array<std::int64_t, 256> hist{};
  for (const auto v : image.pixels) ++hist[v];
  int first = 0;
  while (hist[first] == 0) ++first;  // the image is non-empty (checked by run_dmd)
  if (params.selection == LayerSelection::local_maxima) return local_maxima(hist, first, params);
  return cumulative(hist, static_cast<std::int64_t>(image.pixels.size()), first, params);
}

std::array<std::uint8_t, 256> nearest_level_index(const std::vector<int>& levels) {
  std::array<std::uint8_t, 256> idx{};
  std::size_t k = 0;
  for (int g = 0; g < 256; ++g) {
    while (k + 1 < levels.size() && levels[k + 1] - g < g - levels[k]) ++k;
    idx[g] = static_cast<std::uint8_t>(k);
  }
  return idx;
}

}  // namespace trailscope::dmd::detail
