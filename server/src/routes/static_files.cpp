#include <fstream>
#include <sstream>

#include "errors/error_table.hpp"
#include "routes/handlers.hpp"

namespace trailscope::server::handlers {
namespace fs = std::filesystem;

namespace {
std::string content_type(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".woff2") return "font/woff2";
  if (ext == ".wasm") return "application/wasm";
  if (ext == ".ico") return "image/x-icon";
  return "application/octet-stream";
}
}  // namespace

Response static_file(App& app, const Request& req, const PathParams&) {
  if (app.web_root.empty()) return error_response(404, "not_found", "path", "no route for " + req.path);
  const fs::path rel = fs::path(req.path).relative_path();
  for (const auto& part : rel)
    if (part == "..") return error_response(400, "invalid_argument", "path", "path must not contain '..'");
  fs::path file = app.web_root / rel;
  std::error_code ec;
  bool is_index = false;
  if (req.path == "/" || fs::is_directory(file, ec)) file /= "index.html", is_index = true;
  if (!fs::is_regular_file(file, ec)) {
    // Unknown paths under /api/ or /tiles/ are API errors; anything else is the single-page app.
    if (req.path.rfind("/api/", 0) == 0 || req.path.rfind("/tiles/", 0) == 0 || rel.has_extension())
      return error_response(404, "not_found", "path", "no route for " + req.path);
    file = app.web_root / "index.html", is_index = true;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) return error_response(404, "not_found", "path", "no route for " + req.path);
  std::ostringstream buf;
  buf << in.rdbuf();
  Response res;
  res.content_type = content_type(file), res.body = buf.str();
  // Vite names assets by content hash, so they never change; the index must always be revalidated.
  res.headers.emplace_back("Cache-Control", is_index ? "no-cache" : "public, max-age=31536000, immutable");
  return res;
}

}  // namespace trailscope::server::handlers
