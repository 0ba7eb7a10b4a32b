// Classical MDS products (compute/src/projection/projection_ocl.cpp). OpenCL C 1.2, float only.

// Row sums of the n×n squared-distance matrix (the host turns them into means in double).
__kernel void row_sums(__global const float* d2, const int n, __global float* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  float s = 0.0f;
  for (int j = 0; j < n; ++j) s += d2[(size_t)i * n + j];
  out[i] = s;
}

// In place: B_ij = −½·(D²_ij − m_i − m_j + m) (double centring).
__kernel void double_centre(__global float* d2, __global const float* rowmean, const float grand,
                            const int n) {
  const size_t g = get_global_id(0);
  if (g >= (size_t)n * (size_t)n) return;
  const int i = (int)(g / (size_t)n), j = (int)(g % (size_t)n);
  d2[g] = -0.5f * (d2[g] - rowmean[i] - rowmean[j] + grand);
}

// out (n × p) = B (n × n) · v (n × p), p ≤ 8, one work-item per row.
__kernel void block_matmul(__global const float* b, __global const float* v, const int n, const int p,
                           __global float* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const __global float* row = b + (size_t)i * n;
  for (int j = 0; j < n; ++j) {
    const float bij = row[j];
    for (int c = 0; c < p; ++c) acc[c] += bij * v[(size_t)j * p + c];
  }
  for (int c = 0; c < p; ++c) out[(size_t)i * p + c] = acc[c];
}
