// The OpenCL runtime as the public header shows it: device description, warm-up builds every kernel
// variant, backend parsing.
#include <gtest/gtest.h>

#include "trailscope/core/backend.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope {
namespace {

TEST(OclRuntime, DescribesTheDevice) {
  const OpenClInfo info = opencl_info();
  EXPECT_TRUE(info.compiled_in);
  if (!info.available) GTEST_SKIP() << "no OpenCL device: " << info.error;
  EXPECT_TRUE(info.error.empty());
  EXPECT_FALSE(info.platform.empty());
  EXPECT_FALSE(info.device.empty());
  EXPECT_NE(info.version.find("OpenCL"), std::string::npos);
  EXPECT_TRUE(info.device_type == "gpu" || info.device_type == "cpu" || info.device_type == "accelerator" ||
              info.device_type == "other");
  EXPECT_EQ(opencl_available(), true);
  EXPECT_NO_THROW(opencl_warm_up());  // every kernel variant builds with -cl-std=CL1.2
}

TEST(OclRuntime, BackendNames) {
  EXPECT_EQ(parse_backend("cpu"), Backend::cpu);
  EXPECT_EQ(parse_backend("opencl"), Backend::opencl);
  EXPECT_EQ(parse_backend("auto"), Backend::auto_);
  EXPECT_STREQ(to_string(Backend::auto_), "auto");
  try {
    parse_backend("gpu", "backend");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    EXPECT_EQ(e.param(), "backend");
  }
  const Backend old = default_backend();
  set_default_backend(Backend::cpu);
  EXPECT_EQ(default_backend(), Backend::cpu);
  set_default_backend(old);
}

}  // namespace
}  // namespace trailscope
