#pragma once
// FFT-accelerated interpolation of the t-SNE repulsion (FIt-SNE; see TsneFftOptions in projection.hpp),
// the host parts shared by the C++ reference (tsne_fft.cpp) and the OpenCL path
// (compute/src/projection/tsne_fft_ocl.cpp): the grid layout, the Lagrange weights, the sort of the points by
// box and the grid convolution by FFT.
//
// Layout: boxes × boxes square boxes of side h cover the bounding square of the points; box b spans
// [x0 + b·h, x0 + (b+1)·h) and holds p nodes at x0 + (b·p + k + ½)·h/p, k < p, so that all nodes form one
// uniform grid of m = boxes·p nodes per axis with spacing h/p. A point is spread to (and gathered from)
// the p × p nodes of its own box with the weights L_a(tx)·L_b(ty), L the Lagrange basis of the p nodes
// and t the point's position inside its box in [0, 1].
#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "trailscope/projection/projection.hpp"

namespace trailscope::projection::detail {

/// Throws invalid_argument("fft") unless nodes_per_box ∈ [2, 8], box_width > 0 (finite),
/// 1 ≤ min_boxes ≤ 512 and max_boxes ∈ {0} ∪ [min_boxes, 512].
void check_fft_options(const TsneFftOptions& f);

/// Largest number of grid nodes per axis (boxes·p); beyond it the boxes grow instead.
inline constexpr int kMaxFftNodes = 512;
/// The automatic cap on the boxes (TsneFftOptions::max_boxes = 0) allows at least this many nodes per
/// axis: below ~5,000 points √N nodes would make boxes wider than ~2 units over the usual 30–50-unit
/// layouts, coarser than the kernel (trustworthiness 0.965 against 0.974 at 1,000 points), and the
/// grid is cheap there anyway.
inline constexpr int kMinAutoFftNodes = 72;

struct FftLayout {
  int p = 3;      ///< nodes per box and axis
  int boxes = 1;  ///< boxes per axis
  int m = 3;      ///< nodes per axis (boxes·p)
  int l = 8;      ///< FFT size per axis: ≥ 2m − 1 (linear convolution), a size cv::dft handles fast
  double x0 = 0, y0 = 0;  ///< lower corner of the grid
  double h = 1;           ///< box side
  bool same_grid(const FftLayout& o) const { return p == o.p && boxes == o.boxes && l == o.l && h == o.h; }
};

/// The layout for points y (n × 2): boxes = clamp(⌈extent / box_width⌉, min_boxes, max_boxes or its
/// automatic value) for the
/// larger extent of the two axes, and h = extent / boxes rounded up to box_width·2^(k/4) (integer k),
/// so that h, and with it the kernel on the grid, changes only now and then as the embedding grows (the
/// kernel spectra are cached per (boxes, h)). The grid is centred on the points' bounding box.
FftLayout fft_layout(const std::vector<double>& y, std::size_t n, const TsneFftOptions& f);

/// Lagrange weights of the p nodes (k + ½)/p of a box at t ∈ [0, 1].
inline void lagrange_weights(int p, double t, double* w) {
  for (int k = 0; k < p; ++k) {
    const double tk = (k + 0.5) / p;
    double v = 1.0;
    for (int j = 0; j < p; ++j)
      if (j != k) v *= (t - (j + 0.5) / p) / (tk - (j + 0.5) / p);
    w[k] = v;
  }
}

/// Box of coordinate v along one axis, clamped to [0, boxes − 1], and the position t inside it.
inline int box_of(double v, double lo, double h, int boxes, double& t) {
  const double s = (v - lo) / h;
  int b = static_cast<int>(s);
  b = b < 0 ? 0 : (b >= boxes ? boxes - 1 : b);
  t = s - b;
  return b;
}

/// Points sorted by box (counting sort, stable): order lists the point indices box after box (row-major
/// boxes, bx fastest) and start[b]..start[b+1] is box b's slice (boxes² + 1 entries).
void sort_by_box(const std::vector<double>& y, std::size_t n, const FftLayout& g,
                 std::vector<std::int32_t>& order, std::vector<std::int32_t>& start);

/// The grid convolution of the FIt-SNE step. Input: charges q0 (1), q1 (x), q2 (y) on the m × m nodes,
/// written by the caller into `a()` (l × l, 2 channels: q0, q1) and `c()` (l × l, 1 channel: q2), rows
/// ≥ m and columns ≥ m left zero. run() leaves in `out1()` (l × l, 2 channels) the potentials (w² ∗ q0,
/// w² ∗ q1) and in `out2()` (w² ∗ q2, w ∗ q0), valid on the first m × m nodes. Three charges and two
/// kernels take two forward and two inverse complex transforms: the kernels' spectra are real (the
/// kernels are even), so two real fields can share one complex transform.
/// `depth` is CV_64F (reference) or CV_32F (OpenCL path, float charges from the device).
class FftConvolver {
 public:
  explicit FftConvolver(int depth) : depth_(depth) {}
  /// Prepares the buffers and the kernel spectra for layout g (cached while g.same_grid) and zeroes
  /// the charge grids.
  void prepare(const FftLayout& g);
  cv::Mat& a() { return a_; }
  cv::Mat& c() { return c_; }
  const cv::Mat& out1() const { return o1_; }
  const cv::Mat& out2() const { return o2_; }
  void run();

 private:
  int depth_;
  FftLayout grid_{};
  bool have_grid_ = false;
  cv::Mat s1_, s2_;          // spectra of w and w² (real, l × l, 1 channel)
  cv::Mat a_, c_, fa_, fc_;  // charges and their spectra
  cv::Mat g2_, o1_, o2_;
  int m_ = 0;
};

/// The repulsion terms (rows × 3: fx, fy, z; see tsne_repulsion_exact_ref) from the interpolated
/// potentials φ = (w²∗1, w²∗x, w²∗y, w∗1) at point i, the coordinates taken relative to the grid centre:
/// fx = x·φ₀ − φ₁, fy = y·φ₀ − φ₂, z = φ₃ − 1 (the node sums include the point itself, w(0) = 1).
inline void fft_terms(double x, double y, const double* phi, double* out) {
  out[0] = x * phi[0] - phi[1];
  out[1] = y * phi[0] - phi[2];
  out[2] = phi[3] - 1.0;
}

/// The reference repulsion terms (rows × 3, in double), its convolver kept across calls for the cache
/// of kernel spectra (the optimiser calls it once per iteration).
class FftRepulsion {
 public:
  void compute(const std::vector<double>& y, std::size_t n, const TsneFftOptions& f,
               std::vector<double>& terms);

 private:
  FftConvolver conv_{CV_64F};
};

}  // namespace trailscope::projection::detail
