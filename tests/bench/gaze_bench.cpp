// Gaze: ingest rows/s per format, event detection samples/s per method, and the sample-level agreement
// (Cohen's kappa) of I-VT, I-DT and the adaptive detector with the expert coders of two hand-coded data
// sets, next to the coders' agreement with each other:
//  - Lund 2013 (Andersson, Larsson, Holmqvist, Stridh and Nystrom, Behav Res Methods 2017): 9 recordings,
//    two coders (MN, RA) labelling every sample fixation / saccade / PSO / pursuit / blink / undefined;
//  - Hooge, Niehorster, Nystrom, Andersson and Hessels (Behav Res Methods 2018): 70 Tobii TX300 trials
//    (10 adults, 60 infants), fixations hand-coded by 12 coders (a sample is "fixation" when inside one).
// Inputs are read into memory before timing; parsing is timed from memory (gaze::read_gaze).
//
//   gaze_bench --gaze-dir DIR [--reps 5]      (DIR: the gaze folder of the shared data, data/gaze)
//     {"bench":"gaze_ingest", "format", "files", "bytes", "samples", "ms_p50", "rows_per_s_p50", "reps"}
//     {"bench":"gaze_events", "method", "recordings", "samples", "ms_p50", "samples_per_s_p50", "reps"}
//     {"bench":"gaze_kappa", "dataset":"lund", "method", "vs", "type", "kappa"}   (method "coders": MN vs RA)
//     {"bench":"gaze_kappa", "dataset":"hooge", "method", "vs", "type":"fixation", "kappa"}
//     {"bench":"gaze_diag", "dataset", ...}: see diagnostics()
//     {"bench":"gaze_adaptive", "dataset":"lund", "recording", "peak_threshold_deg_s",
//     "onset_threshold_deg_s",
//      "fixation_kappa_vs_MN"}
//         (method "coders": the coder vs each other coder, mean over the 11 pairs)
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "bench_util.hpp"
#include "trailscope/gaze/events.hpp"
#include "trailscope/gaze/ingest.hpp"

using namespace bench;
namespace fs = std::filesystem;
namespace gz = trailscope::gaze;
using ET = gz::EventType;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> v;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

gz::ScreenGeometry geometry(double wpx, double hpx, double wcm, double hcm, double d) {
  gz::ScreenGeometry g;
  g.width_px = wpx, g.height_px = hpx, g.width_cm = wcm, g.height_cm = hcm, g.distance_cm = d;
  return g;
}

/// Why a fixed-threshold detector disagrees with the coders: over the samples that every coder calls
/// fixation ("consensus"), the share that are invalid (coders bridge short gaps, detectors call them blinks),
/// the share whose point-to-point velocity exceeds the I-VT threshold, its median, and the share of I-DT
/// windows (min_duration_ms from a consensus sample, all inside the consensus run) wider than the threshold.
json diagnostics(const std::string& dataset, const std::vector<gz::Recording>& recs,
                 const std::vector<std::vector<bool>>& consensus) {
  const gz::EventParams p;
  std::size_t n = 0, invalid = 0, fast = 0, windows = 0, wide = 0;
  std::vector<double> vel;
  for (std::size_t k = 0; k < recs.size(); ++k) {
    const gz::Recording& r = recs[k];
    std::vector<double> x, y;
    r.degrees(x, y);
    const auto v = gz::point_velocity(r.t_ms, x, y, r.valid);
    for (std::size_t i = 0; i < r.size(); ++i) {
      if (!consensus[k][i]) continue;
      ++n;
      if (!r.valid[i]) {
        ++invalid;
        continue;
      }
      if (std::isfinite(v[i])) vel.push_back(v[i]), fast += v[i] > p.ivt.velocity_threshold_deg_s;
      double x0 = x[i], x1 = x[i], y0 = y[i], y1 = y[i];
      std::size_t j = i;
      bool ok = true;
      while (r.t_ms[j] - r.t_ms[i] < p.idt.min_duration_ms) {
        if (j + 1 >= r.size() || !consensus[k][j + 1] || !r.valid[j + 1]) {
          ok = false;
          break;
        }
        ++j;
        x0 = std::min(x0, x[j]), x1 = std::max(x1, x[j]), y0 = std::min(y0, y[j]), y1 = std::max(y1, y[j]);
      }
      if (ok) ++windows, wide += (x1 - x0) + (y1 - y0) > p.idt.dispersion_threshold_deg;
    }
  }
  std::sort(vel.begin(), vel.end());
  return {{"bench", "gaze_diag"},
          {"dataset", dataset},
          {"consensus_fixation_samples", n},
          {"invalid_share", double(invalid) / double(n)},
          {"ivt_over_threshold_share", double(fast) / double(vel.size())},
          {"median_point_velocity_deg_s", vel.empty() ? 0.0 : vel[vel.size() / 2]},
          {"idt_windows", windows},
          {"idt_window_over_threshold_share", windows ? double(wide) / double(windows) : 0.0}};
}

const gz::Method kMethods[] = {gz::Method::ivt, gz::Method::idt, gz::Method::adaptive};

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const fs::path dir = a.get("gaze-dir");
    if (dir.empty()) throw std::invalid_argument("--gaze-dir DIR (the data/gaze folder) is required");
    const int reps = static_cast<int>(a.num("reps", 5));

    // ---- ingest rows/s per format -------------------------------------------------------------------
    const gz::ScreenGeometry tx300 = geometry(1920, 1080, 50.9174, 28.6411, 65);
    std::map<std::string, std::vector<fs::path>> by_format;
    for (const char* sub :
         {"eyelinker_sr_research", "sp_tool_test_data", "saccades_luketudge", "gazeparser_tests",
          "pymovements_toy", "hooge2018_human_fixation_coding/ETdata", "andersson2017_lund/tsv",
          "i2mc_tobii_tx300/participant1", "i2mc_tobii_tx300/participant2"})
      for (const auto& p : files_in(dir / sub)) {
        const std::string text = slurp(p);
        by_format[gz::to_string(gz::detect_gaze_format(text))].push_back(p);
      }
    for (const auto& [format, paths] : by_format) {
      std::vector<std::string> texts;
      std::size_t bytes = 0, samples = 0;
      for (const auto& p : paths) texts.push_back(slurp(p)), bytes += texts.back().size();
      gz::GazeIngestOptions o;
      o.geometry.width_px = tx300.width_px, o.geometry.height_px = tx300.height_px;  // Tobii SDK needs px
      for (const auto& t : texts) samples += gz::read_gaze(t, o).total_samples();
      std::vector<double> ms;
      for (int r = 0; r < reps; ++r) {
        const auto t0 = Clock::now();
        std::size_t n = 0;
        for (const auto& t : texts) n += gz::read_gaze(t, o).total_samples();
        ms.push_back(ms_since(t0));
        if (n != samples) throw std::runtime_error("ingest not deterministic");
      }
      const Stats st = Stats::of(ms);
      emit({{"bench", "gaze_ingest"},
            {"format", format},
            {"files", paths.size()},
            {"bytes", bytes},
            {"samples", samples},
            {"ms_p50", st.p50},
            {"rows_per_s_p50", double(samples) / (st.p50 / 1000.0)},
            {"reps", reps}});
    }

    // ---- the hand-coded data ----------------------------------------------------------------------------
    std::vector<gz::Recording> lund;
    gz::GazeIngestOptions lo;
    lo.geometry = geometry(1024, 768, 38, 30, 67);
    for (const auto& p : files_in(dir / "andersson2017_lund/tsv"))
      for (auto& r : gz::read_gaze_file(p.string(), lo).recordings) lund.push_back(std::move(r));
    std::vector<gz::Recording> hooge;
    std::vector<std::string> hooge_trials;
    gz::GazeIngestOptions ho;
    ho.geometry = tx300;
    ho.geometry.width_cm = 50.9, ho.geometry.height_cm = 28.6;  // the data's README
    for (const auto& p : files_in(dir / "hooge2018_human_fixation_coding/ETdata")) {
      for (auto& r : gz::read_gaze_file(p.string(), ho).recordings) hooge.push_back(std::move(r));
      hooge_trials.push_back(p.stem().string());
    }

    // ---- detection speed ------------------------------------------------------------------------------
    for (gz::Method m : kMethods) {
      gz::EventParams p;
      p.method = m;
      std::size_t samples = 0;
      std::vector<double> ms;
      for (int r = 0; r < reps; ++r) {
        samples = 0;
        const auto t0 = Clock::now();
        for (const auto* set : {&lund, &hooge})
          for (const auto& rec : *set) samples += gz::detect_events(rec, p).labels.size();
        ms.push_back(ms_since(t0));
      }
      const Stats st = Stats::of(ms);
      emit({{"bench", "gaze_events"},
            {"method", gz::to_string(m)},
            {"recordings", lund.size() + hooge.size()},
            {"samples", samples},
            {"ms_p50", st.p50},
            {"samples_per_s_p50", double(samples) / (st.p50 / 1000.0)},
            {"reps", reps}});
    }

    // ---- kappa: Lund ------------------------------------------------------------------------------------
    {
      std::map<std::string, std::vector<ET>> coder;  // pooled over recordings
      for (const auto& r : lund)
        for (const auto& [name, labels] : r.annotations) {
          const std::string c = name == "label_mn" ? "MN" : name == "label_ra" ? "RA" : "";
          if (c.empty()) continue;  // UH29's corrected MN column is not one of the two coders' originals
          for (int l : labels) coder[c].push_back(static_cast<ET>(l));
        }
      {
        std::vector<std::vector<bool>> cons;
        for (const auto& r : lund) {
          std::vector<bool> c(r.size(), true);
          for (const auto& [name, labels] : r.annotations)
            if (name == "label_mn" || name == "label_ra")
              for (std::size_t i = 0; i < r.size(); ++i) c[i] = c[i] && labels[i] == int(ET::fixation);
          cons.push_back(c);
        }
        emit(diagnostics("lund", lund, cons));
      }
      const ET types[] = {ET::fixation, ET::saccade, ET::pso, ET::blink};
      for (ET t : types)
        emit({{"bench", "gaze_kappa"},
              {"dataset", "lund"},
              {"method", "coders"},
              {"vs", "MN-RA"},
              {"type", gz::to_string(t)},
              {"kappa", gz::cohen_kappa(coder["MN"], coder["RA"], t)}});
      for (gz::Method m : kMethods) {
        gz::EventParams p;
        p.method = m;
        std::vector<ET> det;
        for (const auto& r : lund) {
          const auto d = gz::detect_events(r, p);
          det.insert(det.end(), d.labels.begin(), d.labels.end());
          std::vector<ET> mn;
          for (const auto& [name, labels] : r.annotations)
            if (name == "label_mn")
              for (int l : labels) mn.push_back(static_cast<ET>(l));
          if (m == gz::Method::adaptive)  // the thresholds it settled on, per recording
            emit({{"bench", "gaze_adaptive"},
                  {"dataset", "lund"},
                  {"recording", r.participant},
                  {"peak_threshold_deg_s", d.peak_threshold_deg_s},
                  {"onset_threshold_deg_s", d.onset_threshold_deg_s},
                  {"fixation_kappa_vs_MN", gz::cohen_kappa(d.labels, mn, ET::fixation)}});
        }
        for (const char* c : {"MN", "RA"})
          for (ET t : types)
            emit({{"bench", "gaze_kappa"},
                  {"dataset", "lund"},
                  {"method", gz::to_string(m)},
                  {"vs", c},
                  {"type", gz::to_string(t)},
                  {"kappa", gz::cohen_kappa(det, coder[c], t)}});
      }
    }

    // ---- kappa: Hooge et al. 2018 ---------------------------------------------------------------------
    {
      // coder -> trial -> fixation intervals [start, end] ms
      std::map<std::string, std::map<std::string, std::vector<std::pair<double, double>>>> coded;
      for (const auto& p : files_in(dir / "hooge2018_human_fixation_coding/coderSettings")) {
        std::istringstream in(slurp(p));
        std::string line;
        std::getline(in, line);  // header
        while (std::getline(in, line)) {
          std::vector<std::string> f;
          std::stringstream ls(line);
          for (std::string x; std::getline(ls, x, '\t');) f.push_back(x);
          if (f.size() < 4) continue;
          coded[p.stem().string()][f[0]].emplace_back(std::stod(f[2]), std::stod(f[3]));
        }
      }
      const auto labels_of = [&](const std::string& c, std::size_t k) {
        const gz::Recording& r = hooge[k];
        std::vector<ET> l(r.size(), ET::none);
        const auto it = coded[c].find(hooge_trials[k]);
        if (it != coded[c].end())
          for (std::size_t i = 0; i < r.size(); ++i)
            for (const auto& [s, e] : it->second)
              if (r.t_ms[i] >= s && r.t_ms[i] <= e) l[i] = ET::fixation;
        return l;
      };
      // Trials a coder coded (IH and RH list trials absent from ETdata: those never match a recording).
      const auto has = [&](const std::string& c, std::size_t k) {
        return coded[c].count(hooge_trials[k]) > 0;
      };
      std::vector<std::string> coders;
      for (const auto& [c, _] : coded) coders.push_back(c);
      {
        std::vector<std::vector<bool>> cons;
        for (std::size_t k = 0; k < hooge.size(); ++k) {
          std::vector<bool> c(hooge[k].size(), true);
          bool any = false;
          for (const auto& cd : coders)
            if (has(cd, k)) {
              any = true;
              const auto l = labels_of(cd, k);
              for (std::size_t i = 0; i < c.size(); ++i) c[i] = c[i] && l[i] == ET::fixation;
            }
          if (!any) c.assign(c.size(), false);
          cons.push_back(c);
        }
        emit(diagnostics("hooge", hooge, cons));
      }
      std::map<gz::Method, std::vector<std::vector<ET>>> det;
      for (gz::Method m : kMethods) {
        gz::EventParams p;
        p.method = m;
        for (const auto& r : hooge) det[m].push_back(gz::detect_events(r, p).labels);
      }
      for (const auto& c : coders) {
        double sum = 0;
        int pairs = 0;
        for (const auto& o : coders) {
          if (o == c) continue;
          std::vector<ET> a, b;
          for (std::size_t k = 0; k < hooge.size(); ++k)
            if (has(c, k) && has(o, k)) {
              const auto la = labels_of(c, k), lb = labels_of(o, k);
              a.insert(a.end(), la.begin(), la.end());
              b.insert(b.end(), lb.begin(), lb.end());
            }
          sum += gz::cohen_kappa(a, b, ET::fixation), ++pairs;
        }
        emit({{"bench", "gaze_kappa"},
              {"dataset", "hooge"},
              {"method", "coders"},
              {"vs", c},
              {"type", "fixation"},
              {"kappa", sum / pairs}});
        for (gz::Method m : kMethods) {
          std::vector<ET> a, b;
          for (std::size_t k = 0; k < hooge.size(); ++k)
            if (has(c, k)) {
              const auto lb = labels_of(c, k);
              a.insert(a.end(), det[m][k].begin(), det[m][k].end());
              b.insert(b.end(), lb.begin(), lb.end());
            }
          emit({{"bench", "gaze_kappa"},
                {"dataset", "hooge"},
                {"method", gz::to_string(m)},
                {"vs", c},
                {"type", "fixation"},
                {"kappa", gz::cohen_kappa(a, b, ET::fixation)}});
        }
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "gaze_bench: " << e.what() << "\n";
    return 1;
  }
}
