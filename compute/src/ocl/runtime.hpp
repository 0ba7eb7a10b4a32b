#pragma once
// Private OpenCL runtime: the one place (with the other compute/src/ocl/*.cpp files) that includes the
// OpenCL C++ bindings. One context and one in-order queue per process, created lazily and thread-safely
// on the device that ocl_info.hpp describes, and a cache of built programs keyed by kernel name + source
// MD5 + build options.
//
// Portability: kernels are OpenCL C 1.2 (PoCL 3.1 reports "OpenCL C 1.2" only, and NVIDIA's compiler
// takes -cl-std=CL1.2 too), built with -cl-std=CL1.2. The bindings are compiled for 3.0 with a 2.0
// minimum (the one combination besides 1.2/1.2 that compiles with the 2023.02.06 headers), so the queue
// of a platform older than 2.0 is created through the 1.2 C entry point instead of
// clCreateCommandQueueWithProperties.
#ifndef TRAILSCOPE_HAVE_OPENCL
#error "ocl/runtime.hpp is only compiled with TRAILSCOPE_HAVE_OPENCL"
#endif

#define CL_USE_DEPRECATED_OPENCL_1_2_APIS  // clCreateCommandQueue for 1.x platforms
#include <CL/opencl.hpp>

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>

namespace trailscope::ocl {

struct DeviceContext {
  cl::Platform platform;
  cl::Device device;
  cl::Context context;
  cl::CommandQueue queue;  ///< in-order; enqueues are thread-safe, one kernel object per call
  std::string platform_name, device_name, device_version, device_type;
  bool is_gpu = false;         ///< GPU or accelerator
  bool int64_atomics = false;  ///< cl_khr_int64_base_atomics
  std::size_t max_alloc_bytes = 0;
};

/// The process's device context, or nullptr when OpenCL is unavailable (then `reason`, if given, says
/// why). Initialises on first call; never throws.
const DeviceContext* device_context(std::string* reason = nullptr) noexcept;

/// The built program of embedded kernel `kernel_name` with extra build `options` (appended after
/// -cl-std=CL1.2), from the cache or built now. Throws Error(Kind::backend) when OpenCL is unavailable,
/// the kernel is not embedded, or the build fails (the message carries the build log).
cl::Program program(const std::string& kernel_name, const std::string& options = {});

/// "CL_OUT_OF_RESOURCES (-5) in clEnqueueNDRangeKernel" for a cl::Error.
std::string describe(const cl::Error& e);

/// Enqueues `k` over n work-items (none when n is 0) in work-groups of 64, or of the kernel's limit on
/// this device if lower; the kernel ignores the padding work-items (id >= n). A fixed size rather than
/// NullRange: PoCL compiles a kernel again for every new work-group size it picks (~0.1–0.2 s), and a
/// GPU wants a multiple of its warp.
inline void launch(const DeviceContext* ctx, cl::Kernel& k, std::size_t n) {
  if (n == 0) return;
  const std::size_t group = std::max<std::size_t>(
      1, std::min<std::size_t>(64, k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(ctx->device)));
  ctx->queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + group - 1) / group * group),
                                  cl::NDRange(group));
}

/// The frame of every op's host entry point under the dispatch convention (ocl/dispatch.hpp): runs
/// `body(ctx)` (a std::string(const DeviceContext*)) on the process's device and returns what it returns,
/// "" when it ran or why it cannot run. Without a device: "OpenCL unavailable: <reason>"; when an OpenCL
/// call throws cl::Error: "<what> failed: <error>" (a body writes its outputs after its last OpenCL call,
/// so they stay untouched then). Other exceptions propagate.
template <class Body>
std::string run_on_device(std::string_view what, Body&& body) {
  std::string why;
  const DeviceContext* ctx = device_context(&why);
  if (!ctx) return "OpenCL unavailable: " + why;
  try {
    return body(ctx);
  } catch (const cl::Error& e) {
    return std::string(what) + " failed: " + describe(e);
  }
}

}  // namespace trailscope::ocl
