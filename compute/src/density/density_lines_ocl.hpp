#pragma once
// Host side of the line rasteriser on OpenCL (compute/src/density/density_lines_ocl.cpp, kernel
// compute/kernels/density_lines.cl), declared without OpenCL types; the reference is
// density_lines_ref (trailscope/density/density_lines.hpp).
#include <string>

#include "trailscope/density/density_lines.hpp"

namespace trailscope::ocl {

/// Rasterises `segments` into `out` (replaced; out.path = opencl). Follows the dispatch convention of
/// compute/src/ocl/dispatch.hpp: returns "" when the kernel ran, else why it cannot run (no OpenCL,
/// value sums without cl_khr_int64_base_atomics, buffers over the device's allocation limit).
std::string density_lines_ocl(const density::LineSegments& segments, density::Aggregate& out);
/// Runs both kernel variants (with and without values) once, for opencl_warm_up(). Throws
/// Error(Kind::backend).
void density_lines_warm_up();

}  // namespace trailscope::ocl
