#pragma once
// The line-density count tile as ClickHouse SQL: one home for the query the ClickHouse store sends to its
// shards (clickhouse_store.cpp, density_tile()) and the one the tile benchmark runs against its ClickHouse
// peer tables (tests/bench/tile_bench.cpp). Header-only, no dependency beyond the standard library, so that
// the benchmarks use it without linking the server.
//
// What it computes: the pixels of a tile grid that each segment touches, exactly as density_lines()
// (compute/.../density/lines.hpp) defines them — the closed segment meets the half-open pixel square —
// with the pixel of the first endpoint left out for a segment that continues its flight's run; the count
// per pixel. How: orient each segment left to right (lx <= hx); one row per pixel column c it crosses
// inside the tile (arrayJoin(range(...))); in that column the segment spans x in [max(lx, cP),
// min(hx, (c+1)P)] (the right end open when it is the column's edge), and, y being linear in x, the rows
// between the rows of its two ends: y at an x is ly ± (x − lx)·|dy| / dx, done exactly in UInt64 (both
// factors < 2^32) with intDiv and the remainder, so the floors, and the open end's limit (a row boundary
// reached exactly from below belongs to the row beneath), are exact; then one row per pixel row (a second
// arrayJoin). Each (segment, pixel) pair is produced once by construction. ClickHouse 18.16 has every
// function used (range(n) with one argument, arrayJoin, intDiv, modulo, multiIf, greatest/least).
#include <cstdint>
#include <string>

namespace trailscope::server {

/// The pixel grid of a tile in integer Web Mercator units (TrailSet::merc_x/merc_y): pixel edge `pixel`
/// (> 0) units, the tile's first pixel column `col0` and row `row0` (in units of `pixel` from the world's
/// origin), `width` x `height` pixels (> 0).
struct LineTileGrid {
  std::int64_t pixel = 1, col0 = 0, row0 = 0, width = 256, height = 256;
};

/// A SELECT giving `pos` (UInt32, row-major pixel index in the tile: row * width + column) and its count
/// (UInt32), one row per non-empty pixel, unordered. `source` is what the segments are selected from:
/// "FROM table WHERE ..." (no FORMAT) over rows in which `cont` (an SQL boolean: the segment continues
/// its flight's run, so its first endpoint's pixel is left out) and `xa`, `ya`, `xb`, `yb` (SQL
/// expressions of Int64 type: the first and second endpoints) can be evaluated. The caller's WHERE should
/// keep only the segments whose bounding box meets the tile (others produce no row, only work).
/// With `value` and `has_value` (SQL expressions over the same rows: the segment's fixed-point value as
/// Int64, round(v · kValueScale) as density_lines() stores it, and an SQL boolean, whether it has one),
/// each row also gives the pixel's sum of the values (Int64) and the number of valued segments (UInt32)
/// that touched it, as density_lines() sums them: the Aggregate's value_sum and value_count.
inline std::string line_tile_sql(const LineTileGrid& g, const std::string& cont, const std::string& xa,
                                 const std::string& ya, const std::string& xb, const std::string& yb,
                                 const std::string& source, const std::string& value = "",
                                 const std::string& has_value = "") {
  // The value and its flag ride along every stage.
  const bool valued = !value.empty();
  const std::string carry = valued ? "v_, hv_, " : "";
  const std::string sP = std::to_string(g.pixel), sC0 = std::to_string(g.col0), sR0 = std::to_string(g.row0),
                    sCmax = std::to_string(g.col0 + g.width - 1),
                    sRmax = std::to_string(g.row0 + g.height - 1), sW = std::to_string(g.width);
  const std::string segs =
      "SELECT " + cont + " AS cont_, " + (valued ? value + " AS v_, " + has_value + " AS hv_, " : "") + xa +
      " AS xa_, " + ya + " AS ya_, " + xb + " AS xb_, " + yb + " AS yb_, intDiv(xa_, " + sP +
      ") AS pa_c, intDiv(ya_, " + sP +
      ") AS pa_r, xa_ <= xb_ AS fwd, if(fwd, xa_, xb_) AS lx, if(fwd, ya_, yb_) AS ly, if(fwd, xb_, xa_) AS "
      "hx, if(fwd, yb_, ya_) AS hy, hx - lx AS dx, hy - ly AS dy, toUInt64(abs(dy)) AS ady, "
      "toUInt64(greatest(dx, 1)) AS ddx, greatest(intDiv(lx, " +
      sP + "), " + sC0 + ") AS c_lo, least(intDiv(hx, " + sP + "), " + sCmax + ") AS c_hi " + source;
  const std::string cols =
      "SELECT " + carry +
      "cont_, pa_c, pa_r, lx, ly, hx, dx, dy, ady, ddx, "
      "c_lo + toInt64(arrayJoin(range(toUInt64(greatest(c_hi - c_lo + 1, 0))))) AS c FROM (" +
      segs + ")";
  const std::string rows =
      "SELECT " + carry + "cont_, pa_c, pa_r, c, greatest(lx, c * " + sP + ") AS xl, least(hx, (c + 1) * " +
      sP + ") AS xr, hx >= (c + 1) * " + sP +
      " AS open_r, toUInt64(xl - lx) * ady AS ul, toUInt64(xr - lx) * ady AS ur, "
      "toInt64(intDiv(ul, ddx)) AS ql, ul % ddx AS ml, toInt64(intDiv(ur, ddx)) AS qr, ur % ddx AS mr, "
      "toInt64(multiIf(dx = 0, intDiv(least(ly, ly + dy), " +
      sP + "), dy >= 0, intDiv(ly + ql, " + sP + "), intDiv(ly - ql - (ml > 0), " + sP +
      "))) AS j_l, toInt64(multiIf(dx = 0, intDiv(greatest(ly, ly + dy), " + sP +
      "), dy > 0, intDiv(ly + qr, " + sP + ") - (open_r AND mr = 0 AND (ly + qr) % " + sP +
      " = 0), dy = 0, intDiv(ly, " + sP + "), intDiv(ly - qr - (mr > 0), " + sP +
      "))) AS j_r, greatest(least(j_l, j_r), " + sR0 + ") AS r_lo, least(greatest(j_l, j_r), " + sRmax +
      ") AS r_hi FROM (" + cols + ")";
  const std::string pix =
      "SELECT " + carry +
      "cont_, pa_c, pa_r, c, r_lo + toInt64(arrayJoin(range(toUInt64(greatest(r_hi - r_lo + 1, 0))))) "
      "AS r FROM (" +
      rows + ")";
  return "SELECT toUInt32((r - " + sR0 + ") * " + sW + " + (c - " + sC0 + ")) AS pos, toUInt32(count())" +
         (valued ? ", toInt64(sumIf(v_, hv_)), toUInt32(countIf(hv_))" : "") + " FROM (" + pix +
         ") WHERE NOT (cont_ AND c = pa_c AND r = pa_r) GROUP BY pos";
}

}  // namespace trailscope::server
