#include "routes/png_cache.hpp"

#include <cstdint>
#include <cstdio>

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
  return cached_bytes(cache, key, req, "image/png", render);
}

Response cached_bytes(TileCache& cache, const std::string& key, const Request& req,
                      const std::string& content_type, const std::function<std::string()>& render) {
  const std::string etag = etag_of(key);
  if (req.header("if-none-match") == etag) return with_cache_headers(Response::status_only(304), etag);
  auto bytes = cache.get(key);
  if (!bytes) {
    bytes = std::make_shared<const std::string>(render());
    cache.put(key, bytes);
  }
  Response res;
  res.content_type = content_type;
  res.shared_body = std::move(bytes);
  return with_cache_headers(std::move(res), etag);
}

}  // namespace trailscope::server::handlers
