// libFuzzer harness: the server's query parsing. The bytes are a request target ("/path?k=v&..."), split
// and percent-decoded by Boost.URL exactly as net/http_server.cpp's to_request() does, then read by the
// parsers every GET route uses: trails::parse_query (the filters: bbox, t0, t1, altitudes, icao24,
// callsign, on_ground; compute/src/trails/query.cpp), params::integer / number / text and tile_coords
// (server/src/params/query_params.cpp, tile_params.cpp), and congestion::parse_counts_request.
#include <boost/url/parse.hpp>

#include "fuzz_support.hpp"
#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "trailscope/congestion/counts.hpp"
#include "trailscope/trails/query.hpp"

using namespace trailscope;
using namespace trailscope::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto parsed = boost::urls::parse_origin_form(fuzz::bytes_of(data, size));
  if (!parsed) return 0;  // the server answers 400 "malformed request target"
  Request req;
  req.path = parsed->path();
  for (auto param : parsed->params()) req.query[param.key] = param.value;

  try {
    const Query q = parse_query(req.query);
    (void)q.canonical();
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    (void)congestion::parse_counts_request(req.query);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    (void)params::integer(req, "limit", 100, 1, 10000);
    (void)params::number(req, "max_gap", 0);
    (void)params::text(req, "format", "json");
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    // The router always fills z, x and y from /tiles/{z}/{x}/{y}.png; here from the query's own z, x, y
    // (any text), "0" when absent.
    PathParams p;
    for (const char* k : {"z", "x", "y"}) {
      auto it = req.query.find(k);
      p[k] = it != req.query.end() ? it->second : "0";
    }
    (void)params::tile_coords(req, p);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
