#pragma once
// Every limit the compute library enforces, in one place; the server's own limits (requests, uploads,
// stores, replays) are in server/src/limits.hpp, in the same namespace. README.md ("Limits") and
// proto/openapi.yaml list the values of both; tests/server/openapi_test.cpp checks that the OpenAPI file
// quotes them.
#include <cstddef>
#include <cstdint>

namespace trailscope::limits {

// --- queries -----------------------------------------------------------------------------------------
/// Longest time window a query may ask for, t1 - t0 (seconds): 366 days.
inline constexpr double kMaxQuerySpanSeconds = 366.0 * 86400.0;
/// Most icao24 addresses in one query's `icao24` list.
inline constexpr std::size_t kMaxIcao24PerQuery = 1000;
/// Longest callsign pattern (characters).
inline constexpr std::size_t kMaxCallsignPatternLength = 16;
/// Flights per page of GET .../flights (default limits::kDefaultPageSize, server/src/limits.hpp).
inline constexpr std::size_t kMaxPageSize = 1000;
/// Bins of a summary histogram.
inline constexpr int kMaxHistogramBins = 1000;
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
/// Largest rendered bundle image edge (pixels).
inline constexpr int kMaxBundleImagePx = 8192;

// --- streaming bundling (bundling/streaming.hpp) -------------------------------------------------------
/// Most trails one streaming bundler holds at once (the window's trails).
inline constexpr std::size_t kMaxStreamTrails = 100'000;
/// Most points (after the entry resampling) one streaming bundler holds: ~50 ms per iteration on one
/// core of the 2-core build machine at this size.
inline constexpr std::size_t kMaxStreamPoints = 4'000'000;
/// Most CUBu iterations per streaming update.
inline constexpr int kMaxStreamIterations = 5;
/// Longest window W of a stream, seconds (a day).
inline constexpr double kMaxStreamWindowSeconds = 86400.0;

// --- tracker metrics (MOTChallenge text files) -----------------------------------------------------
/// Largest ground-truth or tracker-run text file one evaluation reads (bytes). MOT17's biggest result
/// file is about 5 MB; this leaves room for long teat-tracker logs without letting one request exhaust
/// memory (each row costs ~80 bytes once parsed).
inline constexpr std::uint64_t kMaxRunBytes = 256ull << 20;  // 256 MiB
/// Most data rows in one ground-truth or run file.
inline constexpr std::size_t kMaxRunRows = 5'000'000;
/// Largest frame number a row may carry; frames are 1-based and every frame up to the last costs a
/// little memory even when empty.
inline constexpr std::int64_t kMaxRunFrames = 1'000'000;
/// Most objects (rows) of one file in one frame: similarity is computed for every ground-truth/run pair
/// and the per-frame assignment is O(n^3) in the worst case, so this bounds the work per frame (MOT20,
/// the densest benchmark, has about 250).
inline constexpr std::size_t kMaxObjectsPerFrame = 1000;
/// Most distinct object ids in one file. The identity (IDF1) assignment is dense over the ids of each
/// connected group of overlapping tracks, so this bounds its memory (8 bytes per id pair) and time.
inline constexpr std::size_t kMaxTrackIds = 10000;

// --- tracker (depth videos, synthetic ToF camera) ----------------------------------------------------
/// Most frames of one depth video: an hour at 25 fps with room to spare (the teat-tracker paper's
/// real-life videos are "several minutes each"). Bounds the manifest and every per-frame array.
inline constexpr std::size_t kMaxVideoFrames = 100'000;
/// Most pixels of one depth frame: 1024 x 1024 holds the 176x144 ToF imagers, Kinect v2 (512x424) and
/// the 640x480 structured-light frames.
inline constexpr std::size_t kMaxVideoPixels = 1u << 20;
/// Largest depth-video upload (a pack file, bytes); the same bound as dataset uploads.
inline constexpr std::uint64_t kMaxVideoUploadBytes = 2ull << 30;  // 2 GiB
/// Largest manifest.json (bytes): a frame with ground truth takes up to ~1.1 KB (17-digit numbers, one
/// line per frame), so kMaxVideoFrames need ~110 MB.
inline constexpr std::uint64_t kMaxVideoManifestBytes = 256ull << 20;
/// Most memory one whole-video load may take (frames * pixels * 8 bytes of float depth + amplitude);
/// longer videos are read frame by frame (DepthVideoReader).
inline constexpr std::uint64_t kMaxVideoLoadBytes = 4ull << 30;  // 4 GiB

// Projections
/// Most rows (points) of a table to project: the t-SNE kNN and the quality metrics are brute force, so
/// this bounds their O(N²) distance work (100k points take minutes, 200k four times that).
inline constexpr std::size_t kMaxProjectionRows = 200'000;
/// Most columns (dimensions) of a table to project; also bounds the D×D covariance of PCA.
inline constexpr std::size_t kMaxProjectionColumns = 1000;
/// Largest table file `trailscope project` reads (bytes).
inline constexpr std::uint64_t kMaxProjectionTableBytes = 1ull << 30;  // 1 GiB
/// Rows up to which MDS is exact (the N² matrix B, 4 bytes an entry: 36 MB at 3000); above it,
/// landmark MDS on kMdsLandmarks landmarks.
inline constexpr std::size_t kMaxExactMdsRows = 3000;
inline constexpr std::size_t kMdsLandmarks = 500;
/// Most rows of a Force Scheme projection (it keeps the N² distance matrix: 100 MB at 5000).
inline constexpr std::size_t kMaxForceSchemeRows = 5000;
/// Rows up to which t-SNE uses the exact O(N²) gradient; Barnes-Hut above.
inline constexpr std::size_t kMaxExactTsneRows = 500;
/// Most rows of a t-SNE (the kNN is brute force, O(N²·D)).
inline constexpr std::size_t kMaxTsneRows = 100'000;
/// Largest t-SNE perplexity; each point has ⌊3·perplexity⌋ neighbours (≤ 300, the kNN kernel keeps
/// them in private memory).
inline constexpr double kMaxPerplexity = 100.0;
/// Most iterations of an iterative projection (t-SNE phases, Force Scheme).
inline constexpr int kMaxProjectionIterations = 10'000;
/// Rows up to which the quality metrics are exact; above, this many sampled query rows.
inline constexpr std::size_t kMaxQualitySample = 2000;
/// Largest neighbourhood size k of the quality metrics.
inline constexpr int kMaxQualityK = 100;

// Parameter studies
/// Most runs (samples) a parameter-importance computation takes (the forest sorts them at every split).
inline constexpr std::size_t kMaxImportanceSamples = 100'000;
/// Most tracker runs one sweep may start (parameter points x videos).
inline constexpr std::size_t kMaxSweepRuns = 5000;
/// Most runs compared side by side (lanes of the aligned timelines; the disagreement score is pairwise).
inline constexpr std::size_t kMaxCompareRuns = 8;
/// Most shared frames of a comparison: its series are ~12 numbers per run and frame of JSON, so 8 runs of
/// this many frames are ~20 MB.
inline constexpr std::size_t kMaxCompareFrames = 50'000;
/// Most disagreement frames one comparison lists.
inline constexpr std::size_t kMaxCompareTop = 1000;

// --- congestion: losses of separation and the congestion map ---------------------------------------
/// Most events one losses-of-separation computation returns (each ~250 bytes of JSON); a window with
/// more is refused (narrow it with t0/t1, bbox, the altitude band, callsign or icao24).
inline constexpr std::size_t kMaxSeparationEvents = 100'000;

// --- congestion counts (congestion/counts.hpp, congestion/volumes.hpp) ------------------------------
/// Longest window [t0, t1) of one congestion count (seconds): a week of traffic.
inline constexpr double kMaxCongestionSpanSeconds = 7.0 * 86400.0;
/// Most counting periods (and, separately, entry windows) of one count: a day at 1 s steps fits.
inline constexpr std::size_t kMaxCongestionSteps = 100'000;
/// Most sectors in one upload or one count.
inline constexpr std::size_t kMaxSectors = 1000;
/// Most vertices of one sector's ring (the self-intersection check is quadratic in them).
inline constexpr std::size_t kMaxSectorVertices = 10'000;
/// Longest sector name (bytes).
inline constexpr std::size_t kMaxSectorNameLength = 64;
/// Most cells of a grid extent (bbox x altitude band). The whole world from 0 to 60,000 ft is ~7.8M
/// cells; only cells some flight enters cost memory.
inline constexpr std::uint64_t kMaxGridCells = 10'000'000;
/// Most non-zero series values plus complexity rows in one answer (~12 bytes each in memory, ~20 in
/// JSON): the Europe SO6 day on the grid at 1-min periods gives about 2.5M.
inline constexpr std::size_t kMaxCongestionResultValues = 20'000'000;
/// Most volume visits (a flight's maximal stay in one volume) one count keeps (~100 bytes each while
/// counting); the Europe SO6 day on the grid has about 0.7M.
inline constexpr std::size_t kMaxCongestionPieces = 40'000'000;
/// Most hotspots listed in one answer (the largest excesses; all are counted).
inline constexpr std::size_t kMaxHotspots = 10'000;

// --- gaze (gaze/ingest.hpp, gaze/events.hpp) ---------------------------------------------------------
/// Largest gaze file one ingest reads (bytes): the whole file is parsed in memory (~3 bytes of parsed
/// sample per byte of text at worst). An hour of 2 kHz binocular EyeLink ASC is about 450 MB.
inline constexpr std::uint64_t kMaxGazeFileBytes = 1ull << 30;  // 1 GiB
/// Most samples of one gaze file, all recordings together (~26 bytes each once parsed).
inline constexpr std::size_t kMaxGazeSamples = 50'000'000;
/// Most recordings (trials, blocks, sessions) of one gaze file.
inline constexpr std::size_t kMaxGazeRecordings = 100'000;
/// Largest window (samples) of the I-DT dispersion test and of the adaptive threshold's noise estimate.
inline constexpr std::size_t kMaxGazeWindowSamples = 100'000;
// --- gaze views (gazeview/): AOIs, stimulus-space tiles, saccade bundling -----------------------------
/// Most areas of interest in one AOI query (the transition matrix is their square).
inline constexpr std::size_t kMaxGazeAois = 256;
/// Most vertices of all AOIs of one query together, a rectangle counting 4 (a fixation meets them all).
inline constexpr std::size_t kMaxAoiVertices = 4096;
/// Largest |coordinate| of an AOI corner or vertex (stimulus px): polygons are tested in float
/// (cv::pointPolygonTest), which keeps 1/16 px here, and a double beyond float's range would not convert.
inline constexpr double kMaxAoiCoordinatePx = 1'000'000;
// --- flow maps (flow/): sector velocity fields, evenly spaced streamlines, their bundling -----------
/// Most cells along either side of a flow field grid (traffic fields and uploaded fields alike).
inline constexpr int kMaxFlowGridCells = 1024;
/// Most heading sectors of a traffic field (one vector field each).
inline constexpr int kMaxFlowSectors = 16;
/// Most streamline points of one flow map over all sectors (~40 bytes each with the bundle). Checked
/// up front against the packing bound of the spacing (flow/streamlines.hpp) and again while tracing.
inline constexpr std::size_t kMaxFlowLinePoints = 2'000'000;
/// Largest flow map image edge (pixels).
inline constexpr int kMaxFlowImagePx = 4096;
/// Largest uploaded vector field file (bytes; proto/flow_field.md).
inline constexpr std::uint64_t kMaxFlowFieldBytes = 64ull << 20;

}  // namespace trailscope::limits
