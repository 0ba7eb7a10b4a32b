#include "trailscope/core/backend.hpp"

#include <atomic>
#include <cstdlib>
#include <cstring>

#include "trailscope/core/error.hpp"

namespace trailscope {
namespace {

bool parse_backend_noexcept(std::string_view text, Backend& out) noexcept {
  if (text == "cpu") {
    out = Backend::cpu;
  } else if (text == "opencl") {
    out = Backend::opencl;
  } else if (text == "auto") {
    out = Backend::auto_;
  } else {
    return false;
  }
  return true;
}

// The process-wide default: read once from TRAILSCOPE_BACKEND; an unknown value there is ignored (the
// default stays `auto`) rather than aborting start-up from a noexcept accessor — the server's --backend
// flag goes through parse_backend() and is validated properly.
std::atomic<Backend>& default_slot() noexcept {
  static std::atomic<Backend> slot{[] {
    Backend b = Backend::auto_;
    if (const char* env = std::getenv("TRAILSCOPE_BACKEND")) parse_backend_noexcept(env, b);
    return b;
  }()};
  return slot;
}

}  // namespace

Backend parse_backend(std::string_view text, const std::string& param) {
  Backend b{};
  if (!parse_backend_noexcept(text, b))
    throw invalid_argument(param,
                           "unknown backend '" + std::string(text) + "' (expected cpu, opencl or auto)");
  return b;
}

const char* to_string(Backend b) noexcept {
  switch (b) {
    case Backend::cpu:
      return "cpu";
    case Backend::opencl:
      return "opencl";
    case Backend::auto_:
      return "auto";
  }
  return "auto";
}

Backend default_backend() noexcept {
  return default_slot().load(std::memory_order_relaxed);
}

void set_default_backend(Backend b) noexcept {
  default_slot().store(b, std::memory_order_relaxed);
}

// Read on every call (not cached) so that a test can switch strict mode on for its own scope with
// setenv(); getenv is safe to call concurrently as long as nobody modifies the environment meanwhile.
bool opencl_strict() noexcept {
  const char* env = std::getenv("TRAILSCOPE_OPENCL_STRICT");
  return env && (std::strcmp(env, "1") == 0 || std::strcmp(env, "true") == 0);
}

}  // namespace trailscope
