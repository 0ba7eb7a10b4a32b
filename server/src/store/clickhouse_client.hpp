#pragma once
// A small HTTP client for ClickHouse's HTTP interface (https://clickhouse.com/docs/en/interfaces/http), over
// Boost.Beast: one request per connection, a deadline on every step, and failover across the listed nodes.
// ClickHouse 18.16 (Debian 12) is the oldest server it talks to: no query parameters, so callers quote
// literals with quote() and pass settings as URL parameters.
#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/core/error.hpp"

namespace trailscope::server {

/// One node's HTTP address.
struct ClickHouseEndpoint {
  std::string host;
  unsigned short port = 8123;
  std::string to_string() const { return host + ":" + std::to_string(port); }
};

/// A parsed `--store clickhouse://HOST:PORT[,HOST:PORT...]/DB?cluster=NAME` URL.
struct ClickHouseUrl {
  std::vector<ClickHouseEndpoint> hosts;  ///< 1..16 nodes, in failover order
  std::string database;                   ///< [A-Za-z0-9_], 1..64 chars
  std::string cluster;                    ///< the cluster name of the nodes' remote_servers, same charset
  /// Parses `url`; throws invalid_argument(param) with what is wrong (scheme, host, port, database,
  /// cluster, unknown parameter).
  static ClickHouseUrl parse(const std::string& url, const std::string& param = "--store");
};

/// A query ClickHouse refused (HTTP status != 200): the server's message, and its exception code
/// ("Code: N") when it gave one (0 otherwise).
class ClickHouseError : public Error {
 public:
  ClickHouseError(int code, const std::string& message)
      : Error(Kind::internal, "store", "ClickHouse: " + message), code_(code) {}
  int code() const noexcept { return code_; }

 private:
  int code_;
};

class ClickHouseClient {
 public:
  struct Timeouts {
    std::chrono::milliseconds connect{3000};    ///< per node
    std::chrono::milliseconds request{600000};  ///< sending the request and reading the whole answer
  };
  ClickHouseClient(std::vector<ClickHouseEndpoint> hosts, Timeouts timeouts);
  ClickHouseClient(std::vector<ClickHouseEndpoint> hosts) : ClickHouseClient(std::move(hosts), Timeouts{}) {}

  using Settings = std::map<std::string, std::string>;
  /// Runs `sql` (the query as the body) and returns the answer's body. With `data`, `sql` goes into the URL
  /// and `data` is the body (INSERT ... FORMAT RowBinary). Settings become URL parameters. Tries the nodes
  /// in order starting from the last one that answered; a node that cannot be reached (refused, reset,
  /// connect timeout) is skipped. An INSERT is sent to the next node only when the previous one could not
  /// be connected to, never after its body was sent. Throws ClickHouseError when a node refuses the query,
  /// Error(unavailable, "store") when no node answers, request_timeout when the answer does not end in time.
  std::string query(const std::string& sql, const Settings& settings = {}, std::string_view data = {});

  const std::vector<ClickHouseEndpoint>& hosts() const { return hosts_; }
  /// Quotes a string literal for SQL ('...' with \\ and \' escaped).
  static std::string quote(std::string_view s);

 private:
  std::vector<ClickHouseEndpoint> hosts_;
  Timeouts timeouts_;
  std::mutex mu_;
  std::size_t preferred_ = 0;
};

}  // namespace trailscope::server
