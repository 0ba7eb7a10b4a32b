// CSV tables: parsing, exact errors for bad input, and z-scoring.
#include <gtest/gtest.h>

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/projection/table.hpp"

namespace trailscope::projection {
namespace {

Error error_of(const std::string& csv) {
  try {
    (void)parse_table_csv(csv);
  } catch (const Error& e) {
    return e;
  }
  return Error(Error::Kind::internal, "", "no error");
}

TEST(ProjectionTable, ParsesHeaderNumbersQuotesAndBlankLines) {
  const Table t = parse_table_csv("a,\"b, c\",d\r\n1,2.5,-3e2\n\n+4, 5 ,6\n");
  ASSERT_EQ(t.rows, 2u);
  ASSERT_EQ(t.cols, 3u);
  EXPECT_EQ(t.columns[1], "b, c");
  EXPECT_FLOAT_EQ(t.at(0, 2), -300.0f);
  EXPECT_FLOAT_EQ(t.at(1, 0), 4.0f);
  EXPECT_FLOAT_EQ(t.at(1, 1), 5.0f);
}

TEST(ProjectionTable, NonNumericFieldNamesColumnAndLine) {
  const Error e = error_of("x,name,y\n1,2,3\n4,abc,6\n");
  EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
  EXPECT_EQ(e.param(), "table");
  EXPECT_STREQ(e.what(),
               "table line 3, column 'name': 'abc' is not a number (only numeric columns can be projected)");
}

TEST(ProjectionTable, NanAndInfinityAreRejected) {
  EXPECT_STREQ(error_of("x,y\n1,nan\n2,3\n").what(),
               "table line 2, column 'y': nan is not a finite float value");
  EXPECT_STREQ(error_of("x,y\n1,2\ninf,3\n").what(),
               "table line 3, column 'x': inf is not a finite float value");
  EXPECT_STREQ(error_of("x,y\n1,2\n1e39,3\n").what(),
               "table line 3, column 'x': 1e39 is not a finite float value");
}

TEST(ProjectionTable, ShapeErrors) {
  EXPECT_STREQ(error_of("x,y\n1,2\n3\n").what(), "table line 3: 1 fields, the header has 2");
  EXPECT_EQ(error_of("").kind(), Error::Kind::unprocessable);
  EXPECT_STREQ(error_of("x,y\n").what(), "table has a header but no data rows");
  EXPECT_STREQ(error_of("x,y\n1,2\n").what(), "table has 1 rows; a projection needs at least 2");
  EXPECT_STREQ(error_of("x,y\n1,\n2,3\n").what(),
               "table line 2, column 'y': '' is not a number (only numeric columns can be projected)");
}

TEST(ProjectionTable, ValidateNamesRowAndColumnOfNan) {
  Table t;
  t.rows = 2, t.cols = 2, t.columns = {"a", "b"};
  t.values = {1, 2, 3, std::nanf("")};
  try {
    validate_table(t, "data");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "data");
    EXPECT_STREQ(e.what(), "data row 2, column 'b': NaN or infinite value");
  }
}

TEST(ProjectionTable, StandardizeIsZScoreWithPopulationStd) {
  Table t = parse_table_csv("a,b,c\n1,10,7\n2,10,7\n3,10,7\n6,10,7\n");
  standardize(t);
  // a: mean 3, population variance (4 + 1 + 0 + 9) / 4 = 3.5.
  const double sd = std::sqrt(3.5);
  EXPECT_NEAR(t.at(0, 0), -2 / sd, 1e-6);
  EXPECT_NEAR(t.at(3, 0), 3 / sd, 1e-6);
  for (std::size_t r = 0; r < 4; ++r) EXPECT_EQ(t.at(r, 1), 0.0f);  // constant column: zeros, not NaN
}

TEST(ProjectionTable, ReadMissingFileIsNotFound) {
  try {
    (void)read_table_csv("/nonexistent/table.csv", "input");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::not_found);
    EXPECT_EQ(e.param(), "input");
  }
}

}  // namespace
}  // namespace trailscope::projection
