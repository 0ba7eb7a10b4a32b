// The MOTChallenge readers: accepted variants, and malformed lines reported by number.
#include <gtest/gtest.h>

#include <fstream>

#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/metrics/mot_text.hpp"

namespace trailscope::metrics {
namespace {

/// The error a parse throws (kind unprocessable is checked by the caller).
template <typename F>
Error error_of(F&& parse) {
  try {
    parse();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error thrown";
  return Error(Error::Kind::internal, "", "");
}

TEST(MotText, ReadsGroundTruth) {
  const auto rows = parse_mot_gt("1,1,260,450,102,262,1,1,1\n\n# comment\n2,7,1.5,2,3,4,0,12,0.25\r\n");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].frame, 1);
  EXPECT_EQ(rows[0].id, 1);
  EXPECT_DOUBLE_EQ(rows[0].h, 262);
  EXPECT_TRUE(rows[0].consider);
  EXPECT_EQ(rows[1].object_class, 12);
  EXPECT_FALSE(rows[1].consider);
  EXPECT_DOUBLE_EQ(rows[1].x, 1.5);
  EXPECT_DOUBLE_EQ(rows[1].visibility, 0.25);
  EXPECT_EQ(rows[1].line, 4u);
}

TEST(MotText, ReadsRunsWithFloatsZeroIdsAndSpaces) {
  const auto rows =
      parse_mot_run("1,0,-184.78,237.2,309.3,684.7,1,-1,-1,-1\n2.0 5 1e2 2 3 4\n3, 6, 1, 2, 3, 4, 0.5,");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].id, 0);
  EXPECT_DOUBLE_EQ(rows[0].x, -184.78);
  EXPECT_EQ(rows[1].frame, 2);
  EXPECT_DOUBLE_EQ(rows[1].x, 100);
  EXPECT_DOUBLE_EQ(rows[1].confidence, 1.0);
  EXPECT_DOUBLE_EQ(rows[2].confidence, 0.5);
}

TEST(MotText, EveryMalformedLineIsReportedWithItsNumber) {
  const std::string text =
      "1,1,1,2,3,4,1,1,1\n"
      "1,2,1,2,3\n"             // line 2: too few columns
      "0,3,1,2,3,4,1,1,1\n"     // line 3: frame 0
      "2,1.5,1,2,3,4,1,1,1\n"   // line 4: fractional id
      "2,4,x,2,3,4,1,1,1\n"     // line 5: not a number
      "2,5,1,2,3,4,2,1,1\n"     // line 6: consider 2
      "2,6,1,2,3,4,1,14,1\n"    // line 7: class 14
      "2,7,1,2,nan,4,1,1,1\n";  // line 8: not finite
  const Error e = error_of([&] { parse_mot_gt(text); });
  EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
  EXPECT_EQ(e.param(), "gt");
  const std::string msg = e.what();
  EXPECT_NE(msg.find("7 malformed lines"), std::string::npos) << msg;
  for (const char* part :
       {"line 2: 5 columns", "line 3: frame '0'", "line 4: id '1.5'", "line 5: column 3 'x'",
        "line 6: consider", "line 7: class '14'", "line 8: column 5"})
    EXPECT_NE(msg.find(part), std::string::npos) << part << " missing in: " << msg;
}

TEST(MotText, LongErrorListsAreCut) {
  std::string text;
  for (int k = 0; k < 25; ++k) text += "1,2,3\n";
  const Error e = error_of([&] { parse_mot_run(text); });
  EXPECT_EQ(e.param(), "run");
  const std::string msg = e.what();
  EXPECT_NE(msg.find("25 malformed lines"), std::string::npos);
  EXPECT_NE(msg.find("line 10:"), std::string::npos);
  EXPECT_EQ(msg.find("line 11:"), std::string::npos);
  EXPECT_NE(msg.find("and 15 more"), std::string::npos);
}

TEST(MotText, Points) {
  const auto p = parse_points("3,1,10.5,-2,300\n", "gt");
  ASSERT_EQ(p.size(), 1u);
  EXPECT_DOUBLE_EQ(p[0].z, 300);
  EXPECT_EQ(error_of([] { parse_points("3,1,10.5,-2\n", "run"); }).param(), "run");
}

TEST(MotText, ReadTextFile) {
  test::TempDir dir;
  const auto path = dir.path() / "gt.txt";
  std::ofstream(path) << "1,1,1,2,3,4,1,1,1\n";
  EXPECT_EQ(read_text_file(path, "gt"), "1,1,1,2,3,4,1,1,1\n");
  const Error e = error_of([&] { read_text_file(dir.path() / "missing.txt", "run"); });
  EXPECT_EQ(e.kind(), Error::Kind::not_found);
  EXPECT_EQ(e.param(), "run");
}

}  // namespace
}  // namespace trailscope::metrics
