// opencl_warm_up() (trailscope/ocl_info.hpp): runs each op's warm-up. It lives above the op folders so
// that compute/src/ocl/ stays the runtime only and imports none of them; each op folder owns the warm-up
// of its kernels beside its host code.
#include "bundling/bundle_ocl.hpp"
#include "density/density_lines_ocl.hpp"
#include "projection/projection_ocl.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ocl_info.hpp"
#ifdef TRAILSCOPE_HAVE_OPENCL
#include "ocl/runtime.hpp"
#endif

namespace trailscope {

void opencl_warm_up() {
#ifdef TRAILSCOPE_HAVE_OPENCL
  std::string why;
  if (!ocl::device_context(&why)) throw Error(Error::Kind::backend, "backend", "OpenCL unavailable: " + why);
  // Every op's kernel variants once on a tiny input: that builds the programs and also makes PoCL
  // compile the kernels for the work-group size the ops use (its first enqueue of a kernel costs another
  // 0.1–0.15 s otherwise).
  ocl::density_lines_warm_up();
  ocl::bundle_warm_up();
  ocl::projection_warm_up();
#else
  throw Error(Error::Kind::backend, "backend", "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)");
#endif
}

}  // namespace trailscope
