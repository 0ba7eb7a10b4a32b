#pragma once
// The input of every projection: a dense row-major float matrix of N rows (points) by D columns
// (dimensions), with the column names of the CSV header it came from.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace trailscope::projection {

struct Table {
  std::size_t rows = 0, cols = 0;
  std::vector<float> values;         ///< rows × cols, row-major; finite
  std::vector<std::string> columns;  ///< cols names (may be empty for synthetic tables)

  float at(std::size_t r, std::size_t c) const { return values[r * cols + c]; }
  const float* row(std::size_t r) const { return values.data() + r * cols; }
};

/// Parses CSV text with a header line: every column must be numeric (a decimal or exponent number)
/// in every data row. Blank lines are skipped; fields may be quoted ("..."); the separator is ','.
/// Throws Error(invalid_argument, param) naming the column and the 1-based line for a non-numeric or
/// NaN/Inf field, or a row with the wrong field count; Error(unprocessable, param) when there is no data
/// row; Error(payload_too_large, param) beyond limits::kMaxProjectionRows rows or
/// limits::kMaxProjectionColumns columns.
Table parse_table_csv(std::string_view text, const std::string& param = "table");

/// Reads and parses a CSV file (as parse_table_csv). Throws Error(not_found, param) when it cannot be
/// read.
Table read_table_csv(const std::string& path, const std::string& param = "table");

/// Checks the shape and values of a table built in code: rows ≥ 2, cols ≥ 1, values.size() ==
/// rows·cols, every value finite, sizes within limits. Throws as parse_table_csv.
void validate_table(const Table& t, const std::string& param = "table");

/// Z-scores every column in place: (x − mean) / std with the population std (ddof 0, as scikit-learn's
/// StandardScaler). A constant column becomes all zeros (centred only) rather than NaN. Mean and std are
/// accumulated in double.
void standardize(Table& t);

}  // namespace trailscope::projection
