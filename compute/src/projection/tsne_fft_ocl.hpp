#pragma once
// Host side of compute/kernels/projection_tsne_fft.cl: the FFT-interpolated t-SNE repulsion (see
// projection/tsne_fft.hpp) with the point↔grid interpolation and the attraction on the device and the
// grid convolution (cv::dft, float) on the host. Declared without OpenCL types; each returns "" when it
// ran, else why it cannot run (ocl/dispatch.hpp), and may throw.
#include <string>
#include <vector>

#include "trailscope/projection/projection.hpp"

namespace trailscope::ocl {

/// Repulsion terms (rows × 3: fx, fy, z) at y (rows × 2); the reference is tsne_repulsion_fft_ref.
std::string tsne_fft_repulsion_ocl(const std::vector<double>& y, const projection::TsneFftOptions& f,
                                   std::vector<double>& terms);
/// One gradient (reference tsne_gradient_fft_ref).
std::string tsne_fft_gradient_ocl(const projection::Affinities& p, const std::vector<double>& y,
                                  double exaggeration, const projection::TsneFftOptions& f,
                                  std::vector<double>& grad);
/// The whole optimisation (projection::detail::tsne_optimize) with these gradients; y in/out.
std::string tsne_fft_optimize_ocl(const projection::Affinities& p, const projection::TsneOptions& o,
                                  std::vector<double>& y);

}  // namespace trailscope::ocl
