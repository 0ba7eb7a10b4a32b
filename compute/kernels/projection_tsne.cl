// t-SNE gradient terms (compute/src/projection/projection_ocl.cpp), in openTSNE's convention:
// gradient_i = exaggeration·attraction_i − repulsion_i / Z, with w_ij = 1 / (1 + |y_i − y_j|²).
// OpenCL C 1.2, float only; the host sums Z in double.

// attraction_i = Σ_j p_ij·w_ij·(y_i − y_j) over the sparse row i of P (CSR). Four entries per step in
// float4: the divisions are the cost, and a CPU device (PoCL) does not vectorise this loop across
// work-items (its trip count varies by row), so the vector width has to come from the kernel; a GPU
// runs the float4 as four scalars.
__kernel void tsne_attract(__global const int* row_start, __global const int* col, __global const float* p,
                           __global const float* y, const int n, __global float* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float yx = y[2 * i], yy = y[2 * i + 1];
  float4 ax4 = (float4)(0.0f), ay4 = (float4)(0.0f);
  int e = row_start[i];
  const int end = row_start[i + 1];
  for (; e + 4 <= end; e += 4) {
    const int4 j = vload4(0, col + e);
    const float4 pj = vload4(0, p + e);
    // One 8-byte load per neighbour: cheaper than two gathers on x86.
    const float2 q0 = vload2(j.s0, y), q1 = vload2(j.s1, y), q2 = vload2(j.s2, y), q3 = vload2(j.s3, y);
    const float4 dx = yx - (float4)(q0.x, q1.x, q2.x, q3.x);
    const float4 dy = yy - (float4)(q0.y, q1.y, q2.y, q3.y);
    const float4 w = pj / (1.0f + dx * dx + dy * dy);
    ax4 += w * dx;
    ay4 += w * dy;
  }
  float ax = (ax4.s0 + ax4.s1) + (ax4.s2 + ax4.s3), ay = (ay4.s0 + ay4.s1) + (ay4.s2 + ay4.s3);
  for (; e < end; ++e) {
    const int j = col[e];
    const float dx = yx - y[2 * j], dy = yy - y[2 * j + 1];
    const float w = p[e] / (1.0f + dx * dx + dy * dy);
    ax += w * dx;
    ay += w * dy;
  }
  out[2 * i] = ax;
  out[2 * i + 1] = ay;
}

// Exact: out[4i..] = (Σ_j w²·dx, Σ_j w²·dy, Σ_j w, 0) over j ≠ i.
__kernel void tsne_repulse_exact(__global const float* y, const int n, __global float* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float yx = y[2 * i], yy = y[2 * i + 1];
  float fx = 0.0f, fy = 0.0f, z = 0.0f;
  for (int j = 0; j < n; ++j) {
    if (j == i) continue;
    const float dx = yx - y[2 * j], dy = yy - y[2 * j + 1];
    const float w = 1.0f / (1.0f + dx * dx + dy * dy);
    z += w;
    fx += w * w * dx;
    fy += w * w * dy;
  }
  out[4 * i] = fx;
  out[4 * i + 1] = fy;
  out[4 * i + 2] = z;
  out[4 * i + 3] = 0.0f;
}

#ifdef STACK
// Barnes-Hut: the same sums over the host-built quadtree (projection/detail.hpp, QuadTree and
// bh_repulse, which this mirrors): a cell is summarised by its centre of mass unless it is an inner
// cell with side² ≥ θ²·d². An explicit stack replaces recursion (OpenCL C has none).
// Work-item g handles point order[g]: the host orders the points along a Morton curve, so that
// neighbouring work-items walk nearly the same cells (shared cache lines and, on a CPU, predictable
// branches; on a GPU, less divergence within a warp).
__kernel void tsne_repulse_bh(__global const float* node, __global const int* child, __global const int* point,
                              __global const float* y, __global const int* order, const int n, const float theta2,
                              __global float* out) {
  const int g = get_global_id(0);
  if (g >= n) return;
  const int i = order[g];
  const float yx = y[2 * i], yy = y[2 * i + 1];
  float fx = 0.0f, fy = 0.0f, z = 0.0f;
  int stack[STACK];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int k = stack[--top];
    const float c = node[4 * k + 3];
    if (c <= 0.0f) continue;
    const float dx = yx - node[4 * k], dy = yy - node[4 * k + 1];
    const float d2 = dx * dx + dy * dy;
    float m = c;
    const int first = child[k];
    if (first < 0) {
      if (c == 1.0f && point[k] == i) continue;
      if (c > 1.0f && d2 == 0.0f) m = c - 1.0f;
    } else {
      const float side = node[4 * k + 2];
      if (side * side >= theta2 * d2) {
        for (int q = 3; q >= 0; --q) stack[top++] = first + q;
        continue;
      }
    }
    const float w = 1.0f / (1.0f + d2);
    z += m * w;
    fx += m * w * w * dx;
    fy += m * w * w * dy;
  }
  out[4 * i] = fx;
  out[4 * i + 1] = fy;
  out[4 * i + 2] = z;
  out[4 * i + 3] = 0.0f;
}
#endif
