// LAMP's orthogonal local map (Joia et al. 2011), one work-item per point
// (compute/src/projection/projection_ocl.cpp). With α_i = 1/|x_i − x|² (normalised to sum 1), x̃, ỹ
// the α-weighted means and C = AᵀB (dims × 2, C_ck = Σ_i α_i (x_ic − x̃_c)(y_ik − ỹ_k)), the map U·Vᵀ
// of the SVD of C equals the polar factor C·(CᵀC)^(−1/2), so y = ((x − x̃)ᵀ·C)·(CᵀC)^(−1/2) + ỹ needs
// only the 2-vector (x − x̃)ᵀC and the 2×2 matrix CᵀC, accumulated column by column without storing C.
// Singular values of C below 1e-3 of the largest are dropped (their direction is undefined), as the
// reference does.
// OpenCL C 1.2, float only.
__kernel void lamp_map(__global const float* x, const int dims, const int first, const int count,
                       __global const float* cx, __global const float* cy, const int nc,
                       __global float* alpha_scratch, __global float* out) {
  const int a = get_global_id(0);
  if (a >= count) return;
  const __global float* xa = x + (size_t)(first + a) * dims;
  __global float* al = alpha_scratch + (size_t)a * nc;
  float asum = 0.0f;
  for (int i = 0; i < nc; ++i) {
    float s = 0.0f;
    for (int c = 0; c < dims; ++c) {
      const float v = cx[(size_t)i * dims + c] - xa[c];
      s += v * v;
    }
    if (s < 1e-12f) {  // on a control point: its position
      out[2 * a] = cy[2 * i];
      out[2 * a + 1] = cy[2 * i + 1];
      return;
    }
    al[i] = 1.0f / s;
    asum += al[i];
  }
  float yt0 = 0.0f, yt1 = 0.0f;
  for (int i = 0; i < nc; ++i) {
    al[i] /= asum;
    yt0 += al[i] * cy[2 * i];
    yt1 += al[i] * cy[2 * i + 1];
  }
  float z0 = 0.0f, z1 = 0.0f, g00 = 0.0f, g01 = 0.0f, g11 = 0.0f;
  for (int c = 0; c < dims; ++c) {
    float xt = 0.0f;
    for (int i = 0; i < nc; ++i) xt += al[i] * cx[(size_t)i * dims + c];
    float c0 = 0.0f, c1 = 0.0f;
    for (int i = 0; i < nc; ++i) {
      const float u = al[i] * (cx[(size_t)i * dims + c] - xt);
      c0 += u * (cy[2 * i] - yt0);
      c1 += u * (cy[2 * i + 1] - yt1);
    }
    const float xd = xa[c] - xt;
    z0 += xd * c0;
    z1 += xd * c1;
    g00 += c0 * c0;
    g01 += c0 * c1;
    g11 += c1 * c1;
  }
  // (CᵀC)^(−1/2) from the eigen-decomposition of the symmetric 2×2 matrix [g00 g01; g01 g11].
  const float mean = 0.5f * (g00 + g11), hdiff = 0.5f * (g00 - g11);
  const float r = sqrt(hdiff * hdiff + g01 * g01);
  const float l1 = mean + r, l2 = mean - r;
  float e0, e1;  // eigenvector of l1: the better conditioned of (g01, l1 − g00) and (l1 − g11, g01)
  const float ax = g01, ay = l1 - g00, bx = l1 - g11, by = g01;
  if (ax * ax + ay * ay >= bx * bx + by * by) {
    e0 = ax;
    e1 = ay;
  } else {
    e0 = bx;
    e1 = by;
  }
  const float en = sqrt(e0 * e0 + e1 * e1);
  if (en > 0.0f) {
    e0 /= en;
    e1 /= en;
  } else {  // C is 0 or a multiple of the identity: any basis
    e0 = 1.0f;
    e1 = 0.0f;
  }
  const float s1 = l1 > 0.0f ? rsqrt(l1) : 0.0f;
  const float s2 = l2 > 1e-6f * l1 && l2 > 0.0f ? rsqrt(l2) : 0.0f;
  // M = s1·e·eᵀ + s2·f·fᵀ with f = (−e1, e0); y = z·M + ỹ.
  const float p1 = (z0 * e0 + z1 * e1) * s1, p2 = (-z0 * e1 + z1 * e0) * s2;
  out[2 * a] = p1 * e0 - p2 * e1 + yt0;
  out[2 * a + 1] = p1 * e1 + p2 * e0 + yt1;
}
