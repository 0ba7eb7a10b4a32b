#include "store/bundle_store.hpp"

#include <algorithm>

#include "store/column_io.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
constexpr char kMagic[] = "TRAILSCOPE-BUNDLE-1";
constexpr int kFormatVersion = 1;
/// Bundles whose geometry stays in memory after use: enough for a dashboard flipping between a few
/// results, while 100 stored bundles of millions of points each would not fit.
constexpr std::size_t kLoadedBundles = 8;

nlohmann::json frame_json(const bundling::Frame& f) {
  return {{"size", f.size},
          {"x0", f.x0},
          {"y0", f.y0},
          {"scale", f.scale},
          {"offset_x", f.offset_x},
          {"offset_y", f.offset_y},
          {"flip_y", f.flip_y}};
}

bundling::Frame frame_from(const nlohmann::json& j) {
  bundling::Frame f;
  f.size = j.at("size"), f.x0 = j.at("x0"), f.y0 = j.at("y0"), f.scale = j.at("scale");
  f.offset_x = j.at("offset_x"), f.offset_y = j.at("offset_y"), f.flip_y = j.at("flip_y");
  return f;
}

// Geometry is stored as float32: bundle pixels lie in 0..4096, where float keeps 1/4000 px, and it halves
// the files. jobs/bundle_job.cpp rounds a fresh result the same way, so a reloaded bundle draws the same
// bytes as the one computed in this run (ETags stay valid across restarts).
std::vector<float> to_float(const std::vector<double>& v) {
  return {v.begin(), v.end()};
}
std::vector<double> to_double(const std::vector<float>& v) {
  return {v.begin(), v.end()};
}

void read_xy(const fs::path& dir, const char* xn, const char* yn, bundling::Polylines& p, std::size_t n) {
  std::vector<float> x, y;
  read_column(dir, xn, x, n);
  read_column(dir, yn, y, n);
  p.x = to_double(x), p.y = to_double(y);
}
}  // namespace

const char* to_string(BundleUnits u) noexcept {
  switch (u) {
    case BundleUnits::merc32:
      return "merc32";
    case BundleUnits::epsg3857:
      return "epsg3857";
    case BundleUnits::plane:
      return "plane";
  }
  return "plane";
}

BundleUnits parse_bundle_units(const std::string& text) {
  if (text == "merc32") return BundleUnits::merc32;
  if (text == "epsg3857") return BundleUnits::epsg3857;
  if (text == "plane") return BundleUnits::plane;
  throw Error(Error::Kind::internal, "", "store: unknown bundle units '" + text + "'");
}

nlohmann::json StoredBundle::to_json() const {
  const bundling::Bundled& b = bundled;
  const auto& q = b.quality;
  const auto& t = b.times;
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [k, v] : b.params.to_map()) params[k] = v;
  return {
      {"id", id},
      {"created", created},
      {"source", source},
      {"units", to_string(units)},
      {"coordinates", units == BundleUnits::plane ? "source" : "lonlat"},
      {"params", params},
      {"polylines", b.lines.size()},
      {"input_points", input_points},
      {"points", b.lines.points()},
      {"frame", frame_json(b.frame)},
      {"quality",
       {{"ink_raw_px", q.ink_raw_px},
        {"ink_bundled_px", q.ink_bundled_px},
        {"ink_reduction", q.ink_reduction},
        {"mean_displacement_px", q.mean_displacement_px},
        {"max_displacement_px", q.max_displacement_px}}},
      {"times_ms",
       {{"resample", t.resample_ms},
        {"splat", t.splat_ms},
        {"convolve", t.convolve_ms},
        {"advect", t.advect_ms},
        {"smooth", t.smooth_ms},
        {"endpoints", t.endpoints_ms},
        {"post", t.post_ms},
        {"total", t.total_ms}}},
      {"path", b.path},
      {"device", b.device},
      {"owner", owner},
  };
}

std::uint64_t BundleStore::bytes_estimate(const StoredBundle& b) {
  return b.bundled.lines.points() * kBytesPerPoint + (b.bundled.lines.size() + 1) * kBytesPerPolyline +
         (64u << 10);
}

void BundleStore::write_bundle(const StoredBundle& sb, const fs::path& dir) {
  const bundling::Bundled& b = sb.bundled;
  write_column(dir, "x", to_float(b.lines.x));
  write_column(dir, "y", to_float(b.lines.y));
  write_column(dir, "offsets", b.lines.offsets);
  write_column(dir, "original_x", to_float(b.original.x));
  write_column(dir, "original_y", to_float(b.original.y));
  write_column(dir, "t", b.t);
  write_column(dir, "displacement", b.displacement);
  write_column(dir, "length", b.length);
  write_column(dir, "angle", b.angle);
  nlohmann::json m = sb.to_json();
  m["magic"] = kMagic, m["version"] = kFormatVersion, m["dataset"] = sb.dataset;
  write_manifest(dir, m);
}

std::shared_ptr<StoredBundle> BundleStore::read_bundle(const fs::path& dir) {
  const nlohmann::json m = read_manifest(dir);
  if (m.value("magic", "") != kMagic || m.value("version", 0) != kFormatVersion)
    throw io_error(dir, "recognise the format of");
  auto sb = std::make_shared<StoredBundle>();
  sb->id = m.at("id").get<std::string>();
  sb->created = m.at("created").get<std::string>();
  sb->source = m.at("source");
  sb->dataset = m.value("dataset", "");
  sb->units = parse_bundle_units(m.at("units").get<std::string>());
  sb->input_points = m.value("input_points", std::uint64_t{0});
  sb->owner = m.value("owner", "");
  bundling::Bundled& b = sb->bundled;
  b.frame = frame_from(m.at("frame"));
  for (const auto& [k, v] : m.at("params").items()) b.params.set(k, v.get<std::string>());
  const std::size_t n = m.at("polylines").get<std::size_t>(), pts = m.at("points").get<std::size_t>();
  read_column(dir, "offsets", b.lines.offsets, n + 1);
  if (b.lines.offsets.front() != 0 || b.lines.offsets.back() != pts ||
      !std::is_sorted(b.lines.offsets.begin(), b.lines.offsets.end()))
    throw io_error(dir, "validate the offsets of");
  read_xy(dir, "x", "y", b.lines, pts);
  b.original.offsets = b.lines.offsets;
  read_xy(dir, "original_x", "original_y", b.original, pts);
  read_column(dir, "t", b.t, pts);
  read_column(dir, "displacement", b.displacement, pts);
  read_column(dir, "length", b.length, n);
  read_column(dir, "angle", b.angle, n);
  const auto& q = m.at("quality");
  b.quality.ink_raw_px = q.at("ink_raw_px"), b.quality.ink_bundled_px = q.at("ink_bundled_px");
  b.quality.ink_reduction = q.at("ink_reduction");
  b.quality.mean_displacement_px = q.at("mean_displacement_px");
  b.quality.max_displacement_px = q.at("max_displacement_px");
  const auto& t = m.at("times_ms");
  b.times.resample_ms = t.at("resample"), b.times.splat_ms = t.at("splat");
  b.times.convolve_ms = t.at("convolve"), b.times.advect_ms = t.at("advect");
  b.times.smooth_ms = t.at("smooth"), b.times.endpoints_ms = t.at("endpoints");
  b.times.post_ms = t.at("post"), b.times.total_ms = t.at("total");
  b.path = m.value("path", ""), b.device = m.value("device", "");
  return sb;
}

BundleStore::BundleStore(fs::path root)
    : folders_(std::move(root), {"bundle", "bundles", 'b', "manifest.json"},
               manifest_meta(kMagic, kFormatVersion, {"dataset"})),
      loaded_(kLoadedBundles) {}

std::vector<nlohmann::json> BundleStore::list() const {
  return folders_.list();
}

nlohmann::json BundleStore::meta(const std::string& id) const {
  return folders_.meta(id);
}

std::shared_ptr<const StoredBundle> BundleStore::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  folders_.check(id);
  // Reading happens under the lock: two requests for the same cold bundle read it once, and a delete
  // cannot move the folder away mid-read.
  return loaded_.get(id, [&] { return read_bundle(folders_.dir(id)); });
}

std::string BundleStore::reserve_id() {
  return folders_.next_id();
}

std::vector<std::string> BundleStore::put(std::shared_ptr<const StoredBundle> b) {
  if (folders_.number(b->id) == 0)
    throw Error(Error::Kind::internal, "", "store: '" + b->id + "' is not a bundle id");
  const fs::path tmp = folders_.stage(b->id);
  std::vector<std::string> evicted;
  try {
    write_bundle(*b, tmp);
    std::lock_guard lock(mu_);
    folders_.publish(b->id, tmp, b->to_json());
    loaded_.put(b->id, b);
    while (folders_.size() > limits::kMaxStoredBundles) {
      evicted.push_back(folders_.oldest());
      folders_.remove(evicted.back());
      loaded_.erase(evicted.back());
    }
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
  return evicted;
}

void BundleStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  folders_.remove(id);
  loaded_.erase(id);
}

std::size_t BundleStore::size() const {
  return folders_.size();
}

}  // namespace trailscope::server
