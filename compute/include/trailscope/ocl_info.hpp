#pragma once
// What the OpenCL backend is doing, for /health, `trailscope --version` and the tests. No OpenCL types
// here: compute/ links OpenCL privately and only compute/src/ocl/ includes the CL headers.
//
// Device choice (made once per process, on first use):
//  - TRAILSCOPE_OPENCL_PLATFORM / TRAILSCOPE_OPENCL_DEVICE: case-insensitive substrings of the platform
//    and device names; the first device matching both is used (GPUs first among the matches);
//  - TRAILSCOPE_OPENCL_DEVICE=none disables OpenCL for the process;
//  - default: the first GPU of any platform, else the first CPU device of PoCL ("Portable Computing
//    Language"), else the first device at all.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace trailscope {

struct OpenClInfo {
  bool compiled_in = false;  ///< built with TRAILSCOPE_WITH_OPENCL
  bool available = false;    ///< a context and queue exist on a usable device
  std::string platform;      ///< e.g. "Portable Computing Language"
  std::string device;        ///< e.g. "pthread-skylake-avx512-AMD EPYC"
  std::string device_type;   ///< "gpu", "cpu", "accelerator" or "other"
  std::string version;       ///< device CL_DEVICE_VERSION, e.g. "OpenCL 3.0 PoCL ..."
  std::string error;         ///< why OpenCL is unavailable (empty when available)
};

/// Describes the OpenCL device, creating the context and queue on the first call (40–130 ms on PoCL).
/// Never throws; thread-safe.
OpenClInfo opencl_info();
/// Shorthand for opencl_info().available.
bool opencl_available();

/// Builds and runs once every kernel variant the ops use, on a tiny input, so that the first request does
/// not pay the compile: measured on PoCL, 0.6 s with an empty kernel cache (70 ms from PoCL's on-disk
/// cache, $POCL_CACHE_DIR) plus 0.1 s for PoCL's first enqueue at the ops' work-group size. Call it at
/// server start-up when the backend may be OpenCL. Throws Error(Kind::backend) (with the build log for a
/// build failure) when OpenCL is unavailable or a kernel fails.
void opencl_warm_up();

/// Which path each compute op took so far in this process (the "log which path ran" of the dispatch
/// convention: counters rather than log lines, so that /health and tests can read them).
struct OpPathStats {
  std::string op;                    ///< op name, e.g. "density_lines"
  std::uint64_t opencl = 0;          ///< runs on the OpenCL device
  std::uint64_t cpu = 0;             ///< runs of the C++ reference (chosen or fallen back to)
  std::uint64_t fallbacks = 0;       ///< of `cpu`: runs where OpenCL was chosen but could not run
  std::string last_path;             ///< "opencl" or "cpu"; empty before the first run
  std::string last_fallback_reason;  ///< why the last fallback happened
};
/// Counters of one op (all zero if it never ran).
OpPathStats op_path_stats(std::string_view op);
/// Counters of every op that ran, sorted by name.
std::vector<OpPathStats> all_op_path_stats();

}  // namespace trailscope
