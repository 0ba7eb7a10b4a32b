#pragma once
// Host sides of the OpenCL ops (compute/src/ocl/<op>_ocl.cpp), declared without OpenCL types so that
// the public ops in compute/src/<area>/ can call them. Each returns "" when the kernel ran and wrote
// its result, or the reason it cannot run; it may also throw (ocl/dispatch.hpp treats that as "cannot
// run").
#include <string>

namespace trailscope::density {
struct LineSegments;
struct Aggregate;
}  // namespace trailscope::density

namespace trailscope::ocl {

std::string density_lines_ocl(const density::LineSegments& segments, density::Aggregate& out);

/// Runs every op's kernel variants once on a tiny input, for opencl_warm_up(): that builds the programs
/// and also makes PoCL compile the kernels for the work-group size the ops use (its first enqueue of a
/// kernel costs another 0.1–0.15 s otherwise). Throws Error(Kind::backend) on any failure.
void warm_up_ops();

}  // namespace trailscope::ocl
