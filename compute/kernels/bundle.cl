// CUBu bundling loop on the device (trailscope/bundling/bundle.hpp, THE LOOP). Each kernel repeats the
// C++ reference in compute/src/bundling/steps.cpp operation for operation — double geometry rounded to
// float on store, integer splats, exact integer convolution rounded to float once — with contraction
// off, so that the two give the same bits. Needs cl_khr_fp64 (the host checks it before building).
//
// Points: float x, y, z and uint edge per point; offsets per polyline + 1. WG (a -D option) is the
// work-group size of the fine-grained kernels (all are 1D).
//
// Two forms of one kernel. resample_count, resample_place and smooth take a range size `chunk`:
// work-item g does items [g·chunk, min((g+1)·chunk, n)) in a plain loop. On a GPU the host passes
// chunk = 1 (one item per work-item, work-groups of WG); on a CPU device (PoCL) it passes n / (a few ×
// compute units) and work-groups of 1, so that each core runs the reference's loop over a contiguous
// range (PoCL cannot vectorise these loops across work-items anyway: variable trip counts). convolve_rows
// takes ranges of rows the same way. advect and the column pass have a GPU form (advect, convolve_cols)
// and a CPU form (advect_ranges, convolve_col_bands), which PoCL compiles 3–4× faster.
// The splat has a GPU form (splat: atomics) and a CPU form (splat_private + splat_reduce: private
// images, no atomics; PoCL's atomics are locked read-modify-writes: 4–7× slower at a million edges).
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

#ifndef WG
#define WG 64
#endif

// The range of work-item g (see the top): [chunk_begin, chunk_end).
uint chunk_begin(const uint n, const uint chunk) {
  return (uint)min((ulong)get_global_id(0) * chunk, (ulong)n);
}
uint chunk_end(const uint n, const uint chunk) {
  return (uint)min(((ulong)get_global_id(0) + 1) * chunk, (ulong)n);
}

// --- resample -------------------------------------------------------------------------------------------
ulong splitmix64(ulong x) {
  x += 0x9E3779B97F4A7C15UL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9UL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBUL;
  return x ^ (x >> 31);
}

double jitter_unit(ulong seed, uint iteration, uint edge, ulong sample) {
  ulong u = splitmix64(seed ^ ((ulong)iteration << 40));
  u = splitmix64(u ^ (ulong)edge);
  u = splitmix64(u ^ sample);
  return (double)(u >> 11) * 0x1p-52 - 1.0;
}

double seg_length(__global const float* x, __global const float* y, uint k) {
  const double dx = (double)x[k + 1] - (double)x[k];
  const double dy = (double)y[k + 1] - (double)y[k];
  return sqrt(dx * dx + dy * dy);
}

ulong interior_samples(double length, double spl) {
  if (!(length > 0.0)) return 0;
  double m = floor(length / spl);
  if (m * spl >= length) m -= 1.0;
  return (ulong)fmin(m, 2147483648.0);
}

// Per polyline: its point count after resampling.
__kernel void resample_count(__global const float* restrict x, __global const float* restrict y,
                             __global const uint* restrict offsets, const uint edges, const double spl,
                             __global uint* restrict counts, const uint chunk) {
  for (uint e = chunk_begin(edges, chunk); e < chunk_end(edges, chunk); ++e) {
    double len = 0.0;
    const uint end = offsets[e + 1];
    for (uint k = offsets[e]; k + 1 < end; ++k) len += seg_length(x, y, k);
    counts[e] = (uint)(2 + interior_samples(len, spl));
  }
}

// Writes polyline e's resampled points (steps.cpp resample_edge).
void place_edge(__global const float* restrict x, __global const float* restrict y,
                __global const uint* restrict offsets, const uint e,
                __global const uint* restrict new_offsets, const double spl, const double jitter_px,
                const ulong seed, const uint iteration, const int block_endpoints,
                __global const float* restrict profile, __global float* restrict ox,
                __global float* restrict oy, __global float* restrict oz, __global uint* restrict oedge) {
  const uint b = offsets[e], end = offsets[e + 1];
  const uint o = new_offsets[e];
  const uint count = new_offsets[e + 1] - o;
  const ulong n = count - 2;
  const ulong last = count - 1;
  ox[o] = x[b];
  oy[o] = y[b];
  oz[o] = block_endpoints ? 0.0f : profile[0];
  oedge[o] = e;
  ox[o + last] = x[end - 1];
  oy[o + last] = y[end - 1];
  oz[o + last] = block_endpoints ? 0.0f : profile[1023];
  oedge[o + last] = e;
  uint k = b;
  double start = 0.0;
  double len = n > 0 ? seg_length(x, y, k) : 0.0;
  for (ulong m = 1; m <= n; ++m) {
    const double s = (double)m * spl;
    while (start + len <= s) {
      start += len;
      ++k;
      len = seg_length(x, y, k);
    }
    double u = (s - start) + jitter_unit(seed, iteration, e, m) * jitter_px;
    if (u < 0.0) u = 0.0;
    if (u > len) u = len;
    const double t = u / len;
    const double x0 = x[k], y0 = y[k];
    const double x1 = x[k + 1], y1 = y[k + 1];
    ox[o + m] = (float)(x0 + t * (x1 - x0));
    oy[o + m] = (float)(y0 + t * (y1 - y0));
    oz[o + m] = profile[m * 1023 / last];
    oedge[o + m] = e;
  }
}

__kernel void resample_place(__global const float* restrict x, __global const float* restrict y,
                             __global const uint* restrict offsets, const uint edges,
                             __global const uint* restrict new_offsets, const double spl,
                             const double jitter_px, const ulong seed, const uint iteration,
                             const int block_endpoints, __global const float* restrict profile,
                             __global float* restrict ox, __global float* restrict oy,
                             __global float* restrict oz, __global uint* restrict oedge, const uint chunk) {
  for (uint e = chunk_begin(edges, chunk); e < chunk_end(edges, chunk); ++e)
    place_edge(x, y, offsets, e, new_offsets, spl, jitter_px, seed, iteration, block_endpoints, profile, ox,
               oy, oz, oedge);
}

// --- density --------------------------------------------------------------------------------------------
// One work-item per row: zeroes the pixels the previous splat wrote (they all lie in its box, `prev`)
// and resets the box of the next splat (`next`, the other of two buffers). Cheaper than clearing the
// whole image, and one command instead of a fill and a write.
__kernel void splat_clear(__global uint* img, const int size, __global const int* prev, __global int* next) {
  const int y = get_global_id(0);
  if (y == 0) {
    next[0] = size;
    next[1] = size;
    next[2] = -1;
    next[3] = -1;
  }
  const int x0 = prev[0], y0 = prev[1], x1 = prev[2], y1 = prev[3];
  if (x0 > x1 || y < y0 || y > y1) return;
  for (int x = x0; x <= x1; ++x) img[y * size + x] = 0;
}

// One work-item per point: integer splat, and the box of the pixels hit (reduced in the work-group, then
// one atomic per group and bound: box = {x0, y0, x1, y1}, reset to {size, size, -1, -1} by
// splat_clear).
__kernel void splat(__global const float* x, __global const float* y, __global const uint* edge, const uint n,
                    __global const uint* weights, const int size, __global uint* img, __global int* box) {
  __local int lo_x[WG], lo_y[WG], hi_x[WG], hi_y[WG];
  const uint i = get_global_id(0);
  const int l = get_local_id(0);
  int ix = size, iy = size, jx = -1, jy = -1;
  if (i < n) {
    const float px = x[i], py = y[i];
    const float lim = (float)size;
    if (px >= 0.0f && px < lim && py >= 0.0f && py < lim) {
      const int cx = (int)px, cy = (int)py;
      atomic_add(&img[cy * size + cx], weights[edge[i]]);
      ix = jx = cx;
      iy = jy = cy;
    }
  }
  lo_x[l] = ix;
  lo_y[l] = iy;
  hi_x[l] = jx;
  hi_y[l] = jy;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = WG / 2; s > 0; s >>= 1) {
    if (l < s) {
      lo_x[l] = min(lo_x[l], lo_x[l + s]);
      lo_y[l] = min(lo_y[l], lo_y[l + s]);
      hi_x[l] = max(hi_x[l], hi_x[l + s]);
      hi_y[l] = max(hi_y[l], hi_y[l + s]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (l == 0 && hi_x[0] >= 0) {
    atomic_min(&box[0], lo_x[0]);
    atomic_min(&box[1], lo_y[0]);
    atomic_max(&box[2], hi_x[0]);
    atomic_max(&box[3], hi_y[0]);
  }
}

// CPU form of the splat: work-item g adds its range of points into its own image — `img` itself for
// g = 0, partial image g − 1 of `partials` (pixels each) otherwise — with plain adds (it is the only
// writer), and merges its box into `box` with 4 atomics. splat_reduce then adds the partial images into
// `img`; integer sums, so the result is the reference's whatever the split.
__kernel void splat_private(__global const float* x, __global const float* y, __global const uint* edge,
                            const uint n, __global const uint* weights, const int size, __global uint* img,
                            __global uint* partials, __global int* box, const uint chunk) {
  const uint g = get_global_id(0);
  __global uint* out = g == 0 ? img : partials + (ulong)(g - 1) * (ulong)size * (ulong)size;
  const float lim = (float)size;
  int ix = size, iy = size, jx = -1, jy = -1;
  for (uint i = chunk_begin(n, chunk); i < chunk_end(n, chunk); ++i) {
    const float px = x[i], py = y[i];
    if (!(px >= 0.0f && px < lim && py >= 0.0f && py < lim)) continue;
    const int cx = (int)px, cy = (int)py;
    out[cy * size + cx] += weights[edge[i]];
    ix = min(ix, cx), jx = max(jx, cx);
    iy = min(iy, cy), jy = max(jy, cy);
  }
  if (jx >= 0) {
    atomic_min(&box[0], ix);
    atomic_min(&box[1], iy);
    atomic_max(&box[2], jx);
    atomic_max(&box[3], jy);
  }
}

// One work-item per row: adds the `parts` partial images into `img` over the box and zeroes them there
// (every pixel a partial image was given lies in the box, so they are all zeros again afterwards).
__kernel void splat_reduce(__global uint* img, __global uint* partials, const uint parts, const int size,
                           __global const int* box) {
  const int y = get_global_id(0);
  const int x0 = box[0], y0 = box[1], x1 = box[2], y1 = box[3];
  if (x0 > x1 || y < y0 || y > y1) return;
  __global uint* row = img + y * size;
  for (uint k = 0; k < parts; ++k) {
    __global uint* part = partials + (ulong)k * (ulong)size * (ulong)size + y * size;
    for (int x = x0; x <= x1; ++x) {
      row[x] += part[x];
      part[x] = 0;
    }
  }
}

// The convolution is exact ulong arithmetic (modulo 2^64): a sliding window of the moments Σf, Σj·f,
// Σj²·f gives Σ f_j·(R² − (x − j)²) = (R² − x²)·Σf + 2x·Σj·f − Σj²·f in O(1) per pixel (steps.cpp
// slide() is the same walk).
//
// Row pass: one row of the box per item (ranges of rows on a CPU device), along the columns of the read
// region (box grown by 2, clipped). (Run in lock step like the column pass below, it measured twice as slow
// on PoCL: the loads of a step are then a column, one cache line each.)
__kernel void convolve_rows(__global const uint* restrict img, const int size,
                            __global const int* restrict box, const int radius, __global ulong* restrict rows,
                            const uint chunk) {
  const int bx0 = box[0], by0 = box[1], bx1 = box[2], by1 = box[3];
  if (bx0 > bx1) return;
  const int rx0 = max(0, bx0 - 2), rx1 = min(size - 1, bx1 + 2);
  const ulong r2 = (ulong)radius * (ulong)radius;
  for (int y = (int)chunk_begin(size, chunk); y < (int)chunk_end(size, chunk); ++y) {
    if (y < by0 || y > by1) continue;
    const int row = y * size;
    ulong ma = 0, mb = 0, mc = 0;
    for (int j = max(bx0, rx0 - radius); j <= min(bx1, rx0 + radius); ++j) {
      const ulong f = img[row + j], uj = (ulong)j;
      ma += f, mb += uj * f, mc += uj * uj * f;
    }
    for (int x = rx0; x <= rx1; ++x) {
      if (x > rx0) {
        const int gone = x - 1 - radius, come = x + radius;
        if (gone >= bx0 && gone <= bx1) {
          const ulong f = img[row + gone], uj = (ulong)gone;
          ma -= f, mb -= uj * f, mc -= uj * uj * f;
        }
        if (come >= bx0 && come <= bx1) {
          const ulong f = img[row + come], uj = (ulong)come;
          ma += f, mb += uj * f, mc += uj * uj * f;
        }
      }
      const ulong ux = (ulong)x;
      rows[row + x] = r2 * ma - ux * ux * ma + 2 * ux * mb - mc;
    }
  }
}

// Column pass, GPU form: one work-item per column, down the rows of the read region, in lock step: the
// barrier in the (work-group uniform) row loop makes PoCL run every work-item's step for row y before row y +
// 1, i.e. read memory along rows with the per-column moments in registers, and lets it vectorise the step
// across work-items. Work-items outside the region take part in the barriers and store nothing.
__kernel void convolve_cols(__global const ulong* restrict rows, const int size,
                            __global const int* restrict box, const int radius,
                            __global float* restrict dens) {
  const int x = get_global_id(0);
  const int bx0 = box[0], by0 = box[1], bx1 = box[2], by1 = box[3];
  if (bx0 > bx1) return;  // uniform: the box is the same for every work-item
  const bool active = x >= bx0 - 2 && x <= bx1 + 2 && x < size;
  const int col = active ? x : 0;  // inactive work-items read a valid column and store nothing
  const int ry0 = max(0, by0 - 2), ry1 = min(size - 1, by1 + 2);
  const ulong r2 = (ulong)radius * (ulong)radius;
  ulong ma = 0, mb = 0, mc = 0;
  for (int j = max(by0, ry0 - radius); j <= min(by1, ry0 + radius); ++j) {
    const ulong f = rows[j * size + col], uj = (ulong)j;
    ma += f, mb += uj * f, mc += uj * uj * f;
  }
  for (int y = ry0; y <= ry1; ++y) {
    if (y > ry0) {
      const int gone = y - 1 - radius, come = y + radius;
      if (gone >= by0 && gone <= by1) {
        const ulong f = rows[gone * size + col], uj = (ulong)gone;
        ma -= f, mb -= uj * f, mc -= uj * uj * f;
      }
      if (come >= by0 && come <= by1) {
        const ulong f = rows[come * size + col], uj = (ulong)come;
        ma += f, mb += uj * f, mc += uj * uj * f;
      }
    }
    const ulong uy = (ulong)y;
    if (active) dens[y * size + col] = convert_float_rte(r2 * ma - uy * uy * ma + 2 * uy * mb - mc);
    barrier(CLK_GLOBAL_MEM_FENCE);
  }
}

// CPU form of the column pass: work-item g walks the columns [rx0 + g·BAND, rx0 + g·BAND + BAND) of the
// read region down its rows, the moments of its columns in private arrays — steps.cpp convolve()'s
// row-by-row walk over a band of columns (rows read along memory, no barriers).
#define BAND 16
__kernel void convolve_col_bands(__global const ulong* restrict rows, const int size,
                                 __global const int* restrict box, const int radius,
                                 __global float* restrict dens) {
  const int bx0 = box[0], by0 = box[1], bx1 = box[2], by1 = box[3];
  if (bx0 > bx1) return;
  const int rx0 = max(0, bx0 - 2), rx1 = min(size - 1, bx1 + 2);
  const int ry0 = max(0, by0 - 2), ry1 = min(size - 1, by1 + 2);
  const int c0 = rx0 + (int)get_global_id(0) * BAND;
  if (c0 > rx1) return;
  const int nc = min(BAND, rx1 - c0 + 1);
  const ulong r2 = (ulong)radius * (ulong)radius;
  ulong ma[BAND], mb[BAND], mc[BAND];
  for (int i = 0; i < BAND; ++i) ma[i] = mb[i] = mc[i] = 0;
  for (int j = max(by0, ry0 - radius); j <= min(by1, ry0 + radius); ++j) {
    __global const ulong* in = rows + j * size + c0;
    const ulong uj = (ulong)j;
    for (int i = 0; i < nc; ++i) {
      const ulong f = in[i];
      ma[i] += f, mb[i] += uj * f, mc[i] += uj * uj * f;
    }
  }
  for (int y = ry0; y <= ry1; ++y) {
    if (y > ry0) {
      const int gone = y - 1 - radius, come = y + radius;
      if (gone >= by0 && gone <= by1) {
        __global const ulong* in = rows + gone * size + c0;
        const ulong uj = (ulong)gone;
        for (int i = 0; i < nc; ++i) {
          const ulong f = in[i];
          ma[i] -= f, mb[i] -= uj * f, mc[i] -= uj * uj * f;
        }
      }
      if (come >= by0 && come <= by1) {
        __global const ulong* in = rows + come * size + c0;
        const ulong uj = (ulong)come;
        for (int i = 0; i < nc; ++i) {
          const ulong f = in[i];
          ma[i] += f, mb[i] += uj * f, mc[i] += uj * uj * f;
        }
      }
    }
    const ulong uy = (ulong)y;
    __global float* out = dens + y * size + c0;
    for (int i = 0; i < nc; ++i)
      out[i] = convert_float_rte(r2 * ma[i] - uy * uy * ma[i] + 2 * uy * mb[i] - mc[i]);
  }
}

// --- advect ---------------------------------------------------------------------------------------------
// Floor and clamp written as conversions and selects (PoCL's floor()/clamp() are library calls). For
// |u| < 2^31 the conversion-based floor equals floor().
#define FLOOR_INT(V) ((int)(V) - ((double)(int)(V) > (V) ? 1 : 0))
#define CLAMP_PX(I) ((I) < 0 ? 0 : ((I) > size - 1 ? size - 1 : (I)))
// The bilinear sample whose top-left texel is (column C0, row R0), next ones C1, R1.
#define BILINEAR(C0, C1, R0, R1)                                                                      \
  ((1.0 - ay) * ((1.0 - ax) * (double)dens[(R0)*size + (C0)] + ax * (double)dens[(R0)*size + (C1)]) + \
   ay * ((1.0 - ax) * (double)dens[(R1)*size + (C0)] + ax * (double)dens[(R1)*size + (C1)]))

// steps.cpp advect(): the four samples at (x ± 1, y), (x, y ± 1) share the floor offset and fraction
// and read the 4 × 4 texels around the point. No early return (only the store is conditional), so
// that every work-item runs the same straight-line code (the GPU form; CPU devices run advect_ranges).
__kernel void advect(__global float* x, __global float* y, __global const float* z, const uint n,
                     __global const float* dens, const int size, const double step) {
  // Padding work-items (i >= n) read the point buffers' spare capacity (the host rounds it up to whole
  // work-groups) and store nothing.
  const uint i = get_global_id(0);
  const float zf = z[i], xf = x[i], yf = y[i];
  const float lim = (float)size;
  const bool inside = zf > 0.0f && xf >= 0.0f && xf < lim && yf >= 0.0f && yf < lim;
  // Points that do not move sample at (0, 0): any in-range position would do.
  const double px = inside ? (double)xf : 0.0, py = inside ? (double)yf : 0.0;
  const double u = px - 0.5, v = py - 0.5;
  const int i0 = FLOOR_INT(u), j0 = FLOOR_INT(v);
  const double ax = u - (double)i0, ay = v - (double)j0;
  const int c0 = CLAMP_PX(i0 - 1), c1 = CLAMP_PX(i0), c2 = CLAMP_PX(i0 + 1), c3 = CLAMP_PX(i0 + 2);
  const int r0 = CLAMP_PX(j0 - 1), r1 = CLAMP_PX(j0), r2 = CLAMP_PX(j0 + 1), r3 = CLAMP_PX(j0 + 2);
  const double gx = BILINEAR(c2, c3, r1, r2) - BILINEAR(c0, c1, r1, r2);
  const double gy = BILINEAR(c1, c2, r2, r3) - BILINEAR(c1, c2, r0, r1);
  const double g2 = gx * gx + gy * gy;
  const double s = step * (double)zf / sqrt(g2);
  if (inside && !(g2 < 1e-4) && i < n) {
    x[i] = (float)(px + s * gx);
    y[i] = (float)(py + s * gy);
  }
}

// CPU form of advect (bundle_ocl.cpp): the same operations over a range of points, skipping the points
// that do not move, with restrict pointers. PoCL compiles this loop 3–4× faster than the one-point form
// above (measured on the 2-core EPYC at 100k edges: 170–230 vs 700 ms of advection), and it is then ~3×
// faster per core than the C++ reference.
__kernel void advect_ranges(__global float* restrict x, __global float* restrict y,
                            __global const float* restrict z, const uint n,
                            __global const float* restrict dens, const int size, const double step,
                            const uint chunk) {
  const float lim = (float)size;
  for (uint i = chunk_begin(n, chunk); i < chunk_end(n, chunk); ++i) {
    const float zf = z[i], xf = x[i], yf = y[i];
    if (!(zf > 0.0f && xf >= 0.0f && xf < lim && yf >= 0.0f && yf < lim)) continue;
    const double px = (double)xf, py = (double)yf;
    const double u = px - 0.5, v = py - 0.5;
    const int i0 = FLOOR_INT(u), j0 = FLOOR_INT(v);
    const double ax = u - (double)i0, ay = v - (double)j0;
    const int c0 = CLAMP_PX(i0 - 1), c1 = CLAMP_PX(i0), c2 = CLAMP_PX(i0 + 1), c3 = CLAMP_PX(i0 + 2);
    const int r0 = CLAMP_PX(j0 - 1), r1 = CLAMP_PX(j0), r2 = CLAMP_PX(j0 + 1), r3 = CLAMP_PX(j0 + 2);
    const double gx = BILINEAR(c2, c3, r1, r2) - BILINEAR(c0, c1, r1, r2);
    const double gy = BILINEAR(c1, c2, r2, r3) - BILINEAR(c1, c2, r0, r1);
    const double g2 = gx * gx + gy * gy;
    if (g2 < 1e-4) continue;
    const double s = step * (double)zf / sqrt(g2);
    x[i] = (float)(px + s * gx);
    y[i] = (float)(py + s * gy);
  }
}

// --- smooth ---------------------------------------------------------------------------------------------
// Point i of one Laplacian pass (steps.cpp smooth()).
void smooth_point(__global const float* restrict x, __global const float* restrict y,
                  __global const float* restrict z, __global const uint* restrict edge,
                  __global const uint* restrict offsets, const uint i, const int window, const double lambda,
                  __global float* restrict nx, __global float* restrict ny) {
  const uint e = edge[i];
  const uint b = offsets[e], end = offsets[e + 1];
  const uint lo = i >= b + (uint)window ? i - (uint)window : b;
  const uint hi = min(end - 1, i + (uint)window);
  double sx = 0.0, sy = 0.0;
  for (uint q = lo; q <= hi; ++q) {
    sx += (double)x[q];
    sy += (double)y[q];
  }
  const double cnt = (double)(hi - lo + 1);
  const double lz = lambda * (double)z[i];
  nx[i] = (float)((1.0 - lz) * (double)x[i] + lz * (sx / cnt));
  ny[i] = (float)((1.0 - lz) * (double)y[i] + lz * (sy / cnt));
}

__kernel void smooth(__global const float* restrict x, __global const float* restrict y,
                     __global const float* restrict z, __global const uint* restrict edge,
                     __global const uint* restrict offsets, const uint n, const int window,
                     const double lambda, __global float* restrict nx, __global float* restrict ny,
                     const uint chunk) {
  for (uint i = chunk_begin(n, chunk); i < chunk_end(n, chunk); ++i)
    smooth_point(x, y, z, edge, offsets, i, window, lambda, nx, ny);
}

// --- directional bundling (compute/src/bundling/directional.cpp) ----------------------------------------
double atan2_poly(const double y, const double x) {
  const double ax = fabs(x), ay = fabs(y);
  const double mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
  if (mx == 0.0) return 0.0;
  const double a = mn / mx, s = a * a;
  double r = ((((0.0208351 * s - 0.085133) * s + 0.180141) * s - 0.3302995) * s + 0.999866) * a;
  if (ay > ax) r = 1.5707963267948966 - r;
  if (x < 0.0) r = 3.141592653589793 - r;
  if (y < 0.0) r = -r;
  return r;
}

__kernel void directions(__global const float* x, __global const float* y, __global const uint* edge,
                         __global const uint* offsets, const uint n, __global float* dirs) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const uint e = edge[i];
  const uint prev = i > offsets[e] ? i - 1 : i, next = i + 1 < offsets[e + 1] ? i + 1 : i;
  const double dx = (double)x[next] - (double)x[prev];
  const double dy = (double)y[next] - (double)y[prev];
  dirs[i] = (float)atan2_poly(dy, dx);
}

// Per pixel, 1 + the largest index of its points (atomic_max: independent of the order of the writes).
__kernel void site_map(__global const float* x, __global const float* y, const uint n, const int size,
                       __global uint* sites) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float px = x[i], py = y[i];
  const float lim = (float)size;
  if (!(px >= 0.0f && px < lim && py >= 0.0f && py < lim)) return;
  atomic_max(&sites[(int)py * size + (int)px], i + 1);
}

double direction_compatibility(const double a, const double b) {
  double d = a - b;
  if (d > 3.141592653589793) d -= 6.283185307179586;
  if (d < -3.141592653589793) d += 6.283185307179586;
  return 1.0 - 0.6366197723675814 * fabs(d);
}

// Reads x, y and writes ox, oy (every point: the unmoved ones are copied).
__kernel void advect_directional(__global const float* x, __global const float* y, __global const float* z,
                                 __global const uint* edge, const uint n, __global const uint* sites,
                                 __global const float* dirs, const int size, const int radius,
                                 const double step, const double repulsion, __global float* ox,
                                 __global float* oy) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float xf = x[i], yf = y[i], zf = z[i];
  const float lim = (float)size;
  ox[i] = xf;
  oy[i] = yf;
  if (!(zf > 0.0f) || !(xf >= 0.0f && xf < lim && yf >= 0.0f && yf < lim)) return;
  const double px = xf, py = yf, pa = dirs[i];
  const double r2 = (double)radius * (double)radius;
  const int ix = (int)xf, iy = (int)yf;
  const uint own = edge[i];
  double vx = 0.0, vy = 0.0, cabs = 0.0;
  int cnt = 0;
  for (int sy = max(0, iy - radius); sy <= min(size - 1, iy + radius); ++sy)
    for (int sx = max(0, ix - radius); sx <= min(size - 1, ix + radius); ++sx) {
      const uint s = sites[sy * size + sx];
      if (s == 0) continue;
      const uint q = s - 1;
      if (edge[q] == own) continue;
      const double dx = (double)x[q] - px, dy = (double)y[q] - py;
      const double d2 = dx * dx + dy * dy;
      if (!(d2 < r2)) continue;
      const double w = 1.0 - d2 / r2;
      double c = direction_compatibility(pa, (double)dirs[q]);
      cabs += fabs(c);
      ++cnt;
      if (c < 0.0) c = c * repulsion;
      vx += dx * (c * w);
      vy += dy * (c * w);
    }
  const double v2 = vx * vx + vy * vy;
  if (cnt == 0 || v2 < 1e-12) return;
  const double s = step * (double)zf * (cabs / (double)cnt) / sqrt(v2);
  ox[i] = (float)(px + s * vx);
  oy[i] = (float)(py + s * vy);
}
