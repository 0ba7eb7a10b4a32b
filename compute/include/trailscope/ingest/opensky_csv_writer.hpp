#pragma once
// Writes a TrailSet as an OpenSky `state_vectors_data4` CSV, the format ingest reads fastest. Used to make
// large benchmark inputs from generated traffic, to export, and as the round-trip check of the CSV reader.
#include <string>

#include "trailscope/trails/trail_set.hpp"

namespace trailscope::ingest {

/// The header written (and the column order): the 16 data columns of state_vectors_data4.
inline constexpr const char* kOpenSkyCsvHeader =
    "time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,alert,spi,squawk,baroaltitude,"
    "geoaltitude,lastposupdate,lastcontact";

/// Writes every point of `set`, flight by flight, one row per point, SI units as OpenSky stores them:
/// time (Unix s), lat/lon (deg), velocity (m/s), heading (deg), vertrate (m/s), baroaltitude (m).
/// Numbers use the shortest text that reads back to the identical float/double, so write → ingest
/// reproduces every value bit for bit (same flights and points, given the same gap_seconds). Unknown (NaN)
/// values are empty fields; onground is true/false; alert and spi are false; squawk and geoaltitude are
/// empty; lastposupdate and lastcontact repeat time.
/// With `gzip` the file is gzip-compressed at level 1: these files are benchmark inputs of gigabytes, and
/// level 1 writes several times faster than the default for a slightly larger file.
/// The file is written under a temporary name next to `path` and renamed at the end, so a reader never
/// sees a partial file.
/// Throws Error(invalid_argument, "dataset") if a flight has no valid icao24 (e.g. SO6 data: OpenSky rows
/// are keyed by icao24), and Error(internal, "path") if the file cannot be written.
void write_opensky_csv(const TrailSet& set, const std::string& path, bool gzip);

}  // namespace trailscope::ingest
