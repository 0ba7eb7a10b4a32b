import { describe, expect, it } from 'vitest';
import { TsrfError, encodeFrameMessage, parseFrameMessage } from './tsrf';

const depth = new Uint8Array([0x89, 0x50, 0x4e, 0x47, 1, 2, 3]);
const amp = new Uint8Array([0x89, 0x50, 0x4e, 0x47, 9]);

function message(extra: Record<string, unknown> = {}) {
  return encodeFrameMessage(
    {
      type: 'frame',
      index: 12,
      timestamp_s: 0.48,
      frame: { index: 12, state: 'STATE_TRACK', matches: 5 },
      truth: { teats: [{ name: 'FL', tip_mm: [1, 2, 3], tip_px: [4, 5], visible: true, box_px: [1, 1, 2, 2] }] },
      depth_png: [0, depth.length],
      amplitude_png: [depth.length, amp.length],
      ...extra,
    },
    [depth, amp],
  );
}

describe('parseFrameMessage', () => {
  it('splits header, JSON and the two PNGs', () => {
    const m = parseFrameMessage(message().buffer as ArrayBuffer);
    expect(m.index).toBe(12);
    expect(m.timestampS).toBe(0.48);
    expect(m.frame.state).toBe('TRACK');
    expect(m.frame.matches).toBe(5);
    expect(m.truth!.teats[0]!.tipPx).toEqual([4, 5]);
    expect([...m.depthPng!]).toEqual([...depth]);
    expect([...m.amplitudePng!]).toEqual([...amp]);
  });

  it('works on a Uint8Array view with an offset', () => {
    const msg = message();
    const big = new Uint8Array(msg.length + 5);
    big.set(msg, 5);
    const m = parseFrameMessage(big.subarray(5));
    expect([...m.amplitudePng!]).toEqual([...amp]);
  });

  it('takes a missing image or truth as null', () => {
    const m = parseFrameMessage(message({ truth: null, amplitude_png: null }));
    expect(m.truth).toBeNull();
    expect(m.amplitudePng).toBeNull();
    expect(m.depthPng).not.toBeNull();
  });

  it('handles non-ASCII JSON (length is in bytes)', () => {
    const m = parseFrameMessage(message({ note: 'größe ✓' }));
    expect([...m.depthPng!]).toEqual([...depth]);
  });

  it('rejects malformed messages with TsrfError', () => {
    const good = message();
    const bad = (b: Uint8Array) => () => parseFrameMessage(b);
    expect(bad(good.subarray(0, 6))).toThrow(TsrfError);
    const magic = good.slice();
    magic[0] = 0x58;
    expect(bad(magic)).toThrow(/magic/);
    const long = good.slice();
    new DataView(long.buffer).setUint32(4, 1e6, true);
    expect(bad(long)).toThrow(/past the message end/);
    expect(bad(message({ depth_png: [0, 1000] }))).toThrow(/outside/);
    expect(bad(message({ depth_png: [-1, 2] }))).toThrow(TsrfError);
    expect(bad(message({ type: 'state' }))).toThrow(/unexpected/);
    expect(bad(encodeFrameMessage({ a: 1 }).subarray(0, 10))).toThrow(TsrfError);
  });
});
