#include "store/dataset_reads.hpp"

namespace trailscope::server {

Summary LocalReads::summarize(const Dataset& ds, const Query& q, const SummaryOptions& opts) const {
  return trailscope::summarize(*ds.trails, q, opts);
}

FlightPage LocalReads::list_flights(const Dataset& ds, const Query& q, std::size_t page,
                                    std::size_t page_size, const FlightSort& sort) const {
  return trailscope::list_flights(*ds.trails, q, page, page_size, sort);
}

Positions LocalReads::positions_at(const Dataset& ds, double t, const Query& q,
                                   std::size_t max_positions) const {
  return trailscope::positions_at(*ds.trails, t, q, max_positions);
}

std::string LocalReads::density_tile(const Dataset& ds, density::DensityRenderer& renderer,
                                     const std::string& dataset_key, const Query& q,
                                     const density::TileRequest& request) const {
  return std::move(renderer.render_tile(*ds.trails, dataset_key, q, request).png);
}

density::Legend LocalReads::density_legend(const Dataset& ds, density::DensityRenderer& renderer,
                                           const std::string& dataset_key, const Query& q,
                                           const density::TileRequest& request, int stops) const {
  return renderer.legend(*ds.trails, dataset_key, q, request, stops);
}

const DatasetReads& reads_of(const DatasetStore& store) {
  static const LocalReads local;
  if (const auto* own = dynamic_cast<const DatasetReads*>(&store)) return *own;
  return local;
}

}  // namespace trailscope::server
