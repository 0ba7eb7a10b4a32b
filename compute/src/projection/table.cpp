// CSV → projection::Table, validation and z-scoring.
#include "trailscope/projection/table.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::projection {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// Splits one CSV line on ',' honouring "quoted" fields ("" inside quotes is a quote).
void split_line(std::string_view line, std::vector<std::string>& out) {
  out.clear();
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field.push_back('"');
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field.push_back(c);
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back(trim(field));
      field.clear();
    } else {
      field.push_back(c);
    }
  }
  out.emplace_back(trim(field));
}

void check_sizes(std::size_t rows, std::size_t cols, const std::string& param) {
  if (cols > limits::kMaxProjectionColumns)
    throw Error(Error::Kind::payload_too_large, param,
                param + " has " + std::to_string(cols) + " columns; at most " +
                    std::to_string(limits::kMaxProjectionColumns) + " are allowed");
  if (rows > limits::kMaxProjectionRows)
    throw Error(Error::Kind::payload_too_large, param,
                param + " has more than " + std::to_string(limits::kMaxProjectionRows) + " rows");
}

}  // namespace

Table parse_table_csv(std::string_view text, const std::string& param) {
  Table t;
  std::vector<std::string> fields;
  std::size_t line_no = 0, pos = 0;
  bool header = false;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trim(text.substr(pos, end - pos));
    pos = end + 1;
    ++line_no;
    if (line.empty()) continue;
    split_line(line, fields);
    if (!header) {
      header = true;
      t.columns = fields;
      t.cols = fields.size();
      for (std::size_t c = 0; c < t.cols; ++c)
        if (t.columns[c].empty()) t.columns[c] = "column " + std::to_string(c + 1);
      check_sizes(0, t.cols, param);
      continue;
    }
    if (fields.size() != t.cols)
      throw invalid_argument(param, param + " line " + std::to_string(line_no) + ": " +
                                        std::to_string(fields.size()) + " fields, the header has " +
                                        std::to_string(t.cols));
    for (std::size_t c = 0; c < t.cols; ++c) {
      const std::string& f = fields[c];
      double v = 0;
      const char* b = f.data();
      const char* e = f.data() + f.size();
      if (b != e && *b == '+') ++b;
      const auto r = std::from_chars(b, e, v);
      if (f.empty() || r.ec != std::errc() || r.ptr != e)
        throw invalid_argument(param, param + " line " + std::to_string(line_no) + ", column '" +
                                          t.columns[c] + "': '" + f +
                                          "' is not a number (only numeric columns can be projected)");
      if (!std::isfinite(v) || std::abs(v) > 3.0e38)
        throw invalid_argument(param, param + " line " + std::to_string(line_no) + ", column '" +
                                          t.columns[c] + "': " + f + " is not a finite float value");
      t.values.push_back(static_cast<float>(v));
    }
    ++t.rows;
    check_sizes(t.rows, t.cols, param);
  }
  if (!header) throw Error(Error::Kind::unprocessable, param, param + " is empty (no header line)");
  if (t.rows == 0) throw Error(Error::Kind::unprocessable, param, param + " has a header but no data rows");
  validate_table(t, param);
  return t;
}

Table read_table_csv(const std::string& path, const std::string& param) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw not_found(param, "cannot read " + param + " file '" + path + "'");
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  if (size > limits::kMaxProjectionTableBytes)
    throw Error(Error::Kind::payload_too_large, param,
                param + " file '" + path + "' is larger than " +
                    std::to_string(limits::kMaxProjectionTableBytes) + " bytes");
  in.seekg(0);
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  return parse_table_csv(text, param);
}

void validate_table(const Table& t, const std::string& param) {
  check_sizes(t.rows, t.cols, param);
  if (t.cols < 1) throw invalid_argument(param, param + " has no columns");
  if (t.rows < 2)
    throw Error(Error::Kind::unprocessable, param,
                param + " has " + std::to_string(t.rows) + " rows; a projection needs at least 2");
  if (t.values.size() != t.rows * t.cols)
    throw invalid_argument(param, param + " holds " + std::to_string(t.values.size()) + " values for " +
                                      std::to_string(t.rows) + " × " + std::to_string(t.cols));
  if (!t.columns.empty() && t.columns.size() != t.cols)
    throw invalid_argument(param, param + " has " + std::to_string(t.columns.size()) + " column names for " +
                                      std::to_string(t.cols) + " columns");
  for (std::size_t i = 0; i < t.values.size(); ++i)
    if (!std::isfinite(t.values[i])) {
      const std::size_t c = i % t.cols;
      const std::string name = t.columns.empty() ? std::to_string(c + 1) : "'" + t.columns[c] + "'";
      throw invalid_argument(param, param + " row " + std::to_string(i / t.cols + 1) + ", column " + name +
                                        ": NaN or infinite value");
    }
}

void standardize(Table& t) {
  const std::size_t n = t.rows, d = t.cols;
  if (n == 0) return;
  std::vector<double> mean(d, 0.0), var(d, 0.0);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < d; ++c) mean[c] += t.values[r * d + c];
  for (double& m : mean) m /= static_cast<double>(n);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < d; ++c) {
      const double x = t.values[r * d + c] - mean[c];
      var[c] += x * x;
    }
  for (std::size_t c = 0; c < d; ++c) {
    const double sd = std::sqrt(var[c] / static_cast<double>(n));
    // A (numerically) constant column carries no information; dividing by ~0 would blow rounding noise
    // up to unit variance.
    const double scale = sd > 1e-12 * (1.0 + std::abs(mean[c])) ? 1.0 / sd : 0.0;
    for (std::size_t r = 0; r < n; ++r)
      t.values[r * d + c] = static_cast<float>((t.values[r * d + c] - mean[c]) * scale);
  }
}

}  // namespace trailscope::projection
