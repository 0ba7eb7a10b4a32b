// Flow maps (flow_map.hpp): sector fields → evenly spaced streamlines → CUBu bundling.
#include "trailscope/flow/flow_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::flow {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double round6(double v) {
  if (v == 0 || !std::isfinite(v)) return v;
  const double m = std::pow(10.0, 5 - std::floor(std::log10(std::abs(v))));
  return std::round(v * m) / m;
}

int to_int(std::string_view name, std::string_view value) {
  const std::string s(value);
  std::size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size())
    throw invalid_argument(std::string(name), std::string(name) + " must be an integer, got '" + s + "'");
  return v;
}

}  // namespace

bundling::BundleParams FlowParams::default_bundle_params() {
  bundling::BundleParams b;
  b.size = 512;
  b.h = 24;
  b.iterations = 10;
  b.spl = 8;
  b.jitter = 0;    // streamlines are already evenly sampled; jitter only makes them wiggle
  b.lambda = 0.5;  // smooth bundles: a flow map shows directions, not the exact tracks
  b.directional = true;
  b.max_displacement = 0.5;
  return b;
}

void FlowParams::validate() const {
  field.validate();
  lines.validate();
  bundle.validate();
}

void FlowParams::set(std::string_view name, std::string_view value) {
  FlowParams p = *this;
  if (name == "grid")
    p.field.grid = to_int(name, value);
  else if (name == "sectors")
    p.field.sectors = to_int(name, value);
  else if (name == "smooth")
    p.field.smooth = to_int(name, value);
  else if (name == "max_gap") {
    const std::string s(value);
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size())
      throw invalid_argument("max_gap", "max_gap must be a number of seconds");
    p.field.max_gap_seconds = v;
  } else if (name.substr(0, 7) == "bundle.")
    p.bundle.set(name.substr(7), value);
  else {
    const auto& infos = streamline_parameter_infos();
    if (std::none_of(infos.begin(), infos.end(), [&](const ParamInfo& i) { return i.name == name; }))
      throw invalid_argument(std::string(name), "unknown flow parameter '" + std::string(name) + "'");
    p.lines.set(name, value);
  }
  p.validate();
  *this = p;
}

void FlowParams::check_cost(int nx, int ny, int sectors) const {
  const double bound = sectors * lines.max_points(nx, ny);
  if (bound > static_cast<double>(limits::kMaxFlowLinePoints))
    throw Error(Error::Kind::payload_too_large, "d_sep",
                "a " + std::to_string(nx) + " × " + std::to_string(ny) + " grid of " +
                    std::to_string(sectors) + " sectors may hold up to " +
                    std::to_string(static_cast<long long>(bound)) +
                    " streamline points at this d_sep, d_test and step (limits::kMaxFlowLinePoints = " +
                    std::to_string(limits::kMaxFlowLinePoints) + "); raise d_sep or step, or lower grid");
}

bundling::Polylines FlowMap::lines_at(double level) const {
  if (!(level >= 0 && level <= 2)) throw invalid_argument("level", "level must be in [0, 2]");
  if (level <= 1 || !has_bundle) return lines;
  return bundled.frame.from_pixels(bundling::relax(bundled, 2 - level, bundled.params.max_displacement));
}

FlowMap flow_map(VectorField field, const FlowParams& params, Backend backend, const ProgressFn& progress,
                 const CancelToken* cancel) {
  params.validate();
  const Grid g = field.grid;
  if (g.nx < 2 || g.ny < 2)
    throw Error(Error::Kind::unprocessable, "query", "the flow field needs at least 2 × 2 cells");
  params.check_cost(g.nx, g.ny, static_cast<int>(field.sectors.size()));
  FlowMap out;
  out.field = std::move(field);
  auto t0 = std::chrono::steady_clock::now();
  std::size_t budget = limits::kMaxFlowLinePoints;
  for (std::size_t s = 0; s < out.field.sectors.size(); ++s) {
    if (cancel) cancel->throw_if_cancelled();
    if (progress) progress(static_cast<double>(s) / out.field.sectors.size(), "lines");
    Streamlines sl =
        evenly_spaced_streamlines(out.field.sectors[s], g.nx, g.ny, params.lines, budget, cancel);
    budget -= sl.lines.points();
    for (std::size_t l = 0; l < sl.lines.size(); ++l) {
      const std::size_t b = sl.lines.begin(l), e = sl.lines.end(l);
      out.lines.add(std::span<const double>(sl.lines.x.data() + b, e - b),
                    std::span<const double>(sl.lines.y.data() + b, e - b));
      out.sector.push_back(static_cast<int>(s));
      double sum = 0;
      for (std::size_t k = b; k < e; ++k) sum += sl.traffic[k];
      out.line_traffic.push_back(static_cast<float>(sum / (e - b)));
    }
    out.traffic.insert(out.traffic.end(), sl.traffic.begin(), sl.traffic.end());
  }
  out.lines_ms = ms_since(t0);
  if (out.lines.size() > 0) {
    t0 = std::chrono::steady_clock::now();
    const bundling::Frame frame = bundling::Frame::view(0, 0, g.nx, g.ny, params.bundle.size);
    const auto bundle_progress = [&](double f, std::string_view) {
      if (progress) progress(f, "bundle");
    };
    out.bundled =
        bundling::bundle(frame.to_pixels(out.lines), frame, params.bundle, backend, bundle_progress, cancel);
    out.has_bundle = true;
    out.bundle_ms = ms_since(t0);
  }
  if (progress) progress(1.0, "bundle");
  return out;
}

FlowMap flow_map(const TrailSet& trails, const Query& query, const FlowParams& params, Backend backend,
                 const ProgressFn& progress, const CancelToken* cancel) {
  params.validate();
  const auto t0 = std::chrono::steady_clock::now();
  // The grid's size is known before any point is read: refuse an over-costly request first.
  const Grid g = traffic_grid(trails, query, params.field.grid);
  params.check_cost(g.nx, g.ny, params.field.sectors);
  VectorField field = traffic_field(trails, query, params.field);
  const double field_ms = ms_since(t0);
  FlowMap m = flow_map(std::move(field), params, backend, progress, cancel);
  m.field_ms = field_ms;
  return m;
}

nlohmann::json flow_json(const FlowMap& map, double level) {
  const bundling::Polylines pl = map.lines_at(level);
  const Grid& g = map.field.grid;
  nlohmann::json lines = nlohmann::json::array();
  for (std::size_t l = 0; l < pl.size(); ++l) {
    nlohmann::json pts = nlohmann::json::array();
    for (std::size_t k = pl.begin(l); k < pl.end(l); ++k) {
      if (g.geographic)
        pts.push_back({round6(g.lon(pl.x[k])), round6(g.lat(pl.y[k]))});
      else
        pts.push_back({round6(pl.x[k]), round6(pl.y[k])});
    }
    const int s = map.sector[l];
    lines.push_back({{"sector", s},
                     {"heading", number_or_null(map.field.sector_heading(s))},
                     {"traffic", round6(map.line_traffic[l])},
                     {"points", std::move(pts)}});
  }
  return {{"grid",
           {{"nx", g.nx},
            {"ny", g.ny},
            {"cell", g.cell},
            {"x0", g.x0},
            {"y0", g.y0},
            {"geographic", g.geographic}}},
          {"level", level},
          {"sectors", map.field.sectors.size()},
          {"lines", std::move(lines)},
          {"times", {{"field_ms", map.field_ms}, {"lines_ms", map.lines_ms}, {"bundle_ms", map.bundle_ms}}},
          {"bundle_path", map.has_bundle ? map.bundled.path : ""}};
}

}  // namespace trailscope::flow
