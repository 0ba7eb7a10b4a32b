// Reference versus OpenCL for density_lines: the same public call with the backend switched, in strict
// mode so that a silent fallback to the reference cannot make the comparison pass. Tolerance: none — the
// kernel uses integer atomics only, so the aggregates must be bit-identical.
#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <thread>

#include "strict_opencl.hpp"
#include "../density/density_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/density.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::density {
namespace {
using test::Seg;
constexpr std::int64_t kWorld = std::int64_t{1} << 32;

class DensityLinesOcl : public test::StrictOpenCl {
 protected:
  // Runs both backends and checks they agree exactly; returns the aggregate.
  static Aggregate both(const LineSegments& s) {
    const Aggregate ref = density_lines(s, Backend::cpu);
    const Aggregate ocl = density_lines(s, Backend::opencl);
    EXPECT_EQ(ref.path, ComputePath::cpu);
    EXPECT_EQ(ocl.path, ComputePath::opencl);
    EXPECT_TRUE(ocl.same_numbers(ref)) << "OpenCL and reference differ on " << s.size() << " segments";
    EXPECT_TRUE(density_lines_ref(s).same_numbers(ref));
    return ref;
  }
};

TEST_F(DensityLinesOcl, RandomSegmentsBitIdentical) {
  std::mt19937 rng(4242);
  const std::vector<Canvas> canvases = {Canvas(0, 0, 1, 40, 30), Canvas(1000, 2000, 16, 256, 256),
                                        Canvas(-7 * 33, 5 * 33 + 3, 33, 300, 200),
                                        Canvas(kWorld - 20 * 64, 100, 64, 512, 384)};
  for (const Canvas& c : canvases)
    for (bool with_value : {false, true}) {
      const LineSegments s = test::prepare(test::random_segments(rng, c, 5000, 0.5), c, with_value, &rng);
      const Aggregate a = both(s);
      EXPECT_GT(a.total_count(), 0u);
    }
}

TEST_F(DensityLinesOcl, ManySegmentsTakeTheParallelReferencePath) {
  // Enough segments for the TBB reference (per-thread grids) and heavy atomic contention on the device.
  std::mt19937 rng(1);
  const Canvas c(0, 0, 1 << 12, 256, 256);
  const LineSegments s = test::prepare(test::random_segments(rng, c, 60000, 0.2), c, true, &rng);
  ASSERT_GE(s.size(), 16384u);
  both(s);
}

TEST_F(DensityLinesOcl, EdgeCases) {
  const std::int64_t p = 1 << 16;
  const Canvas tile(10 * 256 * p, 20 * 256 * p, p, 256, 256);  // a 256 px tile
  const std::int64_t x0 = tile.origin_x(), y0 = tile.origin_y(), x1 = tile.end_x(), y1 = tile.end_y();
  std::vector<Seg> segs = {
      {{x0, y0}, {x1, y0}},                                      // along the north edge (inside: half-open)
      {{x0, y1}, {x1, y1}},                                      // along the south edge (outside)
      {{x0, y0}, {x0, y1}},                                      // along the west edge (inside)
      {{x1, y0}, {x1, y1}},                                      // along the east edge (outside)
      {{x0 - 5 * p, y0 - 5 * p}, {x1 + 5 * p, y1 + 5 * p}},      // corner to corner through the tile
      {{x1 + 3, y0 - 3}, {x0 - 3, y1 + 3}},                      // the other diagonal, just off the corners
      {{x0 + 100 * p + 7, y0 + 9}, {x0 + 100 * p + 7, y0 + 9}},  // zero length
      {{x0 + 3 * p, y0 + 40 * p + 1}, {x0 + 200 * p, y0 + 40 * p + 1}},  // horizontal
      {{x0 + 77 * p, y0 - 1000 * p}, {x0 + 77 * p, y1 + 1000 * p}},      // vertical, long
      {{x1 + p, y0}, {x1 + 900 * p, y1}},                                // entirely outside
      {{0, 0}, {kWorld - 1, kWorld - 1}},                                // huge: the world's diagonal
      {{x0 - kWorld / 3, y0 + 17}, {x1 + kWorld / 7, y1 - 17}},          // huge, clipped on both sides
      {{x0 + 5, y0 + 5}, {x0 + 5 + kWorld / 2 + 10, y0 + 5}},  // > half a world: drawn the other way
  };
  LineSegments s = test::prepare(segs, tile);
  both(s);
  EXPECT_EQ(both(s).count, test::brute_counts(segs, tile));
  // Runs (first pixel left out) and values.
  LineSegments runs = LineSegments::for_canvas(tile, true);
  for (std::size_t k = 0; k < segs.size(); ++k)
    append_segment(runs, tile, segs[k].a, segs[k].b, k % 2 == 1, 100.0 * k);
  both(runs);
  // Nothing at all.
  both(LineSegments::for_canvas(tile, false));
}

TEST_F(DensityLinesOcl, EuropeDayTilesBitIdentical) {
  const TrailSet* ts = test::europe();
  if (!ts) GTEST_SKIP() << "shared data absent";
  for (const geo::TileId t : {geo::TileId{3, 4, 2}, geo::TileId{5, 16, 10}, geo::TileId{7, 65, 44}})
    for (DensityValue v : {DensityValue::count, DensityValue::altitude}) {
      const LineSegments s = prepare_line_segments(*ts, Query{}, Canvas::for_tile(t, 256, 8), v, INFINITY);
      EXPECT_GT(both(s).total_count(), 0u) << geo::to_string(t);
    }
}

TEST_F(DensityLinesOcl, ConcurrentCallsShareTheQueue) {
  // One context and queue per process, one kernel object per call: calls from several threads at once
  // must each get their own, correct result.
  std::mt19937 rng(77);
  const Canvas c(0, 0, 1 << 14, 128, 128);
  std::vector<LineSegments> inputs;
  std::vector<Aggregate> expected;
  for (int k = 0; k < 4; ++k) {
    inputs.push_back(test::prepare(test::random_segments(rng, c, 3000, 0.3), c, k % 2 == 1, &rng));
    expected.push_back(density_lines_ref(inputs.back()));
  }
  std::vector<std::thread> threads;
  std::atomic<int> wrong{0};
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int rep = 0; rep < 5; ++rep) {
        const Aggregate a = density_lines(inputs[static_cast<std::size_t>(t)], Backend::opencl);
        if (a.path != ComputePath::opencl || !a.same_numbers(expected[static_cast<std::size_t>(t)])) ++wrong;
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(wrong.load(), 0);
}

TEST_F(DensityLinesOcl, PathIsRecorded) {
  const Canvas c(0, 0, 4, 16, 16);
  const LineSegments s = test::prepare({{{0, 0}, {60, 30}}}, c);
  const OpPathStats before = op_path_stats("density_lines");
  density_lines(s, Backend::opencl);
  density_lines(s, Backend::cpu);
  const OpPathStats after = op_path_stats("density_lines");
  EXPECT_EQ(after.opencl, before.opencl + 1);
  EXPECT_EQ(after.cpu, before.cpu + 1);
  EXPECT_EQ(after.last_path, "cpu");
}

TEST_F(DensityLinesOcl, StrictModeTurnsAFallbackIntoAnError) {
  const Canvas c(0, 0, 4, 16, 16);
  const LineSegments s = test::prepare({{{0, 0}, {60, 30}}}, c);
  test::ScopedEnv inject("TRAILSCOPE_OPENCL_INJECT_FAILURE", "other_op,density_lines");
  try {
    density_lines(s, Backend::opencl);
    FAIL() << "strict mode let a fallback through";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::backend);
    EXPECT_EQ(e.param(), "backend");
    EXPECT_NE(std::string(e.what()).find("density_lines"), std::string::npos);
  }
  // Without strict mode the same call falls back to the reference and says so.
  test::ScopedEnv lenient("TRAILSCOPE_OPENCL_STRICT", "0");
  const OpPathStats before = op_path_stats("density_lines");
  const Aggregate a = density_lines(s, Backend::opencl);
  EXPECT_EQ(a.path, ComputePath::cpu);
  EXPECT_TRUE(a.same_numbers(density_lines_ref(s)));
  const OpPathStats after = op_path_stats("density_lines");
  EXPECT_EQ(after.fallbacks, before.fallbacks + 1);
  EXPECT_NE(after.last_fallback_reason.find("injected"), std::string::npos);
}

TEST_F(DensityLinesOcl, AutoKeepsSmallInputsOnTheCpu) {
  const Canvas c(0, 0, 4, 16, 16);
  EXPECT_EQ(density_lines(test::prepare({{{0, 0}, {60, 30}}}, c), Backend::auto_).path, ComputePath::cpu);
}

}  // namespace
}  // namespace trailscope::density
