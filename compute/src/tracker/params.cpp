#include "trailscope/tracker/params.hpp"

#include <cmath>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::tracker {
namespace {

// One row per parameter: its metadata and where it lives in TrackerParams. Integers are stored as int
// members; the table converts.
struct Row {
  ParamInfo info;
  double TrackerParams::*d = nullptr;
  int TrackerParams::*i = nullptr;
};

// Every parameter is numeric: the text fields say the same as the numbers.
ParamInfo numeric(std::string name, std::string unit, double def, double lo, double hi, bool integer,
                  std::string help) {
  std::string range = "[";
  append_shortest(range, lo);
  range += ", ";
  append_shortest(range, hi);
  range += ']';
  if (!unit.empty()) range += ' ' + unit;
  ParamInfo i = describe_param(std::move(name), integer ? "integer" : "number", format_double(def),
                               std::move(range), std::move(help));
  i.unit = std::move(unit), i.default_number = def, i.min = lo, i.max = hi, i.integer = integer;
  return i;
}

Row real(std::string name, std::string unit, double TrackerParams::*m, double lo, double hi,
         std::string help) {
  return {numeric(std::move(name), std::move(unit), TrackerParams{}.*m, lo, hi, false, std::move(help)), m,
          nullptr};
}
Row whole(std::string name, std::string unit, int TrackerParams::*m, double lo, double hi, std::string help) {
  return {numeric(std::move(name), std::move(unit), TrackerParams{}.*m, lo, hi, true, std::move(help)),
          nullptr, m};
}

const std::vector<Row>& rows() {
  using P = TrackerParams;
  static const std::vector<Row> r = {
      real("a_min", "", &P::a_min, 0, 10000, "amplitude below which a pixel is invalid"),
      real("z_min_mm", "mm", &P::z_min_mm, 0, 5000, "depth gate, near end"),
      real("z_max_mm", "mm", &P::z_max_mm, 1, 10000, "depth gate, far end"),
      real("flying_mm", "mm", &P::flying_mm, 1, 500, "flying pixel: farther than this from its 3x3 median"),
      whole("median_k", "px", &P::median_k, 1, 5, "median filter window on depth (1 = off, 3 or 5)"),
      whole("templates", "", &P::templates, 1, 8, "tip templates in the NCC bank"),
      real("template_min_px", "px", &P::template_min_px, 1.5, 40, "tip radius of the smallest template"),
      real("template_max_px", "px", &P::template_max_px, 1.5, 40, "tip radius of the largest template"),
      real("ncc_min", "", &P::ncc_min, 0, 1, "NCC score a match needs (inside TRACK windows at least 0.3)"),
      whole("max_candidates", "", &P::max_candidates, 1, 200, "NCC matches kept per frame, best first"),
      real("r_min_mm", "mm", &P::r_min_mm, 1, 100, "smallest plausible teat radius"),
      real("r_max_mm", "mm", &P::r_max_mm, 1, 100, "largest plausible teat radius"),
      real("fit_rms_mm", "mm", &P::fit_rms_mm, 0.1, 50, "largest RMS residual of an accepted tip fit"),
      real("fit_reach_mm", "mm", &P::fit_reach_mm, 5, 200,
           "points within this distance of the tip are fitted"),
      real("radius_tol_mm", "mm", &P::radius_tol_mm, 0.1, 100,
           "in TRACK, a candidate's radius may differ this much from its teat's"),
      real("spacing_min_mm", "mm", &P::spacing_min_mm, 1, 1000,
           "smallest plausible distance between two teats"),
      real("spacing_max_mm", "mm", &P::spacing_max_mm, 1, 1000,
           "largest plausible distance between two teats"),
      real("w_shape", "", &P::w_shape, 0, 100, "weight of the pair-distance error in the model cost"),
      real("w_ncc", "mm", &P::w_ncc, 0, 1000, "weight of (1 - NCC) in the model cost"),
      real("model_max", "mm", &P::model_max, 0, 1000, "largest accepted model cost"),
      real("d_gate_mm", "mm", &P::d_gate_mm, 1, 500, "a teat's match must lie this close to its prediction"),
      whole("n_lost", "frames", &P::n_lost, 1, 1000, "frames without enough teats before TRACK turns LOST"),
      whole("n_confirm", "frames", &P::n_confirm, 1, 1000, "consistent SEARCH frames before TRACK"),
      whole("min_teats", "", &P::min_teats, 1, 4, "teats a frame needs matched to count as tracked"),
      real("kalman_q", "mm/s^2", &P::kalman_q, 0, 1e7,
           "Kalman process noise (acceleration spectral density)"),
      real("kalman_r_mm", "mm", &P::kalman_r_mm, 0.01, 100, "Kalman measurement noise (standard deviation)"),
  };
  return r;
}

const Row& find(std::string_view name) {
  for (const auto& r : rows())
    if (r.info.name == name) return r;
  throw invalid_argument(std::string(name), "unknown tracker parameter '" + std::string(name) + "'");
}

double value_of(const TrackerParams& p, const Row& r) {
  return r.d ? p.*(r.d) : double(p.*(r.i));
}

void check_range(const Row& r, double v) {
  const auto& in = r.info;
  if (!std::isfinite(v) || v < in.min || v > in.max)
    throw invalid_argument(in.name, in.name + " must be in [" + format_double(in.min) + ", " +
                                        format_double(in.max) + "], got " + format_double(v));
  if (in.integer && v != std::floor(v))
    throw invalid_argument(in.name, in.name + " must be a whole number, got " + format_double(v));
}

}  // namespace

const std::vector<ParamInfo>& parameter_infos() {
  static const std::vector<ParamInfo> infos = [] {
    std::vector<ParamInfo> v;
    for (const auto& r : rows()) v.push_back(r.info);
    return v;
  }();
  return infos;
}

std::vector<double> to_vector(const TrackerParams& p) {
  std::vector<double> v;
  for (const auto& r : rows()) v.push_back(value_of(p, r));
  return v;
}

double get_param(const TrackerParams& p, std::string_view name) {
  return value_of(p, find(name));
}

void set_param(TrackerParams& p, std::string_view name, double value) {
  const Row& r = find(name);
  check_range(r, value);
  if (r.d)
    p.*(r.d) = value;
  else
    p.*(r.i) = static_cast<int>(value);
}

void validate(const TrackerParams& p) {
  for (const auto& r : rows()) check_range(r, value_of(p, r));
  if (p.median_k % 2 == 0)
    throw invalid_argument("median_k", "median_k must be 1, 3 or 5, got " + format_double(p.median_k));
  if (p.z_min_mm >= p.z_max_mm)
    throw invalid_argument("z_max_mm", "z_max_mm must exceed z_min_mm (" + format_double(p.z_min_mm) +
                                           "), got " + format_double(p.z_max_mm));
  if (p.r_min_mm >= p.r_max_mm)
    throw invalid_argument("r_max_mm", "r_max_mm must exceed r_min_mm (" + format_double(p.r_min_mm) +
                                           "), got " + format_double(p.r_max_mm));
  if (p.template_min_px > p.template_max_px)
    throw invalid_argument("template_max_px", "template_max_px must be at least template_min_px (" +
                                                  format_double(p.template_min_px) + "), got " +
                                                  format_double(p.template_max_px));
  if (p.spacing_min_mm >= p.spacing_max_mm)
    throw invalid_argument("spacing_max_mm", "spacing_max_mm must exceed spacing_min_mm (" +
                                                 format_double(p.spacing_min_mm) + "), got " +
                                                 format_double(p.spacing_max_mm));
}

}  // namespace trailscope::tracker
