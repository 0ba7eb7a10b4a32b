#pragma once
// The trail file formats TrailScope reads, and how a file's format is recognised from its content.
// Detection looks at bytes, never at the file name: uploads arrive with arbitrary names, and a wrong
// extension must not send a file to the wrong parser.
#include <cstddef>
#include <string>
#include <string_view>

namespace trailscope::ingest {

enum class Format {
  /// OpenSky `state_vectors_data4` CSV (Trino/pyopensky export): a header row naming at least
  /// time, icao24, lat, lon, in any order; extra columns (serials, hour, ...) are ignored.
  opensky_csv,
  /// `traffic` (X. Olive) records: a JSON array of objects, or JSON Lines of the same objects, with
  /// timestamp, icao24, latitude, longitude and optionally callsign, altitude, groundspeed, track,
  /// vertical_rate, onground.
  traffic_json,
  /// Eurocontrol SO6 "m3": one flight segment per line, 20 space-separated columns.
  so6,
  /// readsb / ADS-B Exchange / adsb.lol "trace_full" JSON: one object with icao, timestamp, trace.
  readsb_trace,
};

/// Parses a format name: "opensky_csv", "traffic_json", "so6" or "readsb_trace" (exact, lower case).
/// Throws trailscope::Error(Kind::invalid_argument, param, ...) listing the accepted names otherwise.
Format parse_format(std::string_view text, const std::string& param = "format");

/// The name parse_format() accepts for `f`.
const char* to_string(Format f) noexcept;

/// How many leading (decompressed) bytes detect_format() wants to see; fewer are fine for a short file.
inline constexpr std::size_t kDetectHeadBytes = 64u << 10;

/// Recognises the format from the first bytes of the decompressed content (ideally kDetectHeadBytes, or
/// the whole file when shorter; a trailing partial line or record is fine). A leading UTF-8 BOM is
/// skipped. Rules, in order:
///  - '[' or '{' first: JSON. A top-level object whose keys include "icao" and "trace" is readsb_trace;
///    an array whose first element, or a first JSON Lines object, has the keys "timestamp", "icao24",
///    "latitude" and "longitude" is traffic_json.
///  - a first line with commas: a CSV header, opensky_csv if it names time, icao24, lat and lon
///    (case-insensitive, optionally quoted).
///  - a first line of 20 space-separated fields whose times (hhmmss), dates (yymmdd) and coordinates
///    parse: so6.
/// Throws Error(Kind::unsupported_format, "format", ...) for anything else (empty input, binary data such
/// as an image or an archive, JSON or CSV with other fields, free text); the message says what was seen
/// and lists the supported formats.
Format detect_format(std::string_view head);

}  // namespace trailscope::ingest
