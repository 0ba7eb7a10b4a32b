// Host side of compute/kernels/projection_*.cl (see trailscope/projection/projection.hpp for what each
// method computes and projection/projection_ocl.hpp for the contract of each function).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <tbb/parallel_for.h>

#include "projection/detail.hpp"
#include "projection/projection_ocl.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/projection/projection.hpp"
#ifdef TRAILSCOPE_HAVE_OPENCL
#include "ocl/runtime.hpp"
#endif

namespace trailscope::ocl {

#ifdef TRAILSCOPE_HAVE_OPENCL
namespace {

constexpr std::size_t kMaxGlobal = std::size_t{1} << 31;  // kernels index with int / size_t mixes

cl::Buffer upload(const DeviceContext* ctx, const void* p, std::size_t bytes) {
  // COPY_HOST_PTR: read-only on the device, the host data stays untouched. A zero-sized buffer is
  // invalid in OpenCL, so empty inputs get one element.
  if (bytes == 0) return cl::Buffer(ctx->context, CL_MEM_READ_ONLY, 4);
  return cl::Buffer(ctx->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<void*>(p));
}

template <class T>
cl::Buffer upload(const DeviceContext* ctx, const std::vector<T>& v) {
  return upload(ctx, v.data(), v.size() * sizeof(T));
}

std::string too_big(const DeviceContext* ctx, std::initializer_list<std::size_t> bytes) {
  for (std::size_t b : bytes)
    if (b > ctx->max_alloc_bytes) return "a buffer exceeds the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE";
  return {};
}

// Squared/plain distances of a (na × dims) to the resident buffer b (nb × dims) into the buffer out.
void sqdist_on(const DeviceContext* ctx, const cl::Buffer& a, std::size_t na, const cl::Buffer& b,
               std::size_t nb, std::size_t dims, bool root, const cl::Buffer& out) {
  cl::Kernel k(program("projection_distance"), "sqdist");
  k.setArg(0, a), k.setArg(1, b), k.setArg(2, static_cast<cl_int>(na)), k.setArg(3, static_cast<cl_int>(nb));
  k.setArg(4, static_cast<cl_int>(dims)), k.setArg(5, static_cast<cl_int>(root ? 1 : 0)), k.setArg(6, out);
  launch(ctx, k, na * nb);
}

}  // namespace

std::string projection_sqdist_ocl(const float* a, std::size_t na, const float* b, std::size_t nb,
                                  std::size_t dims, bool root, float* out) {
  return run_on_device("projection sqdist kernel", [&](const DeviceContext* ctx) -> std::string {
    if (na * nb >= kMaxGlobal)
      return "distance block of " + std::to_string(na * nb) + " entries is too large";
    if (auto w = too_big(ctx, {na * nb * 4, na * dims * 4, nb * dims * 4}); !w.empty()) return w;
    cl::Buffer ba = upload(ctx, a, na * dims * 4), bb = upload(ctx, b, nb * dims * 4);
    cl::Buffer bo(ctx->context, CL_MEM_WRITE_ONLY, std::max<std::size_t>(4, na * nb * 4));
    sqdist_on(ctx, ba, na, bb, nb, dims, root, bo);
    if (na * nb > 0) ctx->queue.enqueueReadBuffer(bo, CL_TRUE, 0, na * nb * 4, out);
    return {};
  });
}

std::string projection_knn_ocl(const float* x, std::size_t n, std::size_t dims, int k, std::int32_t* idx,
                               float* sqdist) {
  return run_on_device("projection knn kernel", [&](const DeviceContext* ctx) -> std::string {
    if (k < 1 || static_cast<std::size_t>(k) >= n) return "k out of range";
    // Tiled: the device fills blocks of `rows` × n squared distances (the O(N²·D) part, with j fastest so
    // that PoCL vectorises across work-items and a GPU coalesces), the host selects each row's k
    // smallest by (distance, index) while the device computes the next block. A per-row selection kernel
    // measured 10× slower on PoCL: its private sorted lists defeat the vectoriser.
    const std::size_t rows = std::max<std::size_t>(1, std::min(n, (std::size_t{1} << 23) / n));
    if (auto w = too_big(ctx, {n * dims * 4, rows * n * 4}); !w.empty()) return w;
    cl::Buffer bx = upload(ctx, x, n * dims * 4);
    cl::Buffer out[2] = {cl::Buffer(ctx->context, CL_MEM_WRITE_ONLY, rows * n * 4),
                         cl::Buffer(ctx->context, CL_MEM_WRITE_ONLY, rows * n * 4)};
    std::vector<float> block[2] = {std::vector<float>(rows * n), std::vector<float>(rows * n)};
    const auto enqueue = [&](std::size_t r0, int slot) {
      const std::size_t m = std::min(rows, n - r0);
      cl::Buffer sub = upload(ctx, x + r0 * dims, m * dims * 4);
      sqdist_on(ctx, sub, m, bx, n, dims, false, out[slot]);
      cl::Event done;
      ctx->queue.enqueueReadBuffer(out[slot], CL_FALSE, 0, m * n * 4, block[slot].data(), nullptr, &done);
      return done;
    };
    cl::Event pending = enqueue(0, 0);
    for (std::size_t r0 = 0, slot = 0; r0 < n; r0 += rows, slot ^= 1) {
      pending.wait();
      const std::size_t m = std::min(rows, n - r0);
      if (r0 + rows < n) pending = enqueue(r0 + rows, static_cast<int>(slot ^ 1));
      const float* d = block[slot].data();
      tbb::parallel_for(std::size_t{0}, m, [&](std::size_t a) {
        const std::size_t i = r0 + a;
        std::vector<std::int32_t> cand(n);
        for (std::size_t j = 0; j < n; ++j) cand[j] = static_cast<std::int32_t>(j);
        cand.erase(cand.begin() + static_cast<std::ptrdiff_t>(i));
        const float* row = d + a * n;
        const auto less = [row](std::int32_t p, std::int32_t q) {
          return row[p] < row[q] || (row[p] == row[q] && p < q);
        };
        std::nth_element(cand.begin(), cand.begin() + (k - 1), cand.end(), less);
        std::sort(cand.begin(), cand.begin() + k, less);
        for (int c = 0; c < k; ++c) {
          idx[i * k + c] = cand[c];
          sqdist[i * k + c] = row[cand[c]];
        }
      });
    }
    return {};
  });
}

std::string projection_covariance_ocl(const float* x, std::size_t n, std::size_t dims, const double* mean,
                                      double* cov) {
  return run_on_device("projection covariance kernel", [&](const DeviceContext* ctx) -> std::string {
    const std::size_t dd = dims * dims;
    // Chunks of rows: enough work-items to fill the device, few enough partials (≤ 16M floats), and
    // float sums of at most a few thousand terms.
    std::size_t chunks = std::clamp<std::size_t>((std::size_t{1} << 24) / std::max<std::size_t>(dd, 1), 1,
                                                 std::max<std::size_t>(1, (n + 63) / 64));
    const std::size_t rows_per = (n + chunks - 1) / chunks;
    chunks = (n + rows_per - 1) / rows_per;
    if (auto w = too_big(ctx, {n * dims * 4, chunks * dd * 4}); !w.empty()) return w;
    std::vector<float> meanf(mean, mean + dims), partial(chunks * dd);
    cl::Kernel k(program("projection_pca"), "covariance");
    cl::Buffer bx = upload(ctx, x, n * dims * 4), bm = upload(ctx, meanf);
    cl::Buffer bp(ctx->context, CL_MEM_WRITE_ONLY, partial.size() * 4);
    k.setArg(0, bx), k.setArg(1, bm), k.setArg(2, static_cast<cl_int>(n)),
        k.setArg(3, static_cast<cl_int>(dims));
    k.setArg(4, static_cast<cl_int>(rows_per)), k.setArg(5, static_cast<cl_int>(chunks)), k.setArg(6, bp);
    launch(ctx, k, chunks * dd);
    ctx->queue.enqueueReadBuffer(bp, CL_TRUE, 0, partial.size() * 4, partial.data());
    std::fill(cov, cov + dd, 0.0);
    for (std::size_t c = 0; c < chunks; ++c)
      for (std::size_t e = 0; e < dd; ++e) cov[e] += partial[c * dd + e];
    return {};
  });
}

std::string projection_scores_ocl(const float* x, std::size_t n, std::size_t dims, const double* mean,
                                  const double* w, double* out) {
  return run_on_device("projection scores kernel", [&](const DeviceContext* ctx) -> std::string {
    if (auto e = too_big(ctx, {n * dims * 4}); !e.empty()) return e;
    std::vector<float> meanf(mean, mean + dims), wf(w, w + 2 * dims), res(2 * n);
    cl::Kernel k(program("projection_pca"), "scores");
    cl::Buffer bx = upload(ctx, x, n * dims * 4), bm = upload(ctx, meanf), bw = upload(ctx, wf);
    cl::Buffer bo(ctx->context, CL_MEM_WRITE_ONLY, res.size() * 4);
    k.setArg(0, bx), k.setArg(1, bm), k.setArg(2, bw), k.setArg(3, static_cast<cl_int>(n));
    k.setArg(4, static_cast<cl_int>(dims)), k.setArg(5, bo);
    launch(ctx, k, n);
    ctx->queue.enqueueReadBuffer(bo, CL_TRUE, 0, res.size() * 4, res.data());
    std::copy(res.begin(), res.end(), out);
    return {};
  });
}

std::string projection_mds_exact_ocl(const float* x, std::size_t n, std::size_t dims, std::uint64_t seed,
                                     const CancelToken* cancel, std::vector<double>& xy) {
  return run_on_device("projection MDS kernels", [&](const DeviceContext* ctx) -> std::string {
    if (n * n >= kMaxGlobal) return "MDS matrix too large for the kernels";
    if (auto w = too_big(ctx, {n * n * 4, n * dims * 4}); !w.empty()) return w;
    const cl::Program dist = program("projection_distance"), mds = program("projection_mds");
    cl::Buffer bx = upload(ctx, x, n * dims * 4);
    cl::Buffer bb(ctx->context, CL_MEM_READ_WRITE, n * n * 4);
    sqdist_on(ctx, bx, n, bx, n, dims, false, bb);
    cl::Buffer bs(ctx->context, CL_MEM_READ_WRITE, n * 4);
    cl::Kernel rs(mds, "row_sums");
    rs.setArg(0, bb), rs.setArg(1, static_cast<cl_int>(n)), rs.setArg(2, bs);
    launch(ctx, rs, n);
    std::vector<float> sums(n);
    ctx->queue.enqueueReadBuffer(bs, CL_TRUE, 0, n * 4, sums.data());
    // Means and the grand mean in double; the centring itself in float on the device.
    double grand = 0;
    std::vector<float> rowmean(n);
    for (std::size_t i = 0; i < n; ++i)
      grand += sums[i], rowmean[i] = static_cast<float>(sums[i] / double(n));
    grand /= double(n) * double(n);
    ctx->queue.enqueueWriteBuffer(bs, CL_TRUE, 0, n * 4, rowmean.data());
    cl::Kernel dc(mds, "double_centre");
    dc.setArg(0, bb), dc.setArg(1, bs), dc.setArg(2, static_cast<cl_float>(grand)),
        dc.setArg(3, static_cast<cl_int>(n));
    launch(ctx, dc, n * n);
    cl::Kernel mm(mds, "block_matmul");
    cl::Buffer bv(ctx->context, CL_MEM_READ_ONLY, n * 8 * 4), bo(ctx->context, CL_MEM_WRITE_ONLY, n * 8 * 4);
    std::vector<float> vf, of;
    const projection::detail::TopEigen te = projection::detail::top_eigen(
        n,
        [&](const std::vector<double>& v, int p, std::vector<double>& out) {
          vf.assign(v.begin(), v.end());
          of.resize(n * p);
          ctx->queue.enqueueWriteBuffer(bv, CL_FALSE, 0, vf.size() * 4, vf.data());
          mm.setArg(0, bb), mm.setArg(1, bv), mm.setArg(2, static_cast<cl_int>(n)),
              mm.setArg(3, static_cast<cl_int>(p));
          mm.setArg(4, bo);
          launch(ctx, mm, n);
          ctx->queue.enqueueReadBuffer(bo, CL_TRUE, 0, of.size() * 4, of.data());
          out.assign(of.begin(), of.end());
        },
        seed, projection::detail::kEigenTol, projection::detail::kEigenMaxIter, cancel);
    xy.assign(2 * n, 0.0);
    for (int c = 0; c < 2; ++c) {
      const double s = std::sqrt(std::max(te.lambda[c], 0.0));
      for (std::size_t i = 0; i < n; ++i) xy[2 * i + c] = te.v[2 * i + c] * s;
    }
    return {};
  });
}

namespace {

// The t-SNE gradient with P resident on the device; the quadtree is built on the host each call
// (O(N log N), ~1 ms at 10^4 points) and uploaded.
class TsneDevice {
 public:
  TsneDevice(const DeviceContext* ctx, const projection::Affinities& P, double theta)
      : ctx_(ctx), n_(P.rows), theta_(theta) {
    if (P.col.size() >= kMaxGlobal) throw Error(Error::Kind::backend, "backend", "P has too many entries");
    std::vector<cl_int> rs(P.row_start.begin(), P.row_start.end());
    std::vector<cl_int> col(P.col.begin(), P.col.end());
    std::vector<float> p(P.p.begin(), P.p.end());
    rows_ = upload(ctx, rs), col_ = upload(ctx, col), p_ = upload(ctx, p);
    y_ = cl::Buffer(ctx->context, CL_MEM_READ_ONLY, std::max<std::size_t>(1, n_) * 8);
    attr_ = cl::Buffer(ctx->context, CL_MEM_WRITE_ONLY, std::max<std::size_t>(1, n_) * 8);
    rep_ = cl::Buffer(ctx->context, CL_MEM_WRITE_ONLY, std::max<std::size_t>(1, n_) * 16);
    orderb_ = cl::Buffer(ctx->context, CL_MEM_READ_ONLY, std::max<std::size_t>(1, n_) * 4);
    attract_ = cl::Kernel(program("projection_tsne"), "tsne_attract");
    if (theta > 0)
      repulse_ = cl::Kernel(
          program("projection_tsne", "-DSTACK=" + std::to_string(projection::detail::QuadTree::kStack)),
          "tsne_repulse_bh");
    else
      repulse_ = cl::Kernel(program("projection_tsne"), "tsne_repulse_exact");
    yf_.resize(2 * n_), af_.resize(2 * n_), rf_.resize(4 * n_);
  }

  void gradient(const std::vector<double>& y, double exaggeration, std::vector<double>& g) {
    const cl::CommandQueue& q = ctx_->queue;
    for (std::size_t c = 0; c < 2 * n_; ++c) yf_[c] = static_cast<float>(y[c]);
    q.enqueueWriteBuffer(y_, CL_FALSE, 0, yf_.size() * 4, yf_.data());
    attract_.setArg(0, rows_), attract_.setArg(1, col_), attract_.setArg(2, p_), attract_.setArg(3, y_);
    attract_.setArg(4, static_cast<cl_int>(n_)), attract_.setArg(5, attr_);
    launch(ctx_, attract_, n_);
    if (theta_ > 0) {
      tree_.build(y, n_);
      const std::size_t m = tree_.child.size();
      if (m > cap_) {  // grow the tree buffers geometrically: the tree size changes every iteration
        cap_ = m + m / 2 + 64;
        node_ = cl::Buffer(ctx_->context, CL_MEM_READ_ONLY, cap_ * 16);
        child_ = cl::Buffer(ctx_->context, CL_MEM_READ_ONLY, cap_ * 4);
        point_ = cl::Buffer(ctx_->context, CL_MEM_READ_ONLY, cap_ * 4);
      }
      // Non-blocking: the blocking read below (in-order queue) completes them before the next build
      // touches the tree's vectors.
      q.enqueueWriteBuffer(node_, CL_FALSE, 0, m * 16, tree_.node.data());
      q.enqueueWriteBuffer(child_, CL_FALSE, 0, m * 4, tree_.child.data());
      q.enqueueWriteBuffer(point_, CL_FALSE, 0, m * 4, tree_.point.data());
      projection::detail::morton_order(y, n_, order_);
      q.enqueueWriteBuffer(orderb_, CL_FALSE, 0, n_ * 4, order_.data());
      repulse_.setArg(0, node_), repulse_.setArg(1, child_), repulse_.setArg(2, point_);
      repulse_.setArg(3, y_), repulse_.setArg(4, orderb_), repulse_.setArg(5, static_cast<cl_int>(n_));
      repulse_.setArg(6, static_cast<cl_float>(theta_ * theta_)), repulse_.setArg(7, rep_);
    } else {
      repulse_.setArg(0, y_), repulse_.setArg(1, static_cast<cl_int>(n_)), repulse_.setArg(2, rep_);
    }
    launch(ctx_, repulse_, n_);
    q.enqueueReadBuffer(attr_, CL_FALSE, 0, af_.size() * 4, af_.data());
    q.enqueueReadBuffer(rep_, CL_TRUE, 0, rf_.size() * 4, rf_.data());  // in-order: waits for all
    projection::detail::tsne_combine(af_.data(), rf_.data(), 4, n_, exaggeration, g);
  }

 private:
  const DeviceContext* ctx_;
  std::size_t n_;
  double theta_;
  cl::Buffer rows_, col_, p_, y_, attr_, rep_, node_, child_, point_, orderb_;
  cl::Kernel attract_, repulse_;
  projection::detail::QuadTree tree_;
  std::size_t cap_ = 0;
  std::vector<float> yf_, af_, rf_;
  std::vector<std::int32_t> order_;  // Morton order of the points (the Barnes-Hut launch order)
};

}  // namespace

std::string projection_tsne_optimize_ocl(const projection::Affinities& P, const projection::TsneOptions& o,
                                         double theta, std::vector<double>& y) {
  return run_on_device("projection t-SNE kernels", [&](const DeviceContext* ctx) -> std::string {
    TsneDevice dev(ctx, P, theta);
    projection::detail::tsne_optimize(
        y, P.rows, o,
        [&](const std::vector<double>& yy, double ex, std::vector<double>& g) { dev.gradient(yy, ex, g); });
    return {};
  });
}

std::string projection_tsne_gradient_ocl(const projection::Affinities& P, const std::vector<double>& y,
                                         double exaggeration, double theta, std::vector<double>& grad) {
  return run_on_device("projection t-SNE kernels", [&](const DeviceContext* ctx) -> std::string {
    TsneDevice dev(ctx, P, theta);
    dev.gradient(y, exaggeration, grad);
    return {};
  });
}

std::string projection_force_ocl(const float* x, std::size_t n, std::size_t dims, int iterations,
                                 const CancelToken* cancel, std::vector<double>& y) {
  return run_on_device("projection Force Scheme kernel", [&](const DeviceContext* ctx) -> std::string {
    if (n * n >= kMaxGlobal) return "Force Scheme matrix too large for the kernels";
    if (auto w = too_big(ctx, {n * n * 4, n * dims * 4}); !w.empty()) return w;
    cl::Buffer bx = upload(ctx, x, n * dims * 4);
    cl::Buffer bd(ctx->context, CL_MEM_READ_WRITE, n * n * 4);
    sqdist_on(ctx, bx, n, bx, n, dims, true, bd);
    std::vector<float> yf(y.begin(), y.end());
    cl::Buffer ya(ctx->context, CL_MEM_READ_WRITE, n * 8), yb(ctx->context, CL_MEM_READ_WRITE, n * 8);
    ctx->queue.enqueueWriteBuffer(ya, CL_TRUE, 0, n * 8, yf.data());
    cl::Kernel k(program("projection_force"), "force_step");
    for (int it = 0; it < iterations; ++it) {
      if (cancel && it % 16 == 0) cancel->throw_if_cancelled();
      k.setArg(0, bd), k.setArg(1, ya), k.setArg(2, static_cast<cl_int>(n));
      k.setArg(3, static_cast<cl_float>(1.0 / double(n))), k.setArg(4, yb);
      launch(ctx, k, n);
      std::swap(ya, yb);
    }
    ctx->queue.enqueueReadBuffer(ya, CL_TRUE, 0, n * 8, yf.data());
    y.assign(yf.begin(), yf.end());
    return {};
  });
}

std::string projection_lamp_map_ocl(const float* x, std::size_t n, std::size_t dims,
                                    const std::vector<std::size_t>& controls,
                                    const std::vector<double>& control_xy, std::vector<double>& out) {
  return run_on_device("projection LAMP kernel", [&](const DeviceContext* ctx) -> std::string {
    const std::size_t nc = controls.size();
    if (auto w = too_big(ctx, {n * dims * 4}); !w.empty()) return w;
    std::vector<float> cx(nc * dims), cy(control_xy.begin(), control_xy.end()), res(2 * n);
    for (std::size_t i = 0; i < nc; ++i) std::copy_n(x + controls[i] * dims, dims, cx.data() + i * dims);
    // Points per launch: the weights scratch (batch × controls floats) stays ≤ 64 MiB.
    const std::size_t batch =
        std::max<std::size_t>(1, std::min(n, (std::size_t{16} << 20) / std::max<std::size_t>(nc, 1)));
    cl::Kernel k(program("projection_lamp"), "lamp_map");
    cl::Buffer bx = upload(ctx, x, n * dims * 4), bcx = upload(ctx, cx), bcy = upload(ctx, cy);
    cl::Buffer scratch(ctx->context, CL_MEM_READ_WRITE, batch * nc * 4);
    cl::Buffer bo(ctx->context, CL_MEM_WRITE_ONLY, batch * 8);
    for (std::size_t first = 0; first < n; first += batch) {
      const std::size_t count = std::min(batch, n - first);
      k.setArg(0, bx), k.setArg(1, static_cast<cl_int>(dims)), k.setArg(2, static_cast<cl_int>(first));
      k.setArg(3, static_cast<cl_int>(count)), k.setArg(4, bcx), k.setArg(5, bcy),
          k.setArg(6, static_cast<cl_int>(nc));
      k.setArg(7, scratch), k.setArg(8, bo);
      launch(ctx, k, count);
      ctx->queue.enqueueReadBuffer(bo, CL_TRUE, 0, count * 8, res.data() + 2 * first);
    }
    out.assign(res.begin(), res.end());
    return {};
  });
}

void projection_warm_up() {
  // Builds each projection program and runs most kernels once on a 4×3 table.
  const std::vector<float> x = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::vector<float> d(16);
  std::vector<double> mean(3, 0.25), cov(9), w(6, 0.5), s(8);
  std::string why = projection_sqdist_ocl(x.data(), 4, x.data(), 4, 3, false, d.data());
  if (why.empty()) why = projection_covariance_ocl(x.data(), 4, 3, mean.data(), cov.data());
  if (why.empty()) why = projection_scores_ocl(x.data(), 4, 3, mean.data(), w.data(), s.data());
  std::vector<double> xy;
  if (why.empty()) why = projection_mds_exact_ocl(x.data(), 4, 3, 1, nullptr, xy);
  if (why.empty()) {
    std::vector<double> y = {0, 0, 1, 0, 0, 1, 1, 1};
    why = projection_force_ocl(x.data(), 4, 3, 1, nullptr, y);
    if (why.empty()) why = projection_lamp_map_ocl(x.data(), 4, 3, {0, 1, 2}, {0, 0, 1, 0, 0, 1}, y);
  }
  if (!why.empty())
    throw Error(Error::Kind::backend, "backend", "OpenCL warm-up of the projections failed: " + why);
  try {
    (void)program("projection_tsne");
    (void)program("projection_tsne_fft");
    (void)program("projection_tsne", "-DSTACK=" + std::to_string(projection::detail::QuadTree::kStack));
  } catch (const cl::Error& e) {
    throw Error(Error::Kind::backend, "backend", "OpenCL warm-up of the projections failed: " + describe(e));
  }
}

#else
std::string projection_sqdist_ocl(const float*, std::size_t, const float*, std::size_t, std::size_t, bool,
                                  float*) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_knn_ocl(const float*, std::size_t, std::size_t, int, std::int32_t*, float*) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_covariance_ocl(const float*, std::size_t, std::size_t, const double*, double*) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_scores_ocl(const float*, std::size_t, std::size_t, const double*, const double*,
                                  double*) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_mds_exact_ocl(const float*, std::size_t, std::size_t, std::uint64_t,
                                     const CancelToken*, std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_tsne_optimize_ocl(const projection::Affinities&, const projection::TsneOptions&,
                                         double, std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_tsne_gradient_ocl(const projection::Affinities&, const std::vector<double>&, double,
                                         double, std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_force_ocl(const float*, std::size_t, std::size_t, int, const CancelToken*,
                                 std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
std::string projection_lamp_map_ocl(const float*, std::size_t, std::size_t, const std::vector<std::size_t>&,
                                    const std::vector<double>&, std::vector<double>&) {
  return "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)";
}
void projection_warm_up() {
  throw Error(Error::Kind::backend, "backend", "built without OpenCL (TRAILSCOPE_WITH_OPENCL=OFF)");
}
#endif

}  // namespace trailscope::ocl
