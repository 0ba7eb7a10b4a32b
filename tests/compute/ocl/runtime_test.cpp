// The OpenCL runtime as the public header shows it: device description, warm-up builds every kernel
// variant, backend parsing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "trailscope/core/backend.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope {
namespace {

TEST(OclRuntime, DescribesTheDevice) {
  const OpenClInfo info = opencl_info();
  if (!info.compiled_in) {  // TRAILSCOPE_WITH_OPENCL=OFF: the backend says so and stays off
    EXPECT_FALSE(info.available);
    EXPECT_NE(info.error.find("without OpenCL"), std::string::npos);
    EXPECT_THROW(opencl_warm_up(), Error);
    GTEST_SKIP() << info.error;
  }
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

// The device is chosen once per process, so each environment is tried in a child process (this same
// test binary, re-run on this one test with TS_OCL_CHILD set).
TEST(OclRuntime, DeviceChoiceFromTheEnvironment) {
  if (const char* child = std::getenv("TS_OCL_CHILD")) {
    const OpenClInfo info = opencl_info();
    const std::string expect = child;  // "available" or a fragment of the error
    if (expect == "available") {
      EXPECT_TRUE(info.available) << info.error;
    } else {
      EXPECT_FALSE(info.available);
      EXPECT_NE(info.error.find(expect), std::string::npos) << info.error;
    }
    return;
  }
  if (!opencl_available()) GTEST_SKIP() << "no OpenCL device";
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  auto run = [&](const std::string& env, const std::string& expect) {
    const std::string cmd = env + " TS_OCL_CHILD='" + expect + "' '" + self +
                            "' --gtest_filter=OclRuntime.DeviceChoiceFromTheEnvironment >/dev/null 2>&1";
    return std::system(cmd.c_str());
  };
  EXPECT_EQ(run("TRAILSCOPE_OPENCL_DEVICE=none", "disabled"), 0);
  EXPECT_EQ(run("TRAILSCOPE_OPENCL_DEVICE=no-such-device", "no OpenCL device matches"), 0);
  EXPECT_EQ(run("TRAILSCOPE_OPENCL_PLATFORM=no-such-platform", "no OpenCL device matches"), 0);
  // Case-insensitive substrings of this machine's own platform and device names select it.
  const OpenClInfo info = opencl_info();
  EXPECT_EQ(run("TRAILSCOPE_OPENCL_PLATFORM='" + info.platform.substr(0, 8) + "'", "available"), 0);
  std::string lower = info.device.substr(0, 6);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  EXPECT_EQ(run("TRAILSCOPE_OPENCL_DEVICE='" + lower + "'", "available"), 0);
}

}  // namespace
}  // namespace trailscope
