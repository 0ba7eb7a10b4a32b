#pragma once
// Reading a trail file (plain or gzip) into a TrailSet, with a report of what was accepted and why rows
// were rejected. One entry point, ingest_file(), and its twin for bytes already in memory, ingest_bytes();
// the format is detected from content unless given.
//
// Unit normalisation (everything ends up SI: Unix seconds, degrees WGS84, metres, m/s):
//  - opensky_csv: already SI. time → t (s); lat, lon (deg); velocity → speed (m/s); heading → track (deg);
//    vertrate → vrate (m/s); alt = baroaltitude (m), or geoaltitude (m) when baroaltitude is empty;
//    onground (true/false/1/0) → on_ground; callsign trimmed. Rows without lat/lon (OpenSky keeps
//    position-less state vectors) are rejected as "missing position". Empty, null, NULL, None, NaN and
//    \N all mean "unknown".
//  - traffic_json: timestamp in Unix milliseconds (a number ≥ 1e11) or seconds (below), or an ISO 8601
//    string ("2018-05-30T15:21:38Z", optional fraction and ±hh:mm offset; no zone means UTC) → s;
//    altitude ft → m (× 0.3048; "geoaltitude" in ft is the fallback); groundspeed kt → m/s (× 1852/3600);
//    vertical_rate ft/min → m/s (× 0.00508); track deg; optional onground (bool); an icao24 written as
//    a JSON number (pandas may turn "484506" into 484506) is read back as six zero-padded digits.
//  - so6: each segment line gives two points, begin and end: lat/lon in decimal minutes / 60 → deg;
//    FL × 100 ft → m; time from yymmdd + hhmmss UTC taken literally (yy < 70 → 20yy, else 19yy; a segment
//    whose clock wraps past midnight without a date change keeps its literal time and is put in order by
//    the time sort). Flights are keyed by flight_id: icao24 is empty and the callsign slot holds the
//    callsign, or "CALLSIGN/flight_id" when several flight_ids in the file share a callsign, so that
//    distinct flights never merge. The points of a flight are sorted by time and a point whose time
//    equals the previous one is dropped (consecutive segments share their endpoint; a rare same-time
//    pair with different positions keeps the first and counts as a duplicate). speed and track come from
//    the geodesic (GeographicLib WGS84 inverse) to the next point (the last point takes the previous
//    leg), vrate from the altitude difference over the time difference, on_ground is false; a derived
//    speed above kMaxSpeed or |vrate| above kMaxVerticalRate (about 1.5 % of the Europe sample's points:
//    one-point position spikes, clocks wrapping at midnight) is left NaN, the positions are kept. Gap
//    splitting at gap_seconds does not apply: flight_id already delimits a flight, and Douglas-Peucker
//    simplified segments routinely last longer than limits::kFlightGapSeconds; split_jumps does (one
//    flight_id may carry two legs a day apart).
//  - readsb_trace: t = base "timestamp" + dt; alt ft → m, or "ground" → on_ground with alt NaN (readsb
//    sends no altitude on the ground, and 0 would claim sea level); flag 8 marks the altitude as geometric
//    rather than barometric; it is kept as the best altitude the row has (the same fallback as OpenSky's
//    geoaltitude); gs kt → m/s; track deg; baro_rate ft/min → m/s, falling back to geom_rate; icao from
//    "icao" (a "~" prefix, readsb's mark of a non-ICAO address, is dropped);
//    callsign from the details object's "flight" field, carried forward to later rows until it changes
//    (rows before the first details object take the first callsign of the trace).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/core/limits.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/ingest/format.hpp"
#include "trailscope/ingest/reject.hpp"
#include "trailscope/trails/quality.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::ingest {

/// What an ingest did. Counts are of input rows: CSV/SO6/JSON Lines data lines (blank lines are not
/// rows), JSON array records, readsb trace entries.
struct IngestReport {
  Format format = Format::opensky_csv;
  std::size_t rows = 0;      ///< data rows read
  std::size_t accepted = 0;  ///< rows that passed validation (rows = accepted + rejected)
  std::size_t rejected = 0;  ///< rows refused; the first kMaxReportedRejects are listed in `rejects`
  /// Accepted samples dropped because the same aircraft already had one at that time (for SO6: same-time
  /// points that differ, not the endpoints consecutive segments share by design).
  std::size_t duplicates = 0;
  std::size_t flights = 0;      ///< flights in the resulting TrailSet (after gap splitting)
  std::size_t points = 0;       ///< points in the resulting TrailSet
  std::vector<Reject> rejects;  ///< first limits::kMaxReportedRejects rejected rows, in file order
  double seconds = 0;           ///< wall time of the whole ingest
  /// Implausible values in the resulting TrailSet (trails/quality.hpp): speeds, altitudes and the jumps
  /// left after splitting (one-point spikes are never split, so they stay here).
  QualityReport quality;
  /// Flights split at a teleport (IngestOptions::split_jumps), with the largest jumps: the flight that
  /// starts after each, its time and the implied speed (m/s).
  QualityCount jump_splits;
  /// Flights split between two legs, a gap over kLegGapSeconds (IngestOptions::split_jumps), longest
  /// first: the flight that starts after each, its time and the gap (s).
  QualityCount leg_splits;

  /// {"format", "rows", "accepted", "rejected", "duplicates", "flights", "points",
  ///  "rejects": [{"line", "reason"}...], "seconds", "quality": {QualityReport::to_json(), "jump_splits":
  ///  {"count", "examples": [{"flight_id", "callsign", "t", "value", "value_kt"}]}, "leg_splits": {"count",
  ///  "examples": [{"flight_id", "callsign", "t", "value" (s), "value_h"}]}}}.
  nlohmann::json to_json() const;
};

struct IngestOptions {
  /// Skip detection and read as this format (a file that does not fit still fails with a clear Error).
  std::optional<Format> format;
  /// Consecutive samples of one aircraft further apart than this (seconds, > 0) start a new flight.
  /// Not used for SO6 (see above).
  double gap_seconds = limits::kFlightGapSeconds;
  /// Split a flight where it is two legs or teleports (the rule in trails/quality.hpp: a gap over 20 h, or
  /// a confirmed step of at least 50 km beyond 1600 kt; TrailSetBuilder::build). Unset: on for every
  /// format, all of them positional. The rule leaves real position reports whole (the traffic library's
  /// Belevingsvlucht, Zurich and Airbus samples: no split) and one-point spikes in place (still counted in
  /// IngestReport::quality.jumps); false keeps every flight as the reader grouped it.
  std::optional<bool> split_jumps;
  /// Called on the caller's thread with (fraction of the compressed file consumed, "parse") about every
  /// 65,536 rows and (1, "parse") when parsing ends, then (0, "assemble") and (1, "assemble") around
  /// building the TrailSet. May be empty.
  ProgressFn progress;
  /// Checked at the same points; a cancelled ingest throws Error(Kind::cancelled) and returns nothing.
  const CancelToken* cancel = nullptr;
};

/// Reads a plain or gzip-compressed trail file (gzip is recognised by its magic bytes, not the name;
/// concatenated gzip members are read as one stream) and returns its flights.
/// The file is read sequentially once, decompressed on a helper thread while the caller's thread parses.
/// Throws trailscope::Error:
///  - not_found ("path"): the file does not exist; internal ("path"): it exists but cannot be read;
///  - invalid_argument ("gap_seconds"): gap_seconds is not > 0;
///  - unsupported_format ("format"): the content is not one of the formats (see detect_format()), or a
///    forced format whose structure is absent (a CSV header without time/icao24/lat/lon, JSON that is
///    neither records nor a trace);
///  - unprocessable ("file"): a corrupt or truncated gzip stream, a JSON syntax error inside an array or a
///    trace, a file with no data rows, or one whose every row was rejected (the message quotes the first
///    reasons; this is also what a forced line format gives when no line fits it);
///  - cancelled (""): opts.cancel was set;
///  - payload_too_large: more than 2^32 - 1 points (TrailSetBuilder).
/// `report`, when given, is filled on success and left untouched when an exception is thrown.
TrailSet ingest_file(const std::string& path, const IngestOptions& opts = {}, IngestReport* report = nullptr);

/// ingest_file() over bytes already in memory (plain or gzip, as a file's content): the same inflater, the
/// same readers and the same errors, with `name` where the path would be quoted in messages. Nothing is
/// written to disk and no thread is started (the bytes are cut into blocks on the caller's thread), which
/// suits small inputs (a fuzzer's, a test's). Throws what ingest_file() throws, except not_found and the
/// errors about opening or reading a path.
TrailSet ingest_bytes(std::string_view bytes, const std::string& name, const IngestOptions& opts = {},
                      IngestReport* report = nullptr);

}  // namespace trailscope::ingest
