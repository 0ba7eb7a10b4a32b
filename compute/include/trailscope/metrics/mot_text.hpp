#pragma once
// Readers for the MOTChallenge text formats, the lingua franca of multi-object-tracking evaluation
// (TrackEval, py-motmetrics), plus a plain 3D point format for the teat tracker.
//
//   ground truth  frame,id,x,y,w,h,consider,class[,visibility[,...]]     (>= 8 columns)
//   tracker run   frame,id,x,y,w,h[,conf[,x,y,z[,...]]]                   (>= 6 columns)
//   3D points     frame,id,x,y,z[,...]                                    (>= 5 columns, millimetres)
//
// Boxes are in pixels, (x, y) the top-left corner. Fields are separated by commas or by whitespace
// (TrackEval sniffs either); blank lines and lines starting with '#' are skipped. Numbers may be written
// as floats ("12.0", "1e3"), but frame and id must be integral: frames are 1-based, ids any integer
// (runs often start at 0). Extra trailing columns are ignored.
//
// Every reader checks the whole text and reports every malformed line at once (the first
// kMaxListedLineErrors in the message, then a count), as Error::Kind::unprocessable whose param() is the
// `param` argument ("gt" or "run") and whose message reads "gt: line 12: ...; line 40: ...".
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace trailscope::metrics {

/// Malformed lines quoted in one error message; the rest are only counted.
inline constexpr std::size_t kMaxListedLineErrors = 10;

/// One ground-truth box.
struct GtBox {
  std::int64_t frame = 0;             ///< 1-based frame number
  std::int64_t id = 0;                ///< object id as written in the file
  double x = 0, y = 0, w = 0, h = 0;  ///< pixels; (x, y) is the top-left corner
  bool consider = true;               ///< column 7: 0 = "zero-marked", ignored by the evaluation
  int object_class = 1;   ///< column 8: MOTChallenge class 1..13 (1 = pedestrian), or -1 (MOT15: none)
  double visibility = 1;  ///< column 9 in [0, 1] when present; not used by the metrics
  std::size_t line = 0;   ///< 1-based line in the file, for error messages
};

/// One box of a tracker's output.
struct RunBox {
  std::int64_t frame = 0;
  std::int64_t id = 0;
  double x = 0, y = 0, w = 0, h = 0;  ///< pixels
  double confidence = 1;              ///< column 7 when present; not used by the metrics
  std::size_t line = 0;
};

/// One 3D position (ground truth or tracker output), e.g. a teat tip in camera coordinates.
struct TrackPoint {
  std::int64_t frame = 0;
  std::int64_t id = 0;
  double x = 0, y = 0, z = 0;  ///< millimetres (any unit works if d_max uses the same one)
  std::size_t line = 0;
};

/// Parses ground truth. Throws Error(unprocessable, param) listing malformed lines (too few columns, a
/// number that does not parse or is not finite, a non-integral or out-of-range frame/id, consider not
/// 0/1, class outside 1..13 and not -1), and Error(payload_too_large, param) beyond kMaxRunRows rows.
std::vector<GtBox> parse_mot_gt(std::string_view text, const std::string& param = "gt");

/// Parses a tracker's output. Column 8 (the class column of ground truth) is not read: in result files
/// it holds world coordinates or -1. Throws as parse_mot_gt.
std::vector<RunBox> parse_mot_run(std::string_view text, const std::string& param = "run");

/// Parses 3D points. Throws as parse_mot_gt.
std::vector<TrackPoint> parse_points(std::string_view text, const std::string& param);

/// The whole file as text. Throws Error(not_found, param) when it cannot be opened and
/// Error(payload_too_large, param) when it is larger than limits::kMaxRunBytes.
std::string read_text_file(const std::filesystem::path& path, const std::string& param);

}  // namespace trailscope::metrics
