#pragma once
// Reading gaze files: content detection (never by file name) and one reader per format, all producing
// gaze::Recording (gaze.hpp: units). Every sample row of a file becomes one sample (invalid ones too), so
// a file's sample count is its number of sample rows.
//
// Formats and what each reader takes from the file:
//  - eyelink_asc: SR Research EDF2ASC text. Samples are lines starting with a digit: `t x y pupil ...`
//    (monocular) or `t xL yL pL xR yR pR ...` (binocular, chosen by the preceding SAMPLES line); `.` is
//    missing. Time ms. START..END blocks are recordings; EFIX/ESACC/EBLINK become tracker_events; the
//    SAMPLES line's RATE, the DISPLAY_COORDS/GAZE_COORDS messages (px), TRIALID (trial) and
//    `!V IMGLOAD ... <file>` (stimulus) are read.
//  - tobii_tsv: Tobii SDK raw export (as written by the I2MC tools, Hessels et al., Behav Res Methods
//    2017): a header naming Time (µs), LGazePos2dx/y, LValidity, RGazePos2dx/y, RValidity. Coordinates
//    are normalised 0-1, so the screen size in px must be given. Validity codes 0-1 are valid (I2MC's
//    rule; 2 uncertain, 3 probably the other eye, 4 eye not found are invalid).
//  - psychopy_tobii: psychopy_tobii_controller export: "Recording resolution W x H", then per session a
//    table TimeStamp (ms) GazePointXLeft ... ValidityLeft ... ValidityRight; PsychoPy "pix" units (origin
//    at the screen centre, y up) converted to top-left px; validity 1 = valid; `nan` missing.
//  - smi_idf_text: SMI iView X IDF Converter text: `##` header (Sample Rate, Calibration Area px,
//    Stimulus Dimension mm, Head Distance mm, Subject), then a table Time (µs) Type Trial ... POR X/Y [px].
//    SMP rows are samples; trials are recordings; MSG "Scene Image: <path>" names the stimulus. POR
//    0, 0 is missing.
//  - gazecom_arff: GazeCom ARFF (Dorr et al., J Vis 2010; Agtzidis et al., ETRA 2016): `%@METADATA`
//    width_px height_px width_mm height_mm distance_mm, @ATTRIBUTE time (µs) x y [confidence], @DATA rows;
//    confidence 0 is invalid.
//  - dsf_coord: DSF/GazeCom "coord" text: `#` comments, `gaze W H`, `geometry distance D width W height H`
//    (metres), rows `time_us x y flag`, flag 1 valid.
//  - simple_gaze_tracker: SimpleGazeTracker CSV: `#KEY,value` header (SCREEN_WIDTH/HEIGHT px,
//    DOTS_PER_CENTIMETER_H/V, VIEWING_DISTANCE cm, SCREEN_ORIGIN, #DATAFORMAT,T,X,Y,P or T,LX,LY,RX,RY,..),
//    #START_REC blocks are recordings; time ms; non-numeric positions (NOPURKINJE, ...) are missing;
//    a BottomLeft origin is flipped to top-left.
//  - plain: delimited text `time x y [valid]` (comma, tab or whitespace), with or without a header. With a
//    header, columns are found by name: time (time, timestamp, n, t, time_ms, time_us, time_s), x (x,
//    x_px, gaze_x, x_deg), y, validity ("valid": non-zero = valid; "val" as in GazeBase and
//    "validity" as in Tobii: 0 = valid) and per-sample labels (lab, label*) kept as annotations. Without a
//    header it takes 3 or 4 numeric columns, the 4th a flag, non-zero = valid. Time unit: from the column
//    name (time_us, time_s) or ms. Missing: NaN, an empty field, the EyeLink-export marker -32768 (x and
//    y), and in px exactly (0, 0) (what SMI-based exports such as the Lund 2013 data write when the eye
//    is lost). GazeBase files (columns n x y val lab) and x_deg/y_deg columns are in degrees.
//
// Damaged files are refused with Error(unprocessable, "file", "line N: ...") naming the line and what is
// wrong (a bad number, too few fields: "truncated?"); a file whose format cannot be recognised with
// Error(unsupported_format, "format", ...). Inputs over limits::kMaxGazeFileBytes or kMaxGazeSamples are
// Error(payload_too_large, "file", ...).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "trailscope/core/progress.hpp"
#include "trailscope/gaze/gaze.hpp"

namespace trailscope::gaze {

enum class GazeFormat {
  eyelink_asc,
  tobii_tsv,
  psychopy_tobii,
  smi_idf_text,
  gazecom_arff,
  dsf_coord,
  simple_gaze_tracker,
  plain,
};
/// "eyelink_asc", "tobii_tsv", ... (the enumerator names).
const char* to_string(GazeFormat f) noexcept;
/// The inverse of to_string; throws Error(invalid_argument, param, ...) listing the names.
GazeFormat parse_gaze_format(std::string_view text, const std::string& param = "format");

/// Recognises the format from the first bytes (up to a few KiB are enough; the whole file is fine). A UTF-8
/// BOM is skipped. Throws Error(unsupported_format, "format", ...) saying what was seen.
GazeFormat detect_gaze_format(std::string_view head);

/// Which eye a binocular file's sample takes.
enum class Eye { average, left, right };
/// "average" | "left" | "right"; throws Error(invalid_argument, param, ...) otherwise.
Eye parse_eye(std::string_view text, const std::string& param = "eye");

struct GazeIngestOptions {
  std::optional<GazeFormat> format;  ///< skip detection
  /// Non-zero fields override the file's geometry (ScreenGeometry::overridden_by).
  ScreenGeometry geometry;
  std::string participant;  ///< when non-empty, replaces the file's
  std::string stimulus;     ///< when non-empty, replaces the file's
  /// Binocular files: average of the valid eyes (one valid eye alone is used as is), or one eye.
  Eye eye = Eye::average;
  /// Called with the fraction of the bytes parsed (stage "parse") about every MiB, and 1 at the end.
  ProgressFn progress;
  /// Checked with every progress step; a cancelled ingest throws Error(cancelled).
  const CancelToken* cancel = nullptr;
};

/// Parses one file's content into recordings (in file order). Throws as described above.
GazeDataset read_gaze(std::string_view content, const GazeIngestOptions& options = {});
/// Reads `path` (at most limits::kMaxGazeFileBytes) and parses it; a participant defaults to the file
/// stem when neither the file nor the options name one. Throws Error(not_found, "file", ...) when the
/// file cannot be opened.
GazeDataset read_gaze_file(const std::string& path, const GazeIngestOptions& options = {});

}  // namespace trailscope::gaze
