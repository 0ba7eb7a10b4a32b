// TSBL, the binary polylines of a bundle (proto/bundle_polylines.md), and the relaxation blend done on the
// client so that the slider moves between raw and bundled without asking the server to recompute.

export const TSBL_MAGIC = 'TSBL';
export const TSBL_VERSION = 1;
const HEADER_BYTES = 32;

export interface Tsbl {
  /** Coordinates are lon/lat degrees (flights, geographic graphs); else the graph's own units. */
  lonlat: boolean;
  /** Polylines and points. */
  n: number;
  m: number;
  /** The relaxation the bundled section already has (0 = fully bundled). */
  relaxation: number;
  /** The bundle's displacement cap, a fraction of each polyline's length. */
  maxDisplacement: number;
  /** n + 1 entries: polyline i is points offsets[i] .. offsets[i+1]-1. */
  offsets: Uint32Array;
  /** x, y interleaved, 2m values. */
  bundled: Float32Array;
  original: Float32Array;
  /** Per polyline, in the units of the cap (Mercator degrees for lon/lat). */
  length: Float32Array;
}

export class TsblError extends Error {
  constructor(message: string) {
    super(`TSBL: ${message}`);
    this.name = 'TsblError';
  }
}

/** Decodes a TSBL buffer. The arrays are views on `buf` (no copy); throws TsblError when it is malformed. */
export function decodeTsbl(buf: ArrayBuffer): Tsbl {
  if (buf.byteLength < HEADER_BYTES) throw new TsblError(`${buf.byteLength} bytes is shorter than the header`);
  const dv = new DataView(buf);
  const magic = String.fromCharCode(dv.getUint8(0), dv.getUint8(1), dv.getUint8(2), dv.getUint8(3));
  if (magic !== TSBL_MAGIC) throw new TsblError(`bad magic "${magic}"`);
  const version = dv.getUint32(4, true);
  if (version !== TSBL_VERSION) throw new TsblError(`version ${version} is not supported (expected ${TSBL_VERSION})`);
  const flags = dv.getUint32(8, true);
  const n = dv.getUint32(12, true);
  const m = dv.getUint32(16, true);
  const expected = 36 + 8 * n + 16 * m;
  if (buf.byteLength !== expected) throw new TsblError(`${buf.byteLength} bytes, expected ${expected} for ${n} polylines of ${m} points`);
  // Typed-array views need little-endian data: every browser TrailScope targets is little-endian.
  const offsets = new Uint32Array(buf, HEADER_BYTES, n + 1);
  if (offsets[0] !== 0 || offsets[n] !== m) throw new TsblError('offsets do not run from 0 to the point count');
  for (let i = 0; i < n; i++) if (offsets[i + 1]! < offsets[i]!) throw new TsblError(`offsets decrease at polyline ${i}`);
  const xy = HEADER_BYTES + 4 * (n + 1);
  return {
    lonlat: (flags & 1) !== 0,
    n,
    m,
    relaxation: dv.getFloat32(20, true),
    maxDisplacement: dv.getFloat32(24, true),
    offsets,
    bundled: new Float32Array(buf, xy, 2 * m),
    original: new Float32Array(buf, xy + 8 * m, 2 * m),
    length: new Float32Array(buf, xy + 16 * m, n),
  };
}

/**
 * Lon/lat (degrees) to Web Mercator world units in [0, 1] (x east, y south), the plane the server bundled
 * in (up to a factor of 360 against the "Mercator degrees" of TSBL's lengths). Other data passes through.
 */
export function toPlane(xy: Float32Array, lonlat: boolean): Float64Array {
  const out = new Float64Array(xy.length);
  for (let i = 0; i < xy.length; i += 2) {
    if (lonlat) {
      const lat = Math.max(-85.0511287798, Math.min(85.0511287798, xy[i + 1]!)) * (Math.PI / 180);
      out[i] = (xy[i]! + 180) / 360;
      out[i + 1] = 0.5 - Math.asinh(Math.tan(lat)) / (2 * Math.PI);
    } else {
      out[i] = xy[i]!;
      out[i + 1] = xy[i + 1]!;
    }
  }
  return out;
}

/** Web Mercator world units back to lon/lat. */
export function planeToLonLat(x: number, y: number): [number, number] {
  return [x * 360 - 180, (Math.atan(Math.sinh(Math.PI * (1 - 2 * y))) * 180) / Math.PI];
}

/**
 * The relaxation blend of bundling::relax: with l = 1 − relaxation, capped per point so that
 * l·|p − P| ≤ maxDisplacement · length, every point becomes l·p + (1 − l)·P. `bundled` and `original` are
 * x,y interleaved in one plane, `length` per polyline in that plane's units (`lengthScale` converts the
 * file's lengths: 1/360 for Mercator degrees to world units). Writes into `out` (allocated when absent).
 */
export function blend(
  bundled: ArrayLike<number>,
  original: ArrayLike<number>,
  offsets: ArrayLike<number>,
  length: ArrayLike<number>,
  maxDisplacement: number,
  relaxation: number,
  lengthScale = 1,
  out: Float64Array = new Float64Array(bundled.length),
): Float64Array {
  const r = Math.min(1, Math.max(0, relaxation));
  const n = offsets.length - 1;
  for (let e = 0; e < n; e++) {
    const cap = maxDisplacement * length[e]! * lengthScale;
    for (let i = offsets[e]!; i < offsets[e + 1]!; i++) {
      const px = bundled[2 * i]!, py = bundled[2 * i + 1]!, ox = original[2 * i]!, oy = original[2 * i + 1]!;
      const d = Math.hypot(px - ox, py - oy);
      let l = 1 - r;
      if (l * d > cap) l = cap / d;
      out[2 * i] = l * px + (1 - l) * ox;
      out[2 * i + 1] = l * py + (1 - l) * oy;
    }
  }
  return out;
}

/** A decoded bundle ready to blend: both point sets in the bundling plane. */
export interface BlendSource {
  tsbl: Tsbl;
  bundled: Float64Array;
  original: Float64Array;
  /** Multiplies TSBL lengths into plane units. */
  lengthScale: number;
}

export function blendSource(t: Tsbl): BlendSource {
  return { tsbl: t, bundled: toPlane(t.bundled, t.lonlat), original: toPlane(t.original, t.lonlat), lengthScale: t.lonlat ? 1 / 360 : 1 };
}

/** The polylines at `relaxation`, in the plane (world units for lon/lat). */
export function blendAt(s: BlendSource, relaxation: number, out?: Float64Array): Float64Array {
  return blend(s.bundled, s.original, s.tsbl.offsets, s.tsbl.length, s.tsbl.maxDisplacement, relaxation, s.lengthScale, out);
}
