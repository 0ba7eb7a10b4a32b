// Line density: one work-item per prepared segment walks the pixels the segment touches and adds 1 to
// each pixel's count (and, with WITH_VALUE, the segment's fixed-point value to an int64 sum and 1 to a
// valued-segment count). Integer atomics only, so the result is independent of scheduling and equal,
// bit for bit, to density_lines_ref (compute/src/density/density_lines_ref.cpp), whose walk this is
// line by line. The segments' start state was prepared exactly on the host (density_lines.cpp); here
// only int32/int64 additions and comparisons happen.
//
// OpenCL C 1.2: atomic_inc on int is core; atom_add on long needs cl_khr_int64_base_atomics, which the
// host checks before building the WITH_VALUE variant.
#ifdef WITH_VALUE
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#endif

__kernel void density_lines(__global const long* walk,   // 3 per segment: d, inc_x, inc_y
                            __global const int* cells,   // 6 per segment: i, j, end_i, end_j, flags, value
                            const int n, const int width, const int height,
                            __global int* count
#ifdef WITH_VALUE
                            , __global long* value_sum, __global int* value_count
#endif
) {
  const int s = (int)get_global_id(0);
  if (s >= n) return;
  long d = walk[3 * s];
  const long inc_x = walk[3 * s + 1];
  const long inc_y = walk[3 * s + 2];
  int i = cells[6 * s];
  int j = cells[6 * s + 1];
  const int end_i = cells[6 * s + 2];
  const int end_j = cells[6 * s + 3];
  const int flags = cells[6 * s + 4];
  const int sx = (flags & 3) - 1;
  const int sy = ((flags >> 2) & 3) - 1;
  int skip = (flags >> 4) & 1;
#ifdef WITH_VALUE
  const int has_value = (flags >> 5) & 1;
  const long value = (long)cells[6 * s + 5];
#endif
  // A monotone walk visits at most width + height - 1 pixels of the canvas; the bound only guards
  // against a malformed input ever hanging the device.
  for (int guard = width + height + 2; guard > 0; --guard) {
    if (!skip) {
      const int idx = j * width + i;
      atomic_inc(&count[idx]);
#ifdef WITH_VALUE
      if (has_value) {
        atom_add(&value_sum[idx], value);
        atomic_inc(&value_count[idx]);
      }
#endif
    }
    skip = 0;
    if (i == end_i && j == end_j) break;
    if (sx == 0) {
      j += sy;
    } else if (sy == 0) {
      i += sx;
    } else if (d < 0) {  // the next vertical pixel edge comes first
      i += sx;
      d += inc_x;
    } else if (d > 0) {  // the next horizontal edge comes first
      j += sy;
      d -= inc_y;
    } else if (sx > 0 && sy < 0) {  // through a corner: the half-open rule puts the corner point
      i += sx;                      // in the pixel east of the current one first
      d += inc_x;
    } else if (sx < 0 && sy > 0) {  // ... or south of it first
      j += sy;
      d -= inc_y;
    } else {  // ... or in the diagonal neighbour directly
      i += sx;
      j += sy;
      d += inc_x - inc_y;
    }
    if (i < 0 || i >= width || j < 0 || j >= height) break;
  }
}
