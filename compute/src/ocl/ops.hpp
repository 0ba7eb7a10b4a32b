#pragma once
// Host sides of the OpenCL ops (compute/src/ocl/<op>_ocl.cpp), declared without OpenCL types so that
// the public ops in compute/src/<area>/ can call them. Each returns "" when the kernel ran and wrote
// its result, or the reason it cannot run; it may also throw (ocl/dispatch.hpp treats that as "cannot
// run").
#include <string>
#include <utility>
#include <vector>

namespace trailscope::density {
struct LineSegments;
struct Aggregate;
}  // namespace trailscope::density

namespace trailscope::ocl {

std::string density_lines_ocl(const density::LineSegments& segments, density::Aggregate& out);

/// Every (kernel name, build options) pair the ops build, for opencl_warm_up().
const std::vector<std::pair<std::string, std::string>>& kernel_variants();

}  // namespace trailscope::ocl
