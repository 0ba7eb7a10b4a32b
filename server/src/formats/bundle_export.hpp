#pragma once
// A bundle's polylines on the wire and in files: JSON (for scripts), the binary layout "TSBL" (for the
// browser, which blends between raw and bundled itself) and CUBu .trl text. Coordinates are those of the
// source: lon/lat degrees for flight trails and geographic graphs, the graph's own units otherwise.
//
// TSBL, version 1, little-endian (proto/bundle_polylines.md has the same):
//   offset  type        field
//   0       char[4]     magic "TSBL"
//   4       uint32      version = 1
//   8       uint32      flags: bit 0 = coordinates are lon/lat degrees (else source units)
//   12      uint32      n, polylines
//   16      uint32      m, points
//   20      float32     relaxation applied to `bundled` (0 = fully bundled)
//   24      float32     max_displacement (the bundle's parameter: cap as a fraction of an edge's length)
//   28      uint32      reserved, 0
//   32      uint32[n+1] offsets: polyline i is points offsets[i] .. offsets[i+1]-1
//   then    float32[2m] bundled x, y interleaved
//   then    float32[2m] original x, y interleaved (the point at the same arc-length fraction of the input)
//   then    float32[n]  length of each input polyline, in the units of the relaxation cap: source units,
//                       or for lon/lat "Mercator degrees", the length in the plane (lon, y) with
//                       y = asinh(tan(lat))·180/π, where the bundle was computed
// Every section starts on a 4-byte boundary, so a browser can view it with Float32Array/Uint32Array.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "store/bundle_store.hpp"
#include "limits.hpp"

namespace trailscope::server {

inline constexpr char kPolylinesMagic[4] = {'T', 'S', 'B', 'L'};
inline constexpr std::uint32_t kPolylinesVersion = 1;

/// Whether the bundle's coordinates go out as lon/lat.
bool wire_lonlat(BundleUnits u) noexcept;
/// The relaxation to apply: `requested` when >= 0, else the bundle's own params.relaxation.
double effective_relaxation(const StoredBundle& b, double requested) noexcept;

/// The polylines relaxed by `relaxation` (bundling::relax, with the bundle's max_displacement), in source
/// coordinates. Throws Error(payload_too_large, "format") beyond `max_points` points (a response keeps
/// to limits::kMaxPointsPerResponse and points to the binary form; a file written by the CLI need not).
nlohmann::json polylines_json(const StoredBundle& b, double relaxation,
                              std::size_t max_points = limits::kMaxPointsPerResponse);
/// The TSBL bytes (layout above).
std::string polylines_binary(const StoredBundle& b, double relaxation);
/// CUBu .trl text of the relaxed polylines in source coordinates.
std::string polylines_trl(const StoredBundle& b, double relaxation);

}  // namespace trailscope::server
