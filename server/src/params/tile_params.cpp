#include "params/tile_params.hpp"

#include <cstdint>

#include "params/query_params.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::server::params {

TileCoords tile_coords(const Request& req, const PathParams& p) {
  TileCoords t;
  t.z = static_cast<int>(path_integer(p, "z", limits::kMinZoom, limits::kMaxZoom));
  const std::int64_t n = std::int64_t{1} << t.z;
  t.x = static_cast<int>(path_integer(p, "x", 0, n - 1));
  t.y = static_cast<int>(path_integer(p, "y", 0, n - 1));
  t.size = static_cast<int>(
      integer(req, "size", limits::kTileSizeSmall, limits::kTileSizeSmall, limits::kTileSizeLarge));
  if (t.size != limits::kTileSizeSmall && t.size != limits::kTileSizeLarge)
    throw invalid_argument("size", "size must be 256 or 512");
  return t;
}

std::string dataset_cache_prefix(const std::string& id) {
  return id + "@";
}

std::string bundle_cache_prefix(const std::string& id) {
  return "bundle:" + id + "@";
}

std::string dataset_cache_key(const std::string& id, const std::string& created) {
  return dataset_cache_prefix(id) + created;
}

std::string bundle_cache_key(const std::string& id, const std::string& created) {
  return bundle_cache_prefix(id) + created;
}

}  // namespace trailscope::server::params
