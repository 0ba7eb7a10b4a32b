// Parameter importance over the API, in process: uploaded logs whose track share is an exact increasing
// function of one parameter (another varies at random) rank that parameter first, with correlations 1;
// constant parameters have no correlation (null); the metric and the sweep are checked.
#include <random>

#include <gtest/gtest.h>

#include "tracker_fixture.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {
namespace {

class ImportanceTest : public test_routes::TrackerFixture {
 protected:
  void upload_log(double ncc, double n_lost, std::size_t track) { upload_state_log(ncc, n_lost, track, 80); }
};

TEST_F(ImportanceTest, TheParameterThatDeterminesTheMetricComesFirst) {
  std::mt19937 rng(7);
  for (std::size_t k = 0; k < 60; ++k)
    upload_log(0.1 + 0.01 * static_cast<double>(k), static_cast<double>(1 + rng() % 50), k + 10);
  const Response r = get("/api/v1/importance", {{"metric", "track_share"}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["metric"], "track_share");
  EXPECT_EQ(j["sweep"], nullptr);
  EXPECT_EQ(j["samples"], 60);
  // Each split tries a third of the ~30 inputs, most of them constant here: the forest explains the metric
  // well, not perfectly (0.67 with the default seed).
  EXPECT_GT(j["forest_r2"].get<double>(), 0.5);
  ASSERT_EQ(j["inputs"].size(), tracker::parameter_infos().size());
  double best = -1;
  std::string best_name;
  for (const auto& in : j["inputs"]) {
    if (in["forest"].get<double>() > best) best = in["forest"], best_name = in["name"];
    if (in["name"] == "ncc_min") {
      EXPECT_NEAR(in["pearson"].get<double>(), 1.0, 1e-12);
      EXPECT_NEAR(in["spearman"].get<double>(), 1.0, 1e-12);
    } else if (in["name"] != "n_lost") {
      EXPECT_EQ(in["pearson"], nullptr) << in.dump();  // constant: no correlation
      EXPECT_EQ(in["spearman"], nullptr);
      EXPECT_EQ(in["forest"], 0.0);
    }
  }
  EXPECT_EQ(best_name, "ncc_min");
}

TEST_F(ImportanceTest, MetricAndSweepAreChecked) {
  for (std::size_t k = 0; k < 3; ++k) upload_log(0.3 + 0.1 * static_cast<double>(k), 5, k);
  expect_detail(get("/api/v1/importance"), 400, "invalid_argument", "metric",
                "metric: required (a run-summary figure, e.g. track_share)");
  expect_detail(get("/api/v1/importance", {{"metric", "colour"}}), 400, "invalid_argument", "metric",
                "metric: 'colour' is not a number of the run summary");
  expect_error(get("/api/v1/importance", {{"metric", "has_truth"}}), 400, "invalid_argument", "metric");
  expect_detail(get("/api/v1/importance", {{"metric", "track_share"}, {"sweep", "s4"}}), 404, "not_found",
                "sweep", "sweep 's4' does not exist");
  expect_error(get("/api/v1/importance", {{"metric", "track_share"}, {"x", "1"}}), 400, "invalid_argument",
               "x");
  // Three runs are too few; accuracy without ground truth is null in every run: no usable sample.
  expect_error(get("/api/v1/importance", {{"metric", "track_share"}}), 422, "unprocessable", "y");
  expect_error(get("/api/v1/importance", {{"metric", "accuracy.median_error_mm"}}), 422, "unprocessable",
               "y");
}

}  // namespace
}  // namespace trailscope::server
