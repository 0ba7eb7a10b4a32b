// Gaze file readers (ingest.hpp): detection by content and one reader per format. Every reader walks the
// text once, line by line, and appends samples to the recording it is in.
#include "trailscope/gaze/ingest.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::gaze {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// --- text helpers -----------------------------------------------------------------------------------

/// Lines of a text, '\r' stripped, 1-based numbers.
struct Lines {
  std::string_view s;
  std::size_t pos = 0, number = 0;
  bool next(std::string_view& line) {
    if (pos >= s.size()) return false;
    const std::size_t nl = s.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? s.size() : nl;
    line = s.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = nl == std::string_view::npos ? s.size() : nl + 1;
    ++number;
    return true;
  }
};

std::string_view trim(std::string_view v) {
  while (!v.empty() && (v.front() == ' ' || v.front() == '\t' || v.front() == '"')) v.remove_prefix(1);
  while (!v.empty() && (v.back() == ' ' || v.back() == '\t' || v.back() == '"')) v.remove_suffix(1);
  return v;
}

bool starts_with(std::string_view v, std::string_view p) {
  return v.substr(0, p.size()) == p;
}

std::string lower(std::string_view v) {
  std::string s(v);
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Splits on one delimiter (fields may be empty).
void split(std::string_view line, char delim, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t d = line.find(delim, start);
    if (d == std::string_view::npos) {
      out.push_back(line.substr(start));
      return;
    }
    out.push_back(line.substr(start, d - start));
    start = d + 1;
  }
}

/// Splits on runs of spaces and tabs (no empty fields).
void split_ws(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i >= line.size()) break;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    out.push_back(line.substr(i, j - i));
    i = j;
  }
}

/// A decimal number (leading/trailing blanks and quotes allowed; "nan"/"NaN" parse to NaN).
bool to_num(std::string_view v, double& out) {
  v = trim(v);
  if (v.empty()) return false;
  if (v.front() == '+') v.remove_prefix(1);
  const auto r = std::from_chars(v.data(), v.data() + v.size(), out);
  return r.ec == std::errc() && r.ptr == v.data() + v.size();
}

std::string shown(std::string_view v) {
  v = trim(v);
  return "\"" + std::string(v.substr(0, 40)) + (v.size() > 40 ? "..." : "") + "\"";
}

[[noreturn]] void damaged(std::size_t line, const std::string& what) {
  throw Error(Error::Kind::unprocessable, "file", "line " + std::to_string(line) + ": " + what);
}

/// A number that must parse (the file is damaged otherwise).
double need_num(std::string_view v, std::size_t line, const std::string& column) {
  double d;
  if (!to_num(v, d)) damaged(line, column + " is not a number: " + shown(v));
  return d;
}

/// Number of fields check: a short row is what a cut-off file leaves at its end.
void need_fields(std::size_t have, std::size_t want, std::size_t line, const char* what) {
  if (have < want)
    damaged(line, std::string(what) + " has " + std::to_string(have) + " field" + (have == 1 ? "" : "s") +
                      ", expected at least " + std::to_string(want) + " (truncated?)");
}

std::string basename_of(std::string_view path) {
  const std::size_t p = path.find_last_of("/\\");
  return std::string(trim(p == std::string_view::npos ? path : path.substr(p + 1)));
}

// --- accumulation -------------------------------------------------------------------------------------

struct Ctx {
  const GazeIngestOptions& opt;
  GazeFormat format;
  std::size_t total_bytes;
  GazeDataset ds;
  std::size_t samples = 0, next_progress = 1u << 20;

  Recording& start(ScreenGeometry file_geometry = {}) {
    if (ds.recordings.size() >= limits::kMaxGazeRecordings)
      throw Error(Error::Kind::payload_too_large, "file",
                  "more than " + std::to_string(limits::kMaxGazeRecordings) +
                      " recordings in one gaze file (limits::kMaxGazeRecordings)");
    Recording& r = ds.recordings.emplace_back();
    r.format = to_string(format);
    r.geometry = file_geometry.overridden_by(opt.geometry);
    return r;
  }
  Recording& current() { return ds.recordings.empty() ? start() : ds.recordings.back(); }

  void push(Recording& r, double t_ms, double x, double y, bool valid) {
    if (++samples > limits::kMaxGazeSamples)
      throw Error(Error::Kind::payload_too_large, "file",
                  "more than " + std::to_string(limits::kMaxGazeSamples) +
                      " samples in one gaze file (limits::kMaxGazeSamples)");
    valid = valid && std::isfinite(x) && std::isfinite(y);
    r.t_ms.push_back(t_ms);
    r.x.push_back(valid ? x : kNaN);
    r.y.push_back(valid ? y : kNaN);
    r.valid.push_back(valid ? 1 : 0);
  }
  void tick(std::size_t pos) {
    if (pos < next_progress) return;
    next_progress = pos + (1u << 20);
    if (opt.cancel) opt.cancel->throw_if_cancelled();
    if (opt.progress) opt.progress(double(pos) / double(std::max<std::size_t>(total_bytes, 1)), "parse");
  }
};

/// One binocular sample from two eyes, each with its validity.
void combine(double xl, double yl, bool vl, double xr, double yr, bool vr, Eye eye, double& x, double& y,
             bool& v) {
  vl = vl && std::isfinite(xl) && std::isfinite(yl);
  vr = vr && std::isfinite(xr) && std::isfinite(yr);
  if (eye == Eye::left || (eye == Eye::average && !vr)) {
    x = xl, y = yl, v = vl;
  } else if (eye == Eye::right || !vl) {
    x = xr, y = yr, v = vr;
  } else {
    x = (xl + xr) / 2, y = (yl + yr) / 2, v = true;
  }
}

// --- EyeLink ASC --------------------------------------------------------------------------------------

void read_eyelink(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  ScreenGeometry geometry;
  bool binocular = false;
  char mono_eye = 0;
  double rate = 0;
  Recording* rec = nullptr;
  std::string pending_trial, pending_stimulus;
  auto open = [&]() -> Recording& {
    Recording& r = c.start(geometry);
    r.rate_hz = rate;
    r.trial = pending_trial.empty() ? std::to_string(c.ds.recordings.size()) : pending_trial;
    r.stimulus = pending_stimulus;
    pending_trial.clear(), pending_stimulus.clear();
    rec = &r;
    return r;
  };
  while (lines.next(line)) {
    c.tick(lines.pos);
    if (line.empty()) continue;
    const char first = line.front();
    if (first >= '0' && first <= '9') {
      split_ws(line, f);
      need_fields(f.size(), binocular ? 7 : 4, lines.number, "EyeLink sample");
      if (!rec) open();
      const double t = need_num(f[0], lines.number, "time");
      const auto pos = [&](std::string_view v, const char* col) {
        if (trim(v) == ".") return kNaN;
        return need_num(v, lines.number, col);
      };
      double x, y;
      bool v;
      if (binocular) {
        const double xl = pos(f[1], "x (left)"), yl = pos(f[2], "y (left)");
        const double xr = pos(f[4], "x (right)"), yr = pos(f[5], "y (right)");
        combine(xl, yl, true, xr, yr, true, c.opt.eye, x, y, v);
      } else {
        x = pos(f[1], "x"), y = pos(f[2], "y"), v = true;
      }
      c.push(*rec, t, x, y, v);
      continue;
    }
    split_ws(line, f);
    if (f.empty()) continue;
    const std::string_view key = f[0];
    if (key == "START") {
      open();
    } else if (key == "END") {
      rec = nullptr;
    } else if (key == "SAMPLES") {
      bool l = false, r = false;
      for (std::size_t i = 1; i < f.size(); ++i) {
        if (f[i] == "LEFT") l = true;
        if (f[i] == "RIGHT") r = true;
        if (f[i] == "RATE" && i + 1 < f.size()) rate = need_num(f[i + 1], lines.number, "RATE");
      }
      binocular = l && r;
      mono_eye = l && !r ? 'L' : r && !l ? 'R' : 0;
      if (rec) rec->rate_hz = rate;
    } else if (key == "MSG" && f.size() >= 3) {
      const std::string_view what = f[2];
      if ((what == "DISPLAY_COORDS" || what == "GAZE_COORDS") && f.size() >= 7) {
        // (`what` views the line: it is not NUL-terminated, so it is never passed as a C string.)
        const double x0 = need_num(f[3], lines.number, "x0"), y0 = need_num(f[4], lines.number, "y0");
        const double x1 = need_num(f[5], lines.number, "x1"), y1 = need_num(f[6], lines.number, "y1");
        // DISPLAY_COORDS 0 0 1023 767 (last pixel) and EyeLink I's 0 0 640 480 (size) both occur; the
        // inclusive form is the documented one, so a size that is odd after +1 means the exclusive form.
        double w = x1 - x0 + 1, h = y1 - y0 + 1;
        if (std::fmod(w, 2) != 0 && std::fmod(h, 2) != 0) w -= 1, h -= 1;
        ScreenGeometry g;
        g.width_px = w, g.height_px = h;
        geometry = geometry.overridden_by(g);
        if (rec) rec->geometry = geometry.overridden_by(c.opt.geometry);
      } else if (std::find(f.begin() + 2, f.end(), std::string_view("TRIALID")) != f.end()) {
        const std::size_t p = line.find("TRIALID");
        std::string id(trim(line.substr(p + 7)));
        if (rec)
          rec->trial = id;
        else
          pending_trial = id;
      } else if (what == "!V" && f.size() >= 6 && f[3] == "IMGLOAD") {
        const std::string stim = basename_of(f[5]);
        if (rec)
          rec->stimulus = stim;
        else
          pending_stimulus = stim;
      }
    } else if ((key == "EFIX" || key == "ESACC" || key == "EBLINK") && f.size() >= 4) {
      if (!rec) open();
      GazeEvent e;
      e.type = key == "EFIX" ? EventType::fixation : key == "ESACC" ? EventType::saccade : EventType::blink;
      e.eye = f[1] == "L" ? 'L' : f[1] == "R" ? 'R' : 0;
      e.t_start_ms = need_num(f[2], lines.number, std::string(key) + " start");
      e.t_end_ms = need_num(f[3], lines.number, std::string(key) + " end");
      rec->tracker_events.push_back(e);
    }
  }
  (void)mono_eye;
}

// --- Tobii SDK raw TSV (I2MC layout) ------------------------------------------------------------------

void read_tobii(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  if (!lines.next(line)) damaged(1, "empty file");
  split(line, '\t', f);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < f.size(); ++i) col[std::string(trim(f[i]))] = i;
  const char* needed[] = {"Time",        "LGazePos2dx", "LGazePos2dy", "LValidity",
                          "RGazePos2dx", "RGazePos2dy", "RValidity"};
  std::size_t idx[7];
  for (int k = 0; k < 7; ++k) {
    const auto it = col.find(needed[k]);
    if (it == col.end())
      throw Error(Error::Kind::unprocessable, "file",
                  std::string("line 1: Tobii header has no column ") + needed[k]);
    idx[k] = it->second;
  }
  const std::size_t want = *std::max_element(idx, idx + 7) + 1;
  Recording& r = c.start();
  if (!r.geometry.has_pixels())
    throw invalid_argument("geometry",
                           "Tobii SDK gaze is normalised to 0-1 and the file does not say the screen size: "
                           "give width_px and height_px");
  const double W = r.geometry.width_px, H = r.geometry.height_px;
  while (lines.next(line)) {
    c.tick(lines.pos);
    if (trim(line).empty()) continue;
    split(line, '\t', f);
    need_fields(f.size(), want, lines.number, "Tobii row");
    const double t = need_num(f[idx[0]], lines.number, "Time");
    const double xl = need_num(f[idx[1]], lines.number, "LGazePos2dx");
    const double yl = need_num(f[idx[2]], lines.number, "LGazePos2dy");
    const double vl = need_num(f[idx[3]], lines.number, "LValidity");
    const double xr = need_num(f[idx[4]], lines.number, "RGazePos2dx");
    const double yr = need_num(f[idx[5]], lines.number, "RGazePos2dy");
    const double vr = need_num(f[idx[6]], lines.number, "RValidity");
    double x, y;
    bool v;
    combine(xl * W, yl * H, vl <= 1, xr * W, yr * H, vr <= 1, c.opt.eye, x, y, v);
    c.push(r, t / 1000.0, x, y, v);
  }
}

// --- psychopy_tobii_controller --------------------------------------------------------------------------

void read_psychopy_tobii(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  ScreenGeometry file_geometry;
  Recording* rec = nullptr;
  enum { none, samples, events } table = none;
  std::size_t ix[6] = {};
  bool first_event = false;
  while (lines.next(line)) {
    c.tick(lines.pos);
    if (trim(line).empty()) continue;
    split(line, '\t', f);
    const std::string_view k = trim(f[0]);
    if (k == "Recording resolution" && f.size() >= 2) {
      // "1600 x 1200"
      std::vector<std::string_view> p;
      split_ws(f[1], p);
      if (p.size() != 3) damaged(lines.number, "resolution is not \"W x H\": " + shown(f[1]));
      file_geometry.width_px = need_num(p[0], lines.number, "resolution width");
      file_geometry.height_px = need_num(p[2], lines.number, "resolution height");
    } else if (k == "Session Start") {
      rec = &c.start(file_geometry);
      rec->trial = std::to_string(c.ds.recordings.size());
      table = none;
    } else if (k == "Session End") {
      rec = nullptr, table = none;
    } else if (k == "TimeStamp") {
      if (!rec) damaged(lines.number, "table outside a Session Start .. Session End block");
      if (f.size() >= 2 && trim(f[1]) == "Event") {
        table = events, first_event = true;
        continue;
      }
      std::map<std::string, std::size_t> col;
      for (std::size_t i = 0; i < f.size(); ++i) col[std::string(trim(f[i]))] = i;
      const char* names[] = {"GazePointXLeft",  "GazePointYLeft",  "ValidityLeft",
                             "GazePointXRight", "GazePointYRight", "ValidityRight"};
      for (int i = 0; i < 6; ++i) {
        if (!col.count(names[i]))
          damaged(lines.number, std::string("sample table has no column ") + names[i]);
        ix[i] = col[names[i]];
      }
      if (!rec->geometry.has_pixels())
        throw invalid_argument("geometry",
                               "PsychoPy pix coordinates are centred; the file has no \"Recording "
                               "resolution\": give width_px and height_px");
      table = samples;
    } else if (table == samples) {
      need_fields(f.size(), *std::max_element(ix, ix + 6) + 1, lines.number, "Tobii sample");
      const double t = need_num(f[0], lines.number, "TimeStamp");
      const double W = rec->geometry.width_px, H = rec->geometry.height_px;
      const double xl = need_num(f[ix[0]], lines.number, "GazePointXLeft");
      const double yl = need_num(f[ix[1]], lines.number, "GazePointYLeft");
      const double vl = need_num(f[ix[2]], lines.number, "ValidityLeft");
      const double xr = need_num(f[ix[3]], lines.number, "GazePointXRight");
      const double yr = need_num(f[ix[4]], lines.number, "GazePointYRight");
      const double vr = need_num(f[ix[5]], lines.number, "ValidityRight");
      double x, y;
      bool v;
      // PsychoPy "pix": origin at the screen centre, y up.
      combine(xl + W / 2, H / 2 - yl, vl == 1, xr + W / 2, H / 2 - yr, vr == 1, c.opt.eye, x, y, v);
      c.push(*rec, t, x, y, v);
    } else if (table == events && rec && f.size() >= 2) {
      if (first_event) rec->trial = std::string(trim(f[1]));
      first_event = false;
    }
  }
}

// --- SMI iView X IDF Converter text -----------------------------------------------------------------

void read_smi(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  ScreenGeometry g;
  double rate = 0;
  std::string subject;
  std::size_t ti = 0, ty = 0, tt = 0;
  long lx = -1, ly = -1, rx = -1, ry = -1;
  bool header = false;
  std::map<std::string, std::size_t> trial_rec;
  std::map<std::string, std::string> trial_stim;
  while (lines.next(line)) {
    c.tick(lines.pos);
    if (starts_with(line, "##")) {
      split(line.substr(2), '\t', f);
      const std::string_view k = trim(f[0]);
      const auto num = [&](std::size_t i) { return need_num(f[i], lines.number, std::string(k)); };
      if (k == "Sample Rate:" && f.size() >= 2)
        rate = num(1);
      else if (k == "Calibration Area:" && f.size() >= 3)
        g.width_px = num(1), g.height_px = num(2);
      else if (k == "Stimulus Dimension [mm]:" && f.size() >= 3)
        g.width_cm = num(1) / 10, g.height_cm = num(2) / 10;
      else if (k == "Head Distance [mm]:" && f.size() >= 2)
        g.distance_cm = num(1) / 10;
      else if (k == "Subject:" && f.size() >= 2)
        subject = std::string(trim(f[1]));
      continue;
    }
    if (trim(line).empty()) continue;
    split(line, '\t', f);
    if (!header) {
      if (trim(f[0]) != "Time")
        damaged(lines.number, "expected the table header (Time, Type, Trial, ...), found " + shown(line));
      for (std::size_t i = 0; i < f.size(); ++i) {
        const std::string_view n = trim(f[i]);
        if (n == "Type") ty = i;
        if (n == "Trial") tt = i;
        if (n == "L POR X [px]") lx = long(i);
        if (n == "L POR Y [px]") ly = long(i);
        if (n == "R POR X [px]") rx = long(i);
        if (n == "R POR Y [px]") ry = long(i);
      }
      // An eye counts only with both of its columns (one without the other is read as neither).
      if (lx < 0 || ly < 0) lx = ly = -1;
      if (rx < 0 || ry < 0) rx = ry = -1;
      if (!ty || !tt || (lx < 0 && rx < 0))
        damaged(lines.number, "the table header lacks Type, Trial or a POR X/Y [px] pair");
      header = true;
      continue;
    }
    need_fields(f.size(), std::max(ty, tt) + 1, lines.number, "SMI row");
    const std::string trial(trim(f[tt]));
    const std::string_view type = trim(f[ty]);
    if (type == "MSG") {
      const std::string_view msg = f.size() > tt + 1 ? trim(f[tt + 1]) : std::string_view();
      constexpr std::string_view kScene = "Scene Image:";
      const std::size_t p = msg.find(kScene);
      if (p != std::string_view::npos) {
        const std::string stim = basename_of(msg.substr(p + kScene.size()));
        trial_stim[trial] = stim;
        if (trial_rec.count(trial)) c.ds.recordings[trial_rec[trial]].stimulus = stim;
      }
      continue;
    }
    if (type != "SMP") continue;
    const long want = std::max({lx, ly, rx, ry}) + 1;
    need_fields(f.size(), std::size_t(want), lines.number, "SMI sample");
    if (!trial_rec.count(trial)) {
      Recording& r = c.start(g);
      r.rate_hz = rate, r.trial = trial, r.participant = subject;
      if (trial_stim.count(trial)) r.stimulus = trial_stim[trial];
      trial_rec[trial] = c.ds.recordings.size() - 1;
    }
    Recording& r = c.ds.recordings[trial_rec[trial]];
    const double t = need_num(f[ti], lines.number, "Time");
    // POR exactly (0, 0) is iView's "no gaze" value.
    const auto eye = [&](long ix, long iy, double& x, double& y) {
      if (ix < 0) return false;
      x = need_num(f[ix], lines.number, "POR X"), y = need_num(f[iy], lines.number, "POR Y");
      return !(x == 0 && y == 0);
    };
    double xl = kNaN, yl = kNaN, xr = kNaN, yr = kNaN;
    const bool vl = eye(lx, ly, xl, yl), vr = eye(rx, ry, xr, yr);
    double x, y;
    bool v;
    combine(xl, yl, vl, xr, yr, vr, lx < 0 ? Eye::right : rx < 0 ? Eye::left : c.opt.eye, x, y, v);
    c.push(r, t / 1000.0, x, y, v);
  }
  if (!header) damaged(lines.number, "no sample table (the Time, Type, Trial header line is missing)");
}

// --- GazeCom ARFF ---------------------------------------------------------------------------------------

void read_arff(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  ScreenGeometry g;
  std::vector<std::string> attrs;
  bool data = false;
  long it = -1, ix = -1, iy = -1, ic = -1;
  Recording* r = nullptr;
  while (lines.next(line)) {
    c.tick(lines.pos);
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    if (t.front() == '%') {
      if (starts_with(t, "%@METADATA")) {
        split_ws(t, f);
        if (f.size() >= 3) {
          const double v = need_num(f[2], lines.number, std::string(f[1]));
          if (f[1] == "width_px") g.width_px = v;
          if (f[1] == "height_px") g.height_px = v;
          if (f[1] == "width_mm") g.width_cm = v / 10;
          if (f[1] == "height_mm") g.height_cm = v / 10;
          if (f[1] == "distance_mm") g.distance_cm = v / 10;
        }
      }
      continue;
    }
    if (t.front() == '@') {
      split_ws(t, f);
      const std::string k = lower(f[0]);
      if (k == "@attribute" && f.size() >= 2) {
        const std::string n = lower(f[1]);
        const long i = long(attrs.size());
        if (n == "time") it = i;
        if (n == "x") ix = i;
        if (n == "y") iy = i;
        if (n == "confidence") ic = i;
        attrs.push_back(n);
      } else if (k == "@data") {
        if (it < 0 || ix < 0 || iy < 0)
          damaged(lines.number, "@DATA before @ATTRIBUTE lines naming time, x and y");
        data = true;
        r = &c.start(g);
      }
      continue;
    }
    if (!data) damaged(lines.number, "data row before the @DATA line (header missing?)");
    split(t, ',', f);
    if (f.size() != attrs.size())
      damaged(lines.number, "ARFF row has " + std::to_string(f.size()) + " fields, expected " +
                                std::to_string(attrs.size()) +
                                (f.size() < attrs.size() ? " (truncated?)" : ""));
    const double tm = need_num(f[it], lines.number, "time");
    const double x = need_num(f[ix], lines.number, "x"), y = need_num(f[iy], lines.number, "y");
    const bool v = ic < 0 || need_num(f[ic], lines.number, "confidence") != 0;
    c.push(*r, tm / 1000.0, x, y, v);
  }
  if (!data) damaged(lines.number, "no @DATA line (header or data missing)");
}

// --- DSF coord -------------------------------------------------------------------------------------------

void read_dsf_coord(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  ScreenGeometry g;
  Recording* r = nullptr;
  while (lines.next(line)) {
    c.tick(lines.pos);
    const std::string_view t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    split_ws(t, f);
    if (f[0] == "gaze") {
      need_fields(f.size(), 3, lines.number, "gaze line");
      g.width_px = need_num(f[1], lines.number, "gaze width"),
      g.height_px = need_num(f[2], lines.number, "gaze height");
      continue;
    }
    if (f[0] == "geometry") {
      for (std::size_t i = 1; i + 1 < f.size(); i += 2) {
        const double v = need_num(f[i + 1], lines.number, std::string(f[i])) * 100;  // m -> cm
        if (f[i] == "distance") g.distance_cm = v;
        if (f[i] == "width") g.width_cm = v;
        if (f[i] == "height") g.height_cm = v;
      }
      continue;
    }
    if (!r) r = &c.start(g);
    need_fields(f.size(), 4, lines.number, "coord row");
    const double tm = need_num(f[0], lines.number, "time");
    const double x = need_num(f[1], lines.number, "x"), y = need_num(f[2], lines.number, "y");
    const double flag = need_num(f[3], lines.number, "flag");
    c.push(*r, tm / 1000.0, x, y, flag == 1);
  }
  if (!r) damaged(lines.number, "no samples");
}

// --- SimpleGazeTracker CSV ---------------------------------------------------------------------------------

void read_sgt(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  ScreenGeometry g;
  double dpc_h = 0, dpc_v = 0;
  bool bottom_left = false;
  long ix = -1, iy = -1, ilx = -1, ily = -1, irx = -1, iry = -1;
  std::size_t want = 0;
  Recording* r = nullptr;
  bool msg_pending = false;
  while (lines.next(line)) {
    c.tick(lines.pos);
    if (trim(line).empty()) continue;
    split(line, ',', f);
    if (line.front() == '#') {
      const std::string_view k = trim(f[0]);
      const auto num = [&]() { return f.size() >= 2 ? need_num(f[1], lines.number, std::string(k)) : 0.0; };
      if (k == "#SCREEN_WIDTH")
        g.width_px = num();
      else if (k == "#SCREEN_HEIGHT")
        g.height_px = num();
      else if (k == "#DOTS_PER_CENTIMETER_H")
        dpc_h = num();
      else if (k == "#DOTS_PER_CENTIMETER_V")
        dpc_v = num();
      else if (k == "#VIEWING_DISTANCE")
        g.distance_cm = num();
      else if (k == "#SCREEN_ORIGIN")
        bottom_left = f.size() >= 2 && trim(f[1]) == "BottomLeft";
      else if (k == "#DATAFORMAT") {
        ix = iy = ilx = ily = irx = iry = -1;  // a later #DATAFORMAT replaces the columns of an earlier one
        for (std::size_t i = 1; i < f.size(); ++i) {
          const std::string_view n = trim(f[i]);
          const long j = long(i - 1);
          if (n == "X") ix = j;
          if (n == "Y") iy = j;
          if (n == "LX") ilx = j;
          if (n == "LY") ily = j;
          if (n == "RX") irx = j;
          if (n == "RY") iry = j;
        }
        want = f.size() - 1;
        if ((ix < 0 || iy < 0) && (ilx < 0 || ily < 0 || irx < 0 || iry < 0))
          damaged(lines.number, "#DATAFORMAT names neither X,Y nor LX,LY,RX,RY");
      } else if (k == "#START_REC") {
        if (dpc_h > 0 && g.width_px > 0) g.width_cm = g.width_px / dpc_h;
        if (dpc_v > 0 && g.height_px > 0) g.height_cm = g.height_px / dpc_v;
        r = &c.start(g);
        r->trial = std::to_string(c.ds.recordings.size());
        msg_pending = true;
      } else if (k == "#STOP_REC") {
        r = nullptr;
      } else if (k == "#MESSAGE" && r && msg_pending && f.size() >= 3) {
        r->trial = std::string(trim(f[2]));  // the first message of a recording names the trial
        msg_pending = false;
      }
      continue;
    }
    if (!want) damaged(lines.number, "sample before the #DATAFORMAT line (header missing?)");
    if (!r) {
      r = &c.start(g);
      r->trial = std::to_string(c.ds.recordings.size());
    }
    if (f.size() != want)
      damaged(lines.number, "sample has " + std::to_string(f.size()) + " fields, #DATAFORMAT says " +
                                std::to_string(want) + (f.size() < want ? " (truncated?)" : ""));
    const double t = need_num(f[0], lines.number, "T");
    // Non-numeric positions are the tracker's failure codes (NOPURKINJE, MULTIPURKINJE, ...).
    const auto pos = [&](long i, double& v) {
      if (to_num(f[i], v)) return true;
      const std::string_view s = trim(f[i]);
      if (s.empty() ||
          !std::all_of(s.begin(), s.end(), [](char ch) { return std::isupper((unsigned char)ch); }))
        damaged(lines.number, "position is neither a number nor a failure code: " + shown(s));
      v = kNaN;
      return false;
    };
    double x, y;
    bool v;
    if (ix >= 0 && iy >= 0) {
      double a, b;
      const bool va = pos(ix, a), vb = pos(iy, b);
      x = a, y = b, v = va && vb;
    } else {
      double xl, yl, xr, yr;
      const bool vl = pos(ilx, xl) & pos(ily, yl);
      const bool vr = pos(irx, xr) & pos(iry, yr);
      combine(xl, yl, vl, xr, yr, vr, c.opt.eye, x, y, v);
    }
    if (bottom_left && r->geometry.height_px > 0) y = r->geometry.height_px - y;
    c.push(*r, t, x, y, v);
  }
  if (!want) damaged(lines.number, "no #DATAFORMAT line");
}

// --- plain delimited text ---------------------------------------------------------------------------------

void read_plain(std::string_view text, Ctx& c) {
  Lines lines{text};
  std::string_view line;
  std::vector<std::string_view> f;
  // First non-empty line decides the delimiter and whether there is a header.
  std::size_t first_pos = 0;
  while (true) {
    first_pos = lines.pos;
    if (!lines.next(line)) damaged(lines.number, "no samples");
    if (!trim(line).empty()) break;
  }
  const char delim = line.find('\t') != std::string_view::npos  ? '\t'
                     : line.find(',') != std::string_view::npos ? ','
                                                                : ' ';
  const auto fields = [&](std::string_view l) {
    if (delim == ' ')
      split_ws(l, f);
    else
      split(l, delim, f);
  };
  fields(line);
  double probe;
  const bool header = !to_num(f[0], probe);
  long it = 0, ix = 1, iy = 2, iv = -1;
  bool val_zero_is_valid = false;
  double time_scale = 1;  // to ms
  Units units = Units::px;
  std::vector<std::pair<long, std::string>> label_cols;
  std::size_t width = f.size();
  if (header) {
    it = ix = iy = -1;
    std::map<std::string, long> col;
    for (std::size_t i = 0; i < f.size(); ++i) col[lower(trim(f[i]))] = long(i);
    for (const char* n : {"time_us", "time_ms", "time_s", "time", "timestamp", "t", "n"})
      if (it < 0 && col.count(n)) {
        it = col[n];
        const std::string s = n;
        time_scale = s == "time_us" ? 1e-3 : s == "time_s" ? 1e3 : 1;
      }
    for (const char* n : {"x", "x_px", "gaze_x", "x_deg"})
      if (ix < 0 && col.count(n)) ix = col[n];
    for (const char* n : {"y", "y_px", "gaze_y", "y_deg"})
      if (iy < 0 && col.count(n)) iy = col[n];
    for (const char* n : {"valid", "val", "validity"})
      if (iv < 0 && col.count(n)) {
        iv = col[n];
        val_zero_is_valid = std::string(n) != "valid";
      }
    if (it < 0 || ix < 0 || iy < 0)
      throw Error(
          Error::Kind::unsupported_format, "format",
          "line " + std::to_string(lines.number) +
              ": a delimited header without time, x and y columns (time/timestamp/n, x, y): " + shown(line));
    // GazeBase (Griffith et al., Sci Data 2021): n, x, y in degrees, val, lab.
    if (col.count("x_deg") || (col.count("n") && col.count("val") && col.count("lab"))) units = Units::deg;
    for (const auto& [name, i] : col)
      if (name == "lab" || starts_with(name, "label")) label_cols.emplace_back(i, name);
    std::sort(label_cols.begin(), label_cols.end());
  } else {
    if (f.size() < 3 || f.size() > 4)
      throw Error(Error::Kind::unsupported_format, "format",
                  "line " + std::to_string(lines.number) +
                      ": samples without a header need 3 or 4 columns "
                      "(time x y [valid]); found " +
                      std::to_string(f.size()));
    if (f.size() == 4) iv = 3;
    lines = Lines{text, first_pos, lines.number - 1};
  }
  const std::size_t want =
      std::size_t(std::max({it, ix, iy, iv, label_cols.empty() ? -1L : label_cols.back().first})) + 1;
  Recording& r = c.start();
  r.units = units;
  for (const auto& lc : label_cols) r.annotations.emplace_back(lc.second, std::vector<int>{});
  while (lines.next(line)) {
    c.tick(lines.pos);
    if (trim(line).empty()) continue;
    fields(line);
    need_fields(f.size(), want, lines.number, "row");
    if (!header && f.size() != width)
      damaged(lines.number,
              "row has " + std::to_string(f.size()) + " fields, the first row " + std::to_string(width));
    const double t = need_num(f[it], lines.number, "time") * time_scale;
    const auto pos = [&](long i, const char* n) {
      if (trim(f[i]).empty()) return kNaN;
      return need_num(f[i], lines.number, n);
    };
    const double x = pos(ix, "x"), y = pos(iy, "y");
    bool v = true;
    if (iv >= 0) {
      const double fl = need_num(f[iv], lines.number, "validity");
      v = val_zero_is_valid ? fl == 0 : fl != 0;
    }
    // Missing-value markers: EyeLink exports' -32768, and (0, 0) px that SMI-based exports write when the
    // eye is lost (the Lund 2013 data).
    if (x == -32768 && y == -32768) v = false;
    if (units == Units::px && x == 0 && y == 0) v = false;
    for (std::size_t k = 0; k < label_cols.size(); ++k) {
      const double lv = pos(label_cols[k].first, "label");
      // Labels are event codes (gaze.hpp EventType): a value no int holds is damage, not a code.
      if (std::isfinite(lv) && std::abs(lv) >= 2147483648.0)
        damaged(lines.number, "label is out of range: " + shown(f[label_cols[k].first]));
      r.annotations[k].second.push_back(std::isfinite(lv) ? int(lv) : 0);
    }
    c.push(r, t, x, y, v);
  }
}

std::string_view skip_bom(std::string_view s) {
  if (starts_with(s, "\xEF\xBB\xBF")) s.remove_prefix(3);
  return s;
}

}  // namespace

const char* to_string(GazeFormat f) noexcept {
  switch (f) {
    case GazeFormat::eyelink_asc:
      return "eyelink_asc";
    case GazeFormat::tobii_tsv:
      return "tobii_tsv";
    case GazeFormat::psychopy_tobii:
      return "psychopy_tobii";
    case GazeFormat::smi_idf_text:
      return "smi_idf_text";
    case GazeFormat::gazecom_arff:
      return "gazecom_arff";
    case GazeFormat::dsf_coord:
      return "dsf_coord";
    case GazeFormat::simple_gaze_tracker:
      return "simple_gaze_tracker";
    case GazeFormat::plain:
      return "plain";
  }
  return "?";
}

namespace {
constexpr GazeFormat kAllFormats[] = {GazeFormat::eyelink_asc,         GazeFormat::tobii_tsv,
                                      GazeFormat::psychopy_tobii,      GazeFormat::smi_idf_text,
                                      GazeFormat::gazecom_arff,        GazeFormat::dsf_coord,
                                      GazeFormat::simple_gaze_tracker, GazeFormat::plain};
std::string format_names() {
  std::string s;
  for (GazeFormat f : kAllFormats) s += std::string(s.empty() ? "" : ", ") + to_string(f);
  return s;
}
}  // namespace

GazeFormat parse_gaze_format(std::string_view text, const std::string& param) {
  for (GazeFormat f : kAllFormats)
    if (text == to_string(f)) return f;
  throw invalid_argument(param, "unknown gaze format " + shown(text) + "; one of " + format_names());
}

Eye parse_eye(std::string_view text, const std::string& param) {
  if (text == "average") return Eye::average;
  if (text == "left") return Eye::left;
  if (text == "right") return Eye::right;
  throw invalid_argument(param, "eye must be average, left or right, not " + shown(text));
}

GazeFormat detect_gaze_format(std::string_view head) {
  head = skip_bom(head);
  Lines lines{head};
  std::string_view line, first;
  bool hash_header = false;
  for (int n = 0; n < 200 && lines.next(line); ++n) {
    if (first.empty() && !trim(line).empty()) first = line;
    if (starts_with(line, "** CONVERTED FROM") || starts_with(line, "START\t") ||
        starts_with(line, "SAMPLES\t") || starts_with(line, "MSG\t"))
      return GazeFormat::eyelink_asc;
    if (starts_with(line, "## [iView]") || (starts_with(line, "Time\tType\t") && first.substr(0, 2) == "##"))
      return GazeFormat::smi_idf_text;
    if (starts_with(line, "%@METADATA") || starts_with(lower(line.substr(0, 9)), "@relation"))
      return GazeFormat::gazecom_arff;
    if (starts_with(line, "#SimpleGazeTrackerDataFile")) return GazeFormat::simple_gaze_tracker;
    if (starts_with(line, "Recording resolution\t") ||
        line.find("\tGazePointXLeft\t") != std::string_view::npos)
      return GazeFormat::psychopy_tobii;
    if (line.find("LGazePos2dx") != std::string_view::npos) return GazeFormat::tobii_tsv;
    if (starts_with(line, "#")) {
      hash_header = true;
      continue;
    }
    if (hash_header && (starts_with(line, "gaze ") || starts_with(line, "geometry ")))
      return GazeFormat::dsf_coord;
  }
  if (first.empty()) throw Error(Error::Kind::unsupported_format, "format", "empty input: no gaze samples");
  const bool binary = std::any_of(head.begin(), head.begin() + std::min<std::size_t>(head.size(), 512),
                                  [](char ch) { return ch == 0; });
  if (binary)
    throw Error(Error::Kind::unsupported_format, "format",
                "binary data, not a gaze text file (EDF, MAT and IDF files must be converted to text "
                "first); supported: " +
                    format_names());
  // Plain delimited text: a first line that is a header naming time, x and y, or 3-4 numbers.
  std::vector<std::string_view> f;
  const char delim = first.find('\t') != std::string_view::npos  ? '\t'
                     : first.find(',') != std::string_view::npos ? ','
                                                                 : ' ';
  if (delim == ' ')
    split_ws(first, f);
  else
    split(first, delim, f);
  double probe;
  if (to_num(f[0], probe)) {
    if (f.size() >= 3 && f.size() <= 4 && std::all_of(f.begin(), f.end(), [&](std::string_view v) {
          return to_num(v, probe) || trim(v).empty();
        }))
      return GazeFormat::plain;
  } else {
    bool t = false, x = false, y = false;
    for (auto v : f) {
      const std::string n = lower(trim(v));
      t = t || n == "time" || n == "time_us" || n == "time_ms" || n == "time_s" || n == "timestamp" ||
          n == "t" || n == "n";
      x = x || n == "x" || n == "x_px" || n == "gaze_x" || n == "x_deg";
      y = y || n == "y" || n == "y_px" || n == "gaze_y" || n == "y_deg";
    }
    if (t && x && y) return GazeFormat::plain;
  }
  throw Error(Error::Kind::unsupported_format, "format",
              "not a known gaze format (first line " + shown(first) + "); supported: " + format_names());
}

GazeDataset read_gaze(std::string_view content, const GazeIngestOptions& options) {
  content = skip_bom(content);
  if (content.size() > limits::kMaxGazeFileBytes)
    throw Error(Error::Kind::payload_too_large, "file",
                "gaze file of " + std::to_string(content.size()) +
                    " bytes is over limits::kMaxGazeFileBytes (" + std::to_string(limits::kMaxGazeFileBytes) +
                    ")");
  const GazeFormat format =
      options.format ? *options.format : detect_gaze_format(content.substr(0, 64 << 10));
  Ctx c{options, format, content.size(), {}};
  switch (format) {
    case GazeFormat::eyelink_asc:
      read_eyelink(content, c);
      break;
    case GazeFormat::tobii_tsv:
      read_tobii(content, c);
      break;
    case GazeFormat::psychopy_tobii:
      read_psychopy_tobii(content, c);
      break;
    case GazeFormat::smi_idf_text:
      read_smi(content, c);
      break;
    case GazeFormat::gazecom_arff:
      read_arff(content, c);
      break;
    case GazeFormat::dsf_coord:
      read_dsf_coord(content, c);
      break;
    case GazeFormat::simple_gaze_tracker:
      read_sgt(content, c);
      break;
    case GazeFormat::plain:
      read_plain(content, c);
      break;
  }
  // Blocks without a sample (an EyeLink START..END with events only) are not recordings.
  std::erase_if(c.ds.recordings, [](const Recording& r) { return r.size() == 0; });
  if (c.ds.recordings.empty())
    throw Error(Error::Kind::unprocessable, "file", std::string(to_string(format)) + " file without samples");
  for (std::size_t k = 0; k < c.ds.recordings.size(); ++k) {
    Recording& r = c.ds.recordings[k];
    if (r.trial.empty()) r.trial = std::to_string(k + 1);  // files without trials: their one recording is "1"
    if (!options.participant.empty()) r.participant = options.participant;
    if (!options.stimulus.empty()) r.stimulus = options.stimulus;
  }
  if (options.progress) options.progress(1.0, "parse");
  return std::move(c.ds);
}

GazeDataset read_gaze_file(const std::string& path, const GazeIngestOptions& options) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw not_found("file", "cannot open gaze file " + path + ": " + ec.message());
  if (size > limits::kMaxGazeFileBytes)
    throw Error(Error::Kind::payload_too_large, "file",
                "gaze file of " + std::to_string(size) + " bytes is over limits::kMaxGazeFileBytes (" +
                    std::to_string(limits::kMaxGazeFileBytes) + ")");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw not_found("file", "cannot open gaze file " + path);
  std::string content(size, '\0');
  in.read(content.data(), std::streamsize(size));
  if (std::size_t(in.gcount()) != size) throw Error(Error::Kind::internal, "file", "short read of " + path);
  GazeDataset ds = read_gaze(content, options);
  const std::string stem = std::filesystem::path(path).stem().string();
  for (Recording& r : ds.recordings)
    if (r.participant.empty()) r.participant = stem;
  return ds;
}

}  // namespace trailscope::gaze
