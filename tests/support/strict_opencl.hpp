#pragma once
// The fixture of every test that compares an OpenCL op with its C++ reference: strict mode for the test's
// lifetime (TRAILSCOPE_OPENCL_STRICT=1, so that a silent fallback to the reference throws instead of
// passing as "equal"), and a skip where no OpenCL device exists.
#include <gtest/gtest.h>

#include "test_support.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::test {

class StrictOpenCl : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!opencl_available()) GTEST_SKIP() << "no OpenCL device: " << opencl_info().error;
  }
  ScopedEnv strict_{"TRAILSCOPE_OPENCL_STRICT", "1"};
};

}  // namespace trailscope::test
