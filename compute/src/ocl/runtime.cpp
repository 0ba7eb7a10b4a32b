#ifdef TRAILSCOPE_HAVE_OPENCL
#include "ocl/runtime.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <vector>

#include "ocl/embedded_kernels.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::ocl {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool contains_ci(const std::string& haystack, const std::string& needle) {
  return lower(haystack).find(lower(needle)) != std::string::npos;
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

// "OpenCL 1.2 CUDA 12.2" -> 102; "OpenCL C 1.2 ..." -> 102; 0 when unparseable.
int parse_version(const std::string& text, const std::string& prefix) {
  const auto pos = text.find(prefix);
  if (pos == std::string::npos) return 0;
  int major = 0, minor = 0;
  if (std::sscanf(text.c_str() + pos + prefix.size(), "%d.%d", &major, &minor) != 2) return 0;
  return major * 100 + minor;
}

std::string type_name(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return "gpu";
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  if (t & CL_DEVICE_TYPE_CPU) return "cpu";
  return "other";
}

struct Candidate {
  cl::Platform platform;
  cl::Device device;
  std::string platform_name, device_name;
  cl_device_type type = 0;
};

struct State {
  std::once_flag once;
  DeviceContext ctx;
  bool ok = false;
  std::string reason;
  std::mutex programs_mutex;
  std::map<std::string, cl::Program> programs;  // key: name | md5 | options
};

State& state() {
  static State s;
  return s;
}

// Picks the device as ocl_info.hpp documents. Returns false with `reason` set when none fits.
bool choose(Candidate& out, std::string& reason) {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    reason = "no OpenCL platform (" + describe(e) + ")";
    return false;
  }
  std::vector<Candidate> all;
  for (auto& p : platforms) {
    std::vector<cl::Device> devices;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // a platform with no devices reports CL_DEVICE_NOT_FOUND
    }
    for (auto& d : devices) {
      Candidate c;
      c.platform = p;
      c.device = d;
      c.platform_name = p.getInfo<CL_PLATFORM_NAME>();
      c.device_name = d.getInfo<CL_DEVICE_NAME>();
      c.type = d.getInfo<CL_DEVICE_TYPE>();
      // Kernels are OpenCL C 1.2: skip devices whose compiler is older, and unavailable devices.
      if (parse_version(d.getInfo<CL_DEVICE_OPENCL_C_VERSION>(), "OpenCL C ") < 102) continue;
      if (!d.getInfo<CL_DEVICE_AVAILABLE>() || !d.getInfo<CL_DEVICE_COMPILER_AVAILABLE>()) continue;
      all.push_back(std::move(c));
    }
  }
  std::string listing;
  for (auto& c : all) listing += (listing.empty() ? "" : "; ") + c.platform_name + " / " + c.device_name;
  if (all.empty()) {
    reason = "no OpenCL device with an OpenCL C 1.2 compiler";
    return false;
  }
  const std::string want_platform = env("TRAILSCOPE_OPENCL_PLATFORM");
  const std::string want_device = env("TRAILSCOPE_OPENCL_DEVICE");
  if (lower(want_device) == "none") {
    reason = "disabled by TRAILSCOPE_OPENCL_DEVICE=none";
    return false;
  }
  std::vector<Candidate> matches;
  for (auto& c : all)
    if ((want_platform.empty() || contains_ci(c.platform_name, want_platform)) &&
        (want_device.empty() || contains_ci(c.device_name, want_device)))
      matches.push_back(c);
  if (matches.empty()) {
    reason = "no OpenCL device matches TRAILSCOPE_OPENCL_PLATFORM='" + want_platform +
             "' TRAILSCOPE_OPENCL_DEVICE='" + want_device + "' (devices: " + listing + ")";
    return false;
  }
  auto is_gpu = [](const Candidate& c) {
    return (c.type & (CL_DEVICE_TYPE_GPU | CL_DEVICE_TYPE_ACCELERATOR)) != 0;
  };
  auto it = std::find_if(matches.begin(), matches.end(), is_gpu);
  if (it == matches.end())
    it = std::find_if(matches.begin(), matches.end(), [](const Candidate& c) {
      return (c.type & CL_DEVICE_TYPE_CPU) && (contains_ci(c.platform_name, "Portable Computing Language") ||
                                               contains_ci(c.platform_name, "pocl"));
    });
  out = it != matches.end() ? *it : matches.front();
  return true;
}

void initialise(State& s) {
  Candidate c;
  try {
    if (!choose(c, s.reason)) return;
  } catch (const cl::Error& e) {  // a driver failing a device query
    s.reason = "cannot enumerate OpenCL devices: " + describe(e);
    return;
  }
  try {
    DeviceContext& ctx = s.ctx;
    ctx.platform = c.platform;
    ctx.device = c.device;
    ctx.platform_name = c.platform_name;
    ctx.device_name = c.device_name;
    ctx.device_type = type_name(c.type);
    ctx.is_gpu = (c.type & (CL_DEVICE_TYPE_GPU | CL_DEVICE_TYPE_ACCELERATOR)) != 0;
    ctx.device_version = c.device.getInfo<CL_DEVICE_VERSION>();
    ctx.int64_atomics =
        c.device.getInfo<CL_DEVICE_EXTENSIONS>().find("cl_khr_int64_base_atomics") != std::string::npos;
    ctx.max_alloc_bytes = static_cast<std::size_t>(c.device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>());
    ctx.context = cl::Context(c.device);
    if (parse_version(c.platform.getInfo<CL_PLATFORM_VERSION>(), "OpenCL ") >= 200) {
      ctx.queue = cl::CommandQueue(ctx.context, c.device);
    } else {
      // A 1.x platform has no clCreateCommandQueueWithProperties, which the bindings call when built
      // with a 2.0 minimum.
      cl_int err = CL_SUCCESS;
      cl_command_queue q = clCreateCommandQueue(ctx.context(), c.device(), 0, &err);
      if (err != CL_SUCCESS) throw cl::Error(err, "clCreateCommandQueue");
      ctx.queue = cl::CommandQueue(q);  // takes ownership
    }
    s.ok = true;
  } catch (const cl::Error& e) {
    s.reason =
        "cannot create an OpenCL context on " + c.platform_name + " / " + c.device_name + ": " + describe(e);
  }
}

const char* error_name(cl_int code) {
  switch (code) {
    case CL_DEVICE_NOT_FOUND:
      return "CL_DEVICE_NOT_FOUND";
    case CL_DEVICE_NOT_AVAILABLE:
      return "CL_DEVICE_NOT_AVAILABLE";
    case CL_COMPILER_NOT_AVAILABLE:
      return "CL_COMPILER_NOT_AVAILABLE";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE:
      return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
    case CL_OUT_OF_RESOURCES:
      return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY:
      return "CL_OUT_OF_HOST_MEMORY";
    case CL_BUILD_PROGRAM_FAILURE:
      return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE:
      return "CL_INVALID_VALUE";
    case CL_INVALID_PLATFORM:
      return "CL_INVALID_PLATFORM";
    case CL_INVALID_DEVICE:
      return "CL_INVALID_DEVICE";
    case CL_INVALID_CONTEXT:
      return "CL_INVALID_CONTEXT";
    case CL_INVALID_COMMAND_QUEUE:
      return "CL_INVALID_COMMAND_QUEUE";
    case CL_INVALID_MEM_OBJECT:
      return "CL_INVALID_MEM_OBJECT";
    case CL_INVALID_BUILD_OPTIONS:
      return "CL_INVALID_BUILD_OPTIONS";
    case CL_INVALID_PROGRAM_EXECUTABLE:
      return "CL_INVALID_PROGRAM_EXECUTABLE";
    case CL_INVALID_KERNEL_NAME:
      return "CL_INVALID_KERNEL_NAME";
    case CL_INVALID_KERNEL_ARGS:
      return "CL_INVALID_KERNEL_ARGS";
    case CL_INVALID_ARG_SIZE:
      return "CL_INVALID_ARG_SIZE";
    case CL_INVALID_WORK_GROUP_SIZE:
      return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_GLOBAL_WORK_SIZE:
      return "CL_INVALID_GLOBAL_WORK_SIZE";
    case CL_INVALID_BUFFER_SIZE:
      return "CL_INVALID_BUFFER_SIZE";
    case -1001:
      return "CL_PLATFORM_NOT_FOUND_KHR";
    default:
      return "CL error";
  }
}

}  // namespace

std::string describe(const cl::Error& e) {
  return std::string(error_name(e.err())) + " (" + std::to_string(e.err()) + ") in " +
         (e.what() ? e.what() : "?");
}

const DeviceContext* device_context(std::string* reason) noexcept {
  State& s = state();
  try {
    std::call_once(s.once, [&] { initialise(s); });
  } catch (...) {
    // initialise() catches cl::Error; anything else (bad_alloc) leaves the runtime unavailable.
    if (reason) *reason = "OpenCL initialisation failed";
    return nullptr;
  }
  if (!s.ok) {
    if (reason) *reason = s.reason;
    return nullptr;
  }
  return &s.ctx;
}

cl::Program program(const std::string& kernel_name, const std::string& options) {
  std::string why;
  const DeviceContext* ctx = device_context(&why);
  if (!ctx) throw Error(Error::Kind::backend, "backend", "OpenCL unavailable: " + why);
  const EmbeddedKernel* k = nullptr;
  for (const auto& e : embedded_kernels())
    if (kernel_name == e.name) k = &e;
  if (!k) throw Error(Error::Kind::backend, "backend", "no embedded OpenCL kernel '" + kernel_name + "'");

  const std::string full_options = "-cl-std=CL1.2" + (options.empty() ? std::string() : " " + options);
  const std::string key = kernel_name + "|" + k->md5 + "|" + full_options;
  State& s = state();
  // Builds are rare (once per kernel and option set), so holding the lock through one is simpler than
  // coordinating concurrent builds of the same program.
  std::lock_guard lock(s.programs_mutex);
  if (auto it = s.programs.find(key); it != s.programs.end()) return it->second;
  cl::Program prog;
  try {
    prog = cl::Program(ctx->context, std::string(k->source));
    prog.build(std::vector<cl::Device>{ctx->device}, full_options.c_str());
  } catch (const cl::Error& e) {
    std::string log;
    try {
      log = prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(ctx->device);
    } catch (const cl::Error&) {
      log = "(no build log)";
    }
    throw Error(Error::Kind::backend, "backend",
                "OpenCL build of kernel '" + kernel_name + "' with '" + full_options + "' failed on " +
                    ctx->device_name + ": " + describe(e) + "\n" + log);
  }
  s.programs.emplace(key, prog);
  return prog;
}

}  // namespace trailscope::ocl
#endif  // TRAILSCOPE_HAVE_OPENCL
