// PCA products (compute/src/projection/projection_ocl.cpp). OpenCL C 1.2, float only.

// Scatter partials: work-item g = (chunk·dims + a)·dims + b sums (x_ra − μ_a)(x_rb − μ_b) over the rows
// of its chunk; the host adds the chunks in double (float sums stay short: `rows_per_chunk` terms).
__kernel void covariance(__global const float* x, __global const float* mean, const int n, const int dims,
                         const int rows_per_chunk, const int chunks, __global float* partial) {
  const size_t g = get_global_id(0);
  const size_t dd = (size_t)dims * (size_t)dims;
  if (g >= dd * (size_t)chunks) return;
  const int chunk = (int)(g / dd);
  const int a = (int)((g % dd) / (size_t)dims), b = (int)(g % (size_t)dims);
  const int r0 = chunk * rows_per_chunk;
  const int r1 = min(n, r0 + rows_per_chunk);
  const float ma = mean[a], mb = mean[b];
  float s = 0.0f;
  for (int r = r0; r < r1; ++r) s += (x[(size_t)r * dims + a] - ma) * (x[(size_t)r * dims + b] - mb);
  partial[g] = s;
}

// Scores: out[2r + k] = Σ_c (x_rc − μ_c)·w[2c + k].
__kernel void scores(__global const float* x, __global const float* mean, __global const float* w,
                     const int n, const int dims, __global float* out) {
  const int r = get_global_id(0);
  if (r >= n) return;
  float s0 = 0.0f, s1 = 0.0f;
  for (int c = 0; c < dims; ++c) {
    const float v = x[(size_t)r * dims + c] - mean[c];
    s0 += v * w[2 * c];
    s1 += v * w[2 * c + 1];
  }
  out[2 * r] = s0;
  out[2 * r + 1] = s1;
}
