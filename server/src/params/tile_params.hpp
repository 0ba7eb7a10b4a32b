#pragma once
// Tile coordinates of the tile routes ({z}/{x}/{y}.png with ?size=) and the keys under which rendered
// PNGs are cached (routes/png_cache.hpp): a key holds every input that changes the bytes, and starts with
// its source's prefix, so that deleting the source drops its tiles (TileCache::erase_prefix).
#include <string>

#include "routes/http_types.hpp"

namespace trailscope::server::params {

struct TileCoords {
  int z = 0, x = 0, y = 0;  ///< slippy-map tile: z in limits::kMinZoom..kMaxZoom, x and y in 0..2^z-1
  int size = 0;             ///< edge in pixels: limits::kTileSizeSmall or kTileSizeLarge
};

/// The path parameters z, x, y and the query parameter size (default limits::kTileSizeSmall), checked in
/// that order. Throws invalid_argument naming the first one out of range ("size must be 256 or 512").
TileCoords tile_coords(const Request& req, const PathParams& p);

/// The cache-key prefix of every PNG rendered from dataset `id` ("<id>@").
std::string dataset_cache_prefix(const std::string& id);
/// The cache-key prefix of every PNG rendered from bundle `id` ("bundle:<id>@").
std::string bundle_cache_prefix(const std::string& id);
/// The prefix followed by the source's creation stamp: ids are not reused within a run, and the stamp
/// tells a source from a later one of the same id after a restart.
std::string dataset_cache_key(const std::string& id, const std::string& created);
std::string bundle_cache_key(const std::string& id, const std::string& created);

}  // namespace trailscope::server::params
