// MOTChallenge text readers. Hand-rolled splitting and std::from_chars keep a 5 MB result file well
// under 10 ms; every malformed line is collected so that a user fixes a file in one round trip.
#include "trailscope/metrics/mot_text.hpp"

#include <charconv>
#include <cmath>
#include <fstream>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::metrics {
namespace {

/// Collects "line N: reason" messages and throws them together.
class LineErrors {
 public:
  explicit LineErrors(const std::string& param) : param_(param) {}
  void add(std::size_t line, const std::string& reason) {
    if (count_ < kMaxListedLineErrors)
      text_ += (count_ ? "; line " : "line ") + std::to_string(line) + ": " + reason;
    ++count_;
  }
  void throw_if_any() const {
    if (count_ == 0) return;
    std::string msg =
        param_ + ": " + std::to_string(count_) + " malformed line" + (count_ > 1 ? "s" : "") + ": " + text_;
    if (count_ > kMaxListedLineErrors)
      msg += "; and " + std::to_string(count_ - kMaxListedLineErrors) + " more";
    throw Error(Error::Kind::unprocessable, param_, msg);
  }

 private:
  std::string param_;
  std::string text_;
  std::size_t count_ = 0;
};

/// Splits `line` at commas or runs of whitespace ("1, 2" and "1 2" both give two fields). An empty
/// field between two commas is kept (and later fails to parse), a trailing comma is ignored.
void split_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    if (i >= line.size()) break;
    std::size_t j = i;
    while (j < line.size() && line[j] != ',' && !is_space(line[j])) ++j;
    out.push_back(line.substr(i, j - i));
    while (j < line.size() && is_space(line[j])) ++j;
    if (j < line.size() && line[j] == ',') ++j;
    i = j;
  }
}

bool parse_double(std::string_view s, double& v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(v);
}

/// An integer written as "12" or "12.0" (TrackEval casts float columns to int).
bool parse_integral(std::string_view s, std::int64_t& v) {
  double d = 0;
  if (!parse_double(s, d) || d != std::floor(d) || std::fabs(d) > 9.0e15) return false;
  v = static_cast<std::int64_t>(d);
  return true;
}

/// Runs `row(fields, line_no, errors)` on every data line; `min_cols` columns are required.
template <typename Row>
void for_each_row(std::string_view text, const std::string& param, std::size_t min_cols, const char* layout,
                  Row&& row) {
  LineErrors errors(param);
  std::vector<std::string_view> fields;
  std::size_t line_no = 0, rows = 0, pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    split_fields(line, fields);
    if (fields.empty() || fields[0].front() == '#') continue;
    if (++rows > limits::kMaxRunRows)
      throw Error(Error::Kind::payload_too_large, param,
                  param + ": more than " + std::to_string(limits::kMaxRunRows) + " rows");
    if (fields.size() < min_cols) {
      errors.add(line_no, std::to_string(fields.size()) + " columns, expected at least " +
                              std::to_string(min_cols) + " (" + layout + ")");
      continue;
    }
    row(fields, line_no, errors);
  }
  errors.throw_if_any();
}

/// Frame (column 1) and id (column 2); false after reporting a problem.
bool parse_frame_id(const std::vector<std::string_view>& f, std::size_t line, LineErrors& errors,
                    std::int64_t& frame, std::int64_t& id) {
  if (!parse_integral(f[0], frame) || frame < 1 || frame > limits::kMaxRunFrames) {
    errors.add(line, "frame '" + std::string(f[0]) + "' is not an integer in 1.." +
                         std::to_string(limits::kMaxRunFrames));
    return false;
  }
  if (!parse_integral(f[1], id)) {
    errors.add(line, "id '" + std::string(f[1]) + "' is not an integer");
    return false;
  }
  return true;
}

/// Columns [first, first + n) as finite numbers; false after reporting the first bad one.
bool parse_numbers(const std::vector<std::string_view>& f, std::size_t first, std::size_t n, double* out,
                   std::size_t line, LineErrors& errors) {
  for (std::size_t k = 0; k < n; ++k) {
    if (!parse_double(f[first + k], out[k])) {
      errors.add(line, "column " + std::to_string(first + k + 1) + " '" + std::string(f[first + k]) +
                           "' is not a finite number");
      return false;
    }
  }
  return true;
}

}  // namespace

std::vector<GtBox> parse_mot_gt(std::string_view text, const std::string& param) {
  std::vector<GtBox> out;
  for_each_row(
      text, param, 8, "frame,id,x,y,w,h,consider,class[,visibility]",
      [&](const std::vector<std::string_view>& f, std::size_t line, LineErrors& errors) {
        GtBox b;
        b.line = line;
        double v[4];
        std::int64_t consider = 0, cls = 0;
        if (!parse_frame_id(f, line, errors, b.frame, b.id) || !parse_numbers(f, 2, 4, v, line, errors))
          return;
        if (!parse_integral(f[6], consider) || (consider != 0 && consider != 1)) {
          errors.add(line, "consider flag '" + std::string(f[6]) + "' is not 0 or 1");
          return;
        }
        // TrackEval refuses classes outside MOTChallenge's 1..13; -1 is MOT15's "no class".
        if (!parse_integral(f[7], cls) || !((cls >= 1 && cls <= 13) || cls == -1)) {
          errors.add(line, "class '" + std::string(f[7]) + "' is not a MOTChallenge class 1..13 or -1");
          return;
        }
        if (f.size() >= 9 && !parse_numbers(f, 8, 1, &b.visibility, line, errors)) return;
        b.x = v[0], b.y = v[1], b.w = v[2], b.h = v[3];
        b.consider = consider == 1;
        b.object_class = static_cast<int>(cls);
        out.push_back(b);
      });
  return out;
}

std::vector<RunBox> parse_mot_run(std::string_view text, const std::string& param) {
  std::vector<RunBox> out;
  for_each_row(
      text, param, 6, "frame,id,x,y,w,h[,conf,x,y,z]",
      [&](const std::vector<std::string_view>& f, std::size_t line, LineErrors& errors) {
        RunBox b;
        b.line = line;
        double v[4];
        if (!parse_frame_id(f, line, errors, b.frame, b.id) || !parse_numbers(f, 2, 4, v, line, errors))
          return;
        if (f.size() >= 7 && !parse_numbers(f, 6, 1, &b.confidence, line, errors)) return;
        b.x = v[0], b.y = v[1], b.w = v[2], b.h = v[3];
        out.push_back(b);
      });
  return out;
}

std::vector<TrackPoint> parse_points(std::string_view text, const std::string& param) {
  std::vector<TrackPoint> out;
  for_each_row(
      text, param, 5, "frame,id,x,y,z",
      [&](const std::vector<std::string_view>& f, std::size_t line, LineErrors& errors) {
        TrackPoint p;
        p.line = line;
        double v[3];
        if (!parse_frame_id(f, line, errors, p.frame, p.id) || !parse_numbers(f, 2, 3, v, line, errors))
          return;
        p.x = v[0], p.y = v[1], p.z = v[2];
        out.push_back(p);
      });
  return out;
}

std::string read_text_file(const std::filesystem::path& path, const std::string& param) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) throw Error(Error::Kind::not_found, param, param + ": cannot open " + path.string());
  if (size > limits::kMaxRunBytes)
    throw Error(Error::Kind::payload_too_large, param,
                param + ": " + path.string() + " is " + std::to_string(size) +
                    " bytes, more than the limit of " + std::to_string(limits::kMaxRunBytes));
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size)
    throw Error(Error::Kind::internal, param, param + ": cannot read " + path.string());
  return text;
}

}  // namespace trailscope::metrics
