// Teat tracker benchmark (tracker issue, item 8): speed of TrailScope's tracker per stage and its accuracy
// on the synthetic scenarios, against OpenCV's own single-object trackers (CSRT and KCF from opencv_contrib's
// tracking module, MIL from opencv_video) run in the same process on the same frames.
//
//   tracker_bench [--scenarios standard,noisy,occluded,cups-attached,fast-motion] [--frames 1000]
//                 [--seed 1] [--reps 3] [--peers csrt,kcf] [--peer-reps 3] [--param name=value ...]
//                 [--real DIR [--real-z-max-mm 3000] [--real-passes 20]]
//                 [--robustness-seeds 1000-1019 [--robustness-frames 1000] [--robustness-only]]
//
// Every scenario is synthesised in memory (tof::synthesize, exact ground truth) before anything is timed.
//
// Ours: a fresh Tracker (default TrackerParams unless --param) processes every frame in order on the
// calling thread (the tracker is single-threaded); each process() call is timed. frames/s = frames / the
// summed per-frame times of one run, median over --reps runs; the stage split is the median over all
// frames of all runs of each StageTimes field (µs), plus the mean. Accuracy comes from the first run (the
// tracker is deterministic; later runs are checked to give the same tips):
//  - 3D: tracker::evaluate_accuracy (the acceptance figures of `trailscope track`): tip error (mm) over
//    the (frame, teat) pairs where the truth is visible and the tracker reports the teat visible,
//    median / p95, and the share of frames (with a visible teat) where every visible teat is reported
//    within 10 mm;
//  - 2D: |TeatEstimate::tip_px - TeatTruth::tip_px| (px) over every (frame, teat) pair whose truth is
//    visible; a pair the tracker does not report visible is a miss (infinite error). Median and the share
//    within 3 px.
//
// Peers: one OpenCV tracker per teat, initialised on the ground-truth box (TeatTruth::box_px) of the
// teat's first frame in which it is visible with a box (frame 0 for most), never re-initialised. Input:
// an 8-bit image made from the depth with one fixed mapping per video: near = the 1st percentile and
// far = the 99th percentile of the video's finite depths (every 7th pixel of every frame),
// grey = 1 + 254 (far - z) / (far - near) clamped to [1, 255] (near bright), holes (NaN) 0. The peer's
// tip = the tracked box's corner + the tip's offset inside the initial box, scaled with the box's size
// (CSRT estimates the scale; KCF and MIL keep the initial size). KCF gets the grey image replicated into
// three channels: its 1-channel path throws from the second update() in OpenCV 4.6.0. A frame where update()
// returns false reports nothing (a miss). Timed per frame: the depth → grey conversion plus init (first frame
// of each teat) or update of the four trackers; cv::setNumThreads(1) so that the peers, like ours, run on one
// core. frames/s = median over --peer-reps runs; accuracy from the first run. MIL is not in the default
// --peers: with its default parameters it took about 0.2 s per frame (four teats) on the 2-core development
// machine, slower than CSRT and far from real time; add it with --peers csrt,kcf,mil.
//
// Real frames (--real DIR, a folder of depth PNGs in mm: the Redwood frames of the shared tracker data): the
// tracker with its depth gate widened to --real-z-max-mm (the room lies beyond the default 900 mm) on every
// frame, --real-passes times over the folder after one untimed pass, each frame a whole-frame search (the
// tracker never leaves SEARCH on frames without teats); beside it the same search on synthetic `standard`
// frames synthesised at the real frames' size, with n_confirm at its maximum so that the tracker stays in
// SEARCH there too and every frame is a whole-frame search. Same pixels, same work: the two per-frame times
// show whether real depth (holes, noise, clutter) costs more than the synthetic camera. Teats reported on the
// real frames: must be 0.
//
// Robustness (--robustness-seeds A-B): every scenario again on each seed A..B (seeds never used while
// tuning the tracker; the scenarios above and the tests use seeds 1 and 2, tuning seeds from 2000 on),
// --robustness-frames frames each,
// one run per seed with default parameters: the acceptance figures of `trailscope track`
// (tracker::evaluate_accuracy) and frames/s per seed. The same runs as `trailscope synth --scenario S
// --seed N --frames F` then `trailscope track`.
//
// Records: {"bench":"tracker","scenario",...} for ours, {"bench":"tracker_robustness","scenario","seed",...}
// per seed, {"bench":"tracker_real","video",...} for the real
// frames and their synthetic counterpart, {"bench":"tracker_peer","scenario","peer",...}
// per peer (or with "skipped" and the reason). NaN and infinities are written as the strings "NaN" and
// "Infinity" (as the tracker log's JSON does).
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "bench_util.hpp"
#include "trailscope/tof/depth_video.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tof/synth.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/tracker/tracker.hpp"
#include "trailscope/tracker/tracker_log.hpp"

#ifdef TRAILSCOPE_BENCH_OPENCV_TRACKING
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/tracking.hpp>
#include <opencv2/video/tracking.hpp>
#endif

using namespace bench;
namespace tof = trailscope::tof;
namespace trk = trailscope::tracker;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kTeats = tof::kTeatCount;
constexpr double kWithinPx = 3.0;
constexpr double kWithinMm = 10.0;

/// Quantile by linear interpolation between closest ranks (numpy's default), safe with +inf entries
/// (misses): an exact rank returns that entry, and interpolating towards +inf gives +inf. NaN when empty.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(pos);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  if (frac == 0 || v[lo] == v[hi]) return v[lo];
  return v[lo] + frac * (v[hi] - v[lo]);
}

/// JSON has no NaN or infinity: write them as strings, round finite values to 3 decimals.
json number(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "Infinity" : "-Infinity";
  return std::round(x * 1000.0) / 1000.0;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, sep);)
    if (!item.empty()) out.push_back(item);
  return out;
}

/// 2D tip errors over every (frame, teat) pair with a visible truth that has a projection; a pair without
/// a reported tip is +inf.
struct PxErrors {
  std::vector<double> errors;
  std::size_t reported = 0;

  void add(const tof::TeatTruth& truth, const std::optional<std::array<double, 2>>& reported_px) {
    if (!truth.visible || !truth.tip_px) return;
    if (!reported_px) {
      errors.push_back(kInf);
      return;
    }
    ++reported;
    errors.push_back(
        std::hypot((*reported_px)[0] - (*truth.tip_px)[0], (*reported_px)[1] - (*truth.tip_px)[1]));
  }
  void put(json& j) const {
    std::size_t within = 0;
    std::vector<double> finite;
    for (double e : errors) {
      if (e <= kWithinPx) ++within;
      if (std::isfinite(e)) finite.push_back(e);
    }
    j["px_pairs"] = errors.size();
    j["px_reported"] = reported;
    j["px_error_median"] = number(quantile(errors, 0.5));  // misses count as +inf
    j["px_error_p95"] = number(quantile(errors, 0.95));
    j["px_error_median_reported"] = number(quantile(finite, 0.5));  // over reported pairs only
    j["px_share_within_3"] = number(errors.empty() ? kNaN : static_cast<double>(within) / errors.size());
  }
};

// ------------------------------------------------------------------------------------------------
// Ours

struct OursRun {
  double total_s = 0;
  std::vector<double> frame_us, pre_us, det_us, ver_us, mod_us;
  std::vector<trk::FrameLog> logs;
};

OursRun run_ours(const tof::DepthVideo& video, const trk::TrackerParams& params) {
  OursRun r;
  const std::size_t n = video.frames.size();
  r.frame_us.reserve(n), r.pre_us.reserve(n), r.det_us.reserve(n), r.ver_us.reserve(n), r.mod_us.reserve(n);
  r.logs.reserve(n);
  trk::Tracker tracker(params, video.info.intrinsics);
  for (const tof::DepthFrame& f : video.frames) {
    const auto t0 = Clock::now();
    trk::FrameLog log = tracker.process(f);
    const double us = ms_since(t0) * 1000.0;
    r.total_s += us / 1e6;
    r.frame_us.push_back(us);
    r.pre_us.push_back(log.times.preprocess_us), r.det_us.push_back(log.times.detect_us);
    r.ver_us.push_back(log.times.verify_us), r.mod_us.push_back(log.times.model_us);
    r.logs.push_back(std::move(log));
  }
  return r;
}

bool same_tips(const std::vector<trk::FrameLog>& a, const std::vector<trk::FrameLog>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int t = 0; t < kTeats; ++t)
      if (a[i].teats[t].visible != b[i].teats[t].visible || a[i].teats[t].tip_mm != b[i].teats[t].tip_mm)
        return false;
  return true;
}

/// The acceptance figures of `trailscope track` (tracker::evaluate_accuracy) for `logs` of `video`, put
/// into `j` (mm_* figures, frames_all_within_10mm, track_share, lost_episodes) and returned.
trk::Accuracy score(const tof::DepthVideo& video, const std::vector<trk::FrameLog>& logs, json& j) {
  trk::TrackerLog tlog;
  tlog.frames = logs;
  for (const tof::DepthFrame& f : video.frames) tlog.truth.push_back(f.truth);
  const trk::Accuracy acc = trk::evaluate_accuracy(tlog, kWithinMm);
  j["mm_pairs"] = acc.visible_pairs;
  j["mm_reported"] = acc.reported_pairs;
  j["mm_error_median"] = number(acc.median_error_mm);
  j["mm_error_p95"] = number(acc.p95_error_mm);
  j["frames_all_within_10mm"] = number(acc.frames_all_within);
  j["track_share"] = number(acc.track_share);
  j["lost_episodes"] = acc.lost_episodes;
  return acc;
}

void bench_ours(const std::string& scenario, const tof::DepthVideo& video, const trk::TrackerParams& params,
                int reps) {
  std::vector<OursRun> runs;
  std::vector<double> fps;
  bool deterministic = true;
  for (int i = 0; i < reps; ++i) {
    OursRun r = run_ours(video, params);
    fps.push_back(static_cast<double>(video.frames.size()) / r.total_s);
    if (!runs.empty()) {
      deterministic = deterministic && same_tips(runs.front().logs, r.logs);
      r.logs.clear();  // only the first run's logs are scored
    }
    runs.push_back(std::move(r));
  }
  std::vector<double> frame_us, pre, det, ver, mod;
  for (const OursRun& r : runs) {
    frame_us.insert(frame_us.end(), r.frame_us.begin(), r.frame_us.end());
    pre.insert(pre.end(), r.pre_us.begin(), r.pre_us.end());
    det.insert(det.end(), r.det_us.begin(), r.det_us.end());
    ver.insert(ver.end(), r.ver_us.begin(), r.ver_us.end());
    mod.insert(mod.end(), r.mod_us.begin(), r.mod_us.end());
  }
  const Stats fs = Stats::of(fps);
  const auto& intr = video.info.intrinsics;
  json j{{"bench", "tracker"},
         {"scenario", scenario},
         {"impl", "trailscope"},
         {"tracker_version", std::string(trk::kTrackerVersion)},
         {"frames", video.frames.size()},
         {"width", intr.width},
         {"height", intr.height},
         {"reps", reps},
         {"threads", 1},
         {"fps_p50", number(fs.p50)},
         {"fps_min", number(fs.min)},
         {"fps_max", number(fs.max)},
         {"deterministic", deterministic}};
  const Stats fu = Stats::of(frame_us);
  j["frame_us_p50"] = number(fu.p50);
  j["frame_us_p95"] = number(fu.p95);
  j["frame_us_mean"] = number(fu.mean);
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"preprocess", &pre}, {"detect", &det}, {"verify", &ver}, {"model", &mod}};
  for (const auto& [name, v] : stages) {
    const Stats s = Stats::of(*v);
    j[std::string(name) + "_us_p50"] = number(s.p50);
    j[std::string(name) + "_us_mean"] = number(s.mean);
  }

  // Accuracy of the first run.
  const std::vector<trk::FrameLog>& logs = runs.front().logs;
  const trk::Accuracy acc = score(video, logs, j);
  PxErrors px;
  for (std::size_t i = 0; i < logs.size(); ++i) {
    if (!video.frames[i].truth) continue;
    for (int t = 0; t < kTeats; ++t) {
      const trk::TeatEstimate& e = logs[i].teats[t];
      px.add(video.frames[i].truth->teats[t],
             e.visible ? std::optional<std::array<double, 2>>(e.tip_px) : std::nullopt);
    }
  }
  px.put(j);
  j["peak_rss_mib"] = peak_rss_mib();
  emit(j);
  log(scenario + " ours: " + std::to_string(fs.p50) + " frames/s (p50 of " + std::to_string(reps) +
      "), 3D median " + std::to_string(acc.median_error_mm) + " mm, within 10 mm " +
      std::to_string(acc.frames_all_within));
}

// ------------------------------------------------------------------------------------------------
// Real frames: whole-frame searches on real depth and on synthetic frames of the same size

/// Every frame of `video` searched `passes` times, after one untimed pass (buffers allocated); one record.
/// n_confirm at its maximum keeps the tracker in SEARCH, so every frame is a whole-frame search.
void bench_search(const std::string& label, const tof::DepthVideo& video, trk::TrackerParams params,
                  int passes) {
  params.n_confirm = 1000;
  trk::Tracker tracker(params, video.info.intrinsics);
  std::vector<double> frame_us;
  std::size_t teats = 0, verified = 0, valid = 0, tracked = 0;
  double total_s = 0;
  for (int pass = -1; pass < passes; ++pass)
    for (const tof::DepthFrame& f : video.frames) {
      const auto t0 = Clock::now();
      const trk::FrameLog log = tracker.process(f);
      const double us = ms_since(t0) * 1000.0;
      if (pass < 0) continue;  // warm-up
      total_s += us / 1e6;
      frame_us.push_back(us);
      if (pass > 0) continue;  // the counts of one pass (the tracker is deterministic)
      for (const trk::TeatEstimate& t : log.teats) teats += t.visible;
      verified += static_cast<std::size_t>(log.verified);
      valid += static_cast<std::size_t>(log.valid_pixels);
      tracked += log.state == trk::State::track;
    }
  const Stats fu = Stats::of(frame_us);
  const auto& intr = video.info.intrinsics;
  emit({{"bench", "tracker_real"},
        {"video", label},
        {"frames", video.frames.size()},
        {"passes", passes},
        {"width", intr.width},
        {"height", intr.height},
        {"z_max_mm", params.z_max_mm},
        {"search_us_p50", number(fu.p50)},
        {"search_us_p95", number(fu.p95)},
        {"fps", number(static_cast<double>(frame_us.size()) / total_s)},
        {"valid_pixels_per_frame", number(static_cast<double>(valid) / video.frames.size())},
        {"verified_per_frame", number(static_cast<double>(verified) / video.frames.size())},
        {"teats_reported", teats},
        {"track_frames", tracked}});
  log(label + ": whole-frame search " + std::to_string(fu.p50) + " us p50, " + std::to_string(teats) +
      " teats reported");
}

void bench_real(const std::string& dir, double z_max_mm, int passes) {
  const tof::DepthVideo real = tof::read_depth_video(dir);
  if (real.frames.empty()) throw std::invalid_argument("--real: no frame in " + dir);
  trk::TrackerParams params;
  params.z_max_mm = z_max_mm;
  trk::validate(params);
  bench_search("real: " + std::filesystem::path(dir).parent_path().filename().string(), real, params, passes);
  tof::SynthOptions o;
  o.scenario = tof::Scenario::standard;
  o.frames = real.frames.size();
  o.seed = 1;
  o.width = real.info.intrinsics.width, o.height = real.info.intrinsics.height;
  bench_search("synthetic standard", tof::synthesize(o), params, passes);
}

// ------------------------------------------------------------------------------------------------
// Robustness: the acceptance figures on every seed of a range

void bench_robustness(const std::string& scenario, std::uint64_t seed, std::size_t frames,
                      const trk::TrackerParams& params) {
  tof::SynthOptions o;
  o.scenario = tof::parse_scenario(scenario);
  o.frames = frames;
  o.seed = seed;
  const tof::DepthVideo video = tof::synthesize(o);
  const OursRun r = run_ours(video, params);
  json j{{"bench", "tracker_robustness"},
         {"scenario", scenario},
         {"seed", seed},
         {"frames", video.frames.size()},
         {"fps", number(static_cast<double>(video.frames.size()) / r.total_s)}};
  score(video, r.logs, j);
  emit(j);
}

// ------------------------------------------------------------------------------------------------
// Peers (OpenCV)

#ifdef TRAILSCOPE_BENCH_OPENCV_TRACKING

/// The fixed depth → 8-bit mapping of one video (see the header comment).
struct GreyMap {
  double near_mm = 0, far_mm = 1;

  static GreyMap of(const tof::DepthVideo& video) {
    std::vector<double> z;
    for (const tof::DepthFrame& f : video.frames)
      for (std::size_t i = 0; i < f.depth_mm.size(); i += 7)
        if (std::isfinite(f.depth_mm[i])) z.push_back(f.depth_mm[i]);
    GreyMap g;
    if (z.empty()) return g;
    g.near_mm = quantile(z, 0.01);
    g.far_mm = quantile(z, 0.99);
    if (!(g.far_mm > g.near_mm)) g.far_mm = g.near_mm + 1;
    return g;
  }
  void apply(const tof::DepthFrame& f, cv::Mat& grey) const {
    const double k = 254.0 / (far_mm - near_mm);
    for (int y = 0; y < grey.rows; ++y) {
      auto* row = grey.ptr<std::uint8_t>(y);
      const float* z = f.depth_mm.data() + static_cast<std::size_t>(y) * grey.cols;
      for (int x = 0; x < grey.cols; ++x) {
        if (!std::isfinite(z[x])) {
          row[x] = 0;
          continue;
        }
        const double g = 1.0 + k * (far_mm - z[x]);
        row[x] = static_cast<std::uint8_t>(std::lround(std::clamp(g, 1.0, 255.0)));
      }
    }
  }
};

cv::Ptr<cv::Tracker> make_peer(const std::string& name) {
  if (name == "csrt") return cv::TrackerCSRT::create();
  if (name == "kcf") return cv::TrackerKCF::create();
  if (name == "mil") return cv::TrackerMIL::create();
  throw std::invalid_argument("unknown peer " + name + " (csrt, kcf, mil)");
}

/// BoxPx (pixel-centre convention: the single pixel (3, 4) is {2.5, 3.5, 1, 1}) → cv::Rect of whole
/// pixels (Rect(3, 4, 1, 1)), at least 1×1, clipped to the image.
cv::Rect to_rect(const tof::BoxPx& b, int width, int height) {
  int x0 = static_cast<int>(std::lround(b.x + 0.5)), y0 = static_cast<int>(std::lround(b.y + 0.5));
  int x1 = static_cast<int>(std::lround(b.x + b.w + 0.5)),
      y1 = static_cast<int>(std::lround(b.y + b.h + 0.5));
  x0 = std::clamp(x0, 0, width - 1), y0 = std::clamp(y0, 0, height - 1);
  x1 = std::clamp(x1, x0 + 1, width), y1 = std::clamp(y1, y0 + 1, height);
  return {x0, y0, x1 - x0, y1 - y0};
}

struct PeerTeat {
  cv::Ptr<cv::Tracker> tracker;
  std::size_t start = 0;  ///< first frame with a visible truth and a box
  bool has_start = false, init_ok = false;
  double off_x = 0, off_y = 0;  ///< tip offset inside the initial box, as a fraction of its size
  std::string error;            ///< why init failed
};

struct PeerRun {
  double total_s = 0;
  std::vector<double> frame_us;
  std::vector<std::array<std::optional<std::array<double, 2>>, kTeats>> tips;  ///< per frame, per teat
  std::array<std::string, kTeats> init_error;
  std::size_t failed_updates = 0;
  std::size_t update_exceptions = 0;  ///< of the failed updates, those that threw (counted as misses)
  std::string first_exception;
};

PeerRun run_peer(const std::string& name, const tof::DepthVideo& video, const GreyMap& map, bool keep_tips) {
  const int w = video.info.intrinsics.width, h = video.info.intrinsics.height;
  std::array<PeerTeat, kTeats> teats;
  for (int t = 0; t < kTeats; ++t) {
    for (std::size_t i = 0; i < video.frames.size(); ++i) {
      const auto& truth = video.frames[i].truth;
      if (truth && truth->teats[t].visible && truth->teats[t].box_px && truth->teats[t].tip_px) {
        teats[t].start = i, teats[t].has_start = true;
        break;
      }
    }
  }
  PeerRun r;
  r.frame_us.reserve(video.frames.size());
  if (keep_tips) r.tips.resize(video.frames.size());
  cv::Mat grey(h, w, CV_8UC1), bgr;
  // KCF's 1-channel path throws from its second update() in OpenCV 4.6.0 ("Matrix operand is an empty
  // matrix"); it gets the grey image replicated into three channels instead (converted inside the timing).
  const bool three_channels = name == "kcf";
  for (std::size_t i = 0; i < video.frames.size(); ++i) {
    const tof::DepthFrame& f = video.frames[i];
    const auto t0 = Clock::now();
    map.apply(f, grey);
    if (three_channels) cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
    const cv::Mat& input = three_channels ? bgr : grey;
    for (int t = 0; t < kTeats; ++t) {
      PeerTeat& p = teats[t];
      if (!p.has_start || i < p.start) continue;
      cv::Rect box;
      if (i == p.start) {
        const tof::TeatTruth& truth = f.truth->teats[t];
        box = to_rect(*truth.box_px, w, h);
        // Tip offset inside the box, in the pixel-centre frame: the box's left edge is at box.x - 0.5.
        p.off_x = ((*truth.tip_px)[0] - (box.x - 0.5)) / box.width;
        p.off_y = ((*truth.tip_px)[1] - (box.y - 0.5)) / box.height;
        try {
          p.tracker = make_peer(name);
          p.tracker->init(input, box);
          p.init_ok = true;
        } catch (const std::exception& e) {
          p.error = e.what();
          p.tracker.release();
          continue;
        }
      } else {
        if (!p.init_ok) continue;
        bool ok = false;
        try {
          ok = p.tracker->update(input, box);
        } catch (const std::exception& e) {
          ok = false;
          if (r.update_exceptions++ == 0) r.first_exception = e.what();
        }
        if (!ok) {
          ++r.failed_updates;
          continue;
        }
      }
      if (keep_tips)
        r.tips[i][t] =
            std::array<double, 2>{box.x - 0.5 + p.off_x * box.width, box.y - 0.5 + p.off_y * box.height};
    }
    const double us = ms_since(t0) * 1000.0;
    r.total_s += us / 1e6;
    r.frame_us.push_back(us);
  }
  for (int t = 0; t < kTeats; ++t) r.init_error[t] = teats[t].error;
  return r;
}

void bench_peer(const std::string& scenario, const std::string& name, const tof::DepthVideo& video,
                const GreyMap& map, int reps) {
  std::vector<double> fps, frame_us;
  PeerRun first;
  for (int i = 0; i < reps; ++i) {
    PeerRun r = run_peer(name, video, map, i == 0);
    fps.push_back(static_cast<double>(video.frames.size()) / r.total_s);
    frame_us.insert(frame_us.end(), r.frame_us.begin(), r.frame_us.end());
    if (i == 0) first = std::move(r);
  }
  const Stats fs = Stats::of(fps), fu = Stats::of(frame_us);
  json j{{"bench", "tracker_peer"},
         {"scenario", scenario},
         {"peer", name},
         {"impl", "opencv " + std::string(CV_VERSION)},
         {"frames", video.frames.size()},
         {"reps", reps},
         {"threads", cv::getNumThreads()},
         {"fps_p50", number(fs.p50)},
         {"fps_min", number(fs.min)},
         {"fps_max", number(fs.max)},
         {"frame_us_p50", number(fu.p50)},
         {"frame_us_p95", number(fu.p95)},
         {"grey_near_mm", number(map.near_mm)},
         {"grey_far_mm", number(map.far_mm)},
         {"failed_updates", first.failed_updates},
         {"update_exceptions", first.update_exceptions},
         {"input", name == "kcf" ? "grey replicated to BGR" : "grey"}};
  if (!first.first_exception.empty()) j["first_exception"] = first.first_exception;
  json init_errors = json::array();
  for (int t = 0; t < kTeats; ++t)
    if (!first.init_error[t].empty())
      init_errors.push_back(std::string(tof::kTeatNames[t]) + ": " + first.init_error[t]);
  j["init_errors"] = init_errors;
  PxErrors px;
  for (std::size_t i = 0; i < video.frames.size(); ++i) {
    if (!video.frames[i].truth) continue;
    for (int t = 0; t < kTeats; ++t) px.add(video.frames[i].truth->teats[t], first.tips[i][t]);
  }
  px.put(j);
  emit(j);
  log(scenario + " " + name + ": " + std::to_string(fs.p50) + " frames/s, px median " +
      j["px_error_median"].dump() + ", share <= 3 px " + j["px_share_within_3"].dump());
}

#endif  // TRAILSCOPE_BENCH_OPENCV_TRACKING

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const auto scenarios =
        split(a.get("scenarios", "standard,noisy,occluded,cups-attached,fast-motion"), ',');
    const auto frames = static_cast<std::size_t>(a.num("frames", 1000));
    const auto seed = static_cast<std::uint64_t>(a.num("seed", 1));
    const int reps = static_cast<int>(a.num("reps", 3));
    const int peer_reps = static_cast<int>(a.num("peer-reps", 3));
    const auto peers = split(a.get("peers", "csrt,kcf"), ',');
    const std::string real_dir = a.get("real", "");
    const double real_z_max = a.num("real-z-max-mm", 3000);
    const int real_passes = static_cast<int>(a.num("real-passes", 20));
    // --robustness-seeds A-B (inclusive), or empty for none.
    const std::string seed_range = a.get("robustness-seeds", "");
    std::uint64_t seed_lo = 1, seed_hi = 0;
    if (!seed_range.empty()) {
      const auto dash = seed_range.find('-');
      if (dash == std::string::npos)
        throw std::invalid_argument("--robustness-seeds wants A-B: " + seed_range);
      seed_lo = std::stoull(seed_range.substr(0, dash)), seed_hi = std::stoull(seed_range.substr(dash + 1));
      if (seed_hi < seed_lo || seed_hi - seed_lo >= 1000)
        throw std::invalid_argument("--robustness-seeds: A <= B, at most 1000 seeds: " + seed_range);
    }
    const auto robustness_frames = static_cast<std::size_t>(a.num("robustness-frames", 1000));
    if (reps < 1 || peer_reps < 1) throw std::invalid_argument("--reps and --peer-reps must be >= 1");
    trk::TrackerParams params;
    for (const std::string& kv : a.all("param")) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos) throw std::invalid_argument("--param wants name=value: " + kv);
      trk::set_param(params, kv.substr(0, eq), std::stod(kv.substr(eq + 1)));
    }
    trk::validate(params);
#ifdef TRAILSCOPE_BENCH_OPENCV_TRACKING
    cv::setNumThreads(1);
#endif

    if (!real_dir.empty()) bench_real(real_dir, real_z_max, real_passes);
    for (const std::string& name : scenarios) {
      if (name.empty() || a.has("robustness-only")) continue;  // --scenarios '': the real frames only
      tof::SynthOptions o;
      o.scenario = tof::parse_scenario(name);
      o.frames = frames;
      o.seed = seed;
      const auto t0 = Clock::now();
      const tof::DepthVideo video = tof::synthesize(o);
      log(name + ": synthesised " + std::to_string(video.frames.size()) + " frames (" +
          std::to_string(video.info.intrinsics.width) + "x" + std::to_string(video.info.intrinsics.height) +
          ", seed " + std::to_string(seed) + ") in " + std::to_string(ms_since(t0) / 1000.0) + " s");

      bench_ours(name, video, params, reps);
#ifdef TRAILSCOPE_BENCH_OPENCV_TRACKING
      const GreyMap map = GreyMap::of(video);
      for (const std::string& peer : peers) bench_peer(name, peer, video, map, peer_reps);
#else
      for (const std::string& peer : peers)
        emit({{"bench", "tracker_peer"},
              {"scenario", name},
              {"peer", peer},
              {"skipped",
               "OpenCV's tracking module (opencv_contrib, libopencv-contrib-dev) was not found at "
               "build time"}});
#endif
    }
    for (const std::string& name : scenarios) {
      if (name.empty() || seed_hi < seed_lo) continue;
      const auto t0 = Clock::now();
      for (std::uint64_t seed = seed_lo; seed <= seed_hi; ++seed)
        bench_robustness(name, seed, robustness_frames, params);
      log(name + ": robustness over seeds " + seed_range + " in " + std::to_string(ms_since(t0) / 1000.0) +
          " s");
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "tracker_bench: " << e.what() << "\n";
    return 1;
  }
}
