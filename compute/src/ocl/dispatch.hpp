#pragma once
// The dispatch convention every compute op follows (after OpenCV's CV_OCL_RUN): the public function
// validates its inputs, then
//   1. resolves the Backend: `cpu` and `opencl` are obeyed; `auto` picks OpenCL only when a device is
//      available and the op says it is large enough to gain (`worth_opencl`);
//   2. when OpenCL is picked, calls the op's OpenCL host function, which either runs the kernel or
//      reports that it cannot run (no device, missing extension, build failure, out of resources) by
//      returning a reason or throwing;
//   3. otherwise, or after such a report, runs the same-named C++ reference `<op>_ref`. Under
//      opencl_strict() a fallback from a chosen OpenCL path throws Error(Kind::backend) instead, so that
//      the reference-versus-OpenCL tests cannot pass on a silent fallback;
//   4. records which path ran (op_path_stats in trailscope/ocl_info.hpp).
// No OpenCL types here; the host functions live in ocl/*_ocl.cpp.
#include <string>
#include <utility>

#include "trailscope/core/backend.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::ocl {

enum class Path { cpu, opencl };
inline const char* to_string(Path p) {
  return p == Path::opencl ? "opencl" : "cpu";
}

/// True when a usable device exists (initialises the runtime on first use). Never throws.
bool available() noexcept;
/// True when the device is a GPU or an accelerator: the only devices `auto` considers, since on a CPU
/// device (PoCL) the kernels' atomics are locked read-modify-writes and measured slower than the C++
/// references, which sum private per-thread grids.
bool device_is_gpu() noexcept;
/// Why OpenCL is unavailable ("" when it is available).
std::string unavailable_reason();

/// Fault injection for the tests of the fallback and strict paths: true when the comma-separated
/// environment variable TRAILSCOPE_OPENCL_INJECT_FAILURE names `op` (read on every call).
bool injected_failure(const char* op) noexcept;

/// Records one run of `op` on `path`; `fallback_reason` is non-empty when OpenCL was chosen but could not
/// run.
void record_path(const char* op, Path path, const std::string& fallback_reason = {});

/// Runs an op under the convention above. `try_opencl()` returns "" when it ran, else why it could not;
/// it may also throw trailscope::Error or std::exception, which counts as "cannot run". `run_ref()` runs
/// the reference. Returns the path that ran.
template <class TryOpenCl, class RunRef>
Path dispatch(const char* op, Backend requested, bool worth_opencl, TryOpenCl&& try_opencl,
              RunRef&& run_ref) {
  bool use_opencl =
      requested == Backend::opencl || (requested == Backend::auto_ && worth_opencl && available());
  std::string why;
  if (use_opencl) {
    if (injected_failure(op)) {
      why = "failure injected by TRAILSCOPE_OPENCL_INJECT_FAILURE";
    } else if (!available()) {
      why = "OpenCL unavailable: " + unavailable_reason();
    } else {
      try {
        why = std::forward<TryOpenCl>(try_opencl)();
      } catch (const std::exception& e) {
        why = e.what();
        if (why.empty()) why = "unknown OpenCL error";
      }
    }
    if (why.empty()) {
      record_path(op, Path::opencl);
      return Path::opencl;
    }
    if (opencl_strict())
      throw Error(Error::Kind::backend, "backend",
                  std::string(op) + ": OpenCL could not run and strict mode forbids the fallback: " + why);
  }
  std::forward<RunRef>(run_ref)();
  record_path(op, Path::cpu, why);
  return Path::cpu;
}

}  // namespace trailscope::ocl
