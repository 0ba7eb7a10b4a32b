#pragma once
// Which implementation a compute op runs: the OpenCL kernel, its same-named C++ reference, or `auto`
// (OpenCL when a device is available and the op is large enough to gain from it, else the reference).
#include <string>
#include <string_view>

namespace trailscope {

enum class Backend { cpu, opencl, auto_ };

/// Parses "cpu" | "opencl" | "auto"; throws invalid_argument(param) otherwise.
Backend parse_backend(std::string_view text, const std::string& param = "backend");
const char* to_string(Backend b) noexcept;

/// Process-wide default, from the environment variable TRAILSCOPE_BACKEND (default `auto`), changeable
/// at start-up by `--backend`. Thread-safe to read.
Backend default_backend() noexcept;
void set_default_backend(Backend b) noexcept;

/// When true, an op asked for `opencl` that has to fall back to the reference throws instead
/// (TRAILSCOPE_OPENCL_STRICT=1). Used by the reference-versus-OpenCL tests so a silent fallback
/// cannot make them pass.
bool opencl_strict() noexcept;

}  // namespace trailscope
