// libFuzzer harness: the ClickHouse store URL (server/src/store/clickhouse_client.cpp ClickHouseUrl::parse,
// what `--store clickhouse://HOST:PORT[,HOST:PORT...]/DB?cluster=NAME` goes through). Besides a clean
// refusal, a URL it accepts must hold what the store relies on (1..16 hosts of [A-Za-z0-9.-] with ports
// 1..65535; a database and a cluster of 1..64 of [A-Za-z0-9_], since they are written into SQL unquoted),
// and must read back the same when written out again.
#include "fuzz_support.hpp"
#include "store/clickhouse_client.hpp"

using namespace trailscope;

namespace {
bool name_ok(const std::string& s) {
  return !s.empty() && s.size() <= 64 &&
         s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") ==
             std::string::npos;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto u = server::ClickHouseUrl::parse(std::string(fuzz::bytes_of(data, size)));
    if (u.hosts.empty() || u.hosts.size() > 16 || !name_ok(u.database) || !name_ok(u.cluster)) std::abort();
    std::string again = "clickhouse://";
    for (std::size_t k = 0; k < u.hosts.size(); ++k) {
      const auto& h = u.hosts[k];
      if (h.port == 0 || h.host.empty() ||
          h.host.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-") !=
              std::string::npos)
        std::abort();
      again += (k ? "," : "") + h.to_string();
    }
    again += "/" + u.database + "?cluster=" + u.cluster;
    const auto v = server::ClickHouseUrl::parse(again);
    if (v.database != u.database || v.cluster != u.cluster || v.hosts.size() != u.hosts.size()) std::abort();
    for (std::size_t k = 0; k < u.hosts.size(); ++k)
      if (v.hosts[k].host != u.hosts[k].host || v.hosts[k].port != u.hosts[k].port) std::abort();
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
