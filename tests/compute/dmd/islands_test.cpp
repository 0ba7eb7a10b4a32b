// Island removal against an independent flood fill: exactly the components under the threshold go,
// inside ones (8-connected) first, then outside ones (4-connected).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "draw.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/dmd/medial.hpp"

namespace trailscope::dmd {
namespace {

// Components of the pixels equal to `value` by breadth-first search: label per pixel (0 elsewhere)
// and sizes[label].
struct Components {
  std::vector<int> label;
  std::vector<std::int64_t> size{0};
};
Components flood(const BinaryImage& b, std::uint8_t value, bool eight) {
  Components c;
  c.label.assign(b.pixels.size(), 0);
  std::vector<int> queue;
  for (std::size_t s = 0; s < b.pixels.size(); ++s) {
    if (b.pixels[s] != value || c.label[s]) continue;
    const int id = static_cast<int>(c.size.size());
    c.size.push_back(0);
    queue.assign(1, static_cast<int>(s));
    c.label[s] = id;
    while (!queue.empty()) {
      const int p = queue.back();
      queue.pop_back();
      ++c.size[id];
      const int x = p % b.width, y = p / b.width;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || (!eight && dx != 0 && dy != 0)) continue;
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= b.width || ny >= b.height) continue;
          const int q = ny * b.width + nx;
          if (b.pixels[q] == value && !c.label[q]) {
            c.label[q] = id;
            queue.push_back(q);
          }
        }
    }
  }
  return c;
}

// The expected result, computed with flood().
BinaryImage expected(BinaryImage b, std::int64_t min_area, int& islands, int& holes) {
  const Components in = flood(b, 1, true);
  islands = 0;
  for (std::size_t k = 1; k < in.size.size(); ++k) islands += in.size[k] < min_area;
  for (std::size_t i = 0; i < b.pixels.size(); ++i)
    if (b.pixels[i] && in.size[in.label[i]] < min_area) b.pixels[i] = 0;
  const Components out = flood(b, 0, false);
  holes = 0;
  for (std::size_t k = 1; k < out.size.size(); ++k) holes += out.size[k] < min_area;
  for (std::size_t i = 0; i < b.pixels.size(); ++i)
    if (!b.pixels[i] && out.size[out.label[i]] < min_area) b.pixels[i] = 1;
  return b;
}

TEST(Islands, KnownComponentsUnderTheThresholdGoExactly) {
  BinaryImage b = test::blank(60, 40);
  test::paint(b, std::uint8_t{1}, test::rect(2, 2, 4, 4));      // island of 9
  test::paint(b, std::uint8_t{1}, test::rect(10, 2, 12, 5));    // island of 12
  test::paint(b, std::uint8_t{1}, test::rect(20, 2, 20, 2));    // island of 1
  test::paint(b, std::uint8_t{1}, test::rect(21, 3, 21, 3));    // ... diagonal neighbour: one island of 2
  test::paint(b, std::uint8_t{1}, test::rect(30, 10, 55, 35));  // big region with holes
  test::paint(b, std::uint8_t{0}, test::rect(35, 15, 36, 16));  // hole of 4
  test::paint(b, std::uint8_t{0}, test::rect(45, 15, 48, 17));  // hole of 12
  test::paint(b, std::uint8_t{0}, test::rect(40, 25, 40, 25));  // hole of 1
  test::paint(b, std::uint8_t{0}, test::rect(41, 26, 41, 26));  // diagonal: a separate 4-connected hole of 1
  BinaryImage r = b;
  const IslandStats s = remove_islands(r, 10);
  EXPECT_EQ(s.islands_removed, 2);  // 9 and 2 (the diagonal pair is one 8-connected island)
  EXPECT_EQ(s.pixels_cleared, 11);
  EXPECT_EQ(s.holes_filled, 3);  // 4, 1, 1
  EXPECT_EQ(s.pixels_filled, 6);
  EXPECT_EQ(r.at(3, 3), 0);
  EXPECT_EQ(r.at(11, 3), 1);  // 12 >= 10 stays
  EXPECT_EQ(r.at(20, 2), 0);
  EXPECT_EQ(r.at(21, 3), 0);
  EXPECT_EQ(r.at(35, 15), 1);
  EXPECT_EQ(r.at(46, 16), 0);  // hole of 12 stays
  EXPECT_EQ(r.at(40, 25), 1);
  EXPECT_EQ(r.at(41, 26), 1);
  int islands = 0, holes = 0;
  EXPECT_EQ(r.pixels, expected(b, 10, islands, holes).pixels);
}

TEST(Islands, RandomLayersMatchAFloodFill) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 40; ++trial) {
    BinaryImage b = test::blank(37 + trial % 5, 29);
    const double density = 0.3 + 0.4 * (trial % 4) / 3.0;
    for (auto& p : b.pixels) p = std::uniform_real_distribution<double>(0, 1)(rng) < density;
    const std::int64_t min_area = 1 + trial % 9;
    int islands = 0, holes = 0;
    const BinaryImage want = expected(b, min_area, islands, holes);
    BinaryImage got = b;
    const IslandStats s = remove_islands(got, min_area);
    EXPECT_EQ(got.pixels, want.pixels) << "trial " << trial;
    EXPECT_EQ(s.islands_removed, islands);
    EXPECT_EQ(s.holes_filled, holes);
  }
}

TEST(Islands, ZeroOrOneRemovesNothingAndBadInputIsRejected) {
  BinaryImage b = test::blank(8, 8);
  b.pixels[9] = 1;
  for (const std::int64_t a : {0, 1}) {
    BinaryImage r = b;
    const IslandStats s = remove_islands(r, a);
    EXPECT_EQ(r.pixels, b.pixels);
    EXPECT_EQ(s.islands_removed + s.holes_filled, 0);
  }
  try {
    remove_islands(b, -1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "min_area");
    EXPECT_EQ(std::string(e.what()), "min_area must be >= 0 (got -1)");
  }
}

}  // namespace
}  // namespace trailscope::dmd
