// Selection from a gaze dataset, event lists and scanpaths (query.hpp).
#include "trailscope/gaze/query.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::gaze {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + ("'" + n + "'");
  return out.empty() ? "none" : out;
}

bool in_window(const Recording& r, double t_ms, const GazeFilter& f) {
  const double rel = t_ms - r.t_ms.front();
  return rel >= f.t0_ms && rel < f.t1_ms;
}

/// Calls `fn(type, first, last)` for every run of equal labels other than none (inclusive sample indices),
/// the runs label_runs() makes events of.
template <typename Fn>
void for_each_run(const std::vector<EventType>& labels, Fn&& fn) {
  for (std::size_t i = 0; i < labels.size();) {
    std::size_t j = i;
    while (j + 1 < labels.size() && labels[j + 1] == labels[i]) ++j;
    if (labels[i] != EventType::none) fn(labels[i], i, j);
    i = j + 1;
  }
}

EventRow row_of(const Recording& r, std::size_t rec, EventType type, std::size_t a, std::size_t b) {
  EventRow e;
  e.recording = rec, e.type = type;
  e.t_start_ms = r.t_ms[a], e.t_end_ms = r.t_ms[b];
  e.x = e.y = e.x_end = e.y_end = kNaN;
  if (type == EventType::fixation) {
    double sx = 0, sy = 0;
    std::size_t n = 0;
    for (std::size_t k = a; k <= b; ++k)
      if (r.valid[k]) sx += r.x[k], sy += r.y[k], ++n;
    if (n) e.x = sx / double(n), e.y = sy / double(n);
  } else if (type == EventType::saccade || type == EventType::pso) {
    std::size_t s = a, t = b;
    while (s <= b && !r.valid[s]) ++s;
    while (t > s && !r.valid[t]) --t;
    if (s <= b) e.x = r.x[s], e.y = r.y[s], e.x_end = r.x[t], e.y_end = r.y[t];
  }
  return e;
}
}  // namespace

std::vector<std::size_t> select_recordings(const GazeDataset& ds, const GazeFilter& f) {
  if (std::isnan(f.t0_ms) || f.t0_ms < 0)
    throw invalid_argument(
        "t0_ms",
        "t0_ms must be at least 0 (ms after each recording's first sample), not " + format_double(f.t0_ms));
  if (std::isnan(f.t1_ms) || !(f.t1_ms > f.t0_ms))
    throw invalid_argument("t1_ms",
                           "t1_ms must be later than t0_ms (the window is [t0_ms, t1_ms)), got t0_ms " +
                               format_double(f.t0_ms) + " and t1_ms " + format_double(f.t1_ms));
  if (f.recording && *f.recording >= ds.recordings.size())
    throw invalid_argument(
        "recording", "recording must lie in 0.." +
                         std::to_string(ds.recordings.size() ? ds.recordings.size() - 1 : 0) + ", got " +
                         std::to_string(*f.recording));
  bool participant_seen = false, stimulus_seen = false;
  for (const Recording& r : ds.recordings) {
    participant_seen |= f.participant && r.participant == *f.participant;
    stimulus_seen |= f.stimulus && r.stimulus == *f.stimulus;
  }
  if (f.participant && !participant_seen)
    throw invalid_argument("participant", "participant '" + *f.participant +
                                              "' is not in this gaze dataset (its participants: " +
                                              joined(ds.participants()) + ")");
  if (f.stimulus && !stimulus_seen)
    throw invalid_argument("stimulus",
                           "stimulus '" + *f.stimulus +
                               "' is not in this gaze dataset (its stimuli: " + joined(ds.stimuli()) + ")");
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < ds.recordings.size(); ++i) {
    const Recording& r = ds.recordings[i];
    if ((f.recording && *f.recording != i) || (f.participant && r.participant != *f.participant) ||
        (f.stimulus && r.stimulus != *f.stimulus))
      continue;
    out.push_back(i);
  }
  return out;
}

std::pair<std::size_t, std::size_t> window_samples(const Recording& r, const GazeFilter& f) {
  const std::size_t n = r.size();
  std::size_t a = 0;
  while (a < n && !(r.t_ms[a] - r.t_ms.front() >= f.t0_ms)) ++a;
  std::size_t b = a;
  while (b < n && r.t_ms[b] - r.t_ms.front() < f.t1_ms) ++b;
  return {a, b};
}

EventType parse_event_type(std::string_view text, const std::string& param) {
  for (EventType t : {EventType::fixation, EventType::saccade, EventType::pso, EventType::pursuit,
                      EventType::blink, EventType::undefined})
    if (text == to_string(t)) return t;
  throw invalid_argument(param, param +
                                    " must be fixation, saccade, pso, pursuit, blink or undefined, got '" +
                                    std::string(text) + "'");
}

EventList list_events(const GazeDataset& ds, const GazeFilter& f, const EventParams& p,
                      const std::vector<EventType>& types, std::size_t max_events) {
  validate(p);
  const std::vector<std::size_t> sel = select_recordings(ds, f);
  std::array<bool, 7> wanted{};
  for (EventType t : types) wanted[std::size_t(t)] = true;
  if (types.empty()) wanted.fill(true), wanted[0] = false;
  // Detect first and count, so that an answer over the limit builds no row.
  std::vector<Detection> found;
  found.reserve(sel.size());
  std::size_t total = 0;
  for (std::size_t i : sel) {
    const Recording& r = ds.recordings[i];
    found.push_back(detect_events(r, p));
    if (r.size() == 0) continue;
    for_each_run(found.back().labels, [&](EventType t, std::size_t a, std::size_t) {
      if (wanted[std::size_t(t)] && in_window(r, r.t_ms[a], f)) ++total;
    });
  }
  if (total > max_events)
    throw Error(Error::Kind::payload_too_large, "events",
                "the selection holds " + std::to_string(total) + " events, more than the limit of " +
                    std::to_string(max_events) +
                    "; narrow it with participant, stimulus, recording, t0_ms/t1_ms or type");
  EventList out;
  out.events.reserve(total);
  for (std::size_t k = 0; k < sel.size(); ++k) {
    const Recording& r = ds.recordings[sel[k]];
    if (r.size() == 0) continue;
    for_each_run(found[k].labels, [&](EventType t, std::size_t a, std::size_t b) {
      if (!wanted[std::size_t(t)] || !in_window(r, r.t_ms[a], f)) return;
      out.events.push_back(row_of(r, sel[k], t, a, b));
      ++out.counts[std::size_t(t)];
    });
  }
  return out;
}

std::vector<Scanpath> scanpaths(const GazeDataset& ds, const GazeFilter& f, const EventParams& p,
                                std::size_t max_fixations) {
  const EventList ev = list_events(ds, f, p, {EventType::fixation}, max_fixations);
  std::vector<Scanpath> out;
  std::size_t next = 0;
  for (std::size_t i : select_recordings(ds, f)) {
    Scanpath s;
    s.recording = i;
    s.participant = ds.recordings[i].participant;
    s.stimulus = ds.recordings[i].stimulus;
    for (; next < ev.events.size() && ev.events[next].recording == i; ++next) {
      const EventRow& e = ev.events[next];
      s.fixations.push_back({e.x, e.y, e.t_start_ms, e.t_end_ms - e.t_start_ms});
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace trailscope::gaze
