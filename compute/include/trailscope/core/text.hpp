#pragma once
// Numbers as text: the one formatter of compute/ for doubles that are written out (parameter tables,
// error messages, graph and CSV files, render options). It writes the shortest text that reads back to
// the same value (std::to_chars without a precision): "0.05", "32", "1e-07", "-0", "inf", "nan". That is
// locale-independent and exact, unlike std::ostream (6 significant digits by default) and "%.17g"
// (which writes 0.1 as 0.10000000000000001). Fixed-width report tables (metrics/report.cpp, after
// TrackEval's printout) are layout, not a number's text, and keep printf.
#include <charconv>
#include <string>

namespace trailscope {

/// Appends the shortest round-trip text of `v` to `out` (no allocation beyond out's growth).
inline void append_shortest(std::string& out, double v) {
  char buf[32];  // the longest double is 24 characters ("-2.2250738585072014e-308")
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}
/// The same for a float: the shortest text that reads back to the same float ("0.1", not the double
/// expansion of 0.1f), as a float column's file format wants.
inline void append_shortest(std::string& out, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

/// The shortest round-trip text of `v`, e.g. format_double(0.05) == "0.05", format_double(32) == "32".
inline std::string format_double(double v) {
  std::string s;
  append_shortest(s, v);
  return s;
}

}  // namespace trailscope
