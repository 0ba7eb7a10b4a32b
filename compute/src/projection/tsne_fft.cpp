// FFT-interpolated t-SNE repulsion (FIt-SNE): the host parts (tsne_fft.hpp) and the C++ reference.
#include "projection/tsne_fft.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "ocl/dispatch.hpp"
#include "projection/tsne_fft_ocl.hpp"
#include "projection/detail.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::projection::detail {

void check_fft_options(const TsneFftOptions& f) {
  if (f.nodes_per_box < 2 || f.nodes_per_box > 8)
    throw invalid_argument("fft",
                           "fft.nodes_per_box must be in [2, 8], not " + std::to_string(f.nodes_per_box));
  if (!(f.box_width > 0) || !std::isfinite(f.box_width))
    throw invalid_argument("fft", "fft.box_width must be > 0");
  if (f.min_boxes < 1 || f.min_boxes > 512 || (f.max_boxes != 0 && f.max_boxes < f.min_boxes) ||
      f.max_boxes > 512)
    throw invalid_argument("fft", "fft boxes must satisfy 1 ≤ min_boxes ≤ max_boxes ≤ 512 (or max_boxes 0)");
}

FftLayout fft_layout(const std::vector<double>& y, std::size_t n, const TsneFftOptions& f) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (std::size_t i = 0; i < n; ++i) {
    x0 = std::min(x0, y[2 * i]), x1 = std::max(x1, y[2 * i]);
    y0 = std::min(y0, y[2 * i + 1]), y1 = std::max(y1, y[2 * i + 1]);
  }
  if (n == 0) x0 = x1 = y0 = y1 = 0;
  // A margin of 1e-6 of the extent keeps the largest coordinate strictly inside the last box.
  const double extent = std::max({x1 - x0, y1 - y0, 1e-12}) * (1 + 1e-6);
  FftLayout g;
  g.p = f.nodes_per_box;
  // At most kMaxFftNodes nodes per axis whatever the options: the grids (l ≈ 2m per axis, complex
  // double in the reference: ~10 grids of 1024²) stay within ~160 MiB.
  const int hard = kMaxFftNodes / f.nodes_per_box;
  const int cap = std::min(
      hard, f.max_boxes > 0
                ? f.max_boxes
                : std::clamp(static_cast<int>(std::ceil(std::max(std::sqrt(static_cast<double>(n)),
                                                                 static_cast<double>(kMinAutoFftNodes)) /
                                                        f.nodes_per_box)),
                             f.min_boxes, 512));
  const int floor_boxes = std::min(f.min_boxes, cap);
  g.boxes = static_cast<int>(std::clamp<double>(std::ceil(extent / f.box_width), floor_boxes, cap));
  // h on the ladder box_width·2^(k/4), at least extent / boxes.
  const double k = std::ceil(4.0 * std::log2(extent / g.boxes / f.box_width) - 1e-9);
  g.h = f.box_width * std::exp2(k / 4.0);
  g.m = g.boxes * g.p;
  g.l = cv::getOptimalDFTSize(2 * g.m - 1);
  const double side = g.boxes * g.h;
  g.x0 = 0.5 * (x0 + x1) - 0.5 * side;
  g.y0 = 0.5 * (y0 + y1) - 0.5 * side;
  return g;
}

void sort_by_box(const std::vector<double>& y, std::size_t n, const FftLayout& g,
                 std::vector<std::int32_t>& order, std::vector<std::int32_t>& start) {
  const std::size_t nb = static_cast<std::size_t>(g.boxes) * g.boxes;
  std::vector<std::int32_t> box(n);
  start.assign(nb + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    double t;
    const int bx = box_of(y[2 * i], g.x0, g.h, g.boxes, t), by = box_of(y[2 * i + 1], g.y0, g.h, g.boxes, t);
    box[i] = by * g.boxes + bx;
    ++start[static_cast<std::size_t>(box[i]) + 1];
  }
  for (std::size_t b = 0; b < nb; ++b) start[b + 1] += start[b];
  std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
  order.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    order[static_cast<std::size_t>(fill[box[i]]++)] = static_cast<std::int32_t>(i);
}

namespace {

// g2 = s2·fc + i·s1·(fa + conj(fa(−k)))/2 and fa ← s2·fa, per frequency (fa(−k): indices mod l).
template <class T>
void combine(const cv::Mat& s1, const cv::Mat& s2, cv::Mat& fa, const cv::Mat& fc, cv::Mat& g2, int l) {
  // Row by row in parallel; fa(−k) of row r lives in row (l − r) mod l, so fa is updated only after
  // every g2 row has read it.
  tbb::parallel_for(0, l, [&](int r) {
    const int rr = (l - r) % l;
    const T* a = fa.ptr<T>(r);
    const T* am = fa.ptr<T>(rr);
    const T* c = fc.ptr<T>(r);
    const T* k1 = s1.ptr<T>(r);
    const T* k2 = s2.ptr<T>(r);
    T* o = g2.ptr<T>(r);
    for (int q = 0; q < l; ++q) {
      const int qm = (l - q) % l;
      const T re0 = T(0.5) * (a[2 * q] + am[2 * qm]), im0 = T(0.5) * (a[2 * q + 1] - am[2 * qm + 1]);
      o[2 * q] = k2[q] * c[2 * q] - k1[q] * im0;
      o[2 * q + 1] = k2[q] * c[2 * q + 1] + k1[q] * re0;
    }
  });
  tbb::parallel_for(0, l, [&](int r) {
    T* a = fa.ptr<T>(r);
    const T* k2 = s2.ptr<T>(r);
    for (int q = 0; q < l; ++q) a[2 * q] *= k2[q], a[2 * q + 1] *= k2[q];
  });
}

}  // namespace

void FftConvolver::prepare(const FftLayout& g) {
  if (!have_grid_ || !grid_.same_grid(g)) {
    // The kernels w = 1/(1 + d²) and w² at every node offset, embedded circularly (offset −d at l − d)
    // so that the spectrum is real; w in the real and w² in the imaginary part of one transform.
    const int l = g.l, m = g.m;
    const double s = g.h / g.p;
    cv::Mat k(l, l, CV_64FC2, cv::Scalar::all(0));
    for (int dy = -(m - 1); dy <= m - 1; ++dy) {
      double* row = k.ptr<double>((dy + l) % l);
      for (int dx = -(m - 1); dx <= m - 1; ++dx) {
        const double w = 1.0 / (1.0 + s * s * (double(dx) * dx + double(dy) * dy));
        const int c = (dx + l) % l;
        row[2 * c] = w, row[2 * c + 1] = w * w;
      }
    }
    cv::Mat f, parts[2];
    cv::dft(k, f);
    cv::split(f, parts);
    parts[0].convertTo(s1_, depth_), parts[1].convertTo(s2_, depth_);
    grid_ = g, have_grid_ = true;
    a_.create(l, l, CV_MAKETYPE(depth_, 2)), c_.create(l, l, CV_MAKETYPE(depth_, 1));
    g2_.create(l, l, CV_MAKETYPE(depth_, 2));
  }
  m_ = g.m;
  a_.setTo(cv::Scalar::all(0)), c_.setTo(cv::Scalar::all(0));
}

void FftConvolver::run() {
  // Only the first m rows of the charges are non-zero: the forward transforms skip the rest
  // (nonzeroRows). The inverse ones run in full: with nonzeroRows, OpenCV 4.6's complex inverse 2D
  // transform did not return the first rows of the result (measured), though only those are read.
  tbb::parallel_invoke([&] { cv::dft(a_, fa_, 0, m_); },
                       [&] { cv::dft(c_, fc_, cv::DFT_COMPLEX_OUTPUT, m_); });
  if (depth_ == CV_64F)
    combine<double>(s1_, s2_, fa_, fc_, g2_, grid_.l);
  else
    combine<float>(s1_, s2_, fa_, fc_, g2_, grid_.l);
  tbb::parallel_invoke([&] { cv::dft(fa_, o1_, cv::DFT_INVERSE | cv::DFT_SCALE, 0); },
                       [&] { cv::dft(g2_, o2_, cv::DFT_INVERSE | cv::DFT_SCALE, 0); });
}

void FftRepulsion::compute(const std::vector<double>& y, std::size_t n, const TsneFftOptions& f,
                           std::vector<double>& terms) {
  const FftLayout g = fft_layout(y, n, f);
  conv_.prepare(g);
  const int p = g.p;
  const double cx = g.x0 + 0.5 * g.boxes * g.h, cy = g.y0 + 0.5 * g.boxes * g.h;
  // Spread: serial (each point touches p² nodes; a few hundred µs at 10^5 points).
  double wx[8], wy[8];
  for (std::size_t i = 0; i < n; ++i) {
    double tx, ty;
    const int bx = box_of(y[2 * i], g.x0, g.h, g.boxes, tx),
              by = box_of(y[2 * i + 1], g.y0, g.h, g.boxes, ty);
    lagrange_weights(p, tx, wx), lagrange_weights(p, ty, wy);
    const double ux = y[2 * i] - cx, uy = y[2 * i + 1] - cy;
    for (int b = 0; b < p; ++b) {
      double* ra = conv_.a().ptr<double>(by * p + b);
      double* rc = conv_.c().ptr<double>(by * p + b);
      for (int a = 0; a < p; ++a) {
        const int col = bx * p + a;
        const double w = wx[a] * wy[b];
        ra[2 * col] += w, ra[2 * col + 1] += w * ux, rc[col] += w * uy;
      }
    }
  }
  conv_.run();
  terms.resize(3 * n);
  const cv::Mat &o1 = conv_.out1(), &o2 = conv_.out2();
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    double tx, ty, vx[8], vy[8];
    const int bx = box_of(y[2 * i], g.x0, g.h, g.boxes, tx),
              by = box_of(y[2 * i + 1], g.y0, g.h, g.boxes, ty);
    lagrange_weights(p, tx, vx), lagrange_weights(p, ty, vy);
    double phi[4] = {0, 0, 0, 0};
    for (int b = 0; b < p; ++b) {
      const double* r1 = o1.ptr<double>(by * p + b);
      const double* r2 = o2.ptr<double>(by * p + b);
      for (int a = 0; a < p; ++a) {
        const int col = bx * p + a;
        const double w = vx[a] * vy[b];
        phi[0] += w * r1[2 * col], phi[1] += w * r1[2 * col + 1];
        phi[2] += w * r2[2 * col], phi[3] += w * r2[2 * col + 1];
      }
    }
    fft_terms(y[2 * i] - cx, y[2 * i + 1] - cy, phi, terms.data() + 3 * i);
  });
}

}  // namespace trailscope::projection::detail

namespace trailscope::projection {

namespace {
void check_y(const std::vector<double>& y) {
  if (y.size() % 2 != 0) throw invalid_argument("y", "y must hold rows × 2 coordinates");
  for (double v : y)
    if (!std::isfinite(v)) throw invalid_argument("y", "y must be finite");
}

// g = exaggeration·attraction − (fx, fy) / Z with Z = Σ z.
std::vector<double> assemble(const std::vector<double>& attr, const std::vector<double>& terms,
                             double exaggeration) {
  std::vector<double> g;
  detail::tsne_combine(attr.data(), terms.data(), 3, attr.size() / 2, exaggeration, g);
  return g;
}
}  // namespace

std::vector<double> tsne_repulsion_exact_ref(const std::vector<double>& y) {
  check_y(y);
  const std::size_t n = y.size() / 2;
  std::vector<double> out(3 * n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    double fx = 0, fy = 0, z = 0;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double dx = y[2 * i] - y[2 * j], dy = y[2 * i + 1] - y[2 * j + 1];
      const double w = 1.0 / (1.0 + dx * dx + dy * dy);
      z += w, fx += w * w * dx, fy += w * w * dy;
    }
    out[3 * i] = fx, out[3 * i + 1] = fy, out[3 * i + 2] = z;
  });
  return out;
}

std::vector<double> tsne_repulsion_fft_ref(const std::vector<double>& y, const TsneFftOptions& f) {
  check_y(y);
  detail::check_fft_options(f);
  std::vector<double> terms;
  detail::FftRepulsion r;
  r.compute(y, y.size() / 2, f, terms);
  return terms;
}

std::vector<double> tsne_repulsion_fft(const std::vector<double>& y, const TsneFftOptions& f,
                                       Backend backend) {
  check_y(y);
  detail::check_fft_options(f);
  std::vector<double> out;
  ocl::dispatch(
      "projection_tsne_fft", backend, ocl::device_is_gpu(),
      [&]() { return ocl::tsne_fft_repulsion_ocl(y, f, out); }, [&] { out = tsne_repulsion_fft_ref(y, f); });
  return out;
}

std::vector<double> tsne_gradient_fft_ref(const Affinities& P, const std::vector<double>& y,
                                          double exaggeration, const TsneFftOptions& f) {
  if (y.size() != 2 * P.rows) throw invalid_argument("y", "y must hold rows × 2 coordinates");
  std::vector<double> attr;
  detail::tsne_attraction(P, y, attr);
  return assemble(attr, tsne_repulsion_fft_ref(y, f), exaggeration);
}

std::vector<double> tsne_gradient_fft(const Affinities& P, const std::vector<double>& y, double exaggeration,
                                      const TsneFftOptions& f, Backend backend) {
  if (y.size() != 2 * P.rows) throw invalid_argument("y", "y must hold rows × 2 coordinates");
  check_y(y);
  detail::check_fft_options(f);
  std::vector<double> g;
  ocl::dispatch(
      "projection_tsne_fft", backend, ocl::device_is_gpu(),
      [&]() { return ocl::tsne_fft_gradient_ocl(P, y, exaggeration, f, g); },
      [&] { g = tsne_gradient_fft_ref(P, y, exaggeration, f); });
  return g;
}

}  // namespace trailscope::projection
