#include "store/dataset_store.hpp"

#include <cctype>

#include "trailscope/core/error.hpp"

namespace trailscope::server {

void validate_dataset_id(const std::string& id, const std::string& param) {
  const bool ok = !id.empty() && id.size() <= 64 &&
                  id.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-") == std::string::npos;
  if (!ok)
    throw invalid_argument(param, param + ": '" + id + "' is not a valid dataset id (1-64 of a-z 0-9 _ -)");
}

std::string dataset_id_from_name(const std::string& name) {
  std::string id;
  for (char c : name) {
    const unsigned char u = static_cast<unsigned char>(std::tolower(static_cast<unsigned char>(c)));
    const bool keep = std::isalnum(u) || u == '_' || u == '-';
    if (keep)
      id.push_back(static_cast<char>(u));
    else if (!id.empty() && id.back() != '-')
      id.push_back('-');
    if (id.size() == 64) break;
  }
  while (!id.empty() && id.back() == '-') id.pop_back();
  return id;
}

nlohmann::json Dataset::to_json() const {
  const TrailSet& t = shape();
  double alt_max = 0;
  for (const Flight& f : t.flights())
    if (f.alt_max == f.alt_max && f.alt_max > alt_max) alt_max = f.alt_max;
  return {{"id", id},
          {"name", name},
          {"format", format},
          {"created", created},
          {"flights", t.num_flights()},
          {"points", num_points()},
          {"t_min", t.t_min()},
          {"t_max", t.t_max()},
          {"bbox", {t.lon_min(), t.lat_min(), t.lon_max(), t.lat_max()}},
          {"alt_max_m", alt_max},
          {"ingest", ingest},
          {"owner", owner}};
}

}  // namespace trailscope::server
