// GET /api/v1/datasets/{dataset}/animation: one animation chunk as TSAN (proto/animation_chunks.md;
// compute/.../trails/animation_chunk.hpp chooses the flights and samples, formats/animation_chunk.hpp
// encodes them). Chunks are aligned and immutable, so they are cached by key and revalidated by ETag.
#include <string>

#include "formats/animation_chunk.hpp"
#include "limits.hpp"
#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "routes/handlers.hpp"
#include "routes/png_cache.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/trails/animation_chunk.hpp"

namespace trailscope::server::handlers {

Response animation(App& app, const Request& req, const PathParams& p) {
  // The window filters that do not apply are let through so that they are refused by name below.
  reject_unknown_params(req, params::with_query_keys({"t", "duration", "origin"}));
  const auto ds = app.store->get(p.at("dataset"));
  const auto t_param = req.query.find("t");
  if (t_param == req.query.end())
    throw invalid_argument("t",
                           "t: the chunk start is required (?t=Unix seconds or ISO 8601, a multiple of "
                           "duration)");
  const double t = parse_time(t_param->second, "t");
  const auto duration = params::integer(req, "duration", limits::kDefaultAnimationChunkSeconds,
                                        limits::kMinAnimationChunkSeconds, limits::kMaxAnimationChunkSeconds);
  const double d = static_cast<double>(duration);
  check_animation_chunk_start(t, duration);
  if (req.query.count("alt_unit"))
    throw invalid_argument("alt_unit",
                           "alt_unit does not apply to animation chunks: the player filters positions "
                           "during playback, and the chunk is the time window");
  const Query q = parse_query(req.query);
  check_animation_query(q);  // before the ETag check: a refused request never gets a 304
  const auto o_param = req.query.find("origin");
  const AnimationOrigin origin = o_param == req.query.end()
                                     ? default_animation_origin(*ds->trails)
                                     : parse_animation_origin(o_param->second, "origin");

  // Every input that changes the bytes, and nothing else.
  const std::string key = params::dataset_cache_key(ds->id, ds->created) +
                          "/animation?t=" + format_double(t) + "&duration=" + std::to_string(duration) +
                          "&origin=" + format_double(origin.lon) + "," + format_double(origin.lat) + "&" +
                          q.canonical();
  return cached_bytes(app.animation_chunks, key, req, "application/vnd.trailscope.anim", [&] {
    const AnimationChunk chunk = animation_chunk(*ds->trails, t, d, q, limits::kMaxAnimationChunkSamples);
    return encode_animation_chunk(*ds->trails, chunk, origin);
  });
}

}  // namespace trailscope::server::handlers
