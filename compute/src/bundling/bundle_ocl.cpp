// Host side of compute/kernels/bundle.cl (declared in bundling/bundle_ocl.hpp): the CUBu loop with every
// array on the device. Per iteration the only transfers are the per-polyline counts of the resampling (read,
// scanned on the host against limits::kMaxBundlePoints before the new points are allocated, offsets written
// back) and the 16-byte reset of the splat box; points, splat image and density stay on the device from the
// first resample to the last smoothing, and the counts read is the iteration's only synchronisation. The crop
// of the convolution to the splatted box is read by the kernels from the device, so it costs no round trip.
// Each call gets its own kernel objects and queue (clSetKernelArg is not thread-safe; see
// profiling_queue()).
//
// Work sizes (bundle.cl, top): on a GPU one work-item per edge/point in work-groups of kGroup, the splat
// with atomics; on a CPU device (PoCL) resampling and smoothing as a few contiguous ranges per compute
// unit, one work-item each, and the splat into private images summed afterwards (PoCL's atomics are
// locked read-modify-writes), advection too as ranges (advect_ranges).
#include <algorithm>
#include <array>
#include <cstdlib>
#include <deque>
#include <string>
#include <vector>

#include "bundling/bundle_ocl.hpp"
#include "trailscope/bundling/params.hpp"
#include "trailscope/core/error.hpp"
#ifdef TRAILSCOPE_HAVE_OPENCL
#include "ocl/runtime.hpp"
#endif

namespace trailscope::ocl {

#ifdef TRAILSCOPE_HAVE_OPENCL
namespace {

using bundling::detail::Box;
using bundling::detail::Points;
using bundling::detail::ResampleArgs;

// Work-group size of every kernel: a multiple of PoCL's vector width and of a GPU warp, and fixed, so
// that PoCL compiles each kernel once (it specialises per local size).
constexpr std::size_t kGroup = 64;

std::size_t round_up(std::size_t n) {
  return (n + kGroup - 1) / kGroup * kGroup;
}

// Why the device cannot run the bundling kernels, or "".
std::string unsupported(const DeviceContext& ctx) {
  const std::string ext = ctx.device.getInfo<CL_DEVICE_EXTENSIONS>();
  if (ext.find("cl_khr_fp64") == std::string::npos)
    return "device lacks cl_khr_fp64 (bundling computes geometry in double to match the reference)";
  return {};
}

// An in-order queue of its own with profiling on: the phase times come from the events of the phase's
// commands, so that timing costs no synchronisation (a finish per phase would stop the device five
// times per iteration), and concurrent bundlings do not wait on each other's finish().
cl::CommandQueue profiling_queue(const DeviceContext& ctx) {
  const std::string version = ctx.platform.getInfo<CL_PLATFORM_VERSION>();
  int major = 1;
  if (auto pos = version.find("OpenCL "); pos != std::string::npos)
    major = std::atoi(version.c_str() + pos + 7);
  if (major >= 2) return cl::CommandQueue(ctx.context, ctx.device, CL_QUEUE_PROFILING_ENABLE);
  cl_int err = CL_SUCCESS;
  cl_command_queue q = clCreateCommandQueue(ctx.context(), ctx.device(), CL_QUEUE_PROFILING_ENABLE, &err);
  if (err != CL_SUCCESS) throw cl::Error(err, "clCreateCommandQueue");
  return cl::CommandQueue(q);
}

// Phases of PhaseTimes that the device's commands are booked to.
enum Phase { kResample, kSplat, kConvolve, kAdvect, kSmooth, kOther, kPhases };

// The bundling state of one call on the device: two point sets (resampling and smoothing write the
// other one, then the roles swap), the pixel images, and one kernel object per kernel (kernel objects
// are not shared between calls: clSetKernelArg is not thread-safe).
class DeviceBundle {
 public:
  explicit DeviceBundle(const DeviceContext& ctx) : ctx_(ctx), queue_(profiling_queue(ctx)) {
    cl::Program prog = program("bundle", "-DWG=" + std::to_string(kGroup));
    k_count_ = cl::Kernel(prog, "resample_count");
    k_place_ = cl::Kernel(prog, "resample_place");
    k_splat_ = cl::Kernel(prog, "splat");
    k_splat_private_ = cl::Kernel(prog, "splat_private");
    k_splat_reduce_ = cl::Kernel(prog, "splat_reduce");
    k_clear_ = cl::Kernel(prog, "splat_clear");
    k_rows_ = cl::Kernel(prog, "convolve_rows");
    k_cols_ = cl::Kernel(prog, "convolve_cols");
    k_col_bands_ = cl::Kernel(prog, "convolve_col_bands");
    k_advect_ = cl::Kernel(prog, "advect");
    k_advect_ranges_ = cl::Kernel(prog, "advect_ranges");
    k_smooth_ = cl::Kernel(prog, "smooth");
    k_dirs_ = cl::Kernel(prog, "directions");
    k_sites_ = cl::Kernel(prog, "site_map");
    k_adv_dir_ = cl::Kernel(prog, "advect_directional");
    coarse_ = (ctx.device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) != 0;
    units_ = std::max<std::size_t>(ctx.device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>(), 1);
  }

  // Commands may still read host memory of this object (non-blocking write of host_offsets_) when a call
  // leaves early (cancellation, an error): wait for them.
  ~DeviceBundle() {
    try {
      queue_.finish();
    } catch (...) {  // nothing to do about a failing device in a destructor
    }
  }
  DeviceBundle(const DeviceBundle&) = delete;
  DeviceBundle& operator=(const DeviceBundle&) = delete;

  // Uploads the points (and their polylines) into set `cur_`.
  void upload(const Points& p) {
    edges_ = p.edges();
    n_ = p.size();
    reserve(cur_, n_);
    offsets_[0] = make_buffer(CL_MEM_READ_WRITE, (edges_ + 1) * sizeof(cl_uint));
    offsets_[1] = make_buffer(CL_MEM_READ_WRITE, (edges_ + 1) * sizeof(cl_uint));
    counts_ = make_buffer(CL_MEM_READ_WRITE, std::max<std::size_t>(edges_, 1) * sizeof(cl_uint));
    if (n_ > 0) {
      queue_.enqueueWriteBuffer(x_[cur_], CL_FALSE, 0, n_ * sizeof(float), p.x.data());
      queue_.enqueueWriteBuffer(y_[cur_], CL_FALSE, 0, n_ * sizeof(float), p.y.data());
      queue_.enqueueWriteBuffer(z_[cur_], CL_FALSE, 0, n_ * sizeof(float), p.z.data());
      queue_.enqueueWriteBuffer(edge_[cur_], CL_FALSE, 0, n_ * sizeof(cl_uint), p.edge.data());
    }
    queue_.enqueueWriteBuffer(offsets_[cur_], CL_FALSE, 0, (edges_ + 1) * sizeof(cl_uint), p.offsets.data());
    host_offsets_ = p.offsets;
    queue_.finish();  // the host vectors may go away after this
  }

  void download(Points& p) {
    p.x.resize(n_), p.y.resize(n_), p.z.resize(n_), p.edge.resize(n_);
    if (n_ > 0) {
      queue_.enqueueReadBuffer(x_[cur_], CL_FALSE, 0, n_ * sizeof(float), p.x.data());
      queue_.enqueueReadBuffer(y_[cur_], CL_FALSE, 0, n_ * sizeof(float), p.y.data());
      queue_.enqueueReadBuffer(z_[cur_], CL_FALSE, 0, n_ * sizeof(float), p.z.data());
      queue_.enqueueReadBuffer(edge_[cur_], CL_FALSE, 0, n_ * sizeof(cl_uint), p.edge.data());
    }
    queue_.finish();
    p.offsets = host_offsets_;
  }

  void set_weights(const std::vector<std::uint32_t>& w) {
    weights_ = make_buffer(CL_MEM_READ_ONLY, std::max<std::size_t>(w.size(), 1) * sizeof(cl_uint));
    if (!w.empty()) queue_.enqueueWriteBuffer(weights_, CL_TRUE, 0, w.size() * sizeof(cl_uint), w.data());
  }

  void set_profile(const std::vector<float>& profile) {
    profile_ = make_buffer(CL_MEM_READ_ONLY, profile.size() * sizeof(float));
    queue_.enqueueWriteBuffer(profile_, CL_TRUE, 0, profile.size() * sizeof(float), profile.data());
  }

  void set_size(int size) {
    size_ = size;
    const std::size_t pixels = static_cast<std::size_t>(size) * size;
    img_ = make_buffer(CL_MEM_READ_WRITE, pixels * sizeof(cl_uint));
    rows_ = make_buffer(CL_MEM_READ_WRITE, pixels * sizeof(cl_ulong));
    dens_ = make_buffer(CL_MEM_READ_WRITE, pixels * sizeof(float));
    queue_.enqueueFillBuffer(dens_, 0.0f, 0, pixels * sizeof(float));
    // The splat image starts at zero and each splat_clear zeroes what the previous splat wrote; the two
    // box buffers alternate (the previous splat's box, the next one's).
    queue_.enqueueFillBuffer(img_, cl_uint{0}, 0, pixels * sizeof(cl_uint));
    const cl_int empty[4] = {size, size, -1, -1};
    for (cl::Buffer& b : box_) {
      b = make_buffer(CL_MEM_READ_WRITE, sizeof empty);
      queue_.enqueueWriteBuffer(b, CL_TRUE, 0, sizeof empty, empty);
    }
  }

  // count → host scan (the limit check) → place; the new points become the current set.
  void resample(const ResampleArgs& a) {
    if (edges_ == 0) return;
    const int nxt = 1 - cur_;
    int arg = 0;
    k_count_.setArg(arg++, x_[cur_]);
    k_count_.setArg(arg++, y_[cur_]);
    k_count_.setArg(arg++, offsets_[cur_]);
    k_count_.setArg(arg++, static_cast<cl_uint>(edges_));
    k_count_.setArg(arg++, a.spl);
    k_count_.setArg(arg++, counts_);
    run_chunked(k_count_, arg, edges_);
    std::vector<std::uint32_t> counts(edges_);
    queue_.enqueueReadBuffer(counts_, CL_TRUE, 0, edges_ * sizeof(cl_uint), counts.data(), nullptr, event());
    host_offsets_ = bundling::detail::resample_offsets(counts);  // throws payload_too_large
    const std::size_t total = host_offsets_.back();
    reserve(nxt, total);
    queue_.enqueueWriteBuffer(offsets_[nxt], CL_FALSE, 0, (edges_ + 1) * sizeof(cl_uint),
                              host_offsets_.data(), nullptr, event());
    arg = 0;
    k_place_.setArg(arg++, x_[cur_]);
    k_place_.setArg(arg++, y_[cur_]);
    k_place_.setArg(arg++, offsets_[cur_]);
    k_place_.setArg(arg++, static_cast<cl_uint>(edges_));
    k_place_.setArg(arg++, offsets_[nxt]);
    k_place_.setArg(arg++, a.spl);
    k_place_.setArg(arg++, a.jitter * a.spl);
    k_place_.setArg(arg++, static_cast<cl_ulong>(a.seed));
    k_place_.setArg(arg++, static_cast<cl_uint>(a.iteration));
    k_place_.setArg(arg++, static_cast<cl_int>(a.block_endpoints ? 1 : 0));
    k_place_.setArg(arg++, profile_);
    k_place_.setArg(arg++, x_[nxt]);
    k_place_.setArg(arg++, y_[nxt]);
    k_place_.setArg(arg++, z_[nxt]);
    k_place_.setArg(arg++, edge_[nxt]);
    run_chunked(k_place_, arg, edges_);
    cur_ = nxt;
    n_ = total;
  }

  void splat() {
    k_clear_.setArg(0, img_);
    k_clear_.setArg(1, static_cast<cl_int>(size_));
    k_clear_.setArg(2, box_[bi_]);
    k_clear_.setArg(3, box_[1 - bi_]);
    run1d(k_clear_, static_cast<std::size_t>(size_));
    bi_ = 1 - bi_;
    if (n_ == 0) return;
    if (coarse_) return splat_private();
    int arg = 0;
    k_splat_.setArg(arg++, x_[cur_]);
    k_splat_.setArg(arg++, y_[cur_]);
    k_splat_.setArg(arg++, edge_[cur_]);
    k_splat_.setArg(arg++, static_cast<cl_uint>(n_));
    k_splat_.setArg(arg++, weights_);
    k_splat_.setArg(arg++, static_cast<cl_int>(size_));
    k_splat_.setArg(arg++, img_);
    k_splat_.setArg(arg++, box_[bi_]);
    run1d(k_splat_, n_);
  }

  // CPU form: `parts` ranges of points, each splatted by one work-item into its own image (the first
  // into img_), then the other images summed into img_ over the box. Summing costs (parts − 1) × box
  // pixels, so there are only as many parts as the points pay for: one per `pixels` points, at most one
  // per compute unit, and the partial images within kMaxPartialBytes.
  void splat_private() {
    const std::size_t pixels = static_cast<std::size_t>(size_) * size_;
    constexpr std::size_t kMaxPartialBytes = std::size_t{64} << 20;
    const std::size_t parts = std::clamp<std::size_t>(
        std::min(n_ / pixels, kMaxPartialBytes / (pixels * sizeof(cl_uint)) + 1), 1, units_);
    if (parts > 1 && partials_count_ < parts - 1) {
      partials_ = make_buffer(CL_MEM_READ_WRITE, (parts - 1) * pixels * sizeof(cl_uint));
      queue_.enqueueFillBuffer(partials_, cl_uint{0}, 0, (parts - 1) * pixels * sizeof(cl_uint), nullptr,
                               event());
      partials_count_ = parts - 1;
    }
    int arg = 0;
    k_splat_private_.setArg(arg++, x_[cur_]);
    k_splat_private_.setArg(arg++, y_[cur_]);
    k_splat_private_.setArg(arg++, edge_[cur_]);
    k_splat_private_.setArg(arg++, static_cast<cl_uint>(n_));
    k_splat_private_.setArg(arg++, weights_);
    k_splat_private_.setArg(arg++, static_cast<cl_int>(size_));
    k_splat_private_.setArg(arg++, img_);
    k_splat_private_.setArg(arg++, parts > 1 ? partials_ : img_);  // not written with one part
    k_splat_private_.setArg(arg++, box_[bi_]);
    const std::size_t chunk = (n_ + parts - 1) / parts;
    k_splat_private_.setArg(arg++, static_cast<cl_uint>(chunk));
    queue_.enqueueNDRangeKernel(k_splat_private_, cl::NullRange, cl::NDRange((n_ + chunk - 1) / chunk),
                                cl::NDRange(1), nullptr, event());
    if (parts == 1) return;
    arg = 0;
    k_splat_reduce_.setArg(arg++, img_);
    k_splat_reduce_.setArg(arg++, partials_);
    k_splat_reduce_.setArg(arg++, static_cast<cl_uint>((n_ + chunk - 1) / chunk - 1));
    k_splat_reduce_.setArg(arg++, static_cast<cl_int>(size_));
    k_splat_reduce_.setArg(arg++, box_[bi_]);
    run1d(k_splat_reduce_, static_cast<std::size_t>(size_));
  }

  // Rows, then columns; the kernels read the box from the device. GPU: one work-item per row, then per
  // column (in lock step). CPU: ranges of rows, then bands of columns (convolve_col_bands).
  void convolve(int radius) {
    k_rows_.setArg(0, img_);
    k_rows_.setArg(1, static_cast<cl_int>(size_));
    k_rows_.setArg(2, box_[bi_]);
    k_rows_.setArg(3, static_cast<cl_int>(radius));
    k_rows_.setArg(4, rows_);
    run_chunked(k_rows_, 5, static_cast<std::size_t>(size_));
    cl::Kernel& k = coarse_ ? k_col_bands_ : k_cols_;
    k.setArg(0, rows_);
    k.setArg(1, static_cast<cl_int>(size_));
    k.setArg(2, box_[bi_]);
    k.setArg(3, static_cast<cl_int>(radius));
    k.setArg(4, dens_);
    if (coarse_) {
      constexpr std::size_t kBand = 16;  // BAND in bundle.cl
      queue_.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((size_ + kBand - 1) / kBand), cl::NDRange(1),
                                  nullptr, event());
    } else {
      run1d(k, static_cast<std::size_t>(size_));
    }
  }

  // GPU: one point per work-item (bundle.cl advect); CPU: ranges of points (advect_ranges, which PoCL
  // compiles several times faster).
  void advect(double step) {
    if (n_ == 0) return;
    cl::Kernel& k = coarse_ ? k_advect_ranges_ : k_advect_;
    int arg = 0;
    k.setArg(arg++, x_[cur_]);
    k.setArg(arg++, y_[cur_]);
    k.setArg(arg++, z_[cur_]);
    k.setArg(arg++, static_cast<cl_uint>(n_));
    k.setArg(arg++, dens_);
    k.setArg(arg++, static_cast<cl_int>(size_));
    k.setArg(arg++, step);
    if (coarse_)
      run_chunked(k, arg, n_);
    else
      run1d(k, n_);
  }

  // Ping-pong: each pass reads the current x, y and writes the other set's, which then becomes current
  // (z and edge are copied along only by reference: both sets' z/edge are kept equal by copying once).
  void smooth(int window, double lambda, int passes) {
    if (n_ == 0 || window <= 0 || lambda == 0) return;
    const int nxt = 1 - cur_;
    reserve(nxt, n_);
    for (int pass = 0; pass < passes; ++pass) {
      const int src = pass % 2 == 0 ? cur_ : nxt, dst = 1 - src;
      int arg = 0;
      k_smooth_.setArg(arg++, x_[src]);
      k_smooth_.setArg(arg++, y_[src]);
      k_smooth_.setArg(arg++, z_[cur_]);
      k_smooth_.setArg(arg++, edge_[cur_]);
      k_smooth_.setArg(arg++, offsets_[cur_]);
      k_smooth_.setArg(arg++, static_cast<cl_uint>(n_));
      k_smooth_.setArg(arg++, static_cast<cl_int>(window));
      k_smooth_.setArg(arg++, lambda);
      k_smooth_.setArg(arg++, x_[dst]);
      k_smooth_.setArg(arg++, y_[dst]);
      run_chunked(k_smooth_, arg, n_);
    }
    if (passes % 2 == 1) {
      // The result is in the other set's x, y: swap just those, so z/edge/offsets stay with `cur_`.
      std::swap(x_[0], x_[1]);
      std::swap(y_[0], y_[1]);
      std::swap(cap_xy_[0], cap_xy_[1]);
    }
  }

  // Directional advection (directional.hpp): site map (in the splat image's buffer), directions, then
  // the gather, which writes the other set's x, y (positions are read before any point moves).
  void advect_directional(int radius, double step, double repulsion) {
    if (n_ == 0) return;
    // The site map reuses the splat image (a call never mixes the two advections).
    const std::size_t pixels = static_cast<std::size_t>(size_) * size_;
    queue_.enqueueFillBuffer(img_, cl_uint{0}, 0, pixels * sizeof(cl_uint), nullptr, event());
    int arg = 0;
    k_sites_.setArg(arg++, x_[cur_]);
    k_sites_.setArg(arg++, y_[cur_]);
    k_sites_.setArg(arg++, static_cast<cl_uint>(n_));
    k_sites_.setArg(arg++, static_cast<cl_int>(size_));
    k_sites_.setArg(arg++, img_);
    run1d(k_sites_, n_);
    if (cap_dirs_ < n_) {
      cap_dirs_ = round_up(n_ + n_ / 2);
      dirs_ = make_buffer(CL_MEM_READ_WRITE, cap_dirs_ * sizeof(float));
    }
    arg = 0;
    k_dirs_.setArg(arg++, x_[cur_]);
    k_dirs_.setArg(arg++, y_[cur_]);
    k_dirs_.setArg(arg++, edge_[cur_]);
    k_dirs_.setArg(arg++, offsets_[cur_]);
    k_dirs_.setArg(arg++, static_cast<cl_uint>(n_));
    k_dirs_.setArg(arg++, dirs_);
    run1d(k_dirs_, n_);
    const int nxt = 1 - cur_;
    reserve(nxt, n_);
    arg = 0;
    k_adv_dir_.setArg(arg++, x_[cur_]);
    k_adv_dir_.setArg(arg++, y_[cur_]);
    k_adv_dir_.setArg(arg++, z_[cur_]);
    k_adv_dir_.setArg(arg++, edge_[cur_]);
    k_adv_dir_.setArg(arg++, static_cast<cl_uint>(n_));
    k_adv_dir_.setArg(arg++, img_);
    k_adv_dir_.setArg(arg++, dirs_);
    k_adv_dir_.setArg(arg++, static_cast<cl_int>(size_));
    k_adv_dir_.setArg(arg++, static_cast<cl_int>(radius));
    k_adv_dir_.setArg(arg++, step);
    k_adv_dir_.setArg(arg++, repulsion);
    k_adv_dir_.setArg(arg++, x_[nxt]);
    k_adv_dir_.setArg(arg++, y_[nxt]);
    run1d(k_adv_dir_, n_);
    std::swap(x_[0], x_[1]);
    std::swap(y_[0], y_[1]);
    std::swap(cap_xy_[0], cap_xy_[1]);
  }

  void read_density(std::vector<std::uint32_t>& img, Box& box, std::vector<float>& dens) {
    const std::size_t pixels = static_cast<std::size_t>(size_) * size_;
    img.resize(pixels), dens.resize(pixels);
    cl_int b[4];
    queue_.enqueueReadBuffer(img_, CL_FALSE, 0, pixels * sizeof(cl_uint), img.data());
    queue_.enqueueReadBuffer(dens_, CL_FALSE, 0, pixels * sizeof(float), dens.data());
    queue_.enqueueReadBuffer(box_[bi_], CL_TRUE, 0, sizeof b, b);
    box = Box{b[0], b[1], b[2], b[3]};
  }

  void write_density(const std::vector<float>& dens) {
    queue_.enqueueWriteBuffer(dens_, CL_TRUE, 0, dens.size() * sizeof(float), dens.data());
  }

  void finish() { queue_.finish(); }
  void set_phase(Phase p) { phase_ = p; }

  // Device milliseconds per phase, from the events of every command so far (after finish()).
  std::array<double, kPhases> phase_ms() {
    std::array<double, kPhases> ms{};
    for (auto& [phase, ev] : events_) {
      const cl_ulong start = ev.getProfilingInfo<CL_PROFILING_COMMAND_START>();
      const cl_ulong end = ev.getProfilingInfo<CL_PROFILING_COMMAND_END>();
      ms[phase] += static_cast<double>(end - start) * 1e-6;
    }
    return ms;
  }

 private:
  cl::Buffer make_buffer(cl_mem_flags flags, std::size_t bytes) {
    if (bytes > ctx_.max_alloc_bytes)
      throw Error(Error::Kind::backend, "backend",
                  "a bundling buffer of " + std::to_string(bytes) +
                      " bytes exceeds the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE");
    return cl::Buffer(ctx_.context, flags, std::max<std::size_t>(bytes, 4));
  }

  // Point set `s` holds at least n points (grown by half again, so that the slow growth of bundled
  // polylines does not reallocate every iteration; whole work-groups, so that padding work-items may
  // read). The contents are not kept.
  void reserve(int s, std::size_t n) {
    if (cap_xy_[s] < n || !x_[s]()) {
      const std::size_t cap = round_up(std::max<std::size_t>(n + n / 2, kGroup));
      x_[s] = make_buffer(CL_MEM_READ_WRITE, cap * sizeof(float));
      y_[s] = make_buffer(CL_MEM_READ_WRITE, cap * sizeof(float));
      cap_xy_[s] = cap;
    }
    if (cap_ze_[s] < n || !z_[s]()) {
      const std::size_t cap = round_up(std::max<std::size_t>(n + n / 2, kGroup));
      z_[s] = make_buffer(CL_MEM_READ_WRITE, cap * sizeof(float));
      edge_[s] = make_buffer(CL_MEM_READ_WRITE, cap * sizeof(cl_uint));
      cap_ze_[s] = cap;
    }
  }

  // A kernel of bundle.cl's ranged form over n items (edges or points); `chunk_arg` is the index of its
  // `chunk` argument. GPU: chunk 1, work-groups of kGroup. CPU: kRangesPerUnit ranges per compute unit
  // (a few, so that a core slowed by other work leaves less for the others to wait on), work-groups of
  // one work-item, so that PoCL hands out whole ranges to its threads.
  void run_chunked(cl::Kernel& k, cl_uint chunk_arg, std::size_t n) {
    if (!coarse_) {
      k.setArg(chunk_arg, cl_uint{1});
      return run1d(k, n);
    }
    constexpr std::size_t kRangesPerUnit = 4;
    const std::size_t chunk =
        std::max<std::size_t>((n + kRangesPerUnit * units_ - 1) / (kRangesPerUnit * units_), 1);
    k.setArg(chunk_arg, static_cast<cl_uint>(chunk));
    queue_.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + chunk - 1) / chunk), cl::NDRange(1),
                                nullptr, event());
  }

  void run1d(cl::Kernel& k, std::size_t n) {
    queue_.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n)), cl::NDRange(kGroup), nullptr,
                                event());
  }

  // A slot for the event of the next command, booked to the current phase.
  cl::Event* event() {
    events_.push_back({phase_, cl::Event()});
    return &events_.back().second;
  }

  const DeviceContext& ctx_;
  cl::CommandQueue queue_;
  Phase phase_ = kOther;
  std::deque<std::pair<Phase, cl::Event>> events_;  // deque: the slots must not move
  int bi_ = 0;                                      // box_[bi_]: the box of the latest splat
  bool coarse_ = false;                             // a CPU device: ranged work-items, private splat images
  std::size_t units_ = 1;                           // compute units
  cl::Buffer partials_;                             // the CPU splat's partial images (zeros between splats)
  std::size_t partials_count_ = 0;
  cl::Kernel k_splat_private_, k_splat_reduce_, k_advect_ranges_, k_col_bands_;
  cl::Kernel k_count_, k_place_, k_clear_, k_splat_, k_rows_, k_cols_, k_advect_, k_smooth_, k_dirs_,
      k_sites_, k_adv_dir_;
  cl::Buffer dirs_;
  std::size_t cap_dirs_ = 0;
  cl::Buffer x_[2], y_[2], z_[2], edge_[2], offsets_[2];
  std::size_t cap_xy_[2] = {0, 0}, cap_ze_[2] = {0, 0};
  cl::Buffer counts_, weights_, profile_, img_, rows_, dens_, box_[2];
  std::vector<std::uint32_t> host_offsets_;
  std::size_t edges_ = 0, n_ = 0;
  int cur_ = 0, size_ = 0;
};

// Runs `body` on a fresh DeviceBundle; OpenCL errors become the reason the device cannot run.
template <class Body>
std::string with_device(Body&& body) {
  return run_on_device("bundle kernel", [&](const DeviceContext* ctx) -> std::string {
    if (std::string u = unsupported(*ctx); !u.empty()) return u;
    DeviceBundle dev(*ctx);
    body(dev);
    return {};
  });
}

}  // namespace

std::string bundle_loop_ocl(const Points& in, const bundling::BundleParams& params,
                            const std::vector<std::uint32_t>& weights, Points& out,
                            bundling::detail::LoopTimes& times, const ProgressFn& progress,
                            const CancelToken* cancel) {
  using namespace bundling::detail;
  return with_device([&](DeviceBundle& dev) {
    dev.upload(in);
    dev.set_weights(weights);
    dev.set_profile(profile_table(params.profile));
    dev.set_size(params.size);
    const int window = smooth_window(params);
    for (int it = 0; it < params.iterations; ++it) {
      if (cancel) cancel->throw_if_cancelled();
      const double h = iteration_h(params.h, params.iterations, it);
      if (it == 0 || !params.polyline_style) {
        ResampleArgs a;
        a.spl = params.spl, a.jitter = params.jitter, a.seed = params.seed;
        a.iteration = static_cast<std::uint32_t>(it), a.block_endpoints = params.block_endpoints;
        dev.set_phase(kResample);
        dev.resample(a);  // waits for the counts: the one synchronisation per iteration
      }
      if (params.directional) {
        dev.set_phase(kAdvect);
        dev.advect_directional(kernel_radius(h), params.eps * h, params.repulsion);
      } else {
        dev.set_phase(kSplat);
        dev.splat();
        dev.set_phase(kConvolve);
        dev.convolve(kernel_radius(h));
        dev.set_phase(kAdvect);
        dev.advect(params.eps * h);
      }
      dev.set_phase(kSmooth);
      dev.smooth(window, params.lambda, params.smooth_iterations);
      dev.set_phase(kOther);
      // Progress means "enqueued" here; the next resample's count read waits for it.
      if (progress) progress(static_cast<double>(it + 1) / params.iterations, "bundle");
    }
    dev.finish();
    const auto ms = dev.phase_ms();
    times.resample_ms += ms[kResample], times.splat_ms += ms[kSplat], times.convolve_ms += ms[kConvolve];
    times.advect_ms += ms[kAdvect], times.smooth_ms += ms[kSmooth];
    dev.download(out);
  });
}

std::string bundle_fixed_ocl(Points& p, const std::vector<std::uint32_t>& weights,
                             const bundling::detail::FixedArgs& a, bundling::detail::LoopTimes& times) {
  return with_device([&](DeviceBundle& dev) {
    dev.upload(p);
    dev.set_weights(weights);
    dev.set_size(a.size);
    for (int it = 0; it < a.iterations; ++it) {
      dev.set_phase(kSplat);
      dev.splat();
      dev.set_phase(kConvolve);
      dev.convolve(a.radius);
      dev.set_phase(kAdvect);
      dev.advect(a.step);
      dev.set_phase(kSmooth);
      dev.smooth(a.window, a.lambda, a.passes);
    }
    dev.set_phase(kOther);
    dev.finish();
    const auto ms = dev.phase_ms();
    times.splat_ms += ms[kSplat], times.convolve_ms += ms[kConvolve], times.advect_ms += ms[kAdvect];
    times.smooth_ms += ms[kSmooth];
    dev.download(p);
  });
}

void bundle_warm_up() {
  // A device without fp64 never runs bundling on OpenCL (bundle() falls back): nothing to warm up, and
  // no reason to fail the other ops' warm-up.
  const DeviceContext* ctx = device_context();
  if (!ctx || !unsupported(*ctx).empty()) return;
  // A few short edges, both advection variants, and one with more points than pixels (the CPU splat's
  // partial images and their sum): builds the program and makes PoCL compile every kernel at the
  // work-group size used (its first enqueue of a kernel costs ~0.1 s otherwise).
  Points in;
  for (std::uint32_t e = 0; e < 128; ++e) {
    in.x.insert(in.x.end(), {10.0f + e, 100.0f - e});
    in.y.insert(in.y.end(), {20.0f, 90.0f + e});
    in.z.insert(in.z.end(), {1.0f, 1.0f});
    in.edge.insert(in.edge.end(), {e, e});
    in.offsets.push_back(2 * e + 2);
  }
  for (int variant = 0; variant < 3; ++variant) {
    bundling::BundleParams p;
    p.size = 128, p.iterations = 2, p.directional = variant == 1;
    if (variant == 2) p.size = 64, p.spl = 1;  // ~20k points on 4096 pixels
    Points out;
    bundling::detail::LoopTimes times;
    const std::string why =
        bundle_loop_ocl(in, p, std::vector<std::uint32_t>(in.edges(), 1), out, times, {}, nullptr);
    if (!why.empty()) throw Error(Error::Kind::backend, "backend", "OpenCL warm-up of bundle failed: " + why);
  }
}

std::string bundle_resample_ocl(const Points& in, const ResampleArgs& a, Points& out) {
  return with_device([&](DeviceBundle& dev) {
    dev.upload(in);
    dev.set_profile(std::vector<float>(a.profile, a.profile + 1024));
    dev.resample(a);
    dev.download(out);
  });
}

std::string bundle_density_ocl(const Points& p, const std::vector<std::uint32_t>& weights, int size,
                               int radius, std::vector<std::uint32_t>& img, Box& box,
                               std::vector<float>& dens) {
  return with_device([&](DeviceBundle& dev) {
    dev.upload(p);
    dev.set_weights(weights);
    dev.set_size(size);
    dev.splat();
    dev.convolve(radius);
    dev.read_density(img, box, dens);
  });
}

std::string bundle_advect_ocl(Points& p, const std::vector<float>& dens, int size, double step) {
  return with_device([&](DeviceBundle& dev) {
    dev.upload(p);
    dev.set_size(size);
    dev.write_density(dens);
    dev.advect(step);
    dev.download(p);
  });
}

std::string bundle_smooth_ocl(Points& p, int window, double lambda, int passes) {
  return with_device([&](DeviceBundle& dev) {
    dev.upload(p);
    dev.smooth(window, lambda, passes);
    dev.download(p);
  });
}
#else
void bundle_warm_up() {}
std::string bundle_loop_ocl(const bundling::detail::Points&, const bundling::BundleParams&,
                            const std::vector<std::uint32_t>&, bundling::detail::Points&,
                            bundling::detail::LoopTimes&, const ProgressFn&, const CancelToken*) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string bundle_resample_ocl(const bundling::detail::Points&, const bundling::detail::ResampleArgs&,
                                bundling::detail::Points&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string bundle_fixed_ocl(bundling::detail::Points&, const std::vector<std::uint32_t>&,
                             const bundling::detail::FixedArgs&, bundling::detail::LoopTimes&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string bundle_density_ocl(const bundling::detail::Points&, const std::vector<std::uint32_t>&, int, int,
                               std::vector<std::uint32_t>&, bundling::detail::Box&, std::vector<float>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string bundle_advect_ocl(bundling::detail::Points&, const std::vector<float>&, int, double) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string bundle_smooth_ocl(bundling::detail::Points&, int, double, int) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
#endif

}  // namespace trailscope::ocl
