#include "trailscope/tracker/tracker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "trailscope/core/error.hpp"
#include "tracker/detail/frame_prep.hpp"
#include "tracker/detail/kalman.hpp"
#include "tracker/detail/ncc_detect.hpp"
#include "tracker/detail/tip_fit.hpp"
#include "tracker/detail/udder_model.hpp"

namespace trailscope::tracker {

std::string_view to_string(State s) {
  switch (s) {
    case State::search:
      return "SEARCH";
    case State::track:
      return "TRACK";
    case State::lost:
      return "LOST";
  }
  return "SEARCH";
}

State parse_state(std::string_view s) {
  std::string u(s);
  for (char& ch : u) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (u == "SEARCH") return State::search;
  if (u == "TRACK") return State::track;
  if (u == "LOST") return State::lost;
  throw invalid_argument("state", "unknown tracker state '" + std::string(s) + "' (SEARCH, TRACK, LOST)");
}

namespace {

using V3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

double us_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

// Two verified fits closer than this are the same tip found by two templates or windows.
constexpr double kSameTipMm = 8.0;
// A match this close (px) to a verified tip's projection is that tip again.
constexpr double kSameTipPx = 2.0;
// How fast the udder model follows what it sees (per tracked frame).
constexpr double kModelRate = 0.05;
// A verified candidate within this share of d_gate_mm of an unmatched teat's prediction teaches the teat's
// radius (relearn_radius).
constexpr double kRadiusEvidenceGate = 0.5;
// A frame with a single teat matched still counts as tracked when the match lies within this share of
// d_gate_mm of its prediction. On tuning seeds 2000-2005, 0.5 raised occluded from 0.904 to 0.916 of frames
// within 10 mm and cups-attached from 0.960 to 0.984, standard unchanged; 1.0 (any gated match) let a lone
// match on clutter hold a drifting track on standard seed 2005 (0.965 to 0.79).
constexpr double kSingleTeatGate = 0.5;
// NCC a match in a TRACK window needs (ncc_min if higher). The prediction itself is verified there as a
// seed whatever its score, so a teat that correlates poorly is not lost by this, while clutter correlating
// at 0.25-0.3 inside the windows doubled the fits per frame (cups-attached seed 2001: 7.8 against 4.1
// matches per TRACK frame, 943 against 1,249 frames/s). On tuning seeds 2000-2005, 0.3 gave the same
// shares as no floor; 0.35 cost occluded 0.9 points.
constexpr double kTrackWindowNcc = 0.3;
// A two-teat re-acquisition is taken only when the next best pair or order is this many times worse.
constexpr double kPairUnique = 2.0;
// How fast the learnt offsets between teats follow what is seen (per frame that sees both).
constexpr double kOffsetRate = 0.1;
// Largest error (mm) of every pair distance of a candidate taken for a lost teat by the model alone.
constexpr double kRescueMm = 8.0;
// How fast a teat's axis follows its fits.
constexpr double kAxisRate = 0.2;
// Position uncertainty of a teat placed by its offsets, mm.
constexpr double kCarriedSd = 6.0;
// Confidence of a teat carried by prediction decays by this factor per frame.
constexpr double kConfidenceDecay = 0.8;

// Whether candidate j is already some teat's in labelling l.
bool labelled(const detail::Labelling& l, int j) {
  return std::find(l.begin(), l.end(), j) != l.end();
}

// A tracked teat's axis, offered to matches within reach_px of its predicted pixel.
struct AxisPrior {
  double u = 0, v = 0, reach_px = 0;
  std::array<double, 3> axis{};
};

struct TeatTrack {
  bool tracked = false;
  detail::TipKalman kf;
  V3 axis = V3::Zero();
  int missed = 0;
  double confidence = 0;
};

}  // namespace

struct Tracker::Impl {
  TrackerParams p;
  tof::Intrinsics k;
  detail::NccDetector det;
  detail::PreparedFrame pf;
  State state = State::search;
  bool ever_tracked = false;
  int confirm = 0, bad = 0;
  std::optional<detail::Labelling> pending;
  std::vector<V3> pending_tips;  // per teat (NaN when unlabelled) of the previous acquisition frame
  detail::UdderModel model;
  std::array<TeatTrack, 4> teats;
  std::array<std::array<V3, 4>, 4> rel{};  // rel[a][b]: tip a - tip b, mm
  std::array<std::array<bool, 4>, 4> rel_known{};
  std::size_t frame_no = 0;
  const tof::DepthFrame* current = nullptr;  // the frame being processed
  bool partial = false;                      // pf holds only the TRACK windows
  double last_t = 0;

  Impl(const TrackerParams& params, const tof::Intrinsics& intr) : p(params), k(intr), det(params) {}

  std::array<double, 2> project(const V3& x) const {
    return {k.fx * x.x() / x.z() + k.cx, k.fy * x.y() / x.z() + k.cy};
  }

  // Detection + verification over `windows`; candidates in log form, plus the model's view of the
  // verified ones (index map from model candidate to log candidate).
  void detect_and_verify(const std::vector<detail::SearchWindow>& windows, FrameLog& log,
                         std::vector<detail::ModelCandidate>& mc, std::vector<int>& mc_to_log,
                         const std::vector<detail::Match>& seeds = {},
                         const std::vector<AxisPrior>& priors = {}) {
    auto t0 = Clock::now();
    auto matches = det.detect(windows);
    log.matches += static_cast<int>(matches.size());
    // Predicted tips are verified too, after the NCC matches: a teat at the image border or seen at a
    // grazing angle can correlate poorly and still fit a tip well where the track says it is.
    matches.insert(matches.end(), seeds.begin(), seeds.end());
    log.times.detect_us += us_since(t0);
    t0 = Clock::now();
    for (const auto& m : matches) {
      // A match on a tip already verified this frame (an NCC peak and the track's seed, or two
      // templates) would only repeat its fit.
      bool seen = false;
      for (const auto& o : mc) seen |= std::hypot(o.u - m.u, o.v - m.v) < kSameTipPx;
      if (seen) continue;
      Candidate c;
      c.u = m.u;
      c.v = m.v;
      c.ncc = m.score;
      c.template_index = m.template_index;
      // A match inside a tracked teat's window is fitted with that teat's axis as a prior: at 0.5 m a tip
      // is a few pixels wide and its axis alone is poorly determined.
      detail::TipPrior prior;
      double best = INFINITY;
      for (const auto& a : priors) {
        const double d = std::hypot(m.u - a.u, m.v - a.v);
        if (d <= a.reach_px && d < best) best = d, prior.axis = a.axis;
      }
      const auto fit = detail::fit_tip(pf, k, m.u, m.v, det.bank()[m.template_index].radius_px, p, prior);
      if (fit.ok) {
        c.tip_mm = fit.tip;
        c.axis = fit.axis;
        c.radius_mm = fit.radius;
        c.fit_rms_mm = fit.rms;
        c.points = fit.points;
        // The residual a good fit may have grows with the frame's noise (a 3x3 median leaves about a third
        // of the pixel noise).
        const double rms_max = std::max(p.fit_rms_mm, 0.6 * pf.noise_mm);
        c.verified =
            fit.radius >= p.r_min_mm && fit.radius <= p.r_max_mm && fit.rms <= rms_max && fit.tip[2] > 0;
      }
      if (c.verified) {
        const V3 tip(c.tip_mm[0], c.tip_mm[1], c.tip_mm[2]);
        for (const auto& o : mc)
          if ((o.tip - tip).norm() < kSameTipMm) c.verified = false;  // a stronger match found it first
      }
      if (c.verified) {
        detail::ModelCandidate x;
        x.tip = V3(c.tip_mm[0], c.tip_mm[1], c.tip_mm[2]);
        const auto px = project(x.tip);
        x.u = px[0];
        x.v = px[1];
        x.ncc = c.ncc;
        x.radius = c.radius_mm;
        x.axis = V3(c.axis[0], c.axis[1], c.axis[2]);
        mc.push_back(x);
        mc_to_log.push_back(static_cast<int>(log.candidates.size()));
        ++log.verified;
      }
      log.candidates.push_back(c);
    }
    log.times.verify_us += us_since(t0);
  }

  // Kalman prediction of every tracked teat and its search window (gate plus the tip's size), the
  // prediction itself as a verification seed, and the teat's axis as a prior for fits in its window.
  void predict_windows(double dt, std::array<std::optional<V3>, 4>& pred,
                       std::vector<detail::SearchWindow>& windows, std::vector<detail::Match>& seeds,
                       std::vector<AxisPrior>& priors) {
    for (int t = 0; t < 4; ++t) {
      if (!teats[t].tracked) continue;
      teats[t].kf.predict(dt, p.kalman_q);
      const V3 x = teats[t].kf.position();
      if (x.z() <= 1) continue;
      pred[t] = x;
      const auto px = project(x);
      const double rad_px = k.fx * std::max(model.radius[t], p.r_min_mm) / x.z();
      const int half = static_cast<int>(std::ceil(k.fx * p.d_gate_mm / x.z() + 1.5 * rad_px)) + 1;
      detail::SearchWindow w{std::max(0, static_cast<int>(px[0]) - half),
                             std::max(0, static_cast<int>(px[1]) - half),
                             std::min(k.width, static_cast<int>(px[0]) + half + 1),
                             std::min(k.height, static_cast<int>(px[1]) + half + 1),
                             det.templates_near(rad_px),
                             kTrackWindowNcc};
      if (w.u1 <= w.u0 || w.v1 <= w.v0) continue;
      seeds.push_back({px[0], px[1], 0.0, w.templates.front()});  // score once the frame is prepared
      if (teats[t].axis.squaredNorm() > 0.5)
        priors.push_back(
            {px[0], px[1], double(half), {teats[t].axis.x(), teats[t].axis.y(), teats[t].axis.z()}});
      windows.push_back(w);
    }
  }

  // A window's pixels plus what its correlation kernels and tip fits reach beyond it.
  cv::Rect grow(const detail::SearchWindow& w) const {
    int margin = 2;
    for (int ti : w.templates)
      margin = std::max(margin, det.bank()[ti].kernel.rows * det.bank()[ti].scale / 2 + 2);
    return {w.u0 - margin, w.v0 - margin, w.u1 - w.u0 + 2 * margin, w.v1 - w.v0 + 2 * margin};
  }

  void prepare(const std::vector<cv::Rect>* rois) {
    detail::prepare_frame(*current, k.width, k.height, p, pf, rois);
    det.set_frame(pf);
    partial = rois != nullptr;
  }

  struct Probe {
    FrameLog log;
    std::vector<detail::ModelCandidate> mc;
    std::vector<int> to_log;
  };
  Probe probe_whole_frame() {
    Probe pr;
    if (partial) {
      const auto t0 = Clock::now();
      prepare(nullptr);
      pr.log.times.preprocess_us = us_since(t0);
    }
    detect_and_verify(whole_frame(), pr.log, pr.mc, pr.to_log);
    return pr;
  }
  // Replaces this frame's candidates by a whole-frame probe's (their times and counts included).
  void adopt(FrameLog& log, Probe& pr, std::vector<detail::ModelCandidate>& mc, std::vector<int>& mc_to_log) {
    const int base = static_cast<int>(log.candidates.size());
    log.candidates.insert(log.candidates.end(), pr.log.candidates.begin(), pr.log.candidates.end());
    log.matches += pr.log.matches;
    log.verified += pr.log.verified;
    log.times.preprocess_us += pr.log.times.preprocess_us;
    log.times.detect_us += pr.log.times.detect_us;
    log.times.verify_us += pr.log.times.verify_us;
    mc = std::move(pr.mc);
    mc_to_log.clear();
    for (int i : pr.to_log) mc_to_log.push_back(base + i);
  }
  bool all_placed() const {
    for (int t = 0; t < 4; ++t) {
      if (teats[t].tracked) continue;
      return false;
    }
    return true;
  }

  std::vector<detail::SearchWindow> whole_frame() const {
    detail::SearchWindow w{0, 0, k.width, k.height, {}};
    for (int i = 0; i < static_cast<int>(det.bank().size()); ++i) w.templates.push_back(i);
    return {w};
  }

  // Starts tracks from an acquisition; velocities from the previous acquisition frame when consistent.
  void start_tracking(const std::vector<detail::ModelCandidate>& mc, const detail::Labelling& l, double dt) {
    for (int t = 0; t < 4; ++t) {
      if (l[t] < 0) continue;
      V3 vel = V3::Zero();
      if (t < static_cast<int>(pending_tips.size()) && pending_tips[t].allFinite() && dt > 0)
        vel = (mc[l[t]].tip - pending_tips[t]) / dt;
      teats[t].tracked = true;
      teats[t].kf.init(mc[l[t]].tip, vel, p.kalman_r_mm, 200.0);
      teats[t].missed = 0;
      teats[t].axis = mc[l[t]].axis;
    }
    state = State::track;
    ever_tracked = true;
    bad = 0;
  }

  void learn_axis(int t, const detail::ModelCandidate& c) {
    V3& a = teats[t].axis;
    a = a.squaredNorm() > 0.5 ? V3((a + kAxisRate * (c.axis - a)).normalized()) : c.axis;
  }

  // A teat whose prediction went wrong while it was hidden (its offsets are from another viewpoint)
  // never meets its gate again. An unassigned verified candidate whose distances to the matched teats
  // are the learnt model's is that teat: take it and restart its track there.
  void rescue_by_model(const std::vector<detail::ModelCandidate>& mc, detail::Labelling& l) {
    for (int t = 0; t < 4; ++t) {
      if (l[t] >= 0) continue;
      int best = -1;
      double best_err = kRescueMm;
      for (int j = 0; j < static_cast<int>(mc.size()); ++j) {
        if (labelled(l, j) || !model.radius_fits(t, mc[j].radius, p)) continue;
        double worst = 0;
        int pairs = 0;
        for (int i = 0; i < 6; ++i) {
          const auto [a, b] = kTeatPairs[i];
          const int other = a == t ? b : b == t ? a : -1;
          if (other < 0 || l[other] < 0 || !std::isfinite(model.dist[i])) continue;
          worst = std::max(worst, std::fabs((mc[j].tip - mc[l[other]].tip).norm() - model.dist[i]));
          ++pairs;
        }
        if (pairs >= 2 && worst < best_err) best_err = worst, best = j;
      }
      if (best < 0) continue;
      l[t] = best;
      teats[t].tracked = true;
      teats[t].kf.init(mc[best].tip, V3::Zero(), p.kalman_r_mm, 200.0);
      teats[t].axis = mc[best].axis;
    }
  }

  // A teat's learnt radius gates its candidates (radius_tol_mm), so a radius learnt wrong (a first fit
  // clamped at r_max, a tip first seen from the side) would shut the teat out for good: every later fit
  // of it is refused, and only accepted fits teach the model. A verified candidate close to the prediction
  // of a teat left unmatched is evidence of its radius all the same; the model follows it at the model's
  // rate, so one stray fit moves it little and a run of them re-admits the teat within a few frames.
  void relearn_radius(const std::vector<detail::ModelCandidate>& mc, const detail::Labelling& l,
                      const std::array<std::optional<V3>, 4>& pred) {
    for (int t = 0; t < 4; ++t) {
      if (l[t] >= 0 || !pred[t] || !(model.radius[t] > 0)) continue;
      int best = -1;
      double best_d = kRadiusEvidenceGate * p.d_gate_mm;
      for (int j = 0; j < static_cast<int>(mc.size()); ++j) {
        const double d = (mc[j].tip - *pred[t]).norm();
        if (!labelled(l, j) && d < best_d) best_d = d, best = j;
      }
      if (best >= 0) model.radius[t] += kModelRate * (mc[best].radius - model.radius[t]);
    }
  }

  // Re-acquisition from two teats, in LOST only. A swaying udder takes teats out of the view for dozens of
  // frames, and a labelling by the model's pair distances needs three teats (two candidates fit any pair
  // of equal length, either way round). The learnt offsets are vectors, and two candidates whose
  // difference is one teat pair's offset, with both radii that pair's, are that pair; taken only when no
  // other pair or order comes within kPairUnique times its error (so, alone, within kRescueMm / kPairUnique),
  // and like every acquisition only once confirmed by the next frame (n_confirm).
  std::optional<detail::Labelling> acquire_pair(const std::vector<detail::ModelCandidate>& mc) const {
    const int n = static_cast<int>(mc.size());
    double best = kRescueMm, second = INFINITY;
    detail::Labelling out{-1, -1, -1, -1};
    // Both radii must be learnt: two teats are too few to name without them.
    const auto radius_ok = [&](int t, int j) {
      return model.radius[t] > 0 && model.radius_fits(t, mc[j].radius, p);
    };
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        if (!rel_known[a][b]) continue;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            if (i == j || !radius_ok(a, i) || !radius_ok(b, j)) continue;
            const double e = ((mc[i].tip - mc[j].tip) - rel[a][b]).norm();
            if (e < best) {
              second = best;
              best = e;
              out = {-1, -1, -1, -1};
              out[a] = i;
              out[b] = j;
            } else if (e < second) {
              second = e;
            }
          }
      }
    // best < kRescueMm exactly when a pair was found (it starts there).
    if (!(best < kRescueMm) || second < kPairUnique * best) return std::nullopt;
    return out;
  }

  // Learns where each teat sits relative to each other (camera frame), from frames that see both.
  void learn_offsets(const std::vector<detail::ModelCandidate>& mc, const detail::Labelling& l) {
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        if (a == b || l[a] < 0 || l[b] < 0) continue;
        const V3 d = mc[l[a]].tip - mc[l[b]].tip;
        rel[a][b] = rel_known[a][b] ? V3(rel[a][b] + kOffsetRate * (d - rel[a][b])) : d;
        rel_known[a][b] = true;
      }
  }

  // An unseen teat moves with the udder: place it by its learnt offsets from the teats seen this frame,
  // with their mean velocity (extrapolating its own velocity would let it drift away while occluded).
  void carry_unmatched(const std::vector<detail::ModelCandidate>& mc, const detail::Labelling& l) {
    V3 vel = V3::Zero();
    int nv = 0;
    for (int t = 0; t < 4; ++t)
      if (l[t] >= 0) vel += teats[t].kf.velocity(), ++nv;
    if (nv) vel /= nv;
    for (int t = 0; t < 4; ++t) {
      if (l[t] >= 0) continue;
      V3 sum = V3::Zero();
      int n = 0;
      for (int j = 0; j < 4; ++j)
        if (l[j] >= 0 && rel_known[t][j]) sum += mc[l[j]].tip + rel[t][j], ++n;
      if (n == 0) continue;
      teats[t].tracked = true;
      teats[t].kf.init(sum / n, vel, kCarriedSd, 200.0);
    }
  }

  FrameLog process(const tof::DepthFrame& frame) {
    const std::size_t n = static_cast<std::size_t>(k.width) * k.height;
    if (frame.depth_mm.size() != n)
      throw invalid_argument("frame", "frame " + std::to_string(frame_no) + " has " +
                                          std::to_string(frame.depth_mm.size()) + " depth values, expected " +
                                          std::to_string(n) + " (" + std::to_string(k.width) + "x" +
                                          std::to_string(k.height) + ")");
    FrameLog log;
    log.index = frame_no;
    log.timestamp_s = frame.timestamp_s;
    double dt = frame_no == 0 ? 0.0 : frame.timestamp_s - last_t;
    if (!(dt > 0)) dt = 0.04;
    last_t = frame.timestamp_s;
    ++frame_no;

    // In TRACK, predict first: only the windows around the predictions are prepared and searched.
    std::array<std::optional<V3>, 4> pred;
    std::vector<detail::SearchWindow> windows;
    std::vector<detail::Match> seeds;
    std::vector<AxisPrior> priors;
    if (state == State::track) predict_windows(dt, pred, windows, seeds, priors);

    auto t0 = Clock::now();
    current = &frame;
    std::vector<cv::Rect> rois;
    for (const auto& w : windows) rois.push_back(grow(w));
    prepare(state == State::track ? &rois : nullptr);
    log.valid_pixels = pf.valid;
    log.flying_pixels = pf.flying;
    log.times.preprocess_us = us_since(t0);
    if (state == State::track)
      for (auto& sd : seeds) sd.score = det.score_at(sd.u, sd.v, sd.template_index);

    std::vector<detail::ModelCandidate> mc;
    std::vector<int> mc_to_log;
    detail::Labelling label{-1, -1, -1, -1};
    bool tracked_ok = false;

    if (state == State::track) {
      detect_and_verify(windows, log, mc, mc_to_log, seeds, priors);
      t0 = Clock::now();
      label = detail::assign_tracked(mc, pred, model, p);
      relearn_radius(mc, label, pred);
      log.model = detail::model_metrics(mc, label, model, p);
      tracked_ok = log.model.teats_matched >= p.min_teats && log.model.cost <= p.model_max;
      // One teat matched close to its prediction also holds the track (below min_teats): when an arm, a
      // cup or the image border hides three teats, the fourth is still where the track says it is.
      if (!tracked_ok && log.model.teats_matched == 1)
        for (int t = 0; t < 4; ++t)
          if (label[t] >= 0 && pred[t] &&
              (mc[label[t]].tip - *pred[t]).norm() <= kSingleTeatGate * p.d_gate_mm)
            tracked_ok = log.model.cost <= p.model_max;
      log.times.model_us += us_since(t0);
      if (!tracked_ok) {
        // A jump (a sudden move, a step) can leave every window empty: look at the whole frame for the
        // learnt udder before counting the frame as bad.
        Probe probe = probe_whole_frame();
        t0 = Clock::now();
        const auto again = detail::acquire(probe.mc, model, p, std::max(3, p.min_teats));
        if (again) {
          adopt(log, probe, mc, mc_to_log);
          label = *again;
          log.model = detail::model_metrics(mc, label, model, p);
          for (int t = 0; t < 4; ++t)
            if (label[t] >= 0)
              teats[t].kf.init(mc[label[t]].tip, V3::Zero(), p.kalman_r_mm, 200.0), teats[t].tracked = true;
          tracked_ok = true;
        } else {
          log.times.preprocess_us += probe.log.times.preprocess_us;
          log.times.detect_us += probe.log.times.detect_us;
          log.times.verify_us += probe.log.times.verify_us;
        }
        log.times.model_us += us_since(t0);
      } else if (!all_placed()) {
        // A teat that was hidden when tracking started has no track and no learnt offset: look for the
        // whole udder, and take the missing teat from a labelling that agrees with every tracked one.
        Probe probe = probe_whole_frame();
        t0 = Clock::now();
        const auto full = detail::acquire(probe.mc, model, p, 4);
        bool agrees = full.has_value();
        for (int t = 0; t < 4 && agrees; ++t)
          if (label[t] >= 0) agrees = (probe.mc[(*full)[t]].tip - mc[label[t]].tip).norm() < kSameTipMm;
        log.times.preprocess_us += probe.log.times.preprocess_us;
        log.times.detect_us += probe.log.times.detect_us;
        log.times.verify_us += probe.log.times.verify_us;
        if (agrees) {
          const int base = static_cast<int>(mc.size());
          for (int t = 0; t < 4; ++t) {
            if (label[t] >= 0) continue;
            mc.push_back(probe.mc[(*full)[t]]);
            mc_to_log.push_back(static_cast<int>(log.candidates.size()));
            log.candidates.push_back(probe.log.candidates[probe.to_log[(*full)[t]]]);
            ++log.verified;
            label[t] = static_cast<int>(mc.size()) - 1;
            teats[t].tracked = true;
            teats[t].kf.init(mc[label[t]].tip, V3::Zero(), p.kalman_r_mm, 200.0);
            teats[t].axis = mc[label[t]].axis;
          }
          (void)base;
          log.model = detail::model_metrics(mc, label, model, p);
        }
        log.times.model_us += us_since(t0);
      }
      t0 = Clock::now();
      if (tracked_ok) {
        rescue_by_model(mc, label);
        log.model = detail::model_metrics(mc, label, model, p);
        bad = 0;
        for (int t = 0; t < 4; ++t) {
          if (label[t] < 0) continue;
          teats[t].kf.update(mc[label[t]].tip, p.kalman_r_mm);
          teats[t].missed = 0;
          learn_axis(t, mc[label[t]]);
        }
        carry_unmatched(mc, label);
        learn_offsets(mc, label);
        detail::learn(model, mc, label, kModelRate);
      } else {
        if (++bad >= p.n_lost) {
          state = State::lost;
          confirm = 0;
          pending.reset();
        }
        label = {-1, -1, -1, -1};  // a rejected frame reports no teat as seen
        log.model.teats_matched = 0;
      }
      log.times.model_us += us_since(t0);
    } else {
      detect_and_verify(whole_frame(), log, mc, mc_to_log);
      t0 = Clock::now();
      // The first acquisition labels the teats by their layout alone, which three teats leave ambiguous
      // (a triangle fits the quadrilateral four ways): it waits for all four. Later ones have the learnt
      // model's distances to go by.
      auto acq = detail::acquire(mc, model, p, model.knows_shape() ? std::max(3, p.min_teats) : 4);
      if (!acq && state == State::lost && p.min_teats <= 2) acq = acquire_pair(mc);
      if (acq) {
        label = *acq;
        log.model = detail::model_metrics(mc, label, model, p);
        // Consistent with the previous frame's acquisition: every common teat within the gate.
        bool consistent = pending.has_value();
        for (int t = 0; t < 4 && consistent; ++t)
          if (label[t] >= 0 && pending_tips[t].allFinite())
            consistent = (mc[label[t]].tip - pending_tips[t]).norm() <= p.d_gate_mm;
        confirm = consistent ? confirm + 1 : 1;
        if (confirm >= p.n_confirm) {
          start_tracking(mc, label, dt);
          learn_offsets(mc, label);
          carry_unmatched(mc, label);
          detail::learn(model, mc, label, model.knows_shape() ? kModelRate : 1.0);
        }
        pending = label;
        pending_tips.assign(4, V3::Constant(std::numeric_limits<double>::quiet_NaN()));
        for (int t = 0; t < 4; ++t)
          if (label[t] >= 0) pending_tips[t] = mc[label[t]].tip;
      } else {
        confirm = 0;
        pending.reset();
      }
      log.times.model_us += us_since(t0);
    }

    // Report.
    for (int i = 0; i < static_cast<int>(mc_to_log.size()); ++i)
      for (int t = 0; t < 4; ++t)
        if (label[t] == i) log.candidates[mc_to_log[i]].teat = t;
    log.state = state;
    for (int t = 0; t < 4; ++t) {
      TeatEstimate& e = log.teats[t];
      e.radius_mm = model.radius[t];
      if (label[t] >= 0) {
        const auto& c = log.candidates[mc_to_log[label[t]]];
        const V3 x = state == State::track && teats[t].tracked ? teats[t].kf.position() : mc[label[t]].tip;
        e.tip_mm = {x.x(), x.y(), x.z()};
        e.visible = true;
        e.tracked = true;
        e.confidence = std::clamp(c.ncc, 0.0, 1.0) * std::exp(-c.fit_rms_mm / p.fit_rms_mm);
        teats[t].confidence = e.confidence;
      } else if (state == State::track && teats[t].tracked) {
        const V3 x = teats[t].kf.position();
        e.tip_mm = {x.x(), x.y(), x.z()};
        e.tracked = true;
        teats[t].confidence *= kConfidenceDecay;
        ++teats[t].missed;
        e.confidence = teats[t].confidence;
      }
      if (e.tracked && e.tip_mm[2] > 0) e.tip_px = project(V3(e.tip_mm[0], e.tip_mm[1], e.tip_mm[2]));
    }
    if (state != State::track)
      for (auto& t : teats) t.tracked = false;
    return log;
  }
};

Tracker::Tracker(const TrackerParams& params, const tof::Intrinsics& intrinsics) {
  validate(params);
  if (intrinsics.width < 1 || intrinsics.height < 1 || !(intrinsics.fx > 0) || !(intrinsics.fy > 0) ||
      !std::isfinite(intrinsics.cx) || !std::isfinite(intrinsics.cy))
    throw invalid_argument("intrinsics", "tracker needs positive focal lengths and image size");
  impl_ = std::make_unique<Impl>(params, intrinsics);
}
Tracker::~Tracker() = default;
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

FrameLog Tracker::process(const tof::DepthFrame& frame) {
  return impl_->process(frame);
}

void Tracker::reset() {
  auto params = impl_->p;
  auto k = impl_->k;
  impl_ = std::make_unique<Impl>(params, k);
}

const TrackerParams& Tracker::params() const {
  return impl_->p;
}

std::vector<Tracker::TemplateInfo> Tracker::templates() const {
  std::vector<TemplateInfo> out;
  for (const auto& t : impl_->det.bank()) out.push_back({t.radius_px, t.kernel.rows * t.scale});
  return out;
}

}  // namespace trailscope::tracker
