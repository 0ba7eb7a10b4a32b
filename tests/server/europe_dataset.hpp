#pragma once
// The real Europe SO6 day (11,043 flights, 6.4 M points) as a stored dataset for route tests, ingested once
// per test process; tests skip when the shared data is absent.
#include <filesystem>
#include <memory>
#include <string>

#include "store/dataset_store.hpp"
#include "test_support.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::server::test_routes {

inline std::filesystem::path europe_so6() {
  return test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
}

/// The day as ingested by default (with its report in `report` when given).
inline std::shared_ptr<const TrailSet> europe_trails(ingest::IngestReport* report = nullptr) {
  static ingest::IngestReport rep;
  static const auto set =
      std::make_shared<const TrailSet>(ingest::ingest_file(europe_so6().string(), {}, &rep));
  if (report) *report = rep;
  return set;
}

inline std::shared_ptr<Dataset> europe_dataset(const std::string& id) {
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "so6", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = europe_trails();
  return ds;
}

}  // namespace trailscope::server::test_routes
