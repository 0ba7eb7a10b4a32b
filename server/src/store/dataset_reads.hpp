#pragma once
// The reads the window routes answer from (summary, flight list, positions at an instant, density tiles),
// beside the DatasetStore interface (dataset_store.hpp): a backend that can compute them where its rows are
// implements DatasetReads too (the ClickHouse store, clickhouse_store.hpp, runs them on its shards);
// every other store is read by LocalReads, the computation on the dataset's trails in this process (the
// embedded store's). A route calls reads_of(*app.store).one_function(...) and never computes on
// ds->trails itself for these, so its bytes do not depend on the backend.
#include <cstddef>

#include "store/dataset_store.hpp"
#include "trailscope/density/renderer.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/summary.hpp"

namespace trailscope::server {

/// `ds` is always a dataset the same store's get() returned. Each function answers exactly what the
/// compute/ function it names answers for ds.trails, and throws what that function throws (plus a
/// backend's own errors: Error(unavailable, "store"), ClickHouseError, ...).
class DatasetReads {
 public:
  virtual ~DatasetReads() = default;
  /// trails/summary.hpp summarize().
  virtual Summary summarize(const Dataset& ds, const Query& q, const SummaryOptions& opts) const = 0;
  /// trails/summary.hpp list_flights().
  virtual FlightPage list_flights(const Dataset& ds, const Query& q, std::size_t page, std::size_t page_size,
                                  const FlightSort& sort) const = 0;
  /// trails/positions.hpp positions_at().
  virtual Positions positions_at(const Dataset& ds, double t, const Query& q,
                                 std::size_t max_positions) const = 0;
  /// density/renderer.hpp DensityRenderer::render_tile() of `renderer` (the server's one, whose span
  /// cache `dataset_key` keys); the tile's PNG bytes.
  virtual std::string density_tile(const Dataset& ds, density::DensityRenderer& renderer,
                                   const std::string& dataset_key, const Query& q,
                                   const density::TileRequest& request) const = 0;
  /// density/renderer.hpp DensityRenderer::legend() of `renderer`: the legend of the tiles `request`
  /// describes, from the same span they are shaded with.
  virtual density::Legend density_legend(const Dataset& ds, density::DensityRenderer& renderer,
                                         const std::string& dataset_key, const Query& q,
                                         const density::TileRequest& request, int stops) const = 0;
};

/// compute/'s functions on ds.trails, in this process.
class LocalReads final : public DatasetReads {
 public:
  Summary summarize(const Dataset& ds, const Query& q, const SummaryOptions& opts) const override;
  FlightPage list_flights(const Dataset& ds, const Query& q, std::size_t page, std::size_t page_size,
                          const FlightSort& sort) const override;
  Positions positions_at(const Dataset& ds, double t, const Query& q,
                         std::size_t max_positions) const override;
  std::string density_tile(const Dataset& ds, density::DensityRenderer& renderer,
                           const std::string& dataset_key, const Query& q,
                           const density::TileRequest& request) const override;
  density::Legend density_legend(const Dataset& ds, density::DensityRenderer& renderer,
                                 const std::string& dataset_key, const Query& q,
                                 const density::TileRequest& request, int stops) const override;
};

/// The reads of `store`: its own when it implements DatasetReads, else LocalReads. Never throws.
const DatasetReads& reads_of(const DatasetStore& store);

}  // namespace trailscope::server
