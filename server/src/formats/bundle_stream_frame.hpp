#pragma once
// One update of a bundle stream on the wire: the binary layout "TSBS" (proto/bundle_stream.md has the
// same), version 1, little-endian:
//   offset   type         field
//   0        char[4]      magic "TSBS"
//   4        uint32       version = 1
//   8        uint32       n, trails
//   12       uint32       m, points
//   16       float64      t, the update's clock (Unix seconds; float64, so late times of day keep their
//                         fractions of a second)
//   24       uint32       sequence number of the update (low 32 bits)
//   28       float32      window_s
//   32       float32      mean drift of the update, px of the bundling frame
//   36       uint32       reserved, 0
//   40       uint32[n]    flight id of each trail (its index in the dataset)
//   40+4n    float32[n]   opacity of each trail (its fade)
//   40+8n    uint32[n+1]  offsets: trail i is points offsets[i] .. offsets[i+1]-1
//   44+12n   float32[2m]  lon, lat degrees interleaved
// Total 44 + 12n + 8m bytes; every section on a 4-byte boundary and t on an 8-byte one, so a browser can
// view it with typed arrays.
#include <string>

#include "trailscope/bundling/streaming.hpp"

namespace trailscope::server {

/// The TSBS frame of `u`, its points mapped back from `frame`'s pixels (Web Mercator units) to lon/lat.
std::string encode_stream_frame(const bundling::StreamUpdate& u, const bundling::Frame& frame,
                                double window_s);

}  // namespace trailscope::server
