// FFT-interpolated t-SNE repulsion (FIt-SNE): the point↔grid steps of projection/tsne_fft_ocl.cpp,
// mirroring the reference detail::FftRepulsion (compute/src/projection/tsne_fft.cpp). Coordinates u are
// relative to the grid centre; the grid spans [lo, lo + boxes·h) on both axes, box b holds the p nodes
// (b·p + k + ½)·h/p. Grids are m rows of l floats (or float pairs): the host's zero-padded FFT layout.
// OpenCL C 1.2, float only.

// P (nodes per box and axis) is a build option (-DP=3), so that the loops unroll and the node
// positions and denominators fold to constants.
#ifndef P
#define P 3
#endif

// Lagrange basis polynomial k of the P nodes (j + ½)/P at t.
inline float lagrange(const int k, const float t) {
  const float tk = (k + 0.5f) / P;
  float num = 1.0f, den = 1.0f;
#pragma unroll
  for (int j = 0; j < P; ++j)
    if (j != k) {
      const float tj = (j + 0.5f) / P;
      num *= t - tj;
      den *= tk - tj;
    }
  return num / den;
}

// One work-item per node (gx, gy), gx < l, gy < m: the charges (1, x, y) of the points of its box,
// weighted by the node's basis polynomials; 0 in the padding columns gx ≥ m. Points are sorted by box
// on the host (order, start), so no atomics are needed and a box's items read the same points.
__kernel void tsne_fft_spread(__global const float* u, __global const int* order, __global const int* start,
                              const int boxes, const int l, const int m, const float lo, const float h,
                              __global float* qa, __global float* qc) {
  const int id = get_global_id(0);
  if (id >= l * m) return;
  const int gy = id / l, gx = id - gy * l;
  float q0 = 0.0f, q1 = 0.0f, q2 = 0.0f;
  if (gx < m) {
    const int bx = gx / P, by = gy / P;
    const int a = gx - bx * P, b = gy - by * P;
    const int box = by * boxes + bx;
    for (int e = start[box]; e < start[box + 1]; ++e) {
      const int i = order[e];
      const float x = u[2 * i], y = u[2 * i + 1];
      const float w = lagrange(a, (x - lo) / h - bx) * lagrange(b, (y - lo) / h - by);
      q0 += w;
      q1 += w * x;
      q2 += w * y;
    }
  }
  qa[2 * id] = q0;
  qa[2 * id + 1] = q1;
  qc[id] = q2;
}

// One work-item per point: the potentials (w²∗1, w²∗x) in o1 and (w²∗y, w∗1) in o2 interpolated from
// the p × p nodes of its box, then out = (x·φ₀ − φ₁, y·φ₀ − φ₂, φ₃ − 1, 0).
__kernel void tsne_fft_gather(__global const float* u, const int n, const int boxes, const int l,
                              const float lo, const float h, __global const float* o1,
                              __global const float* o2, __global float* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float x = u[2 * i], y = u[2 * i + 1];
  const float sx = (x - lo) / h, sy = (y - lo) / h;
  const int bx = clamp((int)sx, 0, boxes - 1), by = clamp((int)sy, 0, boxes - 1);
  const float tx = sx - bx, ty = sy - by;
  float wx[P], wy[P];
#pragma unroll
  for (int k = 0; k < P; ++k) {
    wx[k] = lagrange(k, tx);
    wy[k] = lagrange(k, ty);
  }
  float f0 = 0.0f, f1 = 0.0f, f2 = 0.0f, f3 = 0.0f;
#pragma unroll
  for (int b = 0; b < P; ++b) {
    const int row = (by * P + b) * l + bx * P;
#pragma unroll
    for (int a = 0; a < P; ++a) {
      const float w = wx[a] * wy[b];
      const int c = 2 * (row + a);
      f0 += w * o1[c];
      f1 += w * o1[c + 1];
      f2 += w * o2[c];
      f3 += w * o2[c + 1];
    }
  }
  out[4 * i] = x * f0 - f1;
  out[4 * i + 1] = y * f0 - f2;
  out[4 * i + 2] = f3 - 1.0f;
  out[4 * i + 3] = 0.0f;
}
