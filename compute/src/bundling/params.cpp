// BundleParams: one table describes every parameter (name, type, default, range, help, how to read,
// write and check it), so that validate(), set(), to_map() and parameter_infos() cannot disagree.
#include "trailscope/bundling/params.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <system_error>
#include <utility>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::bundling {
namespace {

std::string quoted(std::string_view s) {
  return "'" + std::string(s) + "'";
}

// One parameter: how to print, parse and range-check it. `check` returns "" or the complaint.
struct Field {
  ParamInfo info;
  std::function<std::string(const BundleParams&)> get;
  std::function<void(BundleParams&, std::string_view)> parse;  // throws invalid_argument(name)
  std::function<std::string(const BundleParams&)> check;
};

double parse_number(std::string_view name, std::string_view text) {
  double v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v))
    throw invalid_argument(std::string(name),
                           std::string(name) + " must be a number (got " + quoted(text) + ")");
  return v;
}

long long parse_integer(std::string_view name, std::string_view text) {
  long long v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size())
    throw invalid_argument(std::string(name),
                           std::string(name) + " must be an integer (got " + quoted(text) + ")");
  return v;
}

bool parse_bool(std::string_view name, std::string_view text) {
  if (text == "true" || text == "1") return true;
  if (text == "false" || text == "0") return false;
  throw invalid_argument(std::string(name),
                         std::string(name) + " must be true or false (got " + quoted(text) + ")");
}

// A double member within [lo, hi] (lo excluded when lo_open).
Field real(const char* name, double BundleParams::*m, double lo, double hi, bool lo_open, const char* unit,
           const char* help) {
  const std::string range = (lo_open ? "(" : "[") + format_double(lo) + ", " + format_double(hi) + "]";
  Field f;
  f.info = describe_param(name, "number", format_double(BundleParams{}.*m),
                          range + (*unit ? std::string(" ") + unit : ""), help);
  f.info.unit = unit, f.info.default_number = BundleParams{}.*m, f.info.min = lo, f.info.max = hi;
  f.get = [m](const BundleParams& p) { return format_double(p.*m); };
  f.parse = [m, name](BundleParams& p, std::string_view t) { p.*m = parse_number(name, t); };
  f.check = [=](const BundleParams& p) -> std::string {
    const double v = p.*m;
    const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
    if (ok) return {};
    return std::string(name) + " must be in " + range + (*unit ? std::string(" ") + unit : "") + " (got " +
           format_double(v) + ")";
  };
  return f;
}

// An int member within [lo, hi], optionally odd.
Field integer(const char* name, int BundleParams::*m, int lo, int hi, bool odd, const char* unit,
              const char* help) {
  const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
  auto complaint = [=](long long v) {
    return std::string(name) + " must be " + (odd ? "an odd integer" : "an integer") + " in " + range +
           (*unit ? std::string(" ") + unit : "") + " (got " + std::to_string(v) + ")";
  };
  Field f;
  f.info = describe_param(name, "integer", std::to_string(BundleParams{}.*m),
                          range + (odd ? ", odd" : "") + (*unit ? std::string(" ") + unit : ""), help);
  f.info.unit = unit, f.info.default_number = BundleParams{}.*m, f.info.min = lo, f.info.max = hi;
  f.info.integer = true;
  f.get = [m](const BundleParams& p) { return std::to_string(p.*m); };
  f.parse = [=](BundleParams& p, std::string_view t) {
    const long long v = parse_integer(name, t);
    if (v < lo || v > hi) throw invalid_argument(name, complaint(v));  // before it is narrowed to int
    p.*m = static_cast<int>(v);
  };
  f.check = [=](const BundleParams& p) -> std::string {
    const int v = p.*m;
    return v >= lo && v <= hi && (!odd || v % 2 == 1) ? std::string() : complaint(v);
  };
  return f;
}

Field boolean(const char* name, bool BundleParams::*m, const char* help) {
  Field f;
  f.info = describe_param(name, "boolean", BundleParams{}.*m ? "true" : "false", "true, false", help);
  f.get = [m](const BundleParams& p) { return std::string(p.*m ? "true" : "false"); };
  f.parse = [m, name](BundleParams& p, std::string_view t) { p.*m = parse_bool(name, t); };
  f.check = [](const BundleParams&) { return std::string(); };
  return f;
}

// An enum member with two named values ("density must be weighted or count").
template <class E>
Field choice(const char* name, E BundleParams::*m, std::pair<const char*, E> first,
             std::pair<const char*, E> second, const char* help) {
  const std::array<std::pair<const char*, E>, 2> values = {first, second};
  const std::string a = values[0].first, b = values[1].first;
  const std::string must = std::string(name) + " must be " + a + " or " + b;
  const auto text_of = [values](E e) -> std::string {
    for (const auto& [t, v] : values)
      if (v == e) return t;
    return {};
  };
  Field f;
  f.info = describe_param(name, "enum", text_of(BundleParams{}.*m), a + ", " + b, help);
  f.get = [m, text_of, values](const BundleParams& p) {
    const std::string t = text_of(p.*m);
    return t.empty() ? std::string(values[0].first) : t;  // as to_string(): the first for a stray value
  };
  f.parse = [=](BundleParams& p, std::string_view t) {
    for (const auto& [text, v] : values)
      if (t == text) {
        p.*m = v;
        return;
      }
    throw invalid_argument(name, must + " (got " + quoted(t) + ")");
  };
  f.check = [=](const BundleParams& p) { return text_of(p.*m).empty() ? must : std::string(); };
  return f;
}

const std::vector<Field>& fields() {
  static const std::vector<Field> all = [] {
    std::vector<Field> v;
    v.push_back(integer("size", &BundleParams::size, 64, 4096, false, "px",
                        "edge of the square density image the drawing is fitted into (fboSize)"));
    v.push_back(real("h", &BundleParams::h, 2, 128, false, "px",
                     "initial kernel radius: the bundling scale; shrinks to 2 px over the iterations"));
    v.push_back(
        integer("iterations", &BundleParams::iterations, 1, 100, false, "", "bundling iterations (niter)"));
    v.push_back(real("eps", &BundleParams::eps, 0, 2, true, "",
                     "advection step as a fraction of the current kernel radius"));
    v.push_back(real("lambda", &BundleParams::lambda, 0, 1, false, "", "Laplacian smoothing strength"));
    v.push_back(real("smooth_kernel", &BundleParams::smooth_kernel, 0, 0.5, false, "",
                     "Laplacian half-window as a fraction of size"));
    v.push_back(integer("smooth_iterations", &BundleParams::smooth_iterations, 1, 15, true, "",
                        "Laplacian smoothing passes (liter)"));
    v.push_back(real("spl", &BundleParams::spl, 1, 256, false, "px", "resampling step along each polyline"));
    v.push_back(real("jitter", &BundleParams::jitter, 0, 1, false, "",
                     "random shift of each resampled point along its segment, fraction of spl"));
    {
      Field f;
      f.info = describe_param("seed", "integer", "1", "0..18446744073709551615",
                              "jitter seed: the same input, parameters and seed give the same result");
      f.info.default_number = 1, f.info.max = 18446744073709551615.0, f.info.integer = true;
      f.get = [](const BundleParams& p) { return std::to_string(p.seed); };
      f.parse = [](BundleParams& p, std::string_view t) {
        std::uint64_t v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size())
          throw invalid_argument("seed", "seed must be an unsigned 64-bit integer (got " + quoted(t) + ")");
        p.seed = v;
      };
      f.check = [](const BundleParams&) { return std::string(); };
      v.push_back(std::move(f));
    }
    v.push_back(choice<DensityMode>(
        "density", &BundleParams::density, {"weighted", DensityMode::weighted}, {"count", DensityMode::count},
        "splat weight of a point: its edge's length / the longest edge's (weighted) or 1 (count)"));
    v.push_back(choice<Profile>(
        "profile", &BundleParams::profile, {"uniform", Profile::uniform}, {"hourglass", Profile::hourglass},
        "how strongly points move along an edge: everywhere alike, or less near the ends"));
    v.push_back(boolean("block_endpoints", &BundleParams::block_endpoints, "edge endpoints never move"));
    v.push_back(boolean("polyline_style", &BundleParams::polyline_style,
                        "resample only in the first iteration (keeps trails' own sampling)"));
    v.push_back(real("border", &BundleParams::border, 0, 0.45, false, "",
                     "fraction of size left empty around a fitted drawing"));
    v.push_back(integer("ms_iterations", &BundleParams::ms_iterations, 0, 50, false, "",
                        "endpoint mean-shift clustering iterations (0 = off)"));
    v.push_back(real("ms_h", &BundleParams::ms_h, 2, 128, false, "px", "initial mean-shift kernel radius"));
    v.push_back(real("lambda_ends", &BundleParams::lambda_ends, 0, 1, false, "",
                     "smoothing of the end segments after endpoint clustering"));
    v.push_back(boolean("directional", &BundleParams::directional,
                        "parallel edges attract, antiparallel edges repel"));
    v.push_back(real("repulsion", &BundleParams::repulsion, 0, 10, false, "",
                     "strength of the repulsion of antiparallel edges (directional)"));
    v.push_back(real("relaxation", &BundleParams::relaxation, 0, 1, false, "",
                     "blend toward the original edges: 0 = fully bundled, 1 = the input"));
    v.push_back(
        real("max_displacement", &BundleParams::max_displacement, 0, 10, false, "",
             "largest distance of a point from its original position, fraction of its edge's length"));
    v.push_back(real("dir_separation", &BundleParams::dir_separation, 0, 50, false, "px",
                     "offset between the two directions of a bundle"));
    return v;
  }();
  return all;
}

const Field* find(std::string_view name) {
  for (const Field& f : fields())
    if (f.info.name == name) return &f;
  return nullptr;
}

}  // namespace

void BundleParams::validate() const {
  for (const Field& f : fields())
    if (std::string why = f.check(*this); !why.empty()) throw invalid_argument(f.info.name, why);
}

void BundleParams::set(std::string_view name, std::string_view value) {
  const Field* f = find(name);
  if (!f) throw invalid_argument(std::string(name), "unknown bundling parameter " + quoted(name));
  BundleParams next = *this;
  f->parse(next, value);
  if (std::string why = f->check(next); !why.empty()) throw invalid_argument(f->info.name, why);
  *this = next;
}

std::map<std::string, std::string> BundleParams::to_map() const {
  std::map<std::string, std::string> out;
  for (const Field& f : fields()) out[f.info.name] = f.get(*this);
  return out;
}

const std::vector<ParamInfo>& parameter_infos() {
  static const std::vector<ParamInfo> infos = [] {
    std::vector<ParamInfo> v;
    for (const Field& f : fields()) v.push_back(f.info);
    return v;
  }();
  return infos;
}

const char* to_string(DensityMode m) noexcept {
  return m == DensityMode::count ? "count" : "weighted";
}

const char* to_string(Profile p) noexcept {
  return p == Profile::hourglass ? "hourglass" : "uniform";
}

}  // namespace trailscope::bundling
