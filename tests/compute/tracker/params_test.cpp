#include <gtest/gtest.h>

#include <set>

#include "trailscope/core/error.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/tracker/tracker.hpp"

namespace trailscope::tracker {
namespace {

void expect_error(const std::function<void()>& f, const std::string& param, const std::string& message) {
  try {
    f();
    FAIL() << "expected an error about " << param;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    EXPECT_EQ(e.param(), param);
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(TrackerParams, EveryParameterIsListedOnceWithItsDefaultInRange) {
  const auto& infos = parameter_infos();
  const TrackerParams p;
  const auto v = to_vector(p);
  ASSERT_EQ(infos.size(), v.size());
  std::set<std::string> names;
  for (std::size_t i = 0; i < infos.size(); ++i) {
    EXPECT_TRUE(names.insert(infos[i].name).second) << infos[i].name;
    EXPECT_EQ(infos[i].default_number, v[i]) << infos[i].name;
    EXPECT_EQ(get_param(p, infos[i].name), v[i]);
    EXPECT_GE(v[i], infos[i].min) << infos[i].name;
    EXPECT_LE(v[i], infos[i].max) << infos[i].name;
    EXPECT_FALSE(infos[i].help.empty());
  }
  EXPECT_NO_THROW(validate(p));
}

TEST(TrackerParams, SetParamChecksNameRangeAndWholeness) {
  TrackerParams p;
  set_param(p, "ncc_min", 0.7);
  EXPECT_EQ(p.ncc_min, 0.7);
  set_param(p, "n_lost", 9);
  EXPECT_EQ(p.n_lost, 9);
  expect_error([&] { set_param(p, "ncc", 0.5); }, "ncc", "unknown tracker parameter 'ncc'");
  expect_error([&] { set_param(p, "ncc_min", 1.5); }, "ncc_min", "ncc_min must be in [0, 1], got 1.5");
  expect_error([&] { set_param(p, "n_lost", 2.5); }, "n_lost", "n_lost must be a whole number, got 2.5");
  expect_error([&] { set_param(p, "d_gate_mm", std::nan("")); }, "d_gate_mm",
               "d_gate_mm must be in [1, 500], got nan");
}

TEST(TrackerParams, ValidateChecksTheCrossConstraints) {
  TrackerParams p;
  p.z_min_mm = 900;
  expect_error([&] { validate(p); }, "z_max_mm", "z_max_mm must exceed z_min_mm (900), got 900");
  p = {};
  p.r_max_mm = 5;
  expect_error([&] { validate(p); }, "r_max_mm", "r_max_mm must exceed r_min_mm (6), got 5");
  p = {};
  p.median_k = 4;
  expect_error([&] { validate(p); }, "median_k", "median_k must be 1, 3 or 5, got 4");
  p = {};
  p.template_max_px = 2;
  expect_error([&] { validate(p); }, "template_max_px",
               "template_max_px must be at least template_min_px (3), got 2");
  p = {};
  p.spacing_max_mm = 40;
  expect_error([&] { validate(p); }, "spacing_max_mm",
               "spacing_max_mm must exceed spacing_min_mm (45), got 40");
  // The tracker refuses what validate refuses.
  p = {};
  p.templates = 0;
  tof::Intrinsics k{150, 150, 87.5, 71.5, 176, 144, false};
  expect_error([&] { Tracker t(p, k); }, "templates", "templates must be in [1, 8], got 0");
}

TEST(TrackerState, NamesRoundTrip) {
  for (State s : {State::search, State::track, State::lost}) EXPECT_EQ(parse_state(to_string(s)), s);
  EXPECT_EQ(parse_state("track"), State::track);
  expect_error([] { parse_state("lost!"); }, "state", "unknown tracker state 'lost!' (SEARCH, TRACK, LOST)");
}

}  // namespace
}  // namespace trailscope::tracker
