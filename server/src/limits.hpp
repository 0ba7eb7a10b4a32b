#pragma once
// The limits only the server enforces: requests and uploads, the stores it keeps, jobs, replays and
// synchronous analysis requests. They extend trailscope::limits (compute/include/trailscope/core/limits.hpp,
// the compute library's limits), so every limit reads limits::kName wherever it is used. README.md
// ("Limits") and proto/openapi.yaml list the same values; tests/server/openapi_test.cpp checks that the
// OpenAPI file quotes them.
#include <cstddef>
#include <cstdint>

#include "trailscope/core/limits.hpp"

namespace trailscope::limits {

// --- requests and uploads --------------------------------------------------------------------------
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
/// Messages queued for one WebSocket client; a client that cannot keep up is dropped rather than letting
/// its queue grow without bound.
inline constexpr std::size_t kMaxQueuedWebSocketMessages = 1024;

/// Ended jobs the server remembers for GET /api/v1/jobs/{id}; older ones are forgotten (404).
inline constexpr std::size_t kMaxFinishedJobs = 1000;

// --- queries -----------------------------------------------------------------------------------------
/// Flights per page of GET .../flights when the request does not say (at most kMaxPageSize).
inline constexpr std::size_t kDefaultPageSize = 100;
/// Bins of a summary histogram when `trailscope query` is not told (at most kMaxHistogramBins).
inline constexpr int kDefaultHistogramBins = 96;
/// Points returned by one response (a flight's GeoJSON); longer flights are refused with 413 unless
/// the client asks for a coarser `max_points` sampling.
inline constexpr std::size_t kMaxPointsPerResponse = 200000;
/// Positions in one answer of GET .../positions (and `trailscope query positions`); more are refused with
/// 413 unless the client narrows the filters. The world's busiest instant has about 23,000 aircraft
/// airborne at once, so a whole-world answer fits four times over; at ~250 bytes of JSON per position a
/// full answer is ~25 MB.
inline constexpr std::size_t kMaxPositionsPerResponse = 100000;

// --- picking on the density map --------------------------------------------------------------------
/// Widest picking tolerance (screen pixels) of GET .../pick: a hover halo, not an area query.
inline constexpr double kMaxPickTolerancePx = 32.0;
/// Most flights one pick answers (nearest first).
inline constexpr std::size_t kMaxPickResults = 100;

// --- exports of a window ---------------------------------------------------------------------------
/// Points (CSV rows; GeoJSON coordinates) of one export of a window's flights (GET .../export,
/// `trailscope export`); more is 413 before a byte is sent. The Europe SO6 day (6.4 M points) fits whole:
/// ~600 MB of CSV, streamed a piece at a time, never held in memory.
inline constexpr std::uint64_t kMaxExportPoints = 10'000'000;
/// Bytes of export text built per streamed piece (the work one call of the producer does on the I/O
/// thread).
inline constexpr std::size_t kExportPieceBytes = 256u << 10;
/// Stops of one density legend (GET .../density/legend).
inline constexpr int kMaxLegendStops = 256;

// --- tiles -------------------------------------------------------------------------------------------
/// Bytes of rendered PNG tiles kept by the server's LRU cache.
inline constexpr std::size_t kTileCacheBytes = 256u << 20;

// --- animation chunks ------------------------------------------------------------------------------
/// Length of one chunk of GET .../animation (seconds, an integer; chunks start at multiples of it). Short
/// chunks keep a scrub's first answer small; an hour keeps a day to 24 requests.
inline constexpr int kMinAnimationChunkSeconds = 10;
inline constexpr int kMaxAnimationChunkSeconds = 3600;
inline constexpr int kDefaultAnimationChunkSeconds = 300;
/// Samples in one chunk (bracketing samples included); more are refused with 413. At 29 bytes a sample
/// that is ~116 MB of TSAN; 25,000 aircraft sampled every 10 s fill a 5-minute chunk with ~850k.
inline constexpr std::size_t kMaxAnimationChunkSamples = 4'000'000;
/// Bytes of encoded chunks kept by the server's LRU cache (a day of 25,000 aircraft sampled every 30 s is
/// ~2.5 GB of 5-minute chunks; the cache keeps the hours around a few playheads).
inline constexpr std::size_t kAnimationCacheBytes = 512u << 20;

// --- stores ------------------------------------------------------------------------------------------
/// Bundles the server keeps (the oldest is deleted beyond this).
inline constexpr std::size_t kMaxStoredBundles = 100;
/// Depth videos the server stores (uploads and synthetic); one more is refused (409) until one is deleted,
/// since a user's upload must never disappear to make room.
inline constexpr std::size_t kMaxStoredVideos = 100;
/// Tracker runs the server stores (uploaded logs, track jobs, ended replays); one more is refused (409).
/// Parameter sweeps make a few hundred to a few thousand; a 1000-frame log is about 1 MB.
inline constexpr std::size_t kMaxStoredRuns = 10000;
/// Frame records per page of GET /api/v1/runs/{run}/frames (default kDefaultRunFramesPerPage); a record
/// with its candidates is a few KB of JSON.
inline constexpr std::size_t kMaxRunFramesPerPage = 1000;
inline constexpr std::size_t kDefaultRunFramesPerPage = 100;

// --- live replays ------------------------------------------------------------------------------------
/// Live replays at once: each holds a thread while it tracks and its frame logs in memory.
inline constexpr std::size_t kMaxReplays = 8;
/// Viewers (WebSocket connections) of one replay at once.
inline constexpr std::size_t kMaxReplayViewers = 32;

// --- projections -------------------------------------------------------------------------------------
/// Most rows and cells (rows × columns) of a table POST /api/v1/projections projects: the request is
/// answered synchronously (a t-SNE of 20k rows takes tens of seconds here); larger tables go through
/// `trailscope project`, which reads a CSV file and shows progress.
inline constexpr std::size_t kMaxProjectionRequestRows = 20'000;
inline constexpr std::size_t kMaxProjectionRequestCells = 2'000'000;

// --- bundle streams (GET /api/v1/datasets/{dataset}/bundles/stream, WebSocket) ------------------------
/// Bundle streams open at once: each keeps a streaming bundler of up to kMaxStreamPoints points and runs
/// its updates on the shared workers.
inline constexpr std::size_t kMaxBundleStreams = 4;
/// Threads that run the streams' updates (never the network threads).
inline constexpr unsigned kBundleStreamWorkers = 2;
/// Shortest time between the starts of two updates of one stream, ms: at most 10 updates/s.
inline constexpr int kBundleStreamMinIntervalMs = 100;
/// Updates a stream runs after the client's last control message while the clock stands still (the
/// bundles settle), unless the drift falls below 0.05 px first.
inline constexpr int kBundleStreamSettleUpdates = 100;
// --- congestion: uploaded sectors and the results of congestion jobs ---------------------------------
/// Largest sector upload, POST /api/v1/sectors (bytes of GeoJSON, read in memory): limits::kMaxSectors
/// sectors of a few hundred vertices each fit many times over.
inline constexpr std::uint64_t kMaxSectorUploadBytes = 16u << 20;  // 16 MiB
/// Sector sets the server stores; one more is refused (409) until one is deleted, since an upload must
/// never disappear to make room.
inline constexpr std::size_t kMaxStoredSectorSets = 1000;
/// Results of finished congestion jobs kept in memory for GET /api/v1/congestion/{job} (the oldest is
/// dropped beyond this; its job stays listed). One result holds at most
/// limits::kMaxCongestionResultValues series values (~12 bytes each) and
/// limits::kMaxSeparationEvents events, so this bounds what finished jobs hold.
inline constexpr std::size_t kMaxCongestionResults = 8;

// --- access control (auth/: tokens, sessions, sign-in) -----------------------------------------------
/// Tokens the server stores in <data-dir>/tokens.json; one more is refused (409) until one is revoked.
/// Bounds the file every start (and every change by the CLI) rereads.
inline constexpr std::size_t kMaxTokens = 1000;
/// Longest token name (bytes): the owner name resources record.
inline constexpr std::size_t kMaxTokenNameBytes = 64;
/// Verified tokens kept in memory (keyed BLAKE2b of the token text → who it is), so that Argon2id (tens of
/// milliseconds and 64 MiB by design) runs once per token, not once per request. The oldest is dropped
/// beyond this.
inline constexpr std::size_t kMaxCachedTokens = 1024;
/// Failed token checks one address may cause per minute; beyond this its token checks are refused with
/// 429 (Retry-After: the rest of the minute) without running Argon2id, so invalid tokens cannot be used
/// to burn CPU or guess secrets.
inline constexpr int kMaxFailedAuthPerMinute = 20;
/// Addresses whose failed checks are counted at once (the oldest window is forgotten beyond this).
inline constexpr std::size_t kMaxTrackedAuthAddresses = 10000;
/// Browser sessions (the trailscope_session cookie) kept in memory, and how long one lasts (seconds).
inline constexpr std::size_t kMaxSessions = 10000;
inline constexpr int kSessionSeconds = 86400;
/// How long the one-time sign-in code that `trailscope serve` prints stays valid (seconds).
inline constexpr int kLoginCodeSeconds = 3600;
// --- ownership, ids and the admission of jobs and heavy requests --------------------------------------
/// Threads that run jobs: a short ingest does not wait behind a long synth (the reference machine has 2
/// cores; the compute pool and the I/O threads share them).
inline constexpr unsigned kJobWorkers = 2;
/// Jobs one owner may have queued or running at once; one more is refused with 429 and Retry-After
/// kJobRetryAfterSeconds, so that one client cannot queue work ahead of everyone else.
inline constexpr std::size_t kMaxQueuedJobsPerOwner = 8;
inline constexpr int kJobRetryAfterSeconds = 10;
/// Free disk space (bytes) the jobs never write into: the stores' metadata, the id counters, logs and the
/// system keep working when the jobs have used up what they may.
inline constexpr std::uint64_t kDiskReserveBytes = 1ull << 30;  // 1 GiB
/// Most bytes one job may write (a synthetic video, an ingested dataset, a bundle), checked against its
/// estimate before it starts writing and against what it has written while it writes. A video pack stops
/// at kMaxVideoUploadBytes anyway; a dataset from a 2 GiB upload takes a few GB of columns.
inline constexpr std::uint64_t kMaxJobWriteBytes = 8ull << 30;  // 8 GiB
/// Work of one synchronous POST /api/v1/projections, checked before it starts (larger work goes through
/// `trailscope project`). Force Scheme: rows² × iterations (every pair each iteration); 5,000 rows × 100
/// iterations (2.5e9) took 34 s here, so the budget is ~7 s of it. t-SNE: rows × (250 exaggeration + main
/// iterations); 5,000 rows at the default 750 (3.75e6) took 11 s, 20,000 rows 38 s.
inline constexpr std::uint64_t kMaxForceSchemeRequestWork = 500'000'000;
inline constexpr std::uint64_t kMaxTsneRequestWork = 3'750'000;
/// Pixels (width × height) of one GET /api/v1/bundles/{bundle}/image.png: rendering needs ~40 bytes per
/// pixel, so 4096² peaks near 670 MB (8192² took 12 s and 2.6 GB).
inline constexpr std::uint64_t kMaxImagePixels = 4096ull * 4096ull;
/// Frames of all runs one POST /api/v1/compare reads, checked from the stored rows before any log is read
/// (kMaxCompareRuns runs of kMaxVideoFrames frames; kMaxCompareFrames then bounds the frames they share).
inline constexpr std::uint64_t kMaxCompareReadFrames = 800'000;
/// Rows (ground truth plus result) one POST /api/v1/metrics reads; MOT17's largest result has ~60,000.
inline constexpr std::uint64_t kMaxMetricsRows = 2'000'000;
// --- network admission (net/): compute pool, rate limits, connections, slow bodies -------------------
/// Threads of the compute pool that runs the handlers of Lane::compute routes (net/compute_pool.hpp), niced
/// so that the network threads keep answering while they work.
inline constexpr unsigned kComputeWorkers = 4;
/// Compute requests waiting for a worker; one more is refused with 503 and Retry-After.
inline constexpr std::size_t kMaxQueuedComputeRequests = 256;
/// A compute request that has not finished this many seconds after it was queued is cancelled (its
/// CancelToken is set) and answered 503 with Retry-After.
inline constexpr int kComputeDeadlineSeconds = 60;
/// Retry-After (seconds) of a 503 from a full compute queue, a passed deadline or a connection cap.
inline constexpr int kRetryAfterSeconds = 2;
/// Token buckets: requests per second and burst, per client address (an IPv6 address counts by its /64)
/// and per API token; one more is refused with 429 and Retry-After.
inline constexpr double kRequestsPerSecondPerAddress = 500;
inline constexpr double kRequestBurstPerAddress = 1000;
inline constexpr double kRequestsPerSecondPerToken = 500;
inline constexpr double kRequestBurstPerToken = 1000;
/// Open connections (WebSocket connections of the job-events endpoint included) per client address and in
/// all; a connection beyond either is answered 503 and closed.
inline constexpr std::size_t kMaxConnectionsPerAddress = 128;
inline constexpr std::size_t kMaxConnections = 4096;
/// Slow bodies: after a grace period (seconds) a request body must have arrived at this average rate
/// (bytes/s), else 408; a body without a byte for the grace period is 408 too.
inline constexpr int kBodyRateGraceSeconds = 10;
inline constexpr std::uint64_t kMinBodyBytesPerSecond = 4096;
/// Largest request header (request line and fields, bytes); a larger one is refused with 431.
inline constexpr std::size_t kMaxRequestHeaderBytes = 16u << 10;

// --- stored gaze datasets (store/gaze_store.hpp, routes/gaze.cpp) ------------------------------------
/// Largest gaze file upload of POST /api/v1/gaze (bytes): the whole file is parsed in memory, so no more
/// than the compute library reads (kMaxGazeFileBytes).
inline constexpr std::uint64_t kMaxGazeUploadBytes = kMaxGazeFileBytes;
/// Most events one answer of GET .../gaze/{id}/events lists (and fixations of one .../scanpaths answer);
/// more is 413 (narrow the filters). ~150 bytes of JSON each: ~75 MB at most.
inline constexpr std::size_t kMaxGazeEvents = 500'000;
/// Largest stimulus image of PUT .../gaze/{id}/stimulus (bytes; PNG or JPEG).
inline constexpr std::uint64_t kMaxGazeStimulusBytes = 32u << 20;  // 32 MiB
/// Most pixels (width x height) of a stimulus image, read from its header before it is decoded (~4 bytes
/// each while decoding): a 50 MP photograph, far above any stimulus screen.
inline constexpr std::uint64_t kMaxGazeStimulusPixels = 50'000'000;
/// Gaze datasets the server stores; one more is refused (409).
inline constexpr std::size_t kMaxStoredGazeDatasets = 1000;

// --- gaze views (routes/gaze_views.cpp) ---------------------------------------------------------------
/// Most samples (all selected recordings together) one gaze view reads: a stimulus-space tile or legend
/// bins them and sorts their pixel keys for the zoom's shared span, AOI and bundle requests detect events
/// in them. More is 413 (narrow the filters).
inline constexpr std::uint64_t kMaxGazeViewSamples = 20'000'000;

// --- flow-map tiles ----------------------------------------------------------------------------------
/// Bytes of flow maps (streamlines and their bundles; store/flow_map_cache.hpp) kept for the flow tiles:
/// a map is computed once per dataset, window and flow parameters and every tile is drawn from it. A map
/// costs about 60 bytes per streamline point (the lines, their bundled and original copies, per-point
/// values), so the largest a request may ask for (limits::kMaxFlowLinePoints) fits twice.
inline constexpr std::size_t kFlowMapCacheBytes = 256u << 20;

}  // namespace trailscope::limits
