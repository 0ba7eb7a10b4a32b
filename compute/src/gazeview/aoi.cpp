// AOI measures (aoi.hpp).
#include "trailscope/gazeview/aoi.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <opencv2/imgproc.hpp>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::gazeview {

Aoi Aoi::rect(std::string name, double x0, double y0, double x1, double y1) {
  Aoi a;
  a.name = std::move(name);
  a.is_rect = true;
  a.x0 = x0, a.y0 = y0, a.x1 = x1, a.y1 = y1;
  return a;
}

Aoi Aoi::polygon(std::string name, std::vector<double> xs, std::vector<double> ys) {
  Aoi a;
  a.name = std::move(name);
  a.is_rect = false;
  a.xs = std::move(xs), a.ys = std::move(ys);
  return a;
}

namespace {
/// An AOI ready for many tests: a polygon's contour in the float points cv::pointPolygonTest takes
/// (stimulus coordinates of a few thousand px keep their sub-pixel detail in float) and its bounding box,
/// which rejects most fixations before the contour is walked.
struct Prepared {
  const Aoi* aoi;
  std::vector<cv::Point2f> contour;
  double bx0 = 0, by0 = 0, bx1 = 0, by1 = 0;
  explicit Prepared(const Aoi& a) : aoi(&a) {
    if (a.is_rect) {
      bx0 = a.x0, by0 = a.y0, bx1 = a.x1, by1 = a.y1;
      return;
    }
    contour.resize(a.xs.size());
    bx0 = bx1 = a.xs[0], by0 = by1 = a.ys[0];
    for (std::size_t i = 0; i < a.xs.size(); ++i) {
      contour[i] = {float(a.xs[i]), float(a.ys[i])};
      bx0 = std::min(bx0, a.xs[i]), bx1 = std::max(bx1, a.xs[i]);
      by0 = std::min(by0, a.ys[i]), by1 = std::max(by1, a.ys[i]);
    }
  }
  bool contains(double x, double y) const {
    if (!(x >= bx0 && x <= bx1 && y >= by0 && y <= by1)) return false;
    if (aoi->is_rect) return true;
    return cv::pointPolygonTest(contour, cv::Point2f(float(x), float(y)), false) >= 0;
  }
};
}  // namespace

bool Aoi::contains(double x, double y) const {
  return Prepared(*this).contains(x, y);
}

void validate_aois(const std::vector<Aoi>& aois) {
  if (aois.empty()) throw invalid_argument("aois", "give at least one AOI");
  if (aois.size() > limits::kMaxGazeAois)
    throw invalid_argument(
        "aois", std::to_string(aois.size()) + " AOIs; at most " + std::to_string(limits::kMaxGazeAois));
  std::set<std::string> names;
  std::size_t vertices = 0;
  const std::string beyond = " is beyond +-" + std::to_string(std::int64_t(limits::kMaxAoiCoordinatePx)) +
                             " px (kMaxAoiCoordinatePx)";
  for (std::size_t i = 0; i < aois.size(); ++i) {
    const Aoi& a = aois[i];
    const std::string which = "AOI " + std::to_string(i) + (a.name.empty() ? "" : " (" + a.name + ")");
    vertices += a.is_rect ? 4 : a.xs.size();
    if (vertices > limits::kMaxAoiVertices)
      throw invalid_argument("aois", "the AOIs have more than " + std::to_string(limits::kMaxAoiVertices) +
                                         " vertices together (a rectangle counts 4), reached at " + which);
    if (a.name.empty()) throw invalid_argument("aois", which + " has no name");
    if (a.name.size() > 200) throw invalid_argument("aois", which + ": name longer than 200 bytes");
    if (!names.insert(a.name).second) throw invalid_argument("aois", which + ": name used twice");
    if (a.is_rect) {
      for (double v : {a.x0, a.y0, a.x1, a.y1}) {
        if (!std::isfinite(v)) throw invalid_argument("aois", which + ": a corner is not a finite number");
        if (std::abs(v) > limits::kMaxAoiCoordinatePx)
          throw invalid_argument("aois", which + ": a corner" + beyond);
      }
      if (!(a.x0 < a.x1) || !(a.y0 < a.y1))
        throw invalid_argument("aois", which + ": a rectangle needs x0 < x1 and y0 < y1");
    } else {
      if (a.xs.size() != a.ys.size())
        throw invalid_argument("aois", which + ": polygon x and y counts differ");
      if (a.xs.size() < 3)
        throw invalid_argument(
            "aois", which + ": a polygon needs at least 3 vertices, not " + std::to_string(a.xs.size()));
      for (std::size_t k = 0; k < a.xs.size(); ++k) {
        if (!std::isfinite(a.xs[k]) || !std::isfinite(a.ys[k]))
          throw invalid_argument("aois", which + ": vertex " + std::to_string(k) + " is not finite");
        if (std::abs(a.xs[k]) > limits::kMaxAoiCoordinatePx ||
            std::abs(a.ys[k]) > limits::kMaxAoiCoordinatePx)
          throw invalid_argument("aois", which + ": vertex " + std::to_string(k) + beyond);
      }
    }
  }
}

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
}  // namespace

AoiReport aoi_statistics(const std::vector<Aoi>& aois, const std::vector<Fixation>& fixations) {
  validate_aois(aois);
  const std::size_t m = aois.size();
  AoiReport out;
  out.fixations = fixations.size();
  out.aois.resize(m);
  out.transitions.assign(m, std::vector<std::uint64_t>(m, 0));
  for (std::size_t a = 0; a < m; ++a) out.aois[a].name = aois[a].name;
  std::vector<Prepared> prepared;
  for (const Aoi& a : aois) prepared.emplace_back(a);
  std::vector<std::vector<double>> first(m);  // per AOI, first-fixation onset of each visiting recording
  std::vector<double> first_here(m);          // of the current recording, NaN until visited
  std::size_t prev_aoi = m;                   // m: none yet in this recording
  for (std::size_t i = 0; i < fixations.size(); ++i) {
    const Fixation& f = fixations[i];
    if (i == 0 || f.recording != fixations[i - 1].recording) {
      std::fill(first_here.begin(), first_here.end(), std::nan(""));
      prev_aoi = m;
    }
    std::size_t hit = m;
    for (std::size_t a = 0; a < m && hit == m; ++a)
      if (prepared[a].contains(f.x, f.y)) hit = a;
    if (hit == m) {
      ++out.outside;
      continue;
    }
    AoiStats& s = out.aois[hit];
    ++s.fixations;
    s.dwell_ms += f.duration_ms;
    if (std::isnan(first_here[hit])) {
      first_here[hit] = f.onset_ms;
      first[hit].push_back(f.onset_ms);
      ++s.visitors;
    }
    if (prev_aoi != m) ++out.transitions[prev_aoi][hit];
    prev_aoi = hit;
  }
  for (std::size_t a = 0; a < m; ++a) {
    AoiStats& s = out.aois[a];
    if (s.fixations) s.mean_fixation_ms = s.dwell_ms / double(s.fixations);
    if (!first[a].empty()) {
      s.first_fixation_min_ms = *std::min_element(first[a].begin(), first[a].end());
      s.first_fixation_median_ms = median(first[a]);
    }
  }
  return out;
}

std::vector<Aoi> aois_from_json(const nlohmann::json& j) {
  if (!j.is_array()) throw invalid_argument("aois", "aois must be an array of {name, rect | polygon}");
  if (j.size() > limits::kMaxGazeAois)
    throw invalid_argument(
        "aois", std::to_string(j.size()) + " AOIs; at most " + std::to_string(limits::kMaxGazeAois));
  std::vector<Aoi> out;
  std::size_t vertices = 0;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const nlohmann::json& e = j[i];
    std::string which = "AOI " + std::to_string(i);
    if (!e.is_object()) throw invalid_argument("aois", which + " is not an object");
    if (!e.contains("name") || !e["name"].is_string())
      throw invalid_argument("aois", which + " needs a string name");
    const std::string name = e["name"].get<std::string>();
    which += " (" + name + ")";
    for (const auto& [k, v] : e.items())
      if (k != "name" && k != "rect" && k != "polygon")
        throw invalid_argument("aois", which + ": unknown key '" + k + "' (name, rect, polygon)");
    const bool r = e.contains("rect"), p = e.contains("polygon");
    if (r == p) throw invalid_argument("aois", which + ": give either rect or polygon");
    auto number = [&](const nlohmann::json& v, const char* what) {
      if (!v.is_number()) throw invalid_argument("aois", which + ": " + what + " must be numbers");
      return v.get<double>();
    };
    if (r) {
      const nlohmann::json& a = e["rect"];
      if (!a.is_array() || a.size() != 4)
        throw invalid_argument("aois", which + ": rect must be [x0, y0, x1, y1]");
      vertices += 4;
      out.push_back(Aoi::rect(name, number(a[0], "rect"), number(a[1], "rect"), number(a[2], "rect"),
                              number(a[3], "rect")));
    } else {
      const nlohmann::json& a = e["polygon"];
      if (!a.is_array()) throw invalid_argument("aois", which + ": polygon must be [[x, y], ...]");
      vertices += a.size();
      if (vertices > limits::kMaxAoiVertices)  // before the vertices are read
        throw invalid_argument("aois", "the AOIs have more than " + std::to_string(limits::kMaxAoiVertices) +
                                           " vertices together (a rectangle counts 4), reached at " + which);
      std::vector<double> xs, ys;
      for (const auto& v : a) {
        if (!v.is_array() || v.size() != 2)
          throw invalid_argument("aois", which + ": polygon must be [[x, y], ...]");
        xs.push_back(number(v[0], "polygon vertices")), ys.push_back(number(v[1], "polygon vertices"));
      }
      out.push_back(Aoi::polygon(name, std::move(xs), std::move(ys)));
    }
  }
  validate_aois(out);
  return out;
}

nlohmann::json to_json(const AoiReport& r, std::size_t recordings) {
  nlohmann::json aois = nlohmann::json::array(), names = nlohmann::json::array();
  for (const AoiStats& s : r.aois) {
    aois.push_back({{"name", s.name},
                    {"fixations", s.fixations},
                    {"dwell_ms", s.dwell_ms},
                    {"visitors", s.visitors},
                    {"first_fixation_ms",
                     {{"median", number_or_null(s.first_fixation_median_ms)},
                      {"min", number_or_null(s.first_fixation_min_ms)}}},
                    {"mean_fixation_ms", number_or_null(s.mean_fixation_ms)}});
    names.push_back(s.name);
  }
  return {{"aois", aois},
          {"transitions", {{"names", names}, {"counts", r.transitions}}},
          {"recordings", recordings},
          {"fixations", r.fixations},
          {"outside", r.outside}};
}

}  // namespace trailscope::gazeview
