// proto/openapi.yaml and the router list the same routes, and the OpenAPI file quotes every limit.
#include <fstream>
#include <regex>
#include <set>

#include <gtest/gtest.h>

#include "routes/app.hpp"
#include "store/embedded_store.hpp"
#include "test_support.hpp"
#include "limits.hpp"

namespace trailscope::server {
namespace {

std::vector<std::string> openapi_lines() {
  std::ifstream in(test::source_dir() / "proto" / "openapi.yaml");
  EXPECT_TRUE(in.good());
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

TEST(OpenApi, ListsEveryRouteOfTheRouter) {
  std::set<std::string> documented;
  std::string path;
  const std::regex path_re(R"(^  (/[^:]*):\s*$)"), method_re(R"(^    (get|post|put|delete|patch):)");
  for (const auto& l : openapi_lines()) {
    std::smatch m;
    if (std::regex_match(l, m, path_re))
      path = m[1];
    else if (std::regex_search(l, m, method_re)) {
      std::string method = m[1];
      for (char& c : method) c = static_cast<char>(std::toupper(c));
      documented.insert(method + " " + path);
    }
  }
  test::TempDir tmp;
  auto store = std::make_shared<EmbeddedStore>(tmp.path());
  App app(store, store->upload_dir(), {}, 1 << 20);
  const Router router = make_router(app);
  // The WebSocket upgrades are routes of the table too (Router::add_websocket).
  std::set<std::string> routed = {"GET /api/v1/ws", "GET /api/v1/replays/{replay}/ws"};
  for (const auto& r : router.routes()) routed.insert(r.method + " " + r.pattern);
  EXPECT_EQ(documented, routed);
}

// Every operation says the least role it needs (x-role), the same as the route table; the operations
// anyone may call say `security: []`, and only they.
TEST(OpenApi, NamesEveryRoutesRole) {
  std::map<std::string, std::string> documented;
  std::set<std::string> open;
  std::string path, op;
  const std::regex path_re(R"(^  (/[^:]*):\s*$)"), method_re(R"(^    (get|post|put|delete|patch):)"),
      role_re(R"(^      x-role: (\w+)\s*$)"), open_re(R"(^      security: \[\]\s*$)");
  for (const auto& l : openapi_lines()) {
    std::smatch m;
    if (std::regex_match(l, m, path_re)) {
      path = m[1], op.clear();
    } else if (std::regex_search(l, m, method_re)) {
      std::string method = m[1];
      for (char& c : method) c = static_cast<char>(std::toupper(c));
      op = method + " " + path;
    } else if (!op.empty() && std::regex_match(l, m, role_re)) {
      EXPECT_FALSE(documented.count(op)) << op << " has two x-role";
      documented[op] = m[1];
    } else if (!op.empty() && std::regex_match(l, open_re)) {
      open.insert(op);
    }
  }
  test::TempDir tmp;
  auto store = std::make_shared<EmbeddedStore>(tmp.path());
  App app(store, store->upload_dir(), {}, 1 << 20);
  const Router router = make_router(app);
  const std::map<Role, std::string> names = {
      {Role::anyone, "anyone"}, {Role::reader, "reader"}, {Role::writer, "writer"}, {Role::admin, "admin"}};
  std::size_t anyone = 0;
  for (const auto& r : router.routes()) {
    const std::string op = r.method + " " + r.pattern;
    ASSERT_TRUE(documented.count(op)) << op << " has no x-role";
    EXPECT_EQ(documented[op], names.at(r.role)) << op;
    EXPECT_EQ(open.count(op), r.role == Role::anyone ? 1u : 0u) << op << ": security: [] iff x-role anyone";
    anyone += r.role == Role::anyone;
  }
  EXPECT_EQ(documented.size(), router.routes().size());
  EXPECT_EQ(open.size(), anyone);
}

TEST(OpenApi, QuotesEveryLimit) {
  std::map<std::string, std::string> quoted;
  const std::regex re(R"(^  (k[A-Za-z0-9]+): (\S+))");
  for (const auto& l : openapi_lines()) {
    std::smatch m;
    if (std::regex_search(l, m, re)) quoted[m[1]] = m[2];
  }
  namespace L = limits;
  const std::map<std::string, double> actual = {
      {"kMaxUploadBytes", double(L::kMaxUploadBytes)},
      {"kMaxRequestBodyBytes", double(L::kMaxRequestBodyBytes)},
      {"kRequestTimeoutSeconds", L::kRequestTimeoutSeconds},
      {"kUploadTimeoutSeconds", L::kUploadTimeoutSeconds},
      {"kMaxWebSocketMessageBytes", double(L::kMaxWebSocketMessageBytes)},
      {"kMaxQueuedWebSocketMessages", double(L::kMaxQueuedWebSocketMessages)},
      {"kMaxFinishedJobs", double(L::kMaxFinishedJobs)},
      {"kMaxQuerySpanSeconds", L::kMaxQuerySpanSeconds},
      {"kMaxIcao24PerQuery", double(L::kMaxIcao24PerQuery)},
      {"kMaxCallsignPatternLength", double(L::kMaxCallsignPatternLength)},
      {"kMaxPageSize", double(L::kMaxPageSize)},
      {"kDefaultPageSize", double(L::kDefaultPageSize)},
      {"kMaxPointsPerResponse", double(L::kMaxPointsPerResponse)},
      {"kMaxPositionsPerResponse", double(L::kMaxPositionsPerResponse)},
      {"kMaxHistogramBins", L::kMaxHistogramBins},
      {"kMaxTopCallsigns", L::kMaxTopCallsigns},
      {"kMinZoom", L::kMinZoom},
      {"kMaxZoom", L::kMaxZoom},
      {"kMaxKernelRadiusPx", L::kMaxKernelRadiusPx},
      {"kTileCacheBytes", double(L::kTileCacheBytes)},
      {"kFlightGapSeconds", L::kFlightGapSeconds},
      {"kMaxBundleEdges", double(L::kMaxBundleEdges)},
      {"kMaxBundleInputPoints", double(L::kMaxBundleInputPoints)},
      {"kMaxBundlePoints", double(L::kMaxBundlePoints)},
      {"kMaxGraphUploadBytes", double(L::kMaxGraphUploadBytes)},
      {"kMaxStoredBundles", double(L::kMaxStoredBundles)},
      {"kMaxBundleImagePx", L::kMaxBundleImagePx},
      {"kMaxRunBytes", double(L::kMaxRunBytes)},
      {"kMaxRunRows", double(L::kMaxRunRows)},
      {"kMaxRunFrames", double(L::kMaxRunFrames)},
      {"kMaxObjectsPerFrame", double(L::kMaxObjectsPerFrame)},
      {"kMaxTrackIds", double(L::kMaxTrackIds)},
      {"kMaxVideoFrames", double(L::kMaxVideoFrames)},
      {"kMaxVideoPixels", double(L::kMaxVideoPixels)},
      {"kMaxVideoUploadBytes", double(L::kMaxVideoUploadBytes)},
      {"kMaxVideoManifestBytes", double(L::kMaxVideoManifestBytes)},
      {"kMaxVideoLoadBytes", double(L::kMaxVideoLoadBytes)},
      {"kMaxStoredVideos", double(L::kMaxStoredVideos)},
      {"kMaxStoredRuns", double(L::kMaxStoredRuns)},
      {"kMaxRunFramesPerPage", double(L::kMaxRunFramesPerPage)},
      {"kDefaultRunFramesPerPage", double(L::kDefaultRunFramesPerPage)},
      {"kMaxReplays", double(L::kMaxReplays)},
      {"kMaxReplayViewers", double(L::kMaxReplayViewers)},
      {"kMaxImportanceSamples", double(L::kMaxImportanceSamples)},
      {"kMaxSweepRuns", double(L::kMaxSweepRuns)},
      {"kMaxCompareRuns", double(L::kMaxCompareRuns)},
      {"kMaxCompareFrames", double(L::kMaxCompareFrames)},
      {"kMaxCompareTop", double(L::kMaxCompareTop)},
      {"kMaxProjectionRequestRows", double(L::kMaxProjectionRequestRows)},
      {"kMaxProjectionRequestCells", double(L::kMaxProjectionRequestCells)},
      {"kMaxProjectionRows", double(L::kMaxProjectionRows)},
      {"kMaxProjectionColumns", double(L::kMaxProjectionColumns)},
      {"kMaxProjectionTableBytes", double(L::kMaxProjectionTableBytes)},
      {"kMaxExactMdsRows", double(L::kMaxExactMdsRows)},
      {"kMdsLandmarks", double(L::kMdsLandmarks)},
      {"kMaxForceSchemeRows", double(L::kMaxForceSchemeRows)},
      {"kMaxExactTsneRows", double(L::kMaxExactTsneRows)},
      {"kMaxTsneRows", double(L::kMaxTsneRows)},
      {"kMaxPerplexity", double(L::kMaxPerplexity)},
      {"kMaxProjectionIterations", double(L::kMaxProjectionIterations)},
      {"kMaxQualitySample", double(L::kMaxQualitySample)},
      {"kMaxQualityK", double(L::kMaxQualityK)},
      {"kMaxCongestionSpanSeconds", L::kMaxCongestionSpanSeconds},
      {"kMaxCongestionSteps", double(L::kMaxCongestionSteps)},
      {"kMaxSectors", double(L::kMaxSectors)},
      {"kMaxSectorVertices", double(L::kMaxSectorVertices)},
      {"kMaxSectorNameLength", double(L::kMaxSectorNameLength)},
      {"kMaxGridCells", double(L::kMaxGridCells)},
      {"kMaxCongestionResultValues", double(L::kMaxCongestionResultValues)},
      {"kMaxCongestionPieces", double(L::kMaxCongestionPieces)},
      {"kMaxHotspots", double(L::kMaxHotspots)},
      {"kMaxSeparationEvents", double(L::kMaxSeparationEvents)},
      {"kMaxSectorUploadBytes", double(L::kMaxSectorUploadBytes)},
      {"kMaxStoredSectorSets", double(L::kMaxStoredSectorSets)},
      {"kMaxCongestionResults", double(L::kMaxCongestionResults)},
      {"kMaxFlowGridCells", double(L::kMaxFlowGridCells)},
      {"kMaxFlowSectors", double(L::kMaxFlowSectors)},
      {"kMaxFlowLinePoints", double(L::kMaxFlowLinePoints)},
      {"kMaxFlowImagePx", double(L::kMaxFlowImagePx)},
      {"kMaxFlowFieldBytes", double(L::kMaxFlowFieldBytes)},
      {"kFlowMapCacheBytes", double(L::kFlowMapCacheBytes)},
      {"kMinAnimationChunkSeconds", double(L::kMinAnimationChunkSeconds)},
      {"kMaxAnimationChunkSeconds", double(L::kMaxAnimationChunkSeconds)},
      {"kDefaultAnimationChunkSeconds", double(L::kDefaultAnimationChunkSeconds)},
      {"kMaxAnimationChunkSamples", double(L::kMaxAnimationChunkSamples)},
      {"kAnimationCacheBytes", double(L::kAnimationCacheBytes)},
      {"kMaxStreamTrails", double(L::kMaxStreamTrails)},
      {"kMaxStreamPoints", double(L::kMaxStreamPoints)},
      {"kMaxStreamIterations", double(L::kMaxStreamIterations)},
      {"kMaxStreamWindowSeconds", L::kMaxStreamWindowSeconds},
      {"kMaxBundleStreams", double(L::kMaxBundleStreams)},
      {"kBundleStreamWorkers", double(L::kBundleStreamWorkers)},
      {"kBundleStreamMinIntervalMs", double(L::kBundleStreamMinIntervalMs)},
      {"kBundleStreamSettleUpdates", double(L::kBundleStreamSettleUpdates)},
      {"kMaxTokens", double(L::kMaxTokens)},
      {"kMaxTokenNameBytes", double(L::kMaxTokenNameBytes)},
      {"kMaxCachedTokens", double(L::kMaxCachedTokens)},
      {"kMaxFailedAuthPerMinute", double(L::kMaxFailedAuthPerMinute)},
      {"kMaxTrackedAuthAddresses", double(L::kMaxTrackedAuthAddresses)},
      {"kMaxSessions", double(L::kMaxSessions)},
      {"kSessionSeconds", double(L::kSessionSeconds)},
      {"kLoginCodeSeconds", double(L::kLoginCodeSeconds)},
      {"kJobWorkers", double(L::kJobWorkers)},
      {"kMaxQueuedJobsPerOwner", double(L::kMaxQueuedJobsPerOwner)},
      {"kJobRetryAfterSeconds", double(L::kJobRetryAfterSeconds)},
      {"kDiskReserveBytes", double(L::kDiskReserveBytes)},
      {"kMaxJobWriteBytes", double(L::kMaxJobWriteBytes)},
      {"kMaxForceSchemeRequestWork", double(L::kMaxForceSchemeRequestWork)},
      {"kMaxTsneRequestWork", double(L::kMaxTsneRequestWork)},
      {"kMaxImagePixels", double(L::kMaxImagePixels)},
      {"kMaxCompareReadFrames", double(L::kMaxCompareReadFrames)},
      {"kMaxMetricsRows", double(L::kMaxMetricsRows)},
      // The flight dashboard: picking, exports, data quality.
      {"kMaxPickTolerancePx", L::kMaxPickTolerancePx},
      {"kMaxPickResults", double(L::kMaxPickResults)},
      {"kMaxExportPoints", double(L::kMaxExportPoints)},
      {"kExportPieceBytes", double(L::kExportPieceBytes)},
      {"kMaxLegendStops", double(L::kMaxLegendStops)},
      // The network layer's admission limits (net/).
      {"kComputeWorkers", double(L::kComputeWorkers)},
      {"kMaxQueuedComputeRequests", double(L::kMaxQueuedComputeRequests)},
      {"kComputeDeadlineSeconds", double(L::kComputeDeadlineSeconds)},
      {"kRetryAfterSeconds", double(L::kRetryAfterSeconds)},
      {"kRequestsPerSecondPerAddress", L::kRequestsPerSecondPerAddress},
      {"kRequestBurstPerAddress", L::kRequestBurstPerAddress},
      {"kRequestsPerSecondPerToken", L::kRequestsPerSecondPerToken},
      {"kRequestBurstPerToken", L::kRequestBurstPerToken},
      {"kMaxConnectionsPerAddress", double(L::kMaxConnectionsPerAddress)},
      {"kMaxConnections", double(L::kMaxConnections)},
      {"kBodyRateGraceSeconds", double(L::kBodyRateGraceSeconds)},
      {"kMinBodyBytesPerSecond", double(L::kMinBodyBytesPerSecond)},
      {"kMaxRequestHeaderBytes", double(L::kMaxRequestHeaderBytes)},
      // Stored gaze datasets (store/gaze_store.hpp, routes/gaze.cpp).
      {"kMaxGazeUploadBytes", double(L::kMaxGazeUploadBytes)},
      {"kMaxGazeEvents", double(L::kMaxGazeEvents)},
      {"kMaxGazeStimulusBytes", double(L::kMaxGazeStimulusBytes)},
      {"kMaxGazeStimulusPixels", double(L::kMaxGazeStimulusPixels)},
      {"kMaxStoredGazeDatasets", double(L::kMaxStoredGazeDatasets)},
      // Gaze views (compute gazeview/, routes/gaze_views.cpp).
      {"kMaxGazeAois", double(L::kMaxGazeAois)},
      {"kMaxAoiVertices", double(L::kMaxAoiVertices)},
      {"kMaxAoiCoordinatePx", L::kMaxAoiCoordinatePx},
      {"kMaxGazeViewSamples", double(L::kMaxGazeViewSamples)},
  };
  for (const auto& [name, value] : actual) {
    ASSERT_TRUE(quoted.count(name)) << name << " is missing from x-limits";
    EXPECT_DOUBLE_EQ(std::stod(quoted[name]), value) << name;
  }
  EXPECT_EQ(quoted.size(), actual.size());
}

}  // namespace
}  // namespace trailscope::server
