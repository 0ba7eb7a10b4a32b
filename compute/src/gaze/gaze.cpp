// The gaze dataset model (gaze.hpp): geometry, degrees of visual angle, dataset summaries.
#include "trailscope/gaze/gaze.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "trailscope/core/error.hpp"

namespace trailscope::gaze {

ScreenGeometry ScreenGeometry::overridden_by(const ScreenGeometry& given) const noexcept {
  ScreenGeometry g = *this;
  if (given.width_px > 0) g.width_px = given.width_px;
  if (given.height_px > 0) g.height_px = given.height_px;
  if (given.width_cm > 0) g.width_cm = given.width_cm;
  if (given.height_cm > 0) g.height_cm = given.height_cm;
  if (given.distance_cm > 0) g.distance_cm = given.distance_cm;
  return g;
}

namespace {
void require_physical(const ScreenGeometry& g) {
  if (!g.has_physical())
    throw invalid_argument("geometry",
                           "degrees of visual angle need the screen size in px and cm and the viewing "
                           "distance in cm (width_px, height_px, width_cm, height_cm, distance_cm); the "
                           "file does not give them all, so pass them");
}
double deg(double px, double size_px, double size_cm, double distance_cm) {
  return std::atan((px - size_px / 2) * size_cm / size_px / distance_cm) * 180.0 / std::numbers::pi;
}
}  // namespace

double px_to_deg_x(double x_px, const ScreenGeometry& g) {
  require_physical(g);
  return deg(x_px, g.width_px, g.width_cm, g.distance_cm);
}
double px_to_deg_y(double y_px, const ScreenGeometry& g) {
  require_physical(g);
  return deg(y_px, g.height_px, g.height_cm, g.distance_cm);
}

const char* to_string(Units u) noexcept {
  return u == Units::deg ? "deg" : "px";
}

const char* to_string(EventType t) noexcept {
  switch (t) {
    case EventType::fixation:
      return "fixation";
    case EventType::saccade:
      return "saccade";
    case EventType::pso:
      return "pso";
    case EventType::pursuit:
      return "pursuit";
    case EventType::blink:
      return "blink";
    case EventType::undefined:
      return "undefined";
    case EventType::none:
      break;
  }
  return "none";
}

std::size_t Recording::valid_count() const noexcept {
  return std::size_t(std::count(valid.begin(), valid.end(), std::uint8_t(1)));
}

void Recording::degrees(std::vector<double>& x_deg, std::vector<double>& y_deg) const {
  x_deg.assign(x.begin(), x.end());
  y_deg.assign(y.begin(), y.end());
  if (units == Units::deg) return;
  require_physical(geometry);
  for (std::size_t i = 0; i < x_deg.size(); ++i) {
    x_deg[i] = deg(x[i], geometry.width_px, geometry.width_cm, geometry.distance_cm);
    y_deg[i] = deg(y[i], geometry.height_px, geometry.height_cm, geometry.distance_cm);
  }
}

std::size_t GazeDataset::total_samples() const noexcept {
  std::size_t n = 0;
  for (const auto& r : recordings) n += r.size();
  return n;
}

std::vector<std::string> GazeDataset::participants() const {
  std::set<std::string> s;
  for (const auto& r : recordings)
    if (!r.participant.empty()) s.insert(r.participant);
  return {s.begin(), s.end()};
}

std::vector<std::string> GazeDataset::stimuli() const {
  std::set<std::string> s;
  for (const auto& r : recordings)
    if (!r.stimulus.empty()) s.insert(r.stimulus);
  return {s.begin(), s.end()};
}

}  // namespace trailscope::gaze
