// POST /api/v1/projections in process: an inline table whose points lie in a plane (so PCA must keep every
// pairwise distance exactly), a table of stored runs (varying parameters and figures, the rest dropped with
// the reason), and every refusal with its status, parameter and message.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "tracker_fixture.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {
namespace {

class ProjectionsTest : public test_routes::TrackerFixture {
 protected:
  Response project(const nlohmann::json& body) { return send("POST", "/api/v1/projections", body.dump()); }

  void upload_log(double ncc, double n_lost, std::size_t track) { upload_state_log(ncc, n_lost, track, 40); }
};

TEST_F(ProjectionsTest, PcaOfPlanarPointsKeepsEveryDistance) {
  // 40 points a·u + b·v in 5D with orthonormal u, v: rank 2, so the two leading components span the plane.
  const double s = 1.0 / std::sqrt(2.0);
  const std::array<double, 5> u = {s, s, 0, 0, 0}, v = {0, 0, 0.6, 0.8, 0};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-5, 5);
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::array<double, 5>> points;
  for (int i = 0; i < 40; ++i) {
    const double a = uni(rng), b = uni(rng);
    std::array<double, 5> p{};
    for (int d = 0; d < 5; ++d) p[d] = a * u[d] + b * v[d] + 1.0;
    points.push_back(p);
    rows.push_back(p);
  }
  const Response r = project({{"table", {{"columns", {"a", "b", "c", "d", "e"}}, {"rows", rows}}},
                              {"method", "pca"},
                              {"standardize", false},
                              {"backend", "cpu"}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["method"], "pca");
  EXPECT_EQ(j["rows"], 40);
  EXPECT_EQ(j["columns"], nlohmann::json({"a", "b", "c", "d", "e"}));
  EXPECT_EQ(j["row_ids"], nullptr);
  EXPECT_EQ(j["path"], "cpu");
  ASSERT_EQ(j["coordinates"].size(), 40u);
  for (std::size_t i = 0; i < 40; ++i)
    for (std::size_t k = i + 1; k < 40; ++k) {
      double d2 = 0;
      for (int d = 0; d < 5; ++d) d2 += (points[i][d] - points[k][d]) * (points[i][d] - points[k][d]);
      const double dx = j["coordinates"][i][0].get<double>() - j["coordinates"][k][0].get<double>();
      const double dy = j["coordinates"][i][1].get<double>() - j["coordinates"][k][1].get<double>();
      EXPECT_NEAR(std::hypot(dx, dy), std::sqrt(d2), 1e-4);  // float table values
    }
  EXPECT_NEAR(j["quality"]["trustworthiness"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(j["quality"]["stress"].get<double>(), 0.0, 1e-6);
  EXPECT_EQ(j["quality"]["k"], 10);
}

// A 20-row table (a 20-run sweep) with t-SNE's default perplexity 30: capped at (20 − 1) / 3 as openTSNE
// does, the answer says which perplexity ran, and a perplexity the table holds runs as asked.
TEST_F(ProjectionsTest, TsneOnTwentyRowsCapsThePerplexity) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 20; ++i) rows.push_back({i % 5, (i * 7) % 11, i / 4});
  const auto table = nlohmann::json{{"columns", {"a", "b", "c"}}, {"rows", rows}};
  const Response r = project({{"table", table}, {"method", "tsne"}, {"backend", "cpu"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_DOUBLE_EQ(body(r)["perplexity"].get<double>(), 19.0 / 3.0);
  EXPECT_EQ(body(r)["coordinates"].size(), 20u);
  const Response five =
      project({{"table", table}, {"method", "tsne"}, {"perplexity", 5}, {"backend", "cpu"}});
  ASSERT_EQ(five.status, 200) << five.body;
  EXPECT_DOUBLE_EQ(body(five)["perplexity"].get<double>(), 5.0);
  // PCA has no perplexity.
  EXPECT_FALSE(body(project({{"table", table}, {"method", "pca"}})).contains("perplexity"));
  // Three rows cannot hold any perplexity.
  const Response tiny =
      project({{"table", {{"columns", {"a", "b"}}, {"rows", {{1, 2}, {3, 4}, {5, 7}}}}}, {"method", "tsne"}});
  expect_error(tiny, 400, "invalid_argument", "table");
  EXPECT_EQ(body(tiny)["detail"],
            "t-SNE needs at least 4 rows (perplexity ≥ 1 needs 3 neighbours); the table has 3");
}

TEST_F(ProjectionsTest, StoredRunsBecomeATableOfWhatVaries) {
  std::mt19937 rng(5);
  for (std::size_t k = 0; k < 30; ++k)
    upload_log(0.1 + 0.02 * static_cast<double>(k), static_cast<double>(1 + rng() % 20), k + 5);
  const Response r = project({{"runs", {{"include", {"params", "metrics"}}}}, {"method", "mds"}, {"k", 5}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["columns"], nlohmann::json({"param:ncc_min", "param:n_lost", "metric:track_share"}));
  ASSERT_EQ(j["row_ids"].size(), 30u);
  EXPECT_EQ(j["row_ids"][0], "r1");
  EXPECT_EQ(j["row_ids"][29], "r30");
  EXPECT_EQ(j["coordinates"].size(), 30u);
  EXPECT_EQ(j["quality"]["k"], 5);
  bool constant_dropped = false, missing_dropped = false;
  for (const auto& d : j["dropped_columns"]) {
    if (d["name"] == "param:r_max_mm") constant_dropped = d["why"] == "constant";
    if (d["name"] == "metric:accuracy.median_error_mm") missing_dropped = d["why"] == "missing in some runs";
  }
  EXPECT_TRUE(constant_dropped) << j["dropped_columns"].dump();
  EXPECT_TRUE(missing_dropped) << j["dropped_columns"].dump();
  // A chosen subset, in the order asked for.
  const Response some = project({{"runs", {{"ids", {"r7", "r2", "r5", "r9"}}, {"include", {"params"}}}}});
  ASSERT_EQ(some.status, 200) << some.body;
  EXPECT_EQ(body(some)["row_ids"], nlohmann::json({"r7", "r2", "r5", "r9"}));
  EXPECT_EQ(body(some)["columns"], nlohmann::json({"param:ncc_min", "param:n_lost"}));
}

TEST_F(ProjectionsTest, BadRequestsNameTheirField) {
  const nlohmann::json table = {{"rows", {{1, 2}, {3, 4}, {5, 7}}}};
  expect_detail(project({{"method", "pca"}}), 400, "invalid_argument", "table",
                "table: give exactly one of \"table\" (an inline table) and \"runs\"");
  expect_detail(project({{"table", table}, {"runs", nlohmann::json::object()}}), 400, "invalid_argument",
                "table", "table: give exactly one of \"table\" (an inline table) and \"runs\"");
  expect_detail(project({{"table", {{"rows", {{1, 2}, {3}}}}}}), 400, "invalid_argument", "table",
                "table: row 2 must be an array of 2 numbers");
  expect_detail(project({{"table", {{"rows", {{1, 2}, {3, "x"}}}}}}), 400, "invalid_argument", "table",
                "table: row 2 has a value that is not a number");
  expect_detail(project({{"table", {{"columns", {"a"}}, {"rows", {{1, 2}, {3, 4}}}}}}), 400,
                "invalid_argument", "table", "table: columns must list 2 names");
  expect_error(project({{"table", table}, {"method", "umap"}}), 400, "invalid_argument", "method");
  expect_detail(project({{"table", table}, {"k", 0}}), 400, "invalid_argument", "k",
                "k: must be in [1, 100]");
  expect_detail(project({{"table", table}, {"iterations", -3}}), 400, "invalid_argument", "iterations",
                "iterations: must be in [0, 10000] (0 = default)");
  expect_detail(project({{"table", table}, {"standardize", "yes"}}), 400, "invalid_argument", "standardize",
                "standardize: must be true or false");
  expect_detail(project({{"table", table}, {"colour", 1}}), 400, "invalid_argument", "colour",
                "unknown field 'colour'");
  expect_error(project({{"table", table}, {"backend", "gpu"}}), 400, "invalid_argument", "backend");
  expect_detail(project({{"runs", {{"sweep", "s9"}}}}), 404, "not_found", "sweep",
                "sweep 's9' does not exist");
  expect_detail(project({{"runs", {{"include", {"frames"}}}}}), 400, "invalid_argument", "include",
                "include: \"params\" and/or \"metrics\", not \"frames\"");
  expect_detail(project({{"runs", nlohmann::json::object()}}), 422, "unprocessable", "runs",
                "runs: a projection needs at least 2 runs, got 0");
  nlohmann::json big = nlohmann::json::array();
  for (std::size_t i = 0; i <= limits::kMaxProjectionRequestRows; ++i) big.push_back({1.0});
  expect_detail(project({{"table", {{"rows", big}}}}), 413, "payload_too_large", "table",
                "table: 20001 rows, at most 20000 in a request");
}

}  // namespace
}  // namespace trailscope::server
