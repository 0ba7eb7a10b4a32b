// Implements trailscope/ocl_info.hpp (but opencl_warm_up(), compute/src/opencl_warm_up.cpp, which runs
// the ops' warm-ups) and the non-template parts of ocl/dispatch.hpp. Compiles without
// OpenCL too (TRAILSCOPE_WITH_OPENCL=OFF), where the backend simply reports itself unavailable.
#include "trailscope/ocl_info.hpp"

#include <cstdlib>
#include <map>
#include <mutex>

#include "ocl/dispatch.hpp"
#include "trailscope/core/error.hpp"
#ifdef TRAILSCOPE_HAVE_OPENCL
#include "ocl/runtime.hpp"
#endif

namespace trailscope {
namespace {

struct PathLog {
  std::mutex mutex;
  std::map<std::string, OpPathStats, std::less<>> ops;
};

PathLog& path_log() {
  static PathLog log;
  return log;
}

}  // namespace

OpenClInfo opencl_info() {
  OpenClInfo info;
#ifdef TRAILSCOPE_HAVE_OPENCL
  info.compiled_in = true;
  std::string why;
  if (const ocl::DeviceContext* ctx = ocl::device_context(&why)) {
    info.available = true;
    info.platform = ctx->platform_name;
    info.device = ctx->device_name;
    info.device_type = ctx->device_type;
    info.version = ctx->device_version;
  } else {
    info.error = why;
  }
#else
  info.error = "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
#endif
  return info;
}

bool opencl_available() {
  return ocl::available();
}

OpPathStats op_path_stats(std::string_view op) {
  PathLog& log = path_log();
  std::lock_guard lock(log.mutex);
  if (auto it = log.ops.find(op); it != log.ops.end()) return it->second;
  OpPathStats none;
  none.op = std::string(op);
  return none;
}

std::vector<OpPathStats> all_op_path_stats() {
  PathLog& log = path_log();
  std::lock_guard lock(log.mutex);
  std::vector<OpPathStats> out;
  for (const auto& [name, stats] : log.ops) out.push_back(stats);
  return out;
}

namespace ocl {

bool available() noexcept {
#ifdef TRAILSCOPE_HAVE_OPENCL
  return device_context() != nullptr;
#else
  return false;
#endif
}

bool device_is_gpu() noexcept {
#ifdef TRAILSCOPE_HAVE_OPENCL
  const DeviceContext* ctx = device_context();
  return ctx && ctx->is_gpu;
#else
  return false;
#endif
}

std::string unavailable_reason() {
  return opencl_info().error;
}

bool injected_failure(const char* op) noexcept {
  const char* env = std::getenv("TRAILSCOPE_OPENCL_INJECT_FAILURE");
  if (!env || !*env) return false;
  const std::string_view list(env), name(op);
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = list.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? list.size() : comma;
    if (list.substr(start, end - start) == name) return true;
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return false;
}

void record_path(const char* op, Path path, const std::string& fallback_reason) {
  PathLog& log = path_log();
  std::lock_guard lock(log.mutex);
  auto [it, inserted] = log.ops.try_emplace(op);
  OpPathStats& s = it->second;
  if (inserted) s.op = op;
  if (path == Path::opencl) {
    ++s.opencl;
  } else {
    ++s.cpu;
    if (!fallback_reason.empty()) {
      ++s.fallbacks;
      s.last_fallback_reason = fallback_reason;
    }
  }
  s.last_path = to_string(path);
}

}  // namespace ocl
}  // namespace trailscope
