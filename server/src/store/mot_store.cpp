#include "store/mot_store.hpp"

#include <algorithm>
#include <set>

#include "store/column_io.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/metrics/mot_text.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
constexpr char kMagic[] = "TRAILSCOPE-MOT-1";

/// Rows, last frame and distinct ids of parsed records.
template <typename Rows>
nlohmann::json figures(const Rows& rows) {
  std::int64_t last = 0;
  std::set<std::int64_t> ids;
  for (const auto& r : rows) last = std::max(last, r.frame), ids.insert(r.id);
  return {{"rows", rows.size()}, {"frames", last}, {"ids", ids.size()}};
}

}  // namespace

MotStore::MotStore(fs::path root)
    : rows_(std::move(root), {"mot", 'm', ".txt", kMagic, "MOT file", "MOT files", "mot"}) {}

std::vector<nlohmann::json> MotStore::list() const {
  return rows_.list();
}

nlohmann::json MotStore::meta(const std::string& id, const std::string& param) const {
  return rows_.meta(id, param);
}

std::string MotStore::text(const std::string& id, const std::string& param) const {
  return rows_.read_payload(id, param, [&](const fs::path& p) { return metrics::read_text_file(p, param); });
}

nlohmann::json MotStore::put(const std::string& name, const std::string& kind, const std::string& text,
                             const std::string& owner) {
  nlohmann::json row;
  if (kind == "gt")
    row = figures(metrics::parse_mot_gt(text, "body"));
  else if (kind == "result")
    row = figures(metrics::parse_mot_run(text, "body"));
  else if (kind == "points")
    row = figures(metrics::parse_points(text, "body"));
  else
    throw invalid_argument("kind", "kind must be gt, result or points, got '" + kind + "'");
  row["name"] = name;
  row["kind"] = kind;
  row["owner"] = owner;
  return rows_.put(std::move(row), [&](const fs::path& p) { write_file_atomic(p, text); });
}

void MotStore::remove(const std::string& id) {
  rows_.remove(id);
}

}  // namespace trailscope::server
