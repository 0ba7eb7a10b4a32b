#pragma once
// ETag, 304 and the byte caches for every route whose answer is a pure function of its inputs: rendered
// PNGs (density tiles, bundle tiles and images) and animation chunks. The cache key holds every input that
// changes the bytes, and the ETag is a digest of it.
#include <functional>
#include <string>

#include "routes/http_types.hpp"
#include "store/tile_cache.hpp"

namespace trailscope::server::handlers {

/// A stable 64-bit digest of `key` as a quoted ETag (the same across restarts).
std::string etag_of(const std::string& key);
/// Adds the ETag and Cache-Control (public, revalidate after 5 minutes).
Response with_cache_headers(Response r, const std::string& etag);
/// 304 when If-None-Match is the key's ETag; else the cached PNG, rendering and caching it on a miss.
/// Validate the request before calling: a malformed request must never get a 304.
Response cached_png(TileCache& cache, const std::string& key, const Request& req,
                    const std::function<std::string()>& render);
/// The same for any content type: 304 on a matching If-None-Match, else the cached bytes, rendering and
/// caching them on a miss. What `render` throws reaches the client, and nothing is cached.
Response cached_bytes(TileCache& cache, const std::string& key, const Request& req,
                      const std::string& content_type, const std::function<std::string()>& render);

}  // namespace trailscope::server::handlers
