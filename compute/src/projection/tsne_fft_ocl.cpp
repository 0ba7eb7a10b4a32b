// Host side of compute/kernels/projection_tsne_fft.cl (see projection/tsne_fft_ocl.hpp). Per gradient: the
// host lays out the grid and sorts the points by box (O(N)); the device computes the attraction
// (tsne_attract of projection_tsne.cl) and spreads the charges to the grid; the host convolves the grid
// by FFT (float cv::dft: on PoCL the device is the same CPU, and on a GPU the grid, a few hundred KiB,
// crosses the bus in tens of µs); the device gathers the potentials back to the points.
#include "projection/tsne_fft_ocl.hpp"

#include <algorithm>
#include <cstdint>

#include "projection/detail.hpp"
#include "projection/tsne_fft.hpp"
#include "trailscope/core/error.hpp"
#ifdef TRAILSCOPE_HAVE_OPENCL
#include "ocl/runtime.hpp"
#endif

namespace trailscope::ocl {

#ifdef TRAILSCOPE_HAVE_OPENCL
namespace {

constexpr std::size_t kMaxGlobal = std::size_t{1} << 31;

// A read-write buffer of at least `bytes`, reallocated (1.5×) only when it must grow.
void reserve(const DeviceContext* ctx, cl::Buffer& b, std::size_t& cap, std::size_t bytes) {
  if (bytes <= cap && cap > 0) return;
  cap = std::max<std::size_t>(bytes + bytes / 2, 64);
  b = cl::Buffer(ctx->context, CL_MEM_READ_WRITE, cap);
}

class TsneFftDevice {
 public:
  TsneFftDevice(const DeviceContext* ctx, std::size_t n, const projection::Affinities* P,
                const projection::TsneFftOptions& f)
      : ctx_(ctx), n_(n), f_(f), conv_(CV_32F) {
    const std::size_t nn = std::max<std::size_t>(n, 1);
    u_ = cl::Buffer(ctx->context, CL_MEM_READ_ONLY, nn * 8);
    order_ = cl::Buffer(ctx->context, CL_MEM_READ_ONLY, nn * 4);
    rep_ = cl::Buffer(ctx->context, CL_MEM_WRITE_ONLY, nn * 16);
    const cl::Program prog = program("projection_tsne_fft", "-DP=" + std::to_string(f.nodes_per_box));
    spread_ = cl::Kernel(prog, "tsne_fft_spread");
    gather_ = cl::Kernel(prog, "tsne_fft_gather");
    if (P) {
      if (P->col.size() >= kMaxGlobal) throw Error(Error::Kind::backend, "backend", "P has too many entries");
      std::vector<cl_int> rs(P->row_start.begin(), P->row_start.end()), col(P->col.begin(), P->col.end());
      std::vector<float> p(P->p.begin(), P->p.end());
      rows_ = cl::Buffer(ctx->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, rs.size() * 4, rs.data());
      col_ = cl::Buffer(ctx->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        std::max<std::size_t>(col.size(), 1) * 4, col.empty() ? rs.data() : col.data());
      p_ = cl::Buffer(ctx->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                      std::max<std::size_t>(p.size(), 1) * 4,
                      p.empty() ? static_cast<void*>(rs.data()) : p.data());
      attr_ = cl::Buffer(ctx->context, CL_MEM_WRITE_ONLY, nn * 8);
      attract_ = cl::Kernel(program("projection_tsne"), "tsne_attract");
      af_.resize(2 * n);
    }
    uf_.resize(2 * n), rf_.resize(4 * n);
  }

  // Enqueues the attraction (when P was given) and the repulsion; rf_ (n × 4) and af_ (n × 2) hold
  // the results on return.
  void compute(const std::vector<double>& y) {
    const cl::CommandQueue& q = ctx_->queue;
    const projection::detail::FftLayout g = projection::detail::fft_layout(y, n_, f_);
    projection::detail::sort_by_box(y, n_, g, order_h_, start_h_);
    const double half = 0.5 * g.boxes * g.h, cx = g.x0 + half, cy = g.y0 + half;
    for (std::size_t i = 0; i < n_; ++i)
      uf_[2 * i] = static_cast<float>(y[2 * i] - cx), uf_[2 * i + 1] = static_cast<float>(y[2 * i + 1] - cy);
    const std::size_t cells = static_cast<std::size_t>(g.m) * g.l;
    if (cells >= kMaxGlobal) throw Error(Error::Kind::backend, "backend", "FFT grid too large");
    reserve(ctx_, start_, start_cap_, start_h_.size() * 4);
    reserve(ctx_, qa_, qa_cap_, cells * 8), reserve(ctx_, qc_, qc_cap_, cells * 4);
    reserve(ctx_, o1_, o1_cap_, cells * 8), reserve(ctx_, o2_, o2_cap_, cells * 8);
    q.enqueueWriteBuffer(u_, CL_FALSE, 0, n_ * 8, uf_.data());
    q.enqueueWriteBuffer(order_, CL_FALSE, 0, n_ * 4, order_h_.data());
    q.enqueueWriteBuffer(start_, CL_FALSE, 0, start_h_.size() * 4, start_h_.data());
    if (af_.size()) {
      attract_.setArg(0, rows_), attract_.setArg(1, col_), attract_.setArg(2, p_), attract_.setArg(3, u_);
      attract_.setArg(4, static_cast<cl_int>(n_)), attract_.setArg(5, attr_);
      launch(ctx_, attract_, n_);
    }
    const auto lo = static_cast<cl_float>(-half);
    spread_.setArg(0, u_), spread_.setArg(1, order_), spread_.setArg(2, start_);
    spread_.setArg(3, static_cast<cl_int>(g.boxes)), spread_.setArg(4, static_cast<cl_int>(g.l));
    spread_.setArg(5, static_cast<cl_int>(g.m)), spread_.setArg(6, lo),
        spread_.setArg(7, static_cast<cl_float>(g.h));
    spread_.setArg(8, qa_), spread_.setArg(9, qc_);
    launch(ctx_, spread_, cells);
    conv_.prepare(g);  // zeroes the host grids while the device spreads
    // The first m rows of the l × l grids are contiguous: the device's m × l layout lands in place.
    q.enqueueReadBuffer(qa_, CL_FALSE, 0, cells * 8, conv_.a().ptr<float>(0));
    q.enqueueReadBuffer(qc_, CL_TRUE, 0, cells * 4, conv_.c().ptr<float>(0));
    conv_.run();
    q.enqueueWriteBuffer(o1_, CL_FALSE, 0, cells * 8, conv_.out1().ptr<float>(0));
    q.enqueueWriteBuffer(o2_, CL_FALSE, 0, cells * 8, conv_.out2().ptr<float>(0));
    gather_.setArg(0, u_), gather_.setArg(1, static_cast<cl_int>(n_)),
        gather_.setArg(2, static_cast<cl_int>(g.boxes));
    gather_.setArg(3, static_cast<cl_int>(g.l)), gather_.setArg(4, lo),
        gather_.setArg(5, static_cast<cl_float>(g.h));
    gather_.setArg(6, o1_), gather_.setArg(7, o2_), gather_.setArg(8, rep_);
    launch(ctx_, gather_, n_);
    if (af_.size()) q.enqueueReadBuffer(attr_, CL_FALSE, 0, n_ * 8, af_.data());
    q.enqueueReadBuffer(rep_, CL_TRUE, 0, n_ * 16, rf_.data());  // in-order: waits for all
  }

  void terms(std::vector<double>& out) const {
    out.resize(3 * n_);
    for (std::size_t i = 0; i < n_; ++i)
      out[3 * i] = rf_[4 * i], out[3 * i + 1] = rf_[4 * i + 1], out[3 * i + 2] = rf_[4 * i + 2];
  }

  void gradient(const std::vector<double>& y, double exaggeration, std::vector<double>& g) {
    compute(y);
    projection::detail::tsne_combine(af_.data(), rf_.data(), 4, n_, exaggeration, g);
  }

 private:
  const DeviceContext* ctx_;
  std::size_t n_;
  projection::TsneFftOptions f_;
  projection::detail::FftConvolver conv_;
  cl::Buffer u_, order_, rep_, start_, qa_, qc_, o1_, o2_, rows_, col_, p_, attr_;
  std::size_t start_cap_ = 0, qa_cap_ = 0, qc_cap_ = 0, o1_cap_ = 0, o2_cap_ = 0;
  cl::Kernel spread_, gather_, attract_;
  std::vector<float> uf_, rf_, af_;
  std::vector<std::int32_t> order_h_, start_h_;
};

}  // namespace

std::string tsne_fft_repulsion_ocl(const std::vector<double>& y, const projection::TsneFftOptions& f,
                                   std::vector<double>& terms) {
  return run_on_device("t-SNE FFT kernels", [&](const DeviceContext* ctx) -> std::string {
    TsneFftDevice dev(ctx, y.size() / 2, nullptr, f);
    dev.compute(y);
    dev.terms(terms);
    return {};
  });
}

std::string tsne_fft_gradient_ocl(const projection::Affinities& P, const std::vector<double>& y,
                                  double exaggeration, const projection::TsneFftOptions& f,
                                  std::vector<double>& grad) {
  return run_on_device("t-SNE FFT kernels", [&](const DeviceContext* ctx) -> std::string {
    TsneFftDevice dev(ctx, P.rows, &P, f);
    dev.gradient(y, exaggeration, grad);
    return {};
  });
}

std::string tsne_fft_optimize_ocl(const projection::Affinities& P, const projection::TsneOptions& o,
                                  std::vector<double>& y) {
  return run_on_device("t-SNE FFT kernels", [&](const DeviceContext* ctx) -> std::string {
    TsneFftDevice dev(ctx, P.rows, &P, o.fft);
    projection::detail::tsne_optimize(
        y, P.rows, o,
        [&](const std::vector<double>& yy, double ex, std::vector<double>& g) { dev.gradient(yy, ex, g); });
    return {};
  });
}

#else
std::string tsne_fft_repulsion_ocl(const std::vector<double>&, const projection::TsneFftOptions&,
                                   std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string tsne_fft_gradient_ocl(const projection::Affinities&, const std::vector<double>&, double,
                                  const projection::TsneFftOptions&, std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string tsne_fft_optimize_ocl(const projection::Affinities&, const projection::TsneOptions&,
                                  std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
#endif

}  // namespace trailscope::ocl
