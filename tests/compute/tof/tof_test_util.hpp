#pragma once
// Helpers shared by the depth-video and synthetic-camera tests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include "trailscope/core/error.hpp"

namespace trailscope::test {

/// Runs `f`, expects a trailscope::Error of `kind` with parameter `param` and exactly `message`.
inline void expect_error(const std::function<void()>& f, Error::Kind kind, const std::string& param,
                         const std::string& message) {
  try {
    f();
    ADD_FAILURE() << "no error thrown; expected: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(to_string(e.kind()), std::string(to_string(kind))) << e.what();
    EXPECT_EQ(e.param(), param) << e.what();
    EXPECT_EQ(std::string(e.what()), message);
  }
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

inline void spit(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Bitwise equality of two float images (NaN == NaN, -0 != +0).
inline bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

}  // namespace trailscope::test
