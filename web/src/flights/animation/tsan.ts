// TSAN, the animation stream's binary chunk (proto/animation_chunks.md): the flights present in one
// time chunk with their samples, times as float32 seconds relative to the chunk start and positions as
// float32 EPSG:3857 metres relative to an origin. The column arrays are views on the buffer (no copy).

export const TSAN_MAGIC = 'TSAN';
export const TSAN_VERSION = 1;
export const TSAN_HEADER_BYTES = 64;
export const TSAN_FLIGHT_BYTES = 24;
/** icao24 field value for an unknown/empty address. */
export const TSAN_NO_ICAO = 0xffffffff;
/** MIME type of a chunk. */
export const TSAN_MIME = 'application/vnd.trailscope.anim';

export interface TsanChunk {
  /** Chunk start, float64 Unix seconds. */
  tStart: number;
  /** Chunk length, seconds: the chunk covers [tStart, tStart + duration). */
  duration: number;
  /** EPSG:3857 metres of the origin the x/y columns are relative to. */
  originX: number;
  originY: number;
  nFlights: number;
  nSamples: number;
  /** Per flight (ordered by flight id): dataset flight id, first sample index, sample count, icao24 (24-bit or TSAN_NO_ICAO). */
  flightId: Uint32Array;
  first: Uint32Array;
  count: Uint32Array;
  icao24: Uint32Array;
  /** Per flight, decoded callsign ('' when none). */
  callsign: string[];
  /** Sample columns, nSamples each. t is seconds relative to tStart. */
  t: Float32Array;
  x: Float32Array;
  y: Float32Array;
  alt: Float32Array;
  speed: Float32Array;
  track: Float32Array;
  vrate: Float32Array;
  onGround: Uint8Array;
  /** Size of the encoded chunk in bytes. */
  byteLength: number;
}

export class TsanError extends Error {
  constructor(message: string) {
    super(`TSAN: ${message}`);
    this.name = 'TsanError';
  }
}

const pad8 = (n: number) => (n + 7) & ~7;

/** Bytes of a chunk with these counts (the layout of proto/animation_chunks.md). */
export function tsanByteLength(nFlights: number, nSamples: number, stringsBytes: number): number {
  return TSAN_HEADER_BYTES + pad8(TSAN_FLIGHT_BYTES * nFlights) + 7 * pad8(4 * nSamples) + pad8(nSamples) + pad8(stringsBytes);
}

/** icao24 as the API writes it (6 lower-case hex digits), '' when unknown. */
export function icaoText(v: number): string {
  return v === TSAN_NO_ICAO ? '' : v.toString(16).padStart(6, '0');
}

/**
 * Decodes a TSAN chunk. Throws TsanError when it is malformed: bad magic or version, a length that does
 * not match its counts, a flight whose samples leave the columns or overlap the previous flight's, flights
 * not ordered by id, or a callsign outside the strings blob.
 */
export function decodeTsan(buf: ArrayBuffer): TsanChunk {
  if (buf.byteLength < TSAN_HEADER_BYTES) throw new TsanError(`${buf.byteLength} bytes is shorter than the header`);
  const dv = new DataView(buf);
  const magic = String.fromCharCode(dv.getUint8(0), dv.getUint8(1), dv.getUint8(2), dv.getUint8(3));
  if (magic !== TSAN_MAGIC) throw new TsanError(`bad magic "${magic}"`);
  const version = dv.getUint16(4, true);
  if (version !== TSAN_VERSION) throw new TsanError(`version ${version} is not supported (expected ${TSAN_VERSION})`);
  const tStart = dv.getFloat64(8, true);
  const duration = dv.getFloat64(16, true);
  if (!Number.isFinite(tStart) || !(duration > 0)) throw new TsanError(`bad chunk span (t_start ${tStart}, duration ${duration})`);
  const originX = dv.getFloat64(24, true);
  const originY = dv.getFloat64(32, true);
  const nFlights = dv.getUint32(40, true);
  const nSamples = dv.getUint32(44, true);
  const stringsBytes = dv.getUint32(48, true);
  const expected = tsanByteLength(nFlights, nSamples, stringsBytes);
  if (buf.byteLength !== expected) {
    throw new TsanError(`${buf.byteLength} bytes, expected ${expected} for ${nFlights} flights, ${nSamples} samples and ${stringsBytes} string bytes`);
  }
  // Typed-array views need little-endian data: every browser TrailScope targets is little-endian.
  const table = new Uint32Array(buf, TSAN_HEADER_BYTES, 6 * nFlights);
  let off = TSAN_HEADER_BYTES + pad8(TSAN_FLIGHT_BYTES * nFlights);
  const col = () => {
    const a = new Float32Array(buf, off, nSamples);
    off += pad8(4 * nSamples);
    return a;
  };
  const t = col(), x = col(), y = col(), alt = col(), speed = col(), track = col(), vrate = col();
  const onGround = new Uint8Array(buf, off, nSamples);
  off += pad8(nSamples);
  const strings = new Uint8Array(buf, off, stringsBytes);
  const flightId = new Uint32Array(nFlights), first = new Uint32Array(nFlights), count = new Uint32Array(nFlights);
  const icao24 = new Uint32Array(nFlights);
  const callsign: string[] = new Array<string>(nFlights);
  const utf8 = new TextDecoder('utf-8', { fatal: true });
  let next = 0;
  for (let i = 0; i < nFlights; i++) {
    const r = 6 * i;
    flightId[i] = table[r]!;
    first[i] = table[r + 1]!;
    count[i] = table[r + 2]!;
    icao24[i] = table[r + 3]!;
    const so = table[r + 4]!, sl = table[r + 5]!;
    if (i > 0 && flightId[i]! <= flightId[i - 1]!) throw new TsanError(`flights are not ordered by id at flight ${i}`);
    if (count[i]! < 1) throw new TsanError(`flight ${flightId[i]} has no samples`);
    if (first[i]! < next || first[i]! + count[i]! > nSamples) {
      throw new TsanError(`flight ${flightId[i]}'s samples ${first[i]}..${first[i]! + count[i]!} leave the columns or overlap`);
    }
    next = first[i]! + count[i]!;
    if (so + sl > stringsBytes) throw new TsanError(`flight ${flightId[i]}'s callsign lies outside the strings blob`);
    try {
      callsign[i] = sl === 0 ? '' : utf8.decode(strings.subarray(so, so + sl));
    } catch {
      throw new TsanError(`flight ${flightId[i]}'s callsign is not UTF-8`);
    }
  }
  return {
    tStart, duration, originX, originY, nFlights, nSamples,
    flightId, first, count, icao24, callsign,
    t, x, y, alt, speed, track, vrate, onGround,
    byteLength: buf.byteLength,
  };
}
