// Runs as a table (analysis/run_table): varying columns kept in order, constant and incomplete ones
// dropped with the reason, mismatched runs refused.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "trailscope/analysis/run_table.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

RunFigures run(const std::string& id, double a, double b, double share, double error) {
  return {id, {"a", "b", "c"}, {a, b, 7.0}, {{"track_share", share}, {"accuracy.median_error_mm", error}}};
}

TEST(RunTable, KeepsWhatTellsRunsApart) {
  const RunTable t = run_table(
      {run("r1", 1, 5, 0.5, 2.0), run("r2", 2, 5, 0.9, kNaN), run("r3", 3, 5, 0.7, 1.0)}, true, true);
  EXPECT_EQ(t.table.columns, (std::vector<std::string>{"param:a", "metric:track_share"}));
  EXPECT_EQ(t.row_ids, (std::vector<std::string>{"r1", "r2", "r3"}));
  EXPECT_EQ(t.table.values, (std::vector<float>{1, 0.5f, 2, 0.9f, 3, 0.7f}));
  ASSERT_EQ(t.dropped.size(), 3u);
  EXPECT_EQ(t.dropped[0].name, "param:b");
  EXPECT_EQ(t.dropped[0].why, "constant");
  EXPECT_EQ(t.dropped[1].name, "param:c");
  EXPECT_EQ(t.dropped[2].name, "metric:accuracy.median_error_mm");
  EXPECT_EQ(t.dropped[2].why, "missing in some runs");
  const RunTable params_only = run_table({run("r1", 1, 5, 0.5, 2), run("r2", 2, 6, 0.5, 2)}, true, false);
  EXPECT_EQ(params_only.table.columns, (std::vector<std::string>{"param:a", "param:b"}));
}

TEST(RunTable, RefusesWhatCannotBeTabled) {
  const auto expect = [](auto&& f, Error::Kind kind, const std::string& param, const std::string& detail) {
    try {
      f();
      ADD_FAILURE() << "no error for " << detail;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), kind);
      EXPECT_EQ(e.param(), param);
      EXPECT_EQ(std::string(e.what()), detail);
    }
  };
  RunFigures other = run("r2", 1, 5, 0.5, 1);
  other.param_names[2] = "d";
  expect(
      [&] {
        run_table({run("r1", 1, 5, 0.5, 1), other}, true, true);
      },
      Error::Kind::unprocessable, "runs",
      "runs: run r2 has another parameter vector than run r1 (another tracker version); choose runs of one "
      "version");
  expect([&] { run_table({run("r1", 1, 5, 0.5, 1)}, true, true); }, Error::Kind::unprocessable, "runs",
         "runs: a projection needs at least 2 runs, got 1");
  expect(
      [&] {
        run_table({run("r1", 1, 5, 0.5, 1), run("r2", 1, 5, 0.5, 1)}, true, true);
      },
      Error::Kind::unprocessable, "runs",
      "runs: every column is constant or missing in some runs; nothing tells these runs apart");
  expect(
      [&] {
        run_table({run("r1", 1, 5, 0.5, 1), run("r2", 2, 5, 0.5, 1)}, false, false);
      },
      Error::Kind::invalid_argument, "include", "include: name \"params\", \"metrics\" or both");
}

}  // namespace
}  // namespace trailscope::analysis
