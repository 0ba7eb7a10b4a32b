// Host side of compute/kernels/density_lines.cl (see density/density_lines.hpp for what it computes).
#include "density/density_lines_ocl.hpp"

#include <algorithm>

#include "trailscope/core/error.hpp"
#include "trailscope/density/density_lines.hpp"
#ifdef TRAILSCOPE_HAVE_OPENCL
#include "ocl/runtime.hpp"
#endif

namespace trailscope::ocl {

#ifdef TRAILSCOPE_HAVE_OPENCL
std::string density_lines_ocl(const density::LineSegments& s, density::Aggregate& out) {
  return run_on_device("density_lines kernel", [&](const DeviceContext* ctx) -> std::string {
    if (s.with_value && !ctx->int64_atomics)
      return "device lacks cl_khr_int64_base_atomics (needed for value sums)";
    const std::size_t pixels = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
    const std::size_t n = s.size();
    if (pixels * sizeof(std::int64_t) > ctx->max_alloc_bytes ||
        n * 6 * sizeof(std::int32_t) > ctx->max_alloc_bytes)
      return "buffers exceed the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE";

    density::Aggregate a = density::Aggregate::zeros(s.width, s.height, s.with_value);
    const cl::Context& context = ctx->context;
    const cl::CommandQueue& queue = ctx->queue;
    cl::Program prog = program("density_lines", s.with_value ? "-DWITH_VALUE=1" : "");
    // One kernel object per call: clSetKernelArg on a shared kernel is not thread-safe.
    cl::Kernel kernel(prog, "density_lines");

    cl::Buffer count(context, CL_MEM_READ_WRITE, pixels * sizeof(std::int32_t));
    queue.enqueueFillBuffer(count, std::int32_t{0}, 0, pixels * sizeof(std::int32_t));
    cl::Buffer value_sum, value_count;
    if (s.with_value) {
      value_sum = cl::Buffer(context, CL_MEM_READ_WRITE, pixels * sizeof(std::int64_t));
      value_count = cl::Buffer(context, CL_MEM_READ_WRITE, pixels * sizeof(std::int32_t));
      queue.enqueueFillBuffer(value_sum, std::int64_t{0}, 0, pixels * sizeof(std::int64_t));
      queue.enqueueFillBuffer(value_count, std::int32_t{0}, 0, pixels * sizeof(std::int32_t));
    }
    if (n > 0) {
      // COPY_HOST_PTR: the buffers are read-only on the device, the host data stays untouched.
      cl::Buffer walk(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, s.walk.size() * sizeof(std::int64_t),
                      const_cast<std::int64_t*>(s.walk.data()));
      cl::Buffer cells(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                       s.cells.size() * sizeof(std::int32_t), const_cast<std::int32_t*>(s.cells.data()));
      int arg = 0;
      kernel.setArg(arg++, walk);
      kernel.setArg(arg++, cells);
      kernel.setArg(arg++, static_cast<cl_int>(n));
      kernel.setArg(arg++, static_cast<cl_int>(s.width));
      kernel.setArg(arg++, static_cast<cl_int>(s.height));
      kernel.setArg(arg++, count);
      if (s.with_value) {
        kernel.setArg(arg++, value_sum);
        kernel.setArg(arg++, value_count);
      }
      // A fixed work-group size (ocl::launch): with NullRange PoCL would compile the kernel again for
      // almost every tile.
      launch(ctx, kernel, n);
    }
    queue.enqueueReadBuffer(count, CL_TRUE, 0, pixels * sizeof(std::int32_t), a.count.data());
    if (s.with_value) {
      queue.enqueueReadBuffer(value_sum, CL_TRUE, 0, pixels * sizeof(std::int64_t), a.value_sum.data());
      queue.enqueueReadBuffer(value_count, CL_TRUE, 0, pixels * sizeof(std::int32_t), a.value_count.data());
    }
    a.path = density::ComputePath::opencl;
    out = std::move(a);
    return {};
  });
}
#else
std::string density_lines_ocl(const density::LineSegments&, density::Aggregate&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
#endif

void density_lines_warm_up() {
  // Zero-length segments on a 1×1 canvas, with and without values: both kernel variants. PoCL
  // specialises a kernel for the launch's grid as well as its work-group size: with a handful of
  // work-items here, the first real launch still compiled for ~0.1 s; with 2^17 it does not.
  const density::Canvas canvas(0, 0, 1, 1, 1);
  for (bool with_value : {false, true}) {
    density::LineSegments s = density::LineSegments::for_canvas(canvas, with_value);
    for (int k = 0; k < (1 << 17); ++k) density::append_segment(s, canvas, {0, 0}, {0, 0}, false, 1.0);
    density::Aggregate out;
    if (const std::string why = density_lines_ocl(s, out); !why.empty())
      throw Error(Error::Kind::backend, "backend", "OpenCL warm-up of density_lines failed: " + why);
  }
}

}  // namespace trailscope::ocl
