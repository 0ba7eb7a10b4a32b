// `trailscope gaze ingest|events|tile|aoi|bundle`: reads eye-tracking gaze files (format detected by
// content) and prints what they hold, detects fixations and saccades in them (compute/include/trailscope/
// gaze/), or draws the views of compute/include/trailscope/gazeview/: stimulus-space density tiles, AOI
// measures, bundled saccades.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "jobs/gaze_ingest_job.hpp"
#include "store/gaze_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/gaze/events.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/gazeview/aoi.hpp"
#include "trailscope/gazeview/saccade_bundle.hpp"
#include "trailscope/gazeview/tiles.hpp"
#include "jobs/bundle_job.hpp"
#include "trailscope/bundling/render.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/density/png.hpp"

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

/// The detector flags shared by `events` and the views (the same names as the REST filters' thresholds).
struct EventOpts {
  std::string method = "ivt";
  gaze::EventParams p;

  void add_to(CLI::App* cmd) {
    cmd->add_option("--method", method, "ivt | idt | adaptive")->capture_default_str();
    cmd->add_option("--velocity-threshold", p.ivt.velocity_threshold_deg_s, "I-VT saccade velocity (deg/s)")
        ->capture_default_str();
    cmd->add_option(
           "--min-fixation-ms", p.ivt.min_fixation_ms,
           "I-VT: shortest fixation (ms; the adaptive method has its own, --adaptive-min-fixation-ms)")
        ->capture_default_str();
    cmd->add_option("--dispersion", p.idt.dispersion_threshold_deg, "I-DT dispersion threshold (deg)")
        ->capture_default_str();
    cmd->add_option("--min-duration-ms", p.idt.min_duration_ms, "I-DT shortest fixation / window (ms)")
        ->capture_default_str();
    cmd->add_option("--initial-peak-threshold", p.adaptive.initial_peak_threshold_deg_s,
                    "adaptive: initial peak velocity threshold (deg/s)")
        ->capture_default_str();
    cmd->add_option("--filter-window-ms", p.adaptive.filter_window_ms, "adaptive: Savitzky-Golay window (ms)")
        ->capture_default_str();
    cmd->add_option("--min-saccade-ms", p.adaptive.min_saccade_ms, "adaptive: shortest saccade (ms)")
        ->capture_default_str();
    cmd->add_option("--adaptive-min-fixation-ms", p.adaptive.min_fixation_ms,
                    "adaptive: shortest fixation (ms)")
        ->capture_default_str();
    cmd->add_option("--glissade-window-ms", p.adaptive.glissade_window_ms,
                    "adaptive: window after a saccade for glissades (ms)")
        ->capture_default_str();
    cmd->add_option("--max-acceleration", p.adaptive.max_acceleration_deg_s2,
                    "adaptive: samples whose speed changes faster are noise (deg/s^2)")
        ->capture_default_str();
    cmd->add_option("--max-velocity", p.adaptive.max_velocity_deg_s,
                    "adaptive: faster samples are noise (deg/s)")
        ->capture_default_str();
  }
  void resolve() {
    p.method = gaze::parse_method(method, "method");
    gaze::validate(p);
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
  auto e = std::make_shared<EventOpts>();
  e->add_to(cmd);
  cmd->callback([o, e] {
    e->resolve();  // before reading: a bad flag fails fast
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

// --- the views ---------------------------------------------------------------------------------------

/// Which recordings and which time window the views read (gaze::GazeFilter, as the REST filters).
struct ViewOpts {
  long long recording = -1;  // -1: every recording
  std::string only_participant, only_stimulus;
  double t0_ms = 0, t1_ms = std::numeric_limits<double>::infinity();
  void add_to(CLI::App* cmd) {
    cmd->add_option("--recording", recording, "only this recording: index from 0, across the files in order")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--only-participant", only_participant, "only the recordings of this participant");
    cmd->add_option("--only-stimulus", only_stimulus, "only the recordings of this stimulus");
    cmd->add_option("--t0-ms", t0_ms, "window start, ms after each recording's first sample")
        ->capture_default_str();
    cmd->add_option("--t1-ms", t1_ms, "window end (exclusive), ms after each recording's first sample");
  }
  gaze::GazeFilter filter() const {
    gaze::GazeFilter f;
    if (recording >= 0) f.recording = std::size_t(recording);
    if (!only_participant.empty()) f.participant = only_participant;
    if (!only_stimulus.empty()) f.stimulus = only_stimulus;
    f.t0_ms = t0_ms, f.t1_ms = t1_ms;
    return f;
  }
};

/// Every file's recordings in one dataset, numbered in file order.
gaze::GazeDataset merged(std::vector<gaze::GazeDataset> sets) {
  gaze::GazeDataset ds;
  for (auto& s : sets)
    for (auto& r : s.recordings) ds.recordings.push_back(std::move(r));
  return ds;
}

nlohmann::json stimulus_json(const gazeview::Stimulus& st) {
  return {{"width_px", st.width_px}, {"height_px", st.height_px}};
}

void add_gaze_tile(CLI::App* parent) {
  auto* cmd = parent->add_subcommand(
      "tile",
      "Draw a gaze density tile in stimulus pixel space (samples, or fixations weighted by duration)");
  cmd->footer(
      "Tile 0/0/0 is 256 px over the square of side max(width, height) of the stimulus, origin top-left; "
      "zoom z has 2^z x 2^z tiles. Pixels outside the stimulus are transparent. The colours are shared "
      "by every tile of a zoom, as for flight density tiles. Fixations need a physical geometry (see "
      "`gaze events --help`).");
  auto o = std::make_shared<ReadOpts>();
  o->add_to(cmd);
  auto e = std::make_shared<EventOpts>();
  e->add_to(cmd);
  auto v = std::make_shared<ViewOpts>();
  v->add_to(cmd);
  struct TileOpts {
    std::string out, what = "samples", how = "eq_hist", cmap = "fire";
    int z = 0, x = 0, y = 0;
    double kernel_radius = 0;
    double min_level = std::numeric_limits<double>::quiet_NaN();  // unset: the default level
  };
  auto t = std::make_shared<TileOpts>();
  cmd->add_option("-o,--output", t->out, "PNG file to write")->required();
  cmd->add_option("--z", t->z, "zoom")->capture_default_str();
  cmd->add_option("--x", t->x, "column, 0..2^z-1, left to right")->capture_default_str();
  cmd->add_option("--y", t->y, "row, 0..2^z-1, top to bottom")->capture_default_str();
  cmd->add_option("--what", t->what, "samples | fixations")->capture_default_str();
  cmd->add_option("--how", t->how, "linear | log | eq_hist")->capture_default_str();
  cmd->add_option("--cmap", t->cmap, "fire | gray | inferno | magma | viridis")->capture_default_str();
  cmd->add_option("--kernel-radius", t->kernel_radius, "Gaussian smoothing radius, tile px (0 = none)")
      ->capture_default_str();
  cmd->add_option("--min-level", t->min_level,
                  "colormap position of the lowest value, [0, 1) (default 0.25)");
  cmd->callback([o, e, v, t] {
    e->resolve();
    gazeview::StimulusTileRequest req;
    req.tile = {t->z, t->x, t->y};
    req.how = density::parse_how(t->how, "how");
    req.cmap = t->cmap;
    req.kernel_radius = t->kernel_radius;
    if (!std::isnan(t->min_level)) req.min_level = t->min_level;
    gazeview::validate(req);
    const gazeview::TileWhat what = gazeview::parse_tile_what(t->what, "what");
    const gaze::GazeDataset ds = merged(o->read());
    const gaze::GazeFilter f = v->filter();
    const std::vector<std::size_t> sel = gazeview::pixel_recordings(ds, f);
    const gazeview::Stimulus st = gazeview::stimulus_of(ds, sel);
    const gazeview::GazePoints points =
        gazeview::gaze_points(ds, f, e->p, what, std::numeric_limits<std::size_t>::max());
    const gazeview::StimulusTile tile = gazeview::render_stimulus_tile(points, st, req);
    std::ofstream out(t->out, std::ios::binary | std::ios::trunc);
    out.write(tile.png.data(), std::streamsize(tile.png.size()));
    out.close();
    if (!out) throw Error(Error::Kind::internal, "output", "cannot write " + t->out);
    if (o->json) {
      std::cout << json_text({{"tile", geo::to_string(req.tile)},
                              {"what", gazeview::to_string(what)},
                              {"stimulus", stimulus_json(st)},
                              {"recordings", sel.size()},
                              {"points", points.size()},
                              {"empty", tile.empty},
                              {"max_value", tile.max_value},
                              {"output", t->out},
                              {"legend", gazeview::stimulus_legend(points, st, req, 5).to_json()}},
                             2)
                << std::endl;
    } else {
      std::cout << "tile " << geo::to_string(req.tile) << " of a " << format_double(st.width_px) << "x"
                << format_double(st.height_px) << " px stimulus: " << points.size() << " "
                << gazeview::to_string(what) << ", "
                << (tile.empty ? std::string("nothing drawn")
                               : "largest pixel " + format_double(tile.max_value))
                << " -> " << t->out << "\n";
    }
  });
}

/// "NAME:x0,y0,x1,y1" (a rectangle) or "NAME:x,y,x,y,x,y[,...]" (a polygon) as the REST body's AOI object.
nlohmann::json aoi_spec_json(const std::string& spec) {
  const auto colon = spec.rfind(':');
  if (colon == std::string::npos)
    throw invalid_argument("aoi", "--aoi '" + spec + "': give NAME:x0,y0,x1,y1 or NAME:x,y,x,y,x,y,...");
  std::vector<double> v;
  std::stringstream ss(spec.substr(colon + 1));
  for (std::string item; std::getline(ss, item, ',');) {
    double d = 0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), d);
    if (ec != std::errc() || ptr != item.data() + item.size() || item.empty())
      throw invalid_argument("aoi", "--aoi '" + spec + "': '" + item + "' is not a number");
    v.push_back(d);
  }
  nlohmann::json j = {{"name", spec.substr(0, colon)}};
  if (v.size() == 4) {
    j["rect"] = v;
  } else if (v.size() >= 6 && v.size() % 2 == 0) {
    nlohmann::json poly = nlohmann::json::array();
    for (std::size_t i = 0; i < v.size(); i += 2) poly.push_back({v[i], v[i + 1]});
    j["polygon"] = poly;
  } else {
    throw invalid_argument(
        "aoi", "--aoi '" + spec + "': 4 numbers (a rectangle) or 3 or more x,y pairs (a polygon)");
  }
  return j;
}

void add_gaze_aoi(CLI::App* parent) {
  auto* cmd = parent->add_subcommand(
      "aoi", "Areas of interest: fixations, dwell time, visitors, first-fixation time, transition matrix");
  cmd->footer(
      "A fixation belongs to the first AOI (in the order given) that contains its centroid; fixations "
      "outside "
      "every AOI are not counted and do not break a transition chain. --aoi-file reads a JSON array of "
      "{\"name\", \"rect\": [x0,y0,x1,y1]} or {\"name\", \"polygon\": [[x,y],...]} (or an object with that "
      "array as \"aois\"), as the REST API's body.");
  auto o = std::make_shared<ReadOpts>();
  o->add_to(cmd);
  auto e = std::make_shared<EventOpts>();
  e->add_to(cmd);
  auto v = std::make_shared<ViewOpts>();
  v->add_to(cmd);
  struct AoiOpts {
    std::vector<std::string> specs;
    std::string file;
  };
  auto a = std::make_shared<AoiOpts>();
  cmd->add_option("--aoi", a->specs,
                  "NAME:x0,y0,x1,y1 (rectangle) or NAME:x,y,x,y,x,y,... (polygon); repeat");
  cmd->add_option("--aoi-file", a->file, "JSON file of AOIs");
  cmd->callback([o, e, v, a] {
    e->resolve();
    nlohmann::json list = nlohmann::json::array();
    if (!a->file.empty()) {
      std::ifstream in(a->file, std::ios::binary);
      if (!in) throw not_found("aoi-file", "cannot open " + a->file);
      std::stringstream buf;
      buf << in.rdbuf();
      nlohmann::json j = nlohmann::json::parse(buf.str(), nullptr, false);
      if (j.is_discarded()) throw invalid_argument("aoi-file", a->file + " is not JSON");
      if (j.is_object() && j.contains("aois")) j = j["aois"];
      if (!j.is_array()) throw invalid_argument("aoi-file", a->file + ": expected an array of AOIs");
      for (auto& x : j) list.push_back(x);
    }
    for (const auto& s : a->specs) list.push_back(aoi_spec_json(s));
    if (list.empty()) throw invalid_argument("aoi", "give at least one --aoi or an --aoi-file");
    const std::vector<gazeview::Aoi> aois = gazeview::aois_from_json(list);
    const gaze::GazeDataset ds = merged(o->read());
    const gazeview::ViewEvents ev =
        gazeview::view_events(ds, v->filter(), e->p, std::numeric_limits<std::size_t>::max());
    const gazeview::AoiReport r = gazeview::aoi_statistics(aois, ev.fixations);
    nlohmann::json j = gazeview::to_json(r, ev.recordings.size());
    j["method"] = gaze::to_string(e->p.method);
    if (o->json) {
      std::cout << json_text(j, 2) << std::endl;
      return;
    }
    auto ms = [](double x) { return std::isnan(x) ? std::string("-") : std::to_string(std::lround(x)); };
    std::cout << r.fixations << " fixations in " << ev.recordings.size() << " recording(s), " << r.outside
              << " outside every AOI\n";
    std::cout << "AOI\tfixations\tdwell_ms\tvisitors\tfirst_median_ms\tfirst_min_ms\tmean_fixation_ms\n";
    for (const auto& s : r.aois)
      std::cout << s.name << "\t" << s.fixations << "\t" << ms(s.dwell_ms) << "\t" << s.visitors << "\t"
                << ms(s.first_fixation_median_ms) << "\t" << ms(s.first_fixation_min_ms) << "\t"
                << ms(s.mean_fixation_ms) << "\n";
    std::cout << "transitions (row: from, column: to)\n";
    for (std::size_t i = 0; i < r.aois.size(); ++i) {
      std::cout << r.aois[i].name;
      for (auto c : r.transitions[i]) std::cout << "\t" << c;
      std::cout << "\n";
    }
  });
}

void add_gaze_bundle(CLI::App* parent) {
  auto* cmd = parent->add_subcommand(
      "bundle", "Bundle the saccades (start -> end) with CUBu in stimulus pixel space and draw them");
  cmd->footer(
      "Every bundling parameter of `trailscope bundle` is a flag here too (--size, --h, --iterations, ...). "
      "The stimulus box fills the bundle image; saccade ends stay where they are unless --ms-iterations > "
      "0.");
  auto o = std::make_shared<ReadOpts>();
  o->add_to(cmd);
  auto e = std::make_shared<EventOpts>();
  e->add_to(cmd);
  auto v = std::make_shared<ViewOpts>();
  v->add_to(cmd);
  struct BundleOpts {
    std::string out, backend;
    int width = 1024;
    std::map<std::string, std::string> params;
  };
  auto b = std::make_shared<BundleOpts>();
  cmd->add_option("-o,--output", b->out, "PNG file to write")->required();
  cmd->add_option("--width", b->width, "image width, px (16..8192)")->capture_default_str();
  cmd->add_option("--backend", b->backend, "cpu | opencl | auto");
  for (const auto& info : bundling::parameter_infos()) {
    const std::string name = info.name;
    std::string flag = "--" + name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    cmd->add_option_function<std::string>(
        flag, [b, name](const std::string& x) { b->params[name] = x; },
        info.help + " [" + info.type + ", " + info.range + ", default " + info.default_value + "]");
  }
  cmd->callback([o, e, v, b] {
    e->resolve();
    bundling::BundleParams params;
    for (const auto& [k, x] : b->params) params.set(k, x);
    params.validate();
    bundling::RenderParams rp;
    rp.width = b->width;
    rp.validate();
    const Backend backend = b->backend.empty() ? default_backend() : parse_backend(b->backend, "backend");
    const gaze::GazeDataset ds = merged(o->read());
    const gazeview::ViewEvents ev =
        gazeview::view_events(ds, v->filter(), e->p, std::numeric_limits<std::size_t>::max());
    const gazeview::Stimulus st = gazeview::stimulus_of(ds, ev.recordings);
    gazeview::SaccadeLines lines = gazeview::saccade_lines(ev.saccades, st, params);
    server::BundleInput in;
    in.input_points = lines.px.points();
    in.px = std::move(lines.px);
    in.frame = lines.frame;
    in.units = server::BundleUnits::plane;
    in.source = {{"files", o->files},
                 {"saccades", in.px.size()},
                 {"method", gaze::to_string(e->p.method)},
                 {"stimulus", stimulus_json(st)}};
    std::shared_ptr<server::StoredBundle> res;
    {
      ProgressBar bar("gaze bundle", !o->quiet);
      res = server::run_bundle(std::move(in), "", params, backend, bar.fn(), nullptr);
    }
    density::write_png(bundling::render_bundle(res->bundled, rp), b->out);
    nlohmann::json j = res->to_json();
    j.erase("id");
    j.erase("created");
    j["output"] = b->out;
    if (o->json)
      std::cout << json_text(j, 2) << std::endl;
    else
      std::cout << res->bundled.lines.size() << " saccades bundled (" << res->bundled.path
                << ", ink reduction " << std::lround(res->bundled.quality.ink_reduction * 100) << " %) -> "
                << b->out << "\n";
  });
}

}  // namespace

void add_gaze(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "gaze",
      "Eye-tracking gaze files: ingest (and store), fixation and saccade events, density tiles, AOIs, "
      "saccade bundles; stored gaze datasets");
  cmd->require_subcommand(1);
  add_gaze_ingest(cmd);
  add_gaze_events(cmd);
  add_gaze_list(cmd);
  add_gaze_delete(cmd);
  add_gaze_tile(cmd);
  add_gaze_aoi(cmd);
  add_gaze_bundle(cmd);
}

}  // namespace trailscope::cli
