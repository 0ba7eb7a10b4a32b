#include <cstdio>
#include <limits>

#include "routes/handlers.hpp"
#include "routes/png_cache.hpp"
#include "routes/params.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::server::handlers {

// FNV-1a: a stable 64-bit digest of the cache key, so ETags survive restarts.
std::string etag_of(const std::string& key) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : key) h = (h ^ c) * 1099511628211ull;
  char buf[24];
  std::snprintf(buf, sizeof buf, "\"%016llx\"", static_cast<unsigned long long>(h));
  return buf;
}

Response with_cache_headers(Response r, const std::string& etag) {
  r.headers.emplace_back("ETag", etag);
  // Revalidate after 5 minutes: the URL does not name the data's version, the ETag does.
  r.headers.emplace_back("Cache-Control", "public, max-age=300");
  return r;
}

Response cached_png(TileCache& cache, const std::string& key, const Request& req,
                    const std::function<std::string()>& render) {
  const std::string etag = etag_of(key);
  if (req.header("if-none-match") == etag) return with_cache_headers(Response::status_only(304), etag);
  auto bytes = cache.get(key);
  if (!bytes) {
    bytes = std::make_shared<const std::string>(render());
    cache.put(key, bytes);
  }
  Response res;
  res.content_type = "image/png";
  res.shared_body = std::move(bytes);
  return with_cache_headers(std::move(res), etag);
}

namespace {
std::string param_or(const Request& req, const char* name, const char* fallback) {
  auto it = req.query.find(name);
  return it == req.query.end() ? fallback : it->second;
}
}  // namespace

Response density_tile(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"value", "how", "cmap", "size", "kernel"}));
  const auto ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  const int z = static_cast<int>(params::path_integer(p, "z", limits::kMinZoom, limits::kMaxZoom));
  const std::int64_t n = std::int64_t{1} << z;
  density::TileRequest t;
  t.tile = geo::TileId{z, static_cast<int>(params::path_integer(p, "x", 0, n - 1)),
                       static_cast<int>(params::path_integer(p, "y", 0, n - 1))};
  t.size = static_cast<int>(
      params::integer(req, "size", limits::kTileSizeSmall, limits::kTileSizeSmall, limits::kTileSizeLarge));
  if (t.size != limits::kTileSizeSmall && t.size != limits::kTileSizeLarge)
    throw invalid_argument("size", "size must be 256 or 512");
  const std::string value = param_or(req, "value", "count"), how = param_or(req, "how", "eq_hist");
  t.value = density::parse_density_value(value, "value");
  t.how = density::parse_how(how, "how");
  t.cmap = param_or(req, "cmap", "fire");
  t.kernel_radius = static_cast<int>(params::integer(req, "kernel", 0, 0, limits::kMaxKernelRadiusPx));
  // Flights are already split at long gaps when ingested (SO6 keeps its own flight ids and long
  // simplified legs), so every segment of a stored flight is drawn.
  t.max_gap_seconds = std::numeric_limits<double>::infinity();

  // Every input that changes the bytes, and nothing else (the backend gives identical bytes).
  const std::string dataset_key = ds->id + "@" + ds->created;
  const std::string key = dataset_key + "/" + std::to_string(z) + "/" + p.at("x") + "/" + p.at("y") + "?" +
                          q.canonical() + "&value=" + value + "&how=" + how + "&cmap=" + t.cmap +
                          "&size=" + std::to_string(t.size) + "&kernel=" + std::to_string(t.kernel_radius);
  density::validate(t);  // before the ETag check: a malformed request never gets a 304
  return cached_png(app.tiles, key, req,
                    [&] { return std::move(app.density.render_tile(*ds->trails, dataset_key, q, t).png); });
}

}  // namespace trailscope::server::handlers
