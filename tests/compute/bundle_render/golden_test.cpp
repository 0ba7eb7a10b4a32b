// Golden images of the bundled US airlines graph (classic/airlines.xml, bundle_ref at default
// parameters), one per style and one per colour mode, compared with tests/golden/bundle_airlines_*.png
// (see tests/golden/README.md). Rendering is deterministic, so they match exactly on the machine that
// wrote them; the tolerance (2/255 per channel on all but 0.1 % of the pixels, as the density goldens)
// absorbs libm differences in pow/sqrt/exp between platforms. TRAILSCOPE_UPDATE_GOLDEN=1 rewrites them.
#include <gtest/gtest.h>

#include "golden.hpp"

#include <cstdlib>
#include <memory>

#include "test_support.hpp"
#include "trailscope/bundling/bundle.hpp"
#include "trailscope/bundling/graph_io.hpp"
#include "trailscope/bundling/render.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::bundling {
namespace {

/// The airlines graph bundled once with the C++ reference at default parameters; nullptr without data.
const Bundled* airlines() {
  static const std::unique_ptr<Bundled> b = []() -> std::unique_ptr<Bundled> {
    const auto path = test::shared_data("bundling/classic/airlines.xml");
    if (!std::filesystem::exists(path)) return nullptr;
    const Graph g = read_graph(path);
    const BundleParams params;
    // GraphML classic has y = −10·lat: already y-down, so no flip.
    const Frame f = Frame::fit(g.edges, params.size, params.border, false);
    return std::make_unique<Bundled>(bundle_ref(f.to_pixels(g.edges), f, params));
  }();
  return b.get();
}

using test::compare_with_golden;

TEST(BundleGolden, AirlinesAtTheDefaults) {
  const Bundled* b = airlines();
  if (!b) GTEST_SKIP() << "shared data absent";
  // RenderParams{}: 1024 px, shaded, coloured by length, alpha 0.6, black.
  compare_with_golden(render_bundle(*b, RenderParams{}), "bundle_airlines_shaded.png");
}

TEST(BundleGolden, AirlinesInEachStyle) {
  const Bundled* b = airlines();
  if (!b) GTEST_SKIP() << "shared data absent";
  for (Style s : {Style::lines, Style::tube}) {
    RenderParams p;
    p.style = s;
    compare_with_golden(render_bundle(*b, p), std::string("bundle_airlines_") + to_string(s) + ".png");
  }
}

TEST(BundleGolden, AirlinesInEachColourMode) {
  const Bundled* b = airlines();
  if (!b) GTEST_SKIP() << "shared data absent";
  // The length colouring is the defaults' image; the others at 512 px in the default (shaded) style.
  for (ColorBy c : {ColorBy::direction, ColorBy::density, ColorBy::displacement, ColorBy::flat}) {
    RenderParams p;
    p.width = 512;
    p.color = c;
    compare_with_golden(render_bundle(*b, p), std::string("bundle_airlines_color_") + to_string(c) + ".png");
  }
}

}  // namespace
}  // namespace trailscope::bundling
