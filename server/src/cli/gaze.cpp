// `trailscope gaze ingest|events`: reads eye-tracking gaze files (format detected by content) and prints
// what they hold, or detects fixations and saccades in them (compute/include/trailscope/gaze/).
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "jobs/gaze_ingest_job.hpp"
#include "store/gaze_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/gaze/events.hpp"
#include "trailscope/gaze/ingest.hpp"

namespace trailscope::cli {
namespace {

/// Options shared by both verbs: the files, the format, the geometry and the eye.
struct ReadOpts {
  std::vector<std::string> files;
  std::string format, eye = "average", participant, stimulus;
  gaze::ScreenGeometry geometry;
  bool json = false, quiet = false;

  void add_to(CLI::App* cmd) {
    cmd->add_option("files", files,
                    "gaze files (EyeLink .asc, Tobii TSV, SMI text, ARFF, DSF coord, "
                    "SimpleGazeTracker CSV, plain time x y [valid])")
        ->required();
    cmd->add_option(
        "--format", format,
        "skip detection: eyelink_asc | tobii_tsv | psychopy_tobii | smi_idf_text | gazecom_arff | "
        "dsf_coord | simple_gaze_tracker | plain");
    cmd->add_option("--width-px", geometry.width_px, "screen width (px); overrides the file's");
    cmd->add_option("--height-px", geometry.height_px, "screen height (px)");
    cmd->add_option("--width-cm", geometry.width_cm, "screen width (cm)");
    cmd->add_option("--height-cm", geometry.height_cm, "screen height (cm)");
    cmd->add_option("--distance-cm", geometry.distance_cm, "viewing distance, eye to screen (cm)");
    cmd->add_option("--eye", eye, "binocular files: average | left | right")->capture_default_str();
    cmd->add_option("--participant", participant,
                    "participant of every recording (default: the file's, or "
                    "the file name)");
    cmd->add_option("--stimulus", stimulus, "stimulus of every recording (default: the file's)");
    cmd->add_flag("--json", json, "print JSON instead of a table");
    cmd->add_flag("--quiet", quiet, "no progress bar");
  }

  gaze::GazeIngestOptions options() const {
    gaze::GazeIngestOptions o;
    if (!format.empty()) o.format = gaze::parse_gaze_format(format, "format");
    o.geometry = geometry;
    o.eye = gaze::parse_eye(eye, "eye");
    o.participant = participant;
    o.stimulus = stimulus;
    return o;
  }

  /// Reads every file with one progress bar over all their bytes.
  std::vector<gaze::GazeDataset> read() const {
    std::uintmax_t total = 0, done = 0;
    for (const auto& f : files) {
      std::error_code ec;
      const auto n = std::filesystem::file_size(f, ec);
      if (ec) throw not_found("file", "cannot open gaze file " + f + ": " + ec.message());
      total += n;
    }
    ProgressBar bar("gaze ingest", !quiet);
    std::vector<gaze::GazeDataset> out;
    for (const auto& f : files) {
      gaze::GazeIngestOptions o = options();
      const auto size = std::filesystem::file_size(f);
      o.progress = [&](double frac, std::string_view stage) {
        bar.update(total ? (double(done) + frac * double(size)) / double(total) : 1.0, stage);
      };
      out.push_back(gaze::read_gaze_file(f, o));
      done += size;
    }
    return out;
  }
};

nlohmann::json geometry_json(const gaze::ScreenGeometry& g) {
  return {{"width_px", number_or_null(g.width_px > 0 ? g.width_px : NAN)},
          {"height_px", number_or_null(g.height_px > 0 ? g.height_px : NAN)},
          {"width_cm", number_or_null(g.width_cm > 0 ? g.width_cm : NAN)},
          {"height_cm", number_or_null(g.height_cm > 0 ? g.height_cm : NAN)},
          {"distance_cm", number_or_null(g.distance_cm > 0 ? g.distance_cm : NAN)}};
}

nlohmann::json recording_json(const gaze::Recording& r) {
  nlohmann::json annotations = nlohmann::json::array();
  for (const auto& a : r.annotations) annotations.push_back(a.first);
  return {{"participant", r.participant},
          {"stimulus", r.stimulus},
          {"trial", r.trial},
          {"format", r.format},
          {"units", gaze::to_string(r.units)},
          {"rate_hz", number_or_null(r.rate_hz > 0 ? r.rate_hz : NAN)},
          {"samples", r.size()},
          {"valid_samples", r.valid_count()},
          {"t_start_ms", number_or_null(r.size() ? r.t_ms.front() : NAN)},
          {"t_end_ms", number_or_null(r.size() ? r.t_ms.back() : NAN)},
          {"tracker_events", r.tracker_events.size()},
          {"annotations", annotations},
          {"geometry", geometry_json(r.geometry)}};
}

void add_gaze_ingest(CLI::App* parent) {
  auto* cmd = parent->add_subcommand(
      "ingest",
      "Read gaze files and print their recordings: participant, stimulus, samples, validity, "
      "rate, geometry");
  cmd->footer(
      "The format is detected from the content. Exit 2 with the line and reason when a file is "
      "damaged or not gaze data.");
  auto o = std::make_shared<ReadOpts>();
  o->add_to(cmd);
  auto dir = std::make_shared<std::string>(default_data_dir());
  auto name = std::make_shared<std::string>();
  cmd->add_option("--name", *name,
                  "store the file as gaze dataset NAME (1-64 of a-z 0-9 _ -) in the data folder instead of "
                  "only printing it; recordings that name no participant get NAME");
  cmd->add_option("--data-dir", *dir, "data folder of --name")->capture_default_str();
  cmd->callback([o, dir, name] {
    if (!name->empty()) {
      if (o->files.size() != 1)
        throw invalid_argument("files",
                               "--name stores exactly one file, got " + std::to_string(o->files.size()));
      server::GazeStore store(*dir, server::GazeStore::Leftovers::keep);  // a server may be writing there
      server::GazeIngestRequest req;
      req.file = o->files.front();
      req.name = *name;
      req.options = o->options();
      ProgressBar bar("gaze ingest", !o->quiet);
      const nlohmann::json res = server::ingest_gaze_into_store(
          store, req, [&](double f, std::string_view stage) { bar.update(f, stage); }, nullptr);
      bar.update(1.0, "done");
      if (o->json)
        std::cout << json_text(res, 2) << std::endl;
      else
        std::cout << "stored gaze dataset '" << *name << "' in " << *dir << ": " << res.at("recordings")
                  << " recording(s), " << res.at("samples") << " samples\n";
      return;
    }
    const auto sets = o->read();
    if (o->json) {
      nlohmann::json files = nlohmann::json::array();
      for (std::size_t i = 0; i < sets.size(); ++i) {
        nlohmann::json recs = nlohmann::json::array();
        for (const auto& r : sets[i].recordings) recs.push_back(recording_json(r));
        files.push_back({{"file", o->files[i]},
                         {"samples", sets[i].total_samples()},
                         {"participants", sets[i].participants()},
                         {"stimuli", sets[i].stimuli()},
                         {"recordings", recs}});
      }
      std::cout << json_text({{"files", files}}, 2) << std::endl;
      return;
    }
    for (std::size_t i = 0; i < sets.size(); ++i) {
      const auto& ds = sets[i];
      std::cout << o->files[i] << ": " << ds.recordings.size() << " recording(s), " << ds.total_samples()
                << " samples, format " << ds.recordings.front().format << "\n";
      for (const auto& r : ds.recordings)
        std::cout << "  " << r.participant << " / " << (r.stimulus.empty() ? "-" : r.stimulus) << " / "
                  << r.trial << ": " << r.size() << " samples (" << r.valid_count() << " valid), "
                  << (r.rate_hz > 0 ? std::to_string(int(r.rate_hz)) + " Hz, " : "")
                  << (r.geometry.has_pixels() ? std::to_string(int(r.geometry.width_px)) + "x" +
                                                    std::to_string(int(r.geometry.height_px)) + " px"
                                              : std::string("no screen size"))
                  << (r.geometry.has_physical() ? ", degrees available" : "") << "\n";
    }
  });
}

void add_gaze_events(CLI::App* parent) {
  auto* cmd = parent->add_subcommand(
      "events",
      "Detect fixations and saccades (I-VT, I-DT, or the adaptive velocity threshold of Nystrom and "
      "Holmqvist 2010) in gaze files");
  cmd->footer(
      "Works in degrees of visual angle: files without a physical screen size need --width-px "
      "--height-px --width-cm --height-cm --distance-cm. Invalid samples are blinks.");
  auto o = std::make_shared<ReadOpts>();
  o->add_to(cmd);
  struct EvOpts {
    std::string method = "ivt";
    gaze::EventParams p;
  };
  auto e = std::make_shared<EvOpts>();
  cmd->add_option("--method", e->method, "ivt | idt | adaptive")->capture_default_str();
  cmd->add_option("--velocity-threshold", e->p.ivt.velocity_threshold_deg_s, "I-VT saccade velocity (deg/s)")
      ->capture_default_str();
  cmd->add_option("--min-fixation-ms", e->p.ivt.min_fixation_ms,
                  "I-VT: shortest fixation (ms; the adaptive method has its own, --adaptive-min-fixation-ms)")
      ->capture_default_str();
  cmd->add_option("--dispersion", e->p.idt.dispersion_threshold_deg, "I-DT dispersion threshold (deg)")
      ->capture_default_str();
  cmd->add_option("--min-duration-ms", e->p.idt.min_duration_ms, "I-DT shortest fixation / window (ms)")
      ->capture_default_str();
  cmd->add_option("--initial-peak-threshold", e->p.adaptive.initial_peak_threshold_deg_s,
                  "adaptive: initial peak velocity threshold (deg/s)")
      ->capture_default_str();
  cmd->add_option("--filter-window-ms", e->p.adaptive.filter_window_ms,
                  "adaptive: Savitzky-Golay window (ms)")
      ->capture_default_str();
  cmd->add_option("--min-saccade-ms", e->p.adaptive.min_saccade_ms, "adaptive: shortest saccade (ms)")
      ->capture_default_str();
  cmd->add_option("--adaptive-min-fixation-ms", e->p.adaptive.min_fixation_ms,
                  "adaptive: shortest fixation (ms)")
      ->capture_default_str();
  cmd->add_option("--glissade-window-ms", e->p.adaptive.glissade_window_ms,
                  "adaptive: window after a saccade for glissades (ms)")
      ->capture_default_str();
  cmd->add_option("--max-acceleration", e->p.adaptive.max_acceleration_deg_s2,
                  "adaptive: samples whose speed changes faster are noise (deg/s^2)")
      ->capture_default_str();
  cmd->add_option("--max-velocity", e->p.adaptive.max_velocity_deg_s,
                  "adaptive: faster samples are noise (deg/s)")
      ->capture_default_str();
  cmd->callback([o, e] {
    e->p.method = gaze::parse_method(e->method, "method");
    gaze::validate(e->p);  // before reading: a bad flag fails fast
    const auto sets = o->read();
    nlohmann::json files = nlohmann::json::array();
    for (std::size_t i = 0; i < sets.size(); ++i) {
      nlohmann::json recs = nlohmann::json::array();
      if (!o->json) std::cout << o->files[i] << ":\n";
      for (const auto& r : sets[i].recordings) {
        const gaze::Detection d = gaze::detect_events(r, e->p);
        std::map<gaze::EventType, std::pair<std::size_t, double>> per;  // count, total ms
        nlohmann::json events = nlohmann::json::array();
        for (const auto& ev : d.events) {
          auto& [n, ms] = per[ev.type];
          ++n, ms += ev.t_end_ms - ev.t_start_ms;
          events.push_back(
              {{"type", gaze::to_string(ev.type)}, {"t_start_ms", ev.t_start_ms}, {"t_end_ms", ev.t_end_ms}});
        }
        if (o->json) {
          nlohmann::json rj = recording_json(r);
          rj["method"] = gaze::to_string(e->p.method);
          rj["peak_threshold_deg_s"] = number_or_null(d.peak_threshold_deg_s);
          rj["onset_threshold_deg_s"] = number_or_null(d.onset_threshold_deg_s);
          rj["events"] = events;
          recs.push_back(rj);
        } else {
          std::cout << "  " << r.participant << " / " << (r.stimulus.empty() ? "-" : r.stimulus) << " / "
                    << r.trial << ":";
          for (gaze::EventType t : {gaze::EventType::fixation, gaze::EventType::saccade, gaze::EventType::pso,
                                    gaze::EventType::blink})
            if (per.count(t))
              std::cout << " " << per[t].first << " " << gaze::to_string(t) << (per[t].first == 1 ? "" : "s")
                        << " (mean " << int(std::lround(per[t].second / double(per[t].first))) << " ms)";
          std::cout << "\n";
        }
      }
      if (o->json) files.push_back({{"file", o->files[i]}, {"recordings", recs}});
    }
    if (o->json) std::cout << json_text({{"files", files}}, 2) << std::endl;
  });
}

void add_gaze_list(CLI::App* parent) {
  auto* cmd = parent->add_subcommand("list", "List the gaze datasets of a data folder");
  auto dir = std::make_shared<std::string>(default_data_dir());
  auto json = std::make_shared<bool>(false);
  cmd->add_option("--data-dir", *dir, "data folder")->capture_default_str();
  cmd->add_flag("--json", *json, "print the API's list ({\"datasets\": [...]})");
  cmd->callback([dir, json] {
    const server::GazeStore store(*dir, server::GazeStore::Leftovers::keep);
    const auto list = store.list();
    if (*json) {
      std::cout << json_text({{"datasets", list}}, 2) << std::endl;
      return;
    }
    for (const auto& d : list)
      std::cout << d.at("id").get<std::string>() << ": " << d.at("recordings") << " recording(s), "
                << d.at("samples") << " samples, " << d.at("format").get<std::string>() << ", created "
                << d.at("created").get<std::string>() << "\n";
  });
}

void add_gaze_delete(CLI::App* parent) {
  auto* cmd = parent->add_subcommand("delete", "Delete a gaze dataset of a data folder (atomically)");
  auto dir = std::make_shared<std::string>(default_data_dir());
  auto id = std::make_shared<std::string>();
  cmd->add_option("id", *id, "the gaze dataset")->required();
  cmd->add_option("--data-dir", *dir, "data folder")->capture_default_str();
  cmd->callback([dir, id] {
    server::GazeStore store(*dir, server::GazeStore::Leftovers::keep);
    store.remove(*id);
    std::cout << "deleted gaze dataset '" << *id << "'\n";
  });
}

}  // namespace

void add_gaze(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "gaze",
      "Eye-tracking gaze files: ingest (and store), fixation and saccade events; stored gaze datasets");
  cmd->require_subcommand(1);
  add_gaze_ingest(cmd);
  add_gaze_events(cmd);
  add_gaze_list(cmd);
  add_gaze_delete(cmd);
}

}  // namespace trailscope::cli
