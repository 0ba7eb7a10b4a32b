#pragma once
// The client's side of the bundle-stream protocol (proto/bundle_stream.md) without a socket: its JSON
// control messages applied to a connection's settings, and the bundling frame they ask for. The server's
// frames: formats/bundle_stream_frame.hpp.
#include <cstdint>
#include <optional>
#include <string>

#include "trailscope/bundling/streaming.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::server {

/// What a client has asked of its stream so far.
struct StreamControl {
  std::optional<double> t;  ///< the clock, Unix seconds; no update before the first
  double window_s = 3600;   ///< W, seconds
  double fade_s = 300;      ///< fade ramp, seconds (<= window_s)
  /// The view and the flight filters, in the REST query's text forms: bbox "w,s,e,n" (degrees; the
  /// frame, and flights whose extent misses it are left out), callsign pattern, icao24 "a,b,...".
  std::string bbox, callsign, icao24;
  Query filters;                      ///< parse_query of the three above
  std::uint64_t view_generation = 0;  ///< +1 whenever bbox or a filter changes
};

/// Applies one client message (JSON text) to `c`: an object with any of t (number of Unix seconds, or
/// an ISO 8601 string), window_s (60..limits::kMaxStreamWindowSeconds), fade_s (0..window_s; when only
/// window_s is given, fade_s is clamped to it), bbox ("w,s,e,n" or null for the data's extent),
/// callsign, icao24 (strings; "" clears). Nothing is changed when it throws invalid_argument naming the
/// offending field ("message" for a text that is not a JSON object, the field's own name for an unknown
/// field or a bad value).
void apply_control(const std::string& text, StreamControl& c);

/// The frame of the stream for a dataset and its control: the bbox's Web Mercator box, or the data's
/// extent (a box across 180° spans west .. east + one world), onto `size` pixels.
bundling::Frame stream_frame(const TrailSet& trails, const StreamControl& c, int size);

}  // namespace trailscope::server
