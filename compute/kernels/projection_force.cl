// One Force Scheme iteration, parallel form (see trailscope/projection/projection.hpp): every point
// moves by the mean of (δ_ij − d_ij)·(y_j − y_i)/d_ij over all other points i, from the same positions.
// OpenCL C 1.2, float only.
__kernel void force_step(__global const float* delta, __global const float* y, const int n, const float inv_n,
                         __global float* y_new) {
  const int j = get_global_id(0);
  if (j >= n) return;
  const float yx = y[2 * j], yy = y[2 * j + 1];
  float ax = 0.0f, ay = 0.0f;
  const __global float* row = delta + (size_t)j * n;
  for (int i = 0; i < n; ++i) {
    if (i == j) continue;
    const float vx = yx - y[2 * i], vy = yy - y[2 * i + 1];
    const float d = sqrt(vx * vx + vy * vy);
    if (d < 1e-12f) continue;
    const float f = (row[i] - d) / d;
    ax += f * vx;
    ay += f * vy;
  }
  y_new[2 * j] = yx + ax * inv_n;
  y_new[2 * j + 1] = yy + ay * inv_n;
}
