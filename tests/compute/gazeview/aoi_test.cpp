// AOI measures (gazeview/aoi.hpp) against hand-computed values on a tiny case and against a brute-force
// second implementation (crossing-number point in polygon, per-recording AOI sequences) on real Lund data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/gazeview/aoi.hpp"

using namespace trailscope;
using namespace trailscope::gazeview;
using trailscope::test::shared_data;

namespace {

Fixation fix(std::size_t rec, double onset, double dur, double x, double y) {
  Fixation f;
  f.recording = rec, f.onset_ms = onset, f.t_start_ms = 1000 + onset, f.t_end_ms = 1000 + onset + dur;
  f.duration_ms = dur, f.x = x, f.y = y;
  return f;
}

// Crossing-number test (Franklin's pnpoly), boundary points not handled: the test keeps points off edges.
bool pnpoly(const std::vector<double>& xs, const std::vector<double>& ys, double x, double y) {
  bool c = false;
  for (std::size_t i = 0, j = xs.size() - 1; i < xs.size(); j = i++)
    if (((ys[i] > y) != (ys[j] > y)) && (x < (xs[j] - xs[i]) * (y - ys[i]) / (ys[j] - ys[i]) + xs[i])) c = !c;
  return c;
}

}  // namespace

TEST(GazeAoi, HandMadeCase) {
  // A: rectangle 0..100 x 0..100; B: triangle (200,0) (300,0) (250,100); C: rectangle 50..150 x 50..150,
  // under A (A is listed first, so the overlap 50..100 belongs to A).
  const std::vector<Aoi> aois{Aoi::rect("A", 0, 0, 100, 100), Aoi::polygon("B", {200, 300, 250}, {0, 0, 100}),
                              Aoi::rect("C", 50, 50, 150, 150)};
  const std::vector<Fixation> f{
      // recording 0: A, outside, B, C, C(overlap -> A), B
      fix(0, 0, 100, 10, 10), fix(0, 150, 50, 500, 500), fix(0, 300, 200, 250, 20),
      fix(0, 600, 100, 120, 120), fix(0, 800, 60, 60, 60), fix(0, 1000, 40, 240, 50),
      // recording 1: C, C, on A's edge (x = 100 -> A), outside
      fix(1, 50, 300, 140, 140), fix(1, 400, 100, 149, 60), fix(1, 700, 80, 100, 30),
      fix(1, 900, 10, 180, 10)};
  const AoiReport r = aoi_statistics(aois, f);
  ASSERT_EQ(r.aois.size(), 3u);
  EXPECT_EQ(r.fixations, 10u);
  EXPECT_EQ(r.outside, 2u);
  const AoiStats &a = r.aois[0], &b = r.aois[1], &c = r.aois[2];
  EXPECT_EQ(a.name, "A");
  EXPECT_EQ(a.fixations, 3u);  // (10,10), (60,60), (100,30)
  EXPECT_DOUBLE_EQ(a.dwell_ms, 240);
  EXPECT_DOUBLE_EQ(a.mean_fixation_ms, 80);
  EXPECT_EQ(a.visitors, 2u);
  EXPECT_DOUBLE_EQ(a.first_fixation_min_ms, 0);
  EXPECT_DOUBLE_EQ(a.first_fixation_median_ms, 350);  // (0 + 700) / 2
  EXPECT_EQ(b.fixations, 2u);
  EXPECT_DOUBLE_EQ(b.dwell_ms, 240);
  EXPECT_EQ(b.visitors, 1u);
  EXPECT_DOUBLE_EQ(b.first_fixation_min_ms, 300);
  EXPECT_DOUBLE_EQ(b.first_fixation_median_ms, 300);
  EXPECT_EQ(c.fixations, 3u);
  EXPECT_DOUBLE_EQ(c.dwell_ms, 500);
  EXPECT_EQ(c.visitors, 2u);
  EXPECT_DOUBLE_EQ(c.first_fixation_min_ms, 50);
  EXPECT_DOUBLE_EQ(c.first_fixation_median_ms, 325);  // (600 + 50) / 2
  // Recording 0 sequence A B C A B (outside skipped): A->B, B->C, C->A, A->B. Recording 1: C C A: C->C, C->A.
  const std::vector<std::vector<std::uint64_t>> want{{0, 2, 0}, {0, 0, 1}, {2, 0, 1}};
  EXPECT_EQ(r.transitions, want);
}

TEST(GazeAoi, EmptyAoiHasNaNs) {
  const AoiReport r = aoi_statistics({Aoi::rect("far", 5000, 5000, 5001, 5001)}, {fix(0, 0, 10, 1, 1)});
  EXPECT_EQ(r.aois[0].fixations, 0u);
  EXPECT_EQ(r.aois[0].visitors, 0u);
  EXPECT_TRUE(std::isnan(r.aois[0].first_fixation_median_ms));
  EXPECT_TRUE(std::isnan(r.aois[0].mean_fixation_ms));
  EXPECT_EQ(r.outside, 1u);
}

TEST(GazeAoi, ValidationMessages) {
  auto message = [](const std::vector<Aoi>& a) {
    try {
      validate_aois(a);
    } catch (const Error& e) {
      EXPECT_EQ(e.param(), "aois");
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({}), "give at least one AOI");
  EXPECT_EQ(message({Aoi::rect("", 0, 0, 1, 1)}), "AOI 0 has no name");
  EXPECT_EQ(message({Aoi::rect("a", 0, 0, 1, 1), Aoi::rect("a", 0, 0, 2, 2)}), "AOI 1 (a): name used twice");
  EXPECT_EQ(message({Aoi::rect("a", 5, 0, 1, 1)}), "AOI 0 (a): a rectangle needs x0 < x1 and y0 < y1");
  EXPECT_EQ(message({Aoi::rect("a", 0, 0, NAN, 1)}), "AOI 0 (a): a corner is not a finite number");
  // Beyond kMaxAoiCoordinatePx (float could not hold 1e300 at all); the limit itself is accepted.
  EXPECT_EQ(message({Aoi::rect("a", 0, 0, 1e300, 1)}),
            "AOI 0 (a): a corner is beyond +-1000000 px (kMaxAoiCoordinatePx)");
  EXPECT_EQ(message({Aoi::polygon("p", {0, -1000000.5, 5}, {0, 0, 5})}),
            "AOI 0 (p): vertex 1 is beyond +-1000000 px (kMaxAoiCoordinatePx)");
  EXPECT_NO_THROW(validate_aois({Aoi::rect("a", -1e6, -1e6, 1e6, 1e6)}));
  EXPECT_EQ(message({Aoi::polygon("p", {0, 1}, {0, 1})}),
            "AOI 0 (p): a polygon needs at least 3 vertices, not 2");
  EXPECT_EQ(message({Aoi::rect("r", 0, 0, 1, 1),
                     Aoi::polygon("p", std::vector<double>(4093, 1.0), std::vector<double>(4093, 2.0))}),
            "the AOIs have more than 4096 vertices together (a rectangle counts 4), reached at AOI 1 (p)");
  EXPECT_EQ(message({Aoi::polygon("p", {0, 1, 2}, {0, 1})}), "AOI 0 (p): polygon x and y counts differ");
  std::vector<Aoi> many;
  for (std::size_t i = 0; i <= limits::kMaxGazeAois; ++i)
    many.push_back(Aoi::rect(std::to_string(i), 0, 0, 1, 1));
  EXPECT_EQ(message(many), "257 AOIs; at most 256");
}

TEST(GazeAoi, PolygonIsEvenOddWithBoundaryInside) {
  // A concave "U": the notch is outside.
  const Aoi u = Aoi::polygon("u", {0, 30, 30, 20, 20, 10, 10, 0}, {0, 0, 30, 30, 10, 10, 30, 30});
  EXPECT_TRUE(u.contains(5, 20));
  EXPECT_TRUE(u.contains(25, 20));
  EXPECT_FALSE(u.contains(15, 20));  // in the notch
  EXPECT_TRUE(u.contains(15, 10));   // on the notch's bottom edge
  EXPECT_TRUE(u.contains(0, 0));     // a vertex
  EXPECT_FALSE(u.contains(-0.01, 5));
}

// Real data: the 4 Lund recordings of the Europe image, I-VT fixations, AOIs tiling the image in a 3 x 2
// grid of rectangles with a polygon on top; compared with a brute-force recount.
TEST(GazeAoi, LundEuropeAgainstBruteForce) {
  gaze::GazeIngestOptions o;
  o.geometry = {1024, 768, 38, 30, 67};
  gaze::GazeDataset ds;
  for (const char* name : {"TH34", "UH29", "UH47", "UL23"}) {
    gaze::GazeDataset one = gaze::read_gaze_file(
        shared_data(std::string("gaze/andersson2017_lund/tsv/") + name + "_img_Europe.tsv").string(), o);
    for (auto& r : one.recordings) ds.recordings.push_back(std::move(r));
  }
  ASSERT_EQ(ds.recordings.size(), 4u);
  const ViewEvents ev = view_events(ds, {}, {}, SIZE_MAX);
  EXPECT_EQ(ev.recordings, (std::vector<std::size_t>{0, 1, 2, 3}));
  ASSERT_GT(ev.fixations.size(), 20u);

  // Independent placement check: each fixation's centroid is the mean of the samples in [t_start, t_end].
  for (const Fixation& f : ev.fixations) {
    const auto& r = ds.recordings[f.recording];
    double sx = 0, sy = 0;
    int n = 0;
    for (std::size_t i = 0; i < r.size(); ++i)
      if (r.t_ms[i] >= f.t_start_ms && r.t_ms[i] <= f.t_end_ms) sx += r.x[i], sy += r.y[i], ++n;
    ASSERT_GT(n, 0);
    EXPECT_NEAR(f.x, sx / n, 1e-9);
    EXPECT_NEAR(f.y, sy / n, 1e-9);
    EXPECT_DOUBLE_EQ(f.onset_ms, f.t_start_ms - r.t_ms.front());
  }

  const std::vector<double> px{300, 700, 640, 380}, py{150, 200, 600, 550};
  std::vector<Aoi> aois{Aoi::polygon("poly", px, py)};
  for (int gx = 0; gx < 3; ++gx)
    for (int gy = 0; gy < 2; ++gy)
      aois.push_back(Aoi::rect("g" + std::to_string(gx) + std::to_string(gy), gx * 1024.0 / 3, gy * 384.0,
                               (gx + 1) * 1024.0 / 3, (gy + 1) * 384.0));
  const AoiReport r = aoi_statistics(aois, ev.fixations);

  // Brute force: the AOI of each fixation, then per AOI and per recording the lists.
  const std::size_t m = aois.size();
  auto which = [&](double x, double y) -> std::size_t {
    if (pnpoly(px, py, x, y)) return 0;
    for (std::size_t a = 1; a < m; ++a)
      if (x >= aois[a].x0 && x <= aois[a].x1 && y >= aois[a].y0 && y <= aois[a].y1) return a;
    return m;
  };
  std::vector<std::size_t> count(m, 0);
  std::vector<double> dwell(m, 0);
  std::map<std::size_t, std::vector<std::size_t>> seq;  // recording -> AOI sequence
  std::vector<std::map<std::size_t, double>> first(m);  // AOI -> recording -> first onset
  std::size_t outside = 0;
  for (const Fixation& f : ev.fixations) {
    const std::size_t a = which(f.x, f.y);
    if (a == m) {
      ++outside;
      continue;
    }
    ++count[a], dwell[a] += f.duration_ms;
    seq[f.recording].push_back(a);
    if (!first[a].count(f.recording)) first[a][f.recording] = f.onset_ms;
  }
  std::vector<std::vector<std::uint64_t>> trans(m, std::vector<std::uint64_t>(m, 0));
  for (const auto& [rec, s] : seq)
    for (std::size_t k = 1; k < s.size(); ++k) ++trans[s[k - 1]][s[k]];
  EXPECT_EQ(r.outside, outside);
  EXPECT_EQ(r.transitions, trans);
  std::size_t total = 0;
  for (std::size_t a = 0; a < m; ++a) {
    SCOPED_TRACE(aois[a].name);
    EXPECT_EQ(r.aois[a].fixations, count[a]);
    EXPECT_NEAR(r.aois[a].dwell_ms, dwell[a], 1e-6);
    EXPECT_EQ(r.aois[a].visitors, first[a].size());
    std::vector<double> v;
    for (const auto& [rec, t] : first[a]) v.push_back(t);
    std::sort(v.begin(), v.end());
    if (!v.empty()) {
      EXPECT_DOUBLE_EQ(r.aois[a].first_fixation_min_ms, v.front());
      const double med = v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
      EXPECT_DOUBLE_EQ(r.aois[a].first_fixation_median_ms, med);
    }
    total += count[a];
  }
  EXPECT_EQ(total + outside, ev.fixations.size());
  EXPECT_GT(r.aois[0].fixations, 0u);  // the polygon in the middle of the map is looked at
}

TEST(GazeAoi, TimeWindowKeepsOnsetsInside) {
  gaze::GazeIngestOptions o;
  o.geometry = {1024, 768, 38, 30, 67};
  const gaze::GazeDataset ds =
      gaze::read_gaze_file(shared_data("gaze/andersson2017_lund/tsv/TH34_img_Europe.tsv").string(), o);
  gaze::GazeFilter part;
  part.t0_ms = 1000, part.t1_ms = 5000;
  const auto a = view_events(ds, {}, {}, SIZE_MAX).fixations,
             b = view_events(ds, part, {}, SIZE_MAX).fixations;
  std::size_t in = 0;
  for (const auto& f : a) in += f.onset_ms >= 1000 && f.onset_ms < 5000;
  EXPECT_EQ(b.size(), in);
  EXPECT_LT(b.size(), a.size());
  try {
    view_events(ds, {}, {}, 10);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
  }
  gaze::GazeFilter other;
  other.recording = 3;
  EXPECT_THROW(view_events(ds, other, {}, SIZE_MAX), Error);
}

TEST(GazeAoi, FromJson) {
  const auto a = aois_from_json(nlohmann::json::parse(
      R"([{"name":"r","rect":[0,1,10,11]},{"name":"p","polygon":[[0,0],[5,0],[0,5]]}])"));
  ASSERT_EQ(a.size(), 2u);
  EXPECT_TRUE(a[0].is_rect);
  EXPECT_EQ(a[0].y0, 1);
  EXPECT_EQ(a[0].x1, 10);
  EXPECT_FALSE(a[1].is_rect);
  EXPECT_EQ(a[1].xs, (std::vector<double>{0, 5, 0}));
  auto message = [](const char* text) {
    try {
      aois_from_json(nlohmann::json::parse(text));
    } catch (const Error& e) {
      EXPECT_EQ(e.param(), "aois");
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(R"({"name":"r"})"), "aois must be an array of {name, rect | polygon}");
  EXPECT_EQ(message(R"([3])"), "AOI 0 is not an object");
  EXPECT_EQ(message(R"([{"rect":[0,0,1,1]}])"), "AOI 0 needs a string name");
  EXPECT_EQ(message(R"([{"name":"r","rect":[0,0,1,1],"circle":3}])"),
            "AOI 0 (r): unknown key 'circle' (name, rect, polygon)");
  EXPECT_EQ(message(R"([{"name":"r"}])"), "AOI 0 (r): give either rect or polygon");
  EXPECT_EQ(message(R"([{"name":"r","rect":[0,0,1]}])"), "AOI 0 (r): rect must be [x0, y0, x1, y1]");
  EXPECT_EQ(message(R"([{"name":"r","rect":[0,0,1,"1"]}])"), "AOI 0 (r): rect must be numbers");
  EXPECT_EQ(message(R"([{"name":"p","polygon":[[0,0],[1,1]]}])"),
            "AOI 0 (p): a polygon needs at least 3 vertices, not 2");
  EXPECT_EQ(message(R"([{"name":"p","polygon":[[0,0],[1,1],[2]]}])"),
            "AOI 0 (p): polygon must be [[x, y], ...]");
  EXPECT_EQ(message(R"([])"), "give at least one AOI");
}

TEST(GazeAoi, ReportJson) {
  const AoiReport r = aoi_statistics({Aoi::rect("A", 0, 0, 10, 10), Aoi::rect("B", 20, 0, 30, 10)},
                                     {fix(0, 5, 100, 1, 1), fix(0, 200, 50, 25, 5)});
  const nlohmann::json j = to_json(r, 3);
  EXPECT_EQ(j["recordings"], 3);
  EXPECT_EQ(j["aois"][0]["name"], "A");
  EXPECT_EQ(j["aois"][0]["first_fixation_ms"]["median"], 5.0);
  EXPECT_EQ(j["aois"][1]["mean_fixation_ms"], 50.0);
  EXPECT_EQ(j["transitions"]["counts"], nlohmann::json::parse("[[0,1],[0,0]]"));
  EXPECT_EQ(j["transitions"]["names"], nlohmann::json::parse(R"(["A","B"])"));
  const nlohmann::json none = to_json(aoi_statistics({Aoi::rect("C", 50, 50, 60, 60)}, {}), 0);
  EXPECT_TRUE(none["aois"][0]["first_fixation_ms"]["min"].is_null());
}
