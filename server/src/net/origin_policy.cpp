#include "net/origin_policy.hpp"

#include <algorithm>

#include <boost/asio/ip/address.hpp>

#include "trailscope/core/error.hpp"

namespace trailscope::server {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// "host:port" → {host, port}; "[v6]:port" → {"[v6]", port}; no port → {s, ""}.
std::pair<std::string, std::string> split_host_port(const std::string& s) {
  const auto colon = s.rfind(':');
  const auto bracket = s.rfind(']');
  if (colon == std::string::npos || (bracket != std::string::npos && colon < bracket)) return {s, ""};
  if (s.front() != '[' && s.find(':') != colon) return {s, ""};  // a bare IPv6 address
  return {s.substr(0, colon), s.substr(colon + 1)};
}

bool is_ip_literal(const std::string& host) {
  std::string h = host;
  if (h.size() > 2 && h.front() == '[' && h.back() == ']')
    h = h.substr(1, h.size() - 2);
  else if (h.find(':') != std::string::npos)
    return false;  // IPv6 in a Host must be bracketed
  boost::system::error_code ec;
  boost::asio::ip::make_address(h, ec);
  return !ec;
}

}  // namespace

OriginPolicy::OriginPolicy(std::string listen_host, unsigned short port,
                           std::vector<std::string> server_names, std::vector<std::string> allowed_origins)
    : port_(port) {
  const std::string p = std::to_string(port);
  if (server_names.empty()) {
    boost::system::error_code ec;
    const auto a = boost::asio::ip::make_address(listen_host, ec);
    wildcard_ = !ec && a.is_unspecified();
    if (!ec && a.is_v6()) listen_host = "[" + a.to_string() + "]";
    for (const std::string& n :
         {listen_host, std::string("localhost"), std::string("127.0.0.1"), std::string("[::1]")}) {
      names_.push_back(lower(n) + ":" + p);
      bare_.push_back(lower(n));  // a Host without a port (non-browser clients; a browser names the port)
    }
  } else {
    for (const auto& n : server_names) names_.push_back(lower(n));
  }
  for (auto o : allowed_origins) {
    o = lower(o);
    while (!o.empty() && o.back() == '/') o.pop_back();
    origins_.push_back(o);
  }
}

void OriginPolicy::check_host(const std::string& host_header, bool http11) const {
  if (host_header.empty()) {
    if (http11) throw invalid_argument("host", "an HTTP/1.1 request needs a Host header");
    return;  // HTTP/1.0 without Host: not a browser
  }
  const std::string host = lower(host_header);
  const auto [name, port] = split_host_port(host);
  if (std::find(bare_.begin(), bare_.end(), host) != bare_.end()) return;
  for (const auto& n : names_) {
    if (n == host) return;
    if (split_host_port(n).second.empty() && n == name) return;  // a configured name without a port
  }
  if (wildcard_ && is_ip_literal(name) && port == std::to_string(port_)) return;
  throw Error(Error::Kind::forbidden, "host",
              "Host '" + host_header + "' is not a name of this server (serve --server-name)");
}

bool OriginPolicy::state_changing(const std::string& method) {
  return method != "GET" && method != "HEAD" && method != "OPTIONS";
}

void OriginPolicy::check_origin(const std::string& origin_header, const std::string& host) const {
  if (origin_header.empty()) return;
  std::string origin = lower(origin_header);
  while (!origin.empty() && origin.back() == '/') origin.pop_back();
  const std::string h = lower(host);
  if (!h.empty() && (origin == "http://" + h || origin == "https://" + h)) return;
  if (std::find(origins_.begin(), origins_.end(), origin) != origins_.end()) return;
  throw Error(Error::Kind::forbidden, "origin",
              "Origin '" + origin_header + "' may not send this request (serve --allow-origin)");
}

}  // namespace trailscope::server
