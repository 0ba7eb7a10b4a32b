#pragma once
// The OpenCL C sources of compute/kernels/*.cl, embedded at build time by compute/cmake/embed_kernels.cmake
// (a raw string and the file's MD5 each, as OpenCV's cl2cpp.cmake does), so that no .cl file is read at
// run time. The MD5 is part of the program-cache key (ocl/runtime.hpp).
#include <vector>

namespace trailscope::ocl {

struct EmbeddedKernel {
  const char* name;    ///< file name without ".cl", as in compute/kernels/
  const char* source;  ///< OpenCL C 1.2 source text
  const char* md5;     ///< hex MD5 of the .cl file
};

/// Every embedded kernel file, in the order CMake globbed them. Defined in the generated
/// embedded_kernels.cpp.
const std::vector<EmbeddedKernel>& embedded_kernels();

}  // namespace trailscope::ocl
