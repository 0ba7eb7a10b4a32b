#pragma once
// Every limit TrailScope enforces, in one place. README.md ("Limits") and proto/openapi.yaml list the same
// values; tests/server/openapi_test.cpp checks that the OpenAPI file quotes them.
#include <cstddef>
#include <cstdint>

namespace trailscope::limits {

// --- uploads and requests --------------------------------------------------------------------------
/// Largest dataset upload accepted by POST /api/v1/datasets (bytes, compressed as sent). Keeps one
/// upload from filling the disk of a single-machine deployment.
inline constexpr std::uint64_t kMaxUploadBytes = 2ull << 30;  // 2 GiB
/// Largest body of any other request (bytes).
inline constexpr std::uint64_t kMaxRequestBodyBytes = 1u << 20;  // 1 MiB
/// A request must arrive completely within this many seconds (slow-loris protection); uploads get
/// kUploadTimeoutSeconds instead.
inline constexpr int kRequestTimeoutSeconds = 30;
inline constexpr int kUploadTimeoutSeconds = 3600;
/// Largest WebSocket message the server accepts from a client (bytes).
inline constexpr std::size_t kMaxWebSocketMessageBytes = 64u << 10;

/// Ended jobs the server remembers for GET /api/v1/jobs/{id}; older ones are forgotten (404).
inline constexpr std::size_t kMaxFinishedJobs = 1000;

// --- queries -----------------------------------------------------------------------------------------
/// Longest time window a query may ask for, t1 - t0 (seconds): 366 days.
inline constexpr double kMaxQuerySpanSeconds = 366.0 * 86400.0;
/// Most icao24 addresses in one query's `icao24` list.
inline constexpr std::size_t kMaxIcao24PerQuery = 1000;
/// Longest callsign pattern (characters).
inline constexpr std::size_t kMaxCallsignPatternLength = 16;
/// Flights per page of GET .../flights (default kDefaultPageSize).
inline constexpr std::size_t kMaxPageSize = 1000;
inline constexpr std::size_t kDefaultPageSize = 100;
/// Points returned by one response (a flight's GeoJSON); longer flights are refused with 413 unless
/// the client asks for a coarser `max_points` sampling.
inline constexpr std::size_t kMaxPointsPerResponse = 200000;
/// Bins of a summary histogram.
inline constexpr int kMaxHistogramBins = 1000;
inline constexpr int kDefaultHistogramBins = 96;
/// Entries of the summary's top-callsigns list.
inline constexpr int kMaxTopCallsigns = 100;

// --- tiles -------------------------------------------------------------------------------------------
inline constexpr int kMinZoom = 0;
inline constexpr int kMaxZoom = 22;
/// Tile edge lengths served (pixels).
inline constexpr int kTileSizeSmall = 256;
inline constexpr int kTileSizeLarge = 512;
/// Largest KDE kernel radius (pixels) a density request may ask for.
inline constexpr int kMaxKernelRadiusPx = 32;
/// Bytes of rendered PNG tiles kept by the server's LRU cache.
inline constexpr std::size_t kTileCacheBytes = 256u << 20;

// --- ingest ------------------------------------------------------------------------------------------
/// Two consecutive samples of one aircraft further apart than this (seconds) start a new flight.
inline constexpr double kFlightGapSeconds = 1800.0;
/// Rejected rows whose line and reason are kept in an ingest report (all are counted).
inline constexpr std::size_t kMaxReportedRejects = 1000;

// --- bundling ----------------------------------------------------------------------------------------
/// Most polylines (edges or trails) one bundling takes.
inline constexpr std::size_t kMaxBundleEdges = 2'000'000;
/// Most input points of the polylines of one bundling (before resampling).
inline constexpr std::size_t kMaxBundleInputPoints = 50'000'000;
/// Most points after resampling (what the device holds: ~20 bytes each, twice).
inline constexpr std::size_t kMaxBundlePoints = 64'000'000;
/// Largest graph upload, POST /api/v1/graphs (bytes).
inline constexpr std::uint64_t kMaxGraphUploadBytes = 256ull << 20;
/// Bundles the server keeps (the oldest is deleted beyond this).
inline constexpr std::size_t kMaxStoredBundles = 100;
/// Largest rendered bundle image edge (pixels).
inline constexpr int kMaxBundleImagePx = 8192;

}  // namespace trailscope::limits
