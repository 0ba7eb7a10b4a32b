// Gaze ingest: every gaze file of the shared data, sample counts checked against a count made here with
// plain line rules (no parsing of values), geometry from the files, and the exact errors for damaged files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/gaze/ingest.hpp"

namespace trailscope::gaze {
namespace {

namespace fs = std::filesystem;
using test::shared_data;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> text_lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    out.push_back(l);
  }
  return out;
}

std::size_t count_if_line(const fs::path& p, const std::function<bool(const std::string&)>& pred) {
  std::size_t n = 0;
  for (const auto& l : text_lines(slurp(p))) n += pred(l);
  return n;
}

bool digit_first(const std::string& l) {
  return !l.empty() && l[0] >= '0' && l[0] <= '9';
}
std::vector<std::string> tabs(const std::string& l) {
  std::vector<std::string> f;
  std::string cur;
  for (char c : l) {
    if (c == '\t')
      f.push_back(cur), cur.clear();
    else
      cur += c;
  }
  f.push_back(cur);
  return f;
}
std::string trimmed(std::string s) {
  while (!s.empty() && s.front() == ' ') s.erase(s.begin());
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

/// The error a call throws (kind, param, message).
template <class F>
Error error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error thrown";
  return Error(Error::Kind::internal, "", "");
}

GazeIngestOptions with_px(double w, double h) {
  GazeIngestOptions o;
  o.geometry.width_px = w, o.geometry.height_px = h;
  return o;
}

// --- EyeLink ------------------------------------------------------------------------------------------

TEST(GazeIngest, EyeLinkAscEveryFile) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(shared_data("gaze/eyelinker_sr_research")))
    files.push_back(e.path());
  files.push_back(shared_data("gaze/sp_tool_test_data/eyelink_data_example.asc"));
  files.push_back(shared_data("gaze/saccades_luketudge/example_eyelink_events.txt"));
  ASSERT_EQ(files.size(), 11u);
  for (const auto& p : files) {
    SCOPED_TRACE(p.string());
    const std::string text = slurp(p);
    EXPECT_EQ(detect_gaze_format(text), GazeFormat::eyelink_asc);
    const GazeDataset ds = read_gaze_file(p.string());
    // Independent counts: sample lines start with a digit; blocks are START lines; EFIX/ESACC lines.
    EXPECT_EQ(ds.total_samples(), count_if_line(p, digit_first));
    EXPECT_EQ(ds.recordings.size(),
              count_if_line(p, [](const std::string& l) { return l.rfind("START", 0) == 0; }));
    std::size_t fix = 0, sacc = 0, blink = 0;
    for (const auto& r : ds.recordings)
      for (const auto& e : r.tracker_events)
        (e.type == EventType::fixation ? fix : e.type == EventType::saccade ? sacc : blink)++;
    EXPECT_EQ(fix, count_if_line(p, [](const std::string& l) { return l.rfind("EFIX", 0) == 0; }));
    EXPECT_EQ(sacc, count_if_line(p, [](const std::string& l) { return l.rfind("ESACC", 0) == 0; }));
    EXPECT_EQ(blink, count_if_line(p, [](const std::string& l) { return l.rfind("EBLINK", 0) == 0; }));
    for (const auto& r : ds.recordings) {
      EXPECT_EQ(r.format, "eyelink_asc");
      EXPECT_GT(r.rate_hz, 0);
      EXPECT_TRUE(r.geometry.has_pixels());
    }
  }
}

TEST(GazeIngest, EyeLinkKnownCountsAndMissing) {
  // Known counts of these files (counted once with grep), and missing samples counted per line
  // ('.' in x; binocular: in both eyes, since the average falls back to the valid eye).
  const auto luke = shared_data("gaze/saccades_luketudge/example_eyelink_events.txt");
  const GazeDataset a = read_gaze_file(luke.string());
  EXPECT_EQ(a.total_samples(), 29578u);
  EXPECT_EQ(a.recordings.size(), 84u);
  std::size_t invalid = 0, expected_invalid = 0;
  for (const auto& r : a.recordings) invalid += r.size() - r.valid_count();
  for (const auto& l : text_lines(slurp(luke)))
    if (digit_first(l)) expected_invalid += trimmed(tabs(l)[1]) == ".";
  EXPECT_EQ(expected_invalid, 550u);
  EXPECT_EQ(invalid, expected_invalid);
  EXPECT_EQ(a.recordings[0].geometry.width_px, 640);
  EXPECT_EQ(a.recordings[0].geometry.height_px, 480);
  EXPECT_EQ(a.recordings[0].rate_hz, 250);
  EXPECT_EQ(a.recordings[0].trial.rfind("1 FP:", 0), 0u) << a.recordings[0].trial;

  const auto sp = shared_data("gaze/sp_tool_test_data/eyelink_data_example.asc");
  const GazeDataset b = read_gaze_file(sp.string());
  EXPECT_EQ(b.total_samples(), 10294u);
  std::size_t both = 0, left_only_missing = 0;
  for (const auto& l : text_lines(slurp(sp)))
    if (digit_first(l)) {
      const auto f = tabs(l);
      const bool ml = trimmed(f[1]) == ".", mr = trimmed(f[4]) == ".";
      both += ml && mr;
      left_only_missing += ml;
    }
  std::size_t inv = 0;
  for (const auto& r : b.recordings) inv += r.size() - r.valid_count();
  EXPECT_EQ(inv, both);
  GazeIngestOptions left;
  left.eye = Eye::left;
  const GazeDataset bl = read_gaze_file(sp.string(), left);
  std::size_t inv_l = 0;
  for (const auto& r : bl.recordings) inv_l += r.size() - r.valid_count();
  EXPECT_EQ(inv_l, left_only_missing);
  EXPECT_EQ(b.recordings[0].geometry.width_px, 1680);
  EXPECT_EQ(b.recordings[0].geometry.height_px, 1050);
  // Binocular average of the first sample: (1682.1 + 1723.1) / 2, (993.5 + 1059.1) / 2.
  EXPECT_DOUBLE_EQ(b.recordings[0].x[0], (1682.1 + 1723.1) / 2);
  EXPECT_DOUBLE_EQ(b.recordings[0].y[0], (993.5 + 1059.1) / 2);
  EXPECT_DOUBLE_EQ(bl.recordings[0].x[0], 1682.1);
}

// --- SMI ----------------------------------------------------------------------------------------------

TEST(GazeIngest, SmiIdfText) {
  const auto p = shared_data("gaze/sp_tool_test_data/smi_data_example_recording1_Samples.txt");
  EXPECT_EQ(detect_gaze_format(slurp(p)), GazeFormat::smi_idf_text);
  const GazeDataset ds = read_gaze_file(p.string());
  std::size_t smp = 0, zero = 0;
  std::set<std::string> trials;
  for (const auto& l : text_lines(slurp(p))) {
    const auto f = tabs(l);
    if (f.size() > 2 && f[1] == "SMP") {
      ++smp;
      trials.insert(f[2]);
      zero += f[f.size() - 3] == "0.00" && f[f.size() - 2] == "0.00";  // L POR X, L POR Y before Timing
    }
  }
  EXPECT_EQ(smp, 56116u);
  EXPECT_EQ(zero, 17460u);
  EXPECT_EQ(ds.total_samples(), smp);
  EXPECT_EQ(ds.recordings.size(), trials.size());
  std::size_t inv = 0;
  for (const auto& r : ds.recordings) inv += r.size() - r.valid_count();
  EXPECT_EQ(inv, zero);
  const Recording& r = ds.recordings[0];
  EXPECT_EQ(r.participant, "salmov1");
  EXPECT_EQ(r.stimulus, "cups.bmp");
  EXPECT_EQ(r.rate_hz, 50);
  EXPECT_EQ(r.geometry.width_px, 1024);
  EXPECT_EQ(r.geometry.height_px, 768);
  EXPECT_DOUBLE_EQ(r.geometry.width_cm, 30);
  EXPECT_DOUBLE_EQ(r.geometry.height_cm, 20);
  EXPECT_DOUBLE_EQ(r.geometry.distance_cm, 80);
  EXPECT_DOUBLE_EQ(r.t_ms[0], 2152092084 / 1000.0);
}

TEST(GazeIngest, SmiEyeWithOneColumnIsNoEye) {
  // A right eye with its X column but not its Y: the left pair is read (found by the fuzzer: the right
  // eye's missing Y column was indexed as -1).
  const std::string head = "## [iView]\n## Sample Rate:\t50\n";
  const GazeDataset ds = read_gaze(head +
                                   "Time\tType\tTrial\tR POR X [px]\tL POR X [px]\tL POR Y [px]\n"
                                   "1000\tSMP\t1\t5.5\t100.5\t200.25\n"
                                   "21000\tSMP\t1\t6.5\t101.5\t201.25\n");
  ASSERT_EQ(ds.recordings.size(), 1u);
  const Recording& r = ds.recordings[0];
  ASSERT_EQ(r.size(), 2u);
  EXPECT_DOUBLE_EQ(r.x[0], 100.5);
  EXPECT_DOUBLE_EQ(r.y[1], 201.25);
  // Neither eye whole: refused.
  const Error e = error_of([&] { read_gaze(head + "Time\tType\tTrial\tR POR X [px]\tL POR Y [px]\n"); });
  EXPECT_NE(std::string(e.what()).find("the table header lacks Type, Trial or a POR X/Y [px] pair"),
            std::string::npos)
      << e.what();
}

// --- Tobii --------------------------------------------------------------------------------------------

TEST(GazeIngest, TobiiSdkBothEyesAndValidity) {
  for (int part = 1; part <= 2; ++part)
    for (int trial = 1; trial <= 5; ++trial) {
      const auto p = shared_data("gaze/i2mc_tobii_tx300/participant" + std::to_string(part) + "/" +
                                 std::to_string(trial) + ".txt");
      SCOPED_TRACE(p.string());
      const std::string text = slurp(p);
      EXPECT_EQ(detect_gaze_format(text), GazeFormat::tobii_tsv);
      const GazeDataset ds = read_gaze(text, with_px(1920, 1080));
      const auto lines = text_lines(text);
      std::size_t rows = 0, both_bad = 0;
      for (std::size_t i = 1; i < lines.size(); ++i) {
        if (lines[i].empty()) continue;
        ++rows;
        const auto f = tabs(lines[i]);
        both_bad += std::stod(f[13]) > 1 && std::stod(f[26]) > 1;  // LValidity, RValidity
      }
      EXPECT_EQ(ds.total_samples(), rows);
      EXPECT_EQ(ds.recordings[0].size() - ds.recordings[0].valid_count(), both_bad);
      // A valid sample: the mean of the two eyes' normalised positions times the screen size.
      for (std::size_t i = 1; i < lines.size(); ++i) {
        const auto f = tabs(lines[i]);
        if (f.size() < 27 || std::stod(f[13]) > 1 || std::stod(f[26]) > 1) continue;
        EXPECT_NEAR(ds.recordings[0].x[i - 1], (std::stod(f[7]) + std::stod(f[20])) / 2 * 1920, 1e-9);
        EXPECT_NEAR(ds.recordings[0].y[i - 1], (std::stod(f[8]) + std::stod(f[21])) / 2 * 1080, 1e-9);
        break;
      }
    }
  const Error e =
      error_of([] { read_gaze_file(shared_data("gaze/i2mc_tobii_tx300/participant1/1.txt").string()); });
  EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
  EXPECT_EQ(e.param(), "geometry");
  EXPECT_STREQ(
      e.what(),
      "Tobii SDK gaze is normalised to 0-1 and the file does not say the screen size: give width_px and "
      "height_px");
}

TEST(GazeIngest, PsychoPyTobiiSessions) {
  const auto p = shared_data("gaze/gazeparser_tests/test03_ptc.tsv");
  const std::string text = slurp(p);
  EXPECT_EQ(detect_gaze_format(text), GazeFormat::psychopy_tobii);
  const GazeDataset ds = read_gaze(text);
  std::size_t n = 0, sessions = 0;
  for (const auto& l : text_lines(text)) {
    const auto f = tabs(l);
    n += f.size() == 11 && digit_first(l);
    sessions += l == "Session Start";
  }
  EXPECT_EQ(n, 1528u);
  EXPECT_EQ(ds.total_samples(), n);
  EXPECT_EQ(ds.recordings.size(), sessions);
  EXPECT_EQ(ds.recordings[0].geometry.width_px, 1600);
  EXPECT_EQ(ds.recordings[0].trial, "Trial 1, s (2).jpg");
}

// --- GazeCom ARFF, DSF coord ----------------------------------------------------------------------------

TEST(GazeIngest, GazeComArff) {
  const auto p = shared_data("gaze/sp_tool_test_data/arff_data_example.arff");
  EXPECT_EQ(detect_gaze_format(slurp(p)), GazeFormat::gazecom_arff);
  const GazeDataset ds = read_gaze_file(p.string());
  bool data = false;
  std::size_t rows = 0, invalid = 0;
  for (const auto& l : text_lines(slurp(p))) {
    if (l == "@DATA") {
      data = true;
      continue;
    }
    if (data && !l.empty() && l[0] != '%') {
      ++rows;
      invalid += l.size() > 4 && l.substr(l.size() - 4) == ",0.0";
    }
  }
  EXPECT_EQ(rows, 5002u);
  EXPECT_EQ(invalid, 49u);
  EXPECT_EQ(ds.total_samples(), rows);
  EXPECT_EQ(ds.recordings[0].size() - ds.recordings[0].valid_count(), invalid);
  const auto& g = ds.recordings[0].geometry;
  EXPECT_EQ(g.width_px, 1280);
  EXPECT_DOUBLE_EQ(g.width_cm, 40);
  EXPECT_DOUBLE_EQ(g.height_cm, 22.5);
  EXPECT_DOUBLE_EQ(g.distance_cm, 45);
  EXPECT_DOUBLE_EQ(ds.recordings[0].t_ms[0], 1.0);  // 1000 µs
}

TEST(GazeIngest, DsfCoord) {
  for (const char* rel : {"gaze/sp_tool_test_data/dsf_coord_data_example.coord",
                          "flights/gaze/saccades_s1_actioncliptest00001.txt"}) {
    const auto p = shared_data(rel);
    SCOPED_TRACE(rel);
    EXPECT_EQ(detect_gaze_format(slurp(p)), GazeFormat::dsf_coord);
    const GazeDataset ds = read_gaze_file(p.string());
    std::size_t rows = 0, bad = 0;
    for (const auto& l : text_lines(slurp(p)))
      if (digit_first(l)) {
        ++rows;
        bad += l.back() == '0' && l[l.size() - 2] == ' ';
      }
    EXPECT_EQ(ds.total_samples(), rows);
    EXPECT_EQ(ds.recordings[0].size() - ds.recordings[0].valid_count(), bad);
    EXPECT_TRUE(ds.recordings[0].geometry.has_physical());
  }
  const GazeDataset ds =
      read_gaze_file(shared_data("gaze/sp_tool_test_data/dsf_coord_data_example.coord").string());
  EXPECT_EQ(ds.total_samples(), 4200u);
  EXPECT_EQ(ds.recordings[0].size() - ds.recordings[0].valid_count(), 24u);
  EXPECT_DOUBLE_EQ(ds.recordings[0].geometry.distance_cm, 45);
}

// --- SimpleGazeTracker --------------------------------------------------------------------------------

TEST(GazeIngest, SimpleGazeTracker) {
  for (const char* name : {"test01.csv", "test02.csv"}) {
    const auto p = shared_data(std::string("gaze/gazeparser_tests/") + name);
    SCOPED_TRACE(name);
    EXPECT_EQ(detect_gaze_format(slurp(p)), GazeFormat::simple_gaze_tracker);
    const GazeDataset ds = read_gaze_file(p.string());
    std::size_t rows = 0, recs = 0;
    for (const auto& l : text_lines(slurp(p))) {
      rows += !l.empty() && l[0] != '#';
      recs += l.rfind("#START_REC", 0) == 0;
    }
    EXPECT_EQ(ds.total_samples(), rows);
    EXPECT_EQ(ds.recordings.size(), recs);
    EXPECT_NEAR(ds.recordings[0].geometry.width_cm, 1920 / 37.7, 1e-9);
    EXPECT_NEAR(ds.recordings[0].geometry.distance_cm, 57.2957795131, 1e-9);
  }
  const auto p = shared_data("gaze/gazeparser_tests/test01.csv");
  const GazeDataset ds = read_gaze_file(p.string());
  EXPECT_EQ(ds.total_samples(), 8889u);
  std::size_t inv = 0;
  for (const auto& r : ds.recordings) inv += r.size() - r.valid_count();
  EXPECT_EQ(inv, 416u);
  // Bottom-left origin flipped: the first valid sample's y is 1080 - y in the file.
  for (const auto& l : text_lines(slurp(p))) {
    if (l.empty() || l[0] == '#' || l.find("NOPURKINJE") != std::string::npos) continue;
    const double y_file = std::stod(l.substr(l.find(',', l.find(',') + 1) + 1));
    const auto& r = ds.recordings[0];
    for (std::size_t i = 0; i < r.size(); ++i)
      if (r.valid[i]) {
        EXPECT_DOUBLE_EQ(r.y[i], 1080 - y_file);
        break;
      }
    break;
  }
}

// --- plain `time x y [valid]` -----------------------------------------------------------------------------

TEST(GazeIngest, PlainFilesWithAndWithoutHeader) {
  std::vector<fs::path> with_header;
  for (const auto& e : fs::directory_iterator(shared_data("gaze/hooge2018_human_fixation_coding/ETdata")))
    with_header.push_back(e.path());
  for (const auto& e : fs::directory_iterator(shared_data("gaze/andersson2017_lund/tsv")))
    with_header.push_back(e.path());
  with_header.push_back(shared_data("gaze/pymovements_toy/trial_0_1.csv"));
  with_header.push_back(shared_data("gaze/pymovements_toy/trial_0_2.csv"));
  with_header.push_back(shared_data("gaze/pymovements_tests/gazebase_example.csv"));
  ASSERT_EQ(with_header.size(), 70u + 9u + 3u);
  for (const auto& p : with_header) {
    SCOPED_TRACE(p.string());
    const std::string text = slurp(p);
    EXPECT_EQ(detect_gaze_format(text), GazeFormat::plain);
    const GazeDataset ds = read_gaze(text);
    std::size_t rows = 0;
    for (const auto& l : text_lines(text)) rows += !l.empty();
    EXPECT_EQ(ds.total_samples(), rows - 1);
  }
  // Missing markers counted on the text: NaN (Hooge), -32768 (pymovements), x = y = 0 (Lund).
  const auto hooge = with_header[0];
  std::size_t nan_rows = 0;
  for (const auto& l : text_lines(slurp(hooge))) {
    const auto f = tabs(l);
    nan_rows += f.size() >= 3 && (f[1] == "NaN" || f[2] == "NaN");  // x or y; v is NaN next to gaps too
  }
  const GazeDataset h = read_gaze_file(hooge.string());
  EXPECT_EQ(h.recordings[0].size() - h.recordings[0].valid_count(), nan_rows);
  const GazeDataset toy = read_gaze_file(shared_data("gaze/pymovements_toy/trial_0_2.csv").string());
  EXPECT_EQ(toy.recordings[0].size() - toy.recordings[0].valid_count(), 105u);
  const auto lund = shared_data("gaze/andersson2017_lund/tsv/UL31_img_konijntjes.tsv");
  const GazeDataset l = read_gaze_file(lund.string());
  EXPECT_EQ(l.recordings[0].size(), 4986u);
  EXPECT_EQ(l.recordings[0].size() - l.recordings[0].valid_count(), 608u);
  ASSERT_EQ(l.recordings[0].annotations.size(), 2u);
  EXPECT_EQ(l.recordings[0].annotations[0].first, "label_mn");
  EXPECT_EQ(l.recordings[0].annotations[0].second.size(), 4986u);
  EXPECT_DOUBLE_EQ(l.recordings[0].t_ms[0] * 1000, std::stod(text_lines(slurp(lund))[1]));
  // GazeBase: degrees, val 0 = valid, the lab column kept.
  const GazeDataset gb = read_gaze_file(shared_data("gaze/pymovements_tests/gazebase_example.csv").string());
  EXPECT_EQ(gb.recordings[0].units, Units::deg);
  EXPECT_EQ(gb.recordings[0].valid_count(), 10u);
  EXPECT_EQ(gb.recordings[0].annotations[0].second[7], 1);
  // No header: time x y.
  const auto luke = shared_data("gaze/saccades_luketudge/example.csv");
  EXPECT_EQ(detect_gaze_format(slurp(luke)), GazeFormat::plain);
  EXPECT_EQ(read_gaze_file(luke.string()).total_samples(), 148u);
  EXPECT_EQ(read_gaze_file(luke.string()).recordings[0].participant, "example");
}

// --- geometry ---------------------------------------------------------------------------------------------

TEST(GazeIngest, DegreesOfVisualAngle) {
  ScreenGeometry g;
  g.width_px = 1024, g.height_px = 768, g.width_cm = 38, g.height_cm = 30, g.distance_cm = 67;
  EXPECT_DOUBLE_EQ(px_to_deg_x(512, g), 0);
  EXPECT_NEAR(px_to_deg_x(1024, g), std::atan(19.0 / 67) * 180 / std::numbers::pi, 1e-12);
  EXPECT_NEAR(px_to_deg_y(0, g), -std::atan(15.0 / 67) * 180 / std::numbers::pi, 1e-12);
  // Small steps near the centre: the Lund data's 0.0317 deg/px.
  EXPECT_NEAR(px_to_deg_x(513, g) - px_to_deg_x(512, g), 0.0317, 5e-5);
  ScreenGeometry px_only;
  px_only.width_px = 1024, px_only.height_px = 768;
  const Error e = error_of([&] { px_to_deg_x(1, px_only); });
  EXPECT_EQ(e.param(), "geometry");
  // Given values override the file's, field by field.
  ScreenGeometry given;
  given.distance_cm = 70;
  const ScreenGeometry o = g.overridden_by(given);
  EXPECT_EQ(o.distance_cm, 70);
  EXPECT_EQ(o.width_cm, 38);
}

// --- damaged and foreign files ---------------------------------------------------------------------------

TEST(GazeIngest, TruncatedEyeLinkLine) {
  const std::string text = slurp(shared_data("gaze/eyelinker_sr_research/mono250.asc"));
  const auto lines = text_lines(text);
  std::string cut;
  std::size_t n = 0;
  for (const auto& l : lines) {
    ++n;
    if (digit_first(l)) {
      cut += l.substr(0, l.find('\t', l.find('\t') + 1));  // "time\t  x": two fields
      break;
    }
    cut += l + "\n";
  }
  const Error e = error_of([&] { read_gaze(cut); });
  EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
  EXPECT_EQ(e.param(), "file");
  EXPECT_EQ(std::string(e.what()),
            "line " + std::to_string(n) + ": EyeLink sample has 2 fields, expected at least 4 (truncated?)");
}

TEST(GazeIngest, BadNumberInSmi) {
  std::string text = slurp(shared_data("gaze/sp_tool_test_data/smi_data_example_recording1_Samples.txt"));
  const std::string good = "2152092084\tSMP\t1\t212.15\t75.65\t33.39\t26.98\t217.46\t90.92\t0.00\t0.00\t0";
  const std::size_t at = text.find(good);
  ASSERT_NE(at, std::string::npos);
  std::string bad = good;
  bad.replace(bad.find("\t0.00\t0.00"), 5, "\t1x.5");
  text.replace(at, good.size(), bad);
  const std::size_t line = std::size_t(std::count(text.begin(), text.begin() + long(at), '\n')) + 1;
  const Error e = error_of([&] { read_gaze(text); });
  EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
  EXPECT_EQ(std::string(e.what()), "line " + std::to_string(line) + ": POR X is not a number: \"1x.5\"");
}

TEST(GazeIngest, TruncatedArffRow) {
  std::string text = slurp(shared_data("gaze/sp_tool_test_data/arff_data_example.arff"));
  const std::size_t at = text.find("5000,417.0,188.1,1.0");
  ASSERT_NE(at, std::string::npos);
  text = text.substr(0, at) + "5000,417";
  const std::size_t line = std::size_t(std::count(text.begin(), text.end(), '\n')) + 1;
  const Error e = error_of([&] { read_gaze(text); });
  EXPECT_EQ(std::string(e.what()),
            "line " + std::to_string(line) + ": ARFF row has 2 fields, expected 4 (truncated?)");
}

TEST(GazeIngest, MissingHeaders) {
  // Tobii without its header row: 28 bare numbers per line are no known layout.
  std::string tobii = slurp(shared_data("gaze/i2mc_tobii_tx300/participant1/1.txt"));
  tobii = tobii.substr(tobii.find('\n') + 1);
  Error e = error_of([&] { read_gaze(tobii, with_px(1920, 1080)); });
  EXPECT_EQ(e.kind(), Error::Kind::unsupported_format);
  EXPECT_EQ(
      std::string(e.what()),
      "not a known gaze format (first line \"2619771723\t0.0000\t0.0000\t0.0000\t-1.0000\t...\"); "
      "supported: "
      "eyelink_asc, tobii_tsv, psychopy_tobii, smi_idf_text, gazecom_arff, dsf_coord, simple_gaze_tracker, "
      "plain");
  // SMI without its table header line.
  std::string smi = slurp(shared_data("gaze/sp_tool_test_data/smi_data_example_recording1_Samples.txt"));
  const std::size_t h = smi.find("Time\tType\t");
  smi.erase(h, smi.find('\n', h) + 1 - h);
  e = error_of([&] { read_gaze(smi); });
  EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
  EXPECT_EQ(
      std::string(e.what()),
      "line 19: expected the table header (Time, Type, Trial, ...), found \"2152080664\tMSG\t1\tScene Image: "
      "d:\\PresNG\\...\"");
  // SimpleGazeTracker without its #DATAFORMAT line.
  std::string sgt = slurp(shared_data("gaze/gazeparser_tests/test02.csv"));
  const std::size_t d = sgt.find("#DATAFORMAT");
  sgt.erase(d, sgt.find('\n', d) + 1 - d);
  e = error_of([&] { read_gaze(sgt); });
  EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
  const auto sl = text_lines(sgt);
  std::size_t first_data = 0;
  while (sl[first_data].empty() || sl[first_data][0] == '#') ++first_data;
  EXPECT_EQ(std::string(e.what()), "line " + std::to_string(first_data + 1) +
                                       ": sample before the #DATAFORMAT line (header missing?)");
}

TEST(GazeIngest, ForeignFilesAreRefused) {
  Error e = error_of([] { detect_gaze_format(""); });
  EXPECT_EQ(std::string(e.what()), "empty input: no gaze samples");
  // A MATLAB file (binary).
  e = error_of([] {
    read_gaze_file(shared_data("gaze/andersson2017_lund/mat/TH34_img_Europe_labelled_MN.mat").string());
  });
  EXPECT_EQ(e.kind(), Error::Kind::unsupported_format);
  EXPECT_EQ(
      std::string(e.what()),
      "binary data, not a gaze text file (EDF, MAT and IDF files must be converted to text first); "
      "supported: "
      "eyelink_asc, tobii_tsv, psychopy_tobii, smi_idf_text, gazecom_arff, dsf_coord, simple_gaze_tracker, "
      "plain");
  // Event tables are not samples (REMoDNaV output, hand-coded fixations).
  for (const char* rel : {"gaze/studyforrest_remodnav/sub-10_task-movie_run-1_events.tsv",
                          "gaze/hooge2018_human_fixation_coding/coderSettings/DN.txt"}) {
    e = error_of([&] { read_gaze_file(shared_data(rel).string()); });
    EXPECT_EQ(e.kind(), Error::Kind::unsupported_format) << rel;
    EXPECT_EQ(std::string(e.what()).rfind("not a known gaze format (first line", 0), 0u) << e.what();
  }
  e = error_of([] { read_gaze_file("/nonexistent/gaze.asc"); });
  EXPECT_EQ(e.kind(), Error::Kind::not_found);
  e = error_of([] { parse_gaze_format("asc"); });
  EXPECT_EQ(std::string(e.what()),
            "unknown gaze format \"asc\"; one of eyelink_asc, tobii_tsv, psychopy_tobii, smi_idf_text, "
            "gazecom_arff, "
            "dsf_coord, simple_gaze_tracker, plain");
}

}  // namespace
}  // namespace trailscope::gaze
