#include "store/item_index.hpp"

#include <algorithm>

#include "trailscope/core/error.hpp"

namespace trailscope::server {

std::uint64_t store_id_number(const std::string& id, char prefix) {
  if (id.size() < 2 || id.size() > 20 || id[0] != prefix) return 0;
  std::uint64_t n = 0;
  for (std::size_t i = 1; i < id.size(); ++i) {
    if (id[i] < '0' || id[i] > '9') return 0;
    n = n * 10 + static_cast<std::uint64_t>(id[i] - '0');
  }
  return n;
}

std::string store_id(char prefix, std::uint64_t n) {
  std::string id(1, prefix);
  id += std::to_string(n);  // appended, not `prefix + to_string(n)`: GCC 12 warns falsely on that form
  return id;
}

std::uint64_t ItemIndex::number(const std::string& id) const {
  return store_id_number(id, prefix_);
}

std::string ItemIndex::next_id() {
  return store_id(prefix_, counter_.next());
}

void ItemIndex::add(const std::string& id, nlohmann::json meta) {
  const std::uint64_t n = number(id);
  ids_[n] = id;
  if (meta.is_object() && !meta.contains("owner")) meta["owner"] = "";  // made before owners were recorded
  meta_[id] = std::move(meta);
  counter_.observe(n);
}

void ItemIndex::erase(const std::string& id) {
  ids_.erase(number(id));
  meta_.erase(id);
}

void ItemIndex::check(const std::string& id, const std::string& param) const {
  if (!contains(id)) throw not_found(param, noun_ + " '" + id + "' does not exist");
}

const nlohmann::json& ItemIndex::at(const std::string& id, const std::string& param) const {
  check(id, param);
  return meta_.at(id);
}

nlohmann::json& ItemIndex::at(const std::string& id, const std::string& param) {
  check(id, param);
  return meta_.at(id);
}

std::vector<nlohmann::json> ItemIndex::list() const {
  std::vector<nlohmann::json> out;
  for (const auto& [n, id] : ids_) out.push_back(meta_.at(id));
  return out;
}

}  // namespace trailscope::server
