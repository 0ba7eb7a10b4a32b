// Distances for the projections (compute/src/projection/projection_ocl.cpp): dense distance blocks, also the
// tiles of the brute-force k nearest neighbours. OpenCL C 1.2, float only.

// out[i·nb + j] = |a_i − b_j|² (or |a_i − b_j| with ROOT != 0), one work-item per pair; j varies
// fastest so neighbouring work-items share a_i.
__kernel void sqdist(__global const float* a, __global const float* b, const int na, const int nb,
                     const int dims, const int root, __global float* out) {
  const size_t g = get_global_id(0);
  if (g >= (size_t)na * (size_t)nb) return;
  const int i = (int)(g / (size_t)nb), j = (int)(g % (size_t)nb);
  const __global float* x = a + (size_t)i * dims;
  const __global float* y = b + (size_t)j * dims;
  float s = 0.0f;
  for (int c = 0; c < dims; ++c) {
    const float v = x[c] - y[c];
    s += v * v;
  }
  out[g] = root ? sqrt(s) : s;
}
