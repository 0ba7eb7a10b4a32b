#include "params/upload_body.hpp"

#include <fstream>
#include <random>

#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

std::string read_whole_file(const fs::path& p) {
  std::error_code ec;
  const auto size = fs::file_size(p, ec);
  if (ec) throw Error(Error::Kind::internal, "", "cannot read " + p.string());
  std::ifstream in(p, std::ios::binary);
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (!in) throw Error(Error::Kind::internal, "", "cannot read " + p.string());
  return bytes;
}

std::string upload_bytes(const Request& req, std::uint64_t limit, const std::string& too_large) {
  std::string bytes;
  if (req.body_file.empty()) {
    bytes = req.body;
  } else {
    struct RemoveFile {
      fs::path p;
      ~RemoveFile() {
        std::error_code ec;
        fs::remove(p, ec);
      }
    } cleanup{req.body_file};
    std::error_code ec;
    if (fs::file_size(req.body_file, ec) > limit && !ec)
      throw Error(Error::Kind::payload_too_large, "body", too_large);
    bytes = read_whole_file(req.body_file);
  }
  if (bytes.empty()) throw invalid_argument("body", "body: the upload is empty");
  if (bytes.size() > limit) throw Error(Error::Kind::payload_too_large, "body", too_large);
  return bytes;
}

fs::path upload_file(const Request& req, const fs::path& dir) {
  if (!req.body_file.empty()) return req.body_file;
  if (req.body.empty()) throw invalid_argument("body", "body: the upload is empty");
  // Small bodies (tests, scripts) arrive in memory; the jobs read files, so spill it.
  std::random_device rd;
  const fs::path file = dir / ("inline-" + std::to_string(rd()) + std::to_string(rd()));
  std::ofstream out(file, std::ios::binary);
  out.write(req.body.data(), static_cast<std::streamsize>(req.body.size()));
  out.close();
  if (!out) throw Error(Error::Kind::internal, "", "cannot write upload to " + file.string());
  return file;
}

}  // namespace trailscope::server
