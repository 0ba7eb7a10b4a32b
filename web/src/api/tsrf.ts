// The replay WebSocket's binary frame message: "TSRF", uint32 LE length J, J bytes of UTF-8 JSON
// {"type":"frame", index, timestamp_s, frame, truth, depth_png:[offset,length], amplitude_png:[offset,length]},
// then the PNG bytes; offsets count from the first byte after the JSON.

import { decodeFrameRecord, decodeTruth, toNumber, type FrameRecord, type FrameTruth } from './trackerLog';

export interface FrameMessage {
  index: number;
  timestampS: number;
  frame: FrameRecord;
  truth: FrameTruth | null;
  /** Views into the message buffer (no copy), or null when absent. */
  depthPng: Uint8Array | null;
  amplitudePng: Uint8Array | null;
}

export class TsrfError extends Error {
  constructor(message: string) {
    super(message);
    this.name = 'TsrfError';
  }
}

const MAGIC = [0x54, 0x53, 0x52, 0x46]; // "TSRF"
const decoder = new TextDecoder('utf-8', { fatal: true });

function slice(payload: Uint8Array, range: unknown, what: string): Uint8Array | null {
  if (range === null || range === undefined) return null;
  if (!Array.isArray(range) || range.length !== 2) throw new TsrfError(`${what}: expected [offset, length]`);
  const off = toNumber(range[0], NaN);
  const len = toNumber(range[1], NaN);
  if (!Number.isInteger(off) || !Number.isInteger(len) || off < 0 || len < 0 || off + len > payload.length) {
    throw new TsrfError(`${what}: range [${off}, ${len}] outside the ${payload.length} image bytes`);
  }
  return len === 0 ? null : payload.subarray(off, off + len);
}

/** Parses one binary message. Throws TsrfError for a message that is not a well-formed TSRF frame. */
export function parseFrameMessage(buf: ArrayBuffer | Uint8Array): FrameMessage {
  const bytes = buf instanceof Uint8Array ? buf : new Uint8Array(buf);
  if (bytes.length < 8) throw new TsrfError(`message of ${bytes.length} bytes is shorter than the 8-byte header`);
  for (let i = 0; i < 4; i++) if (bytes[i] !== MAGIC[i]) throw new TsrfError('not a TSRF frame message (bad magic)');
  const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const jsonLen = dv.getUint32(4, true);
  if (8 + jsonLen > bytes.length) throw new TsrfError(`JSON length ${jsonLen} runs past the message end (${bytes.length} bytes)`);
  let meta: unknown;
  try {
    meta = JSON.parse(decoder.decode(bytes.subarray(8, 8 + jsonLen)));
  } catch (e) {
    throw new TsrfError(`frame JSON does not parse: ${String(e)}`);
  }
  if (typeof meta !== 'object' || meta === null || Array.isArray(meta)) throw new TsrfError('frame JSON is not an object');
  const m = meta as Record<string, unknown>;
  if (m.type !== undefined && m.type !== 'frame') throw new TsrfError(`unexpected message type ${JSON.stringify(m.type)}`);
  const payload = bytes.subarray(8 + jsonLen);
  const index = toNumber(m.index, NaN);
  const frame = decodeFrameRecord(m.frame, Number.isFinite(index) ? index : 0);
  return {
    index: Number.isFinite(index) ? index : frame.index,
    timestampS: toNumber(m.timestamp_s ?? m.timestampS, frame.timestampS),
    frame,
    truth: decodeTruth(m.truth),
    depthPng: slice(payload, m.depth_png ?? m.depthPng, 'depth_png'),
    amplitudePng: slice(payload, m.amplitude_png ?? m.amplitudePng, 'amplitude_png'),
  };
}

/** Builds a TSRF message (tests and tools). */
export function encodeFrameMessage(meta: Record<string, unknown>, images: Uint8Array[] = []): Uint8Array {
  const json = new TextEncoder().encode(JSON.stringify(meta));
  const total = images.reduce((s, b) => s + b.length, 0);
  const out = new Uint8Array(8 + json.length + total);
  out.set(MAGIC, 0);
  new DataView(out.buffer).setUint32(4, json.length, true);
  out.set(json, 8);
  let off = 8 + json.length;
  for (const b of images) {
    out.set(b, off);
    off += b.length;
  }
  return out;
}
