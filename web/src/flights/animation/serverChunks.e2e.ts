// Against a running server (tests/e2e/run.sh: TRAILSCOPE_URL, DATASET = the ingested Europe SO6 day): chunks
// of GET /api/v1/datasets/{id}/animation decoded by tsan.ts and interpolated by frame.ts give the same
// flights and positions as GET /api/v1/datasets/{id}/positions?t= at instants over the day, the last
// second of the day included, to the metre; filters on the client give the API's filtered answer; the
// chunk revalidates with its ETag (304).
import { describe, expect, it } from 'vitest';
import { decodeTsan, icaoText, TSAN_MIME, type TsanChunk } from './tsan';
import { frameAt } from './frame';
import { compileFilter } from './filter';
import type { TrafficFilter } from './types';

// Not BASE_URL: Vite sets that one to the app's base path.
const BASE = process.env.TRAILSCOPE_URL ?? 'http://127.0.0.1:8080';
const DATASET = process.env.DATASET ?? 'europe';
const api = (p: string) => `${BASE}/api/v1/datasets/${DATASET}${p}`;
// Access control is on: run.sh's admin token (TRAILSCOPE_TOKEN) on every request.
const TOKEN = process.env.TRAILSCOPE_TOKEN ?? '';
const fetch = (url: string, init: RequestInit = {}) => {
  const headers = new Headers(init.headers);
  if (TOKEN) headers.set('Authorization', `Bearer ${TOKEN}`);
  return globalThis.fetch(url, { ...init, headers });
};

interface Pos { id: number; lat: number; lon: number; alt_m: number | null; callsign: string; icao24: string }

async function chunkAt(t: number, d: number): Promise<{ chunk: TsanChunk; etag: string; url: string }> {
  const url = api(`/animation?t=${Math.floor(t / d) * d}&duration=${d}`);
  const res = await fetch(url);
  expect(res.status).toBe(200);
  expect(res.headers.get('content-type')).toContain(TSAN_MIME);
  return { chunk: decodeTsan(await res.arrayBuffer()), etag: res.headers.get('etag') ?? '', url };
}

async function positions(t: number, extra = ''): Promise<Pos[]> {
  const res = await fetch(api(`/positions?t=${t}${extra}`));
  expect(res.status).toBe(200);
  return ((await res.json()) as { positions: Pos[] }).positions;
}

function metres(lon1: number, lat1: number, lon2: number, lat2: number) {
  const k = (6371008.8 * Math.PI) / 180;
  let dl = lon2 - lon1;
  if (dl > 180) dl -= 360;
  if (dl < -180) dl += 360;
  return Math.hypot(dl * k * Math.cos(((lat1 + lat2) / 2) * (Math.PI / 180)), (lat2 - lat1) * k);
}

function compare(chunk: TsanChunk, t: number, ref: Pos[], filter: TrafficFilter = {}) {
  const fr = frameAt(chunk, t, compileFilter(filter));
  expect(fr.n).toBe(ref.length);
  let worst = 0;
  for (let i = 0; i < fr.n; i++) {
    const p = ref[i]!, f = fr.flight[i]!;
    expect(chunk.flightId[f]).toBe(p.id);
    expect(chunk.callsign[f]).toBe(p.callsign);
    expect(icaoText(chunk.icao24[f]!)).toBe(p.icao24);
    worst = Math.max(worst, metres(fr.lon[i]!, fr.lat[i]!, p.lon, p.lat));
    if (p.alt_m === null) expect(Number.isNaN(fr.alt[i]!)).toBe(true);
    else expect(Math.abs(fr.alt[i]! - p.alt_m)).toBeLessThan(0.01);
  }
  expect(worst).toBeLessThan(1);
  return { n: fr.n, worst };
}

describe(`animation chunks of ${DATASET} against its positions`, async () => {
  const ds = (await (await fetch(`${BASE}/api/v1/datasets`)).json()) as { datasets: Array<{ id: string; name: string; t_min: number; t_max: number }> };
  const d = ds.datasets.find((x) => x.id === DATASET || x.name === DATASET)!;
  const day = Math.floor(d.t_min / 86400) * 86400;
  // Morning, midday, evening and the last second of the day (float32 epoch seconds are 128 s apart there).
  const instants = [day + 6 * 3600 + 0.5, day + 12 * 3600 + 1234.25, day + 19 * 3600 + 7.75, day + 86399.5]
    .filter((t) => t >= d.t_min && t <= d.t_max);

  for (const dur of [300, 60]) {
    it(`chunks of ${dur} s give the positions endpoint's flights and positions`, async () => {
      for (const t of instants) {
        const { chunk } = await chunkAt(t, dur);
        const { n } = compare(chunk, t, await positions(t));
        if (t < day + 86399) expect(n).toBeGreaterThan(50);
      }
    });
  }

  it('client filters (altitude band, bbox, callsign prefix) give the API\'s filtered positions', async () => {
    const t = instants[1]!;
    const { chunk } = await chunkAt(t, 300);
    compare(chunk, t, await positions(t, '&alt_min=6000&alt_max=10000&alt_unit=m'), { altMinM: 6000, altMaxM: 10000 });
    compare(chunk, t, await positions(t, '&bbox=0,45,15,55'), { bbox: [0, 45, 15, 55] });
    const all = await positions(t);
    const pre = all.find((p) => p.callsign.length >= 3)!.callsign.slice(0, 3);
    compare(chunk, t, all.filter((p) => p.callsign.toUpperCase().startsWith(pre)), { callsign: pre });
  });

  it('a chunk revalidates with its ETag', async () => {
    const { etag, url } = await chunkAt(instants[0]!, 300);
    expect(etag).toMatch(/^"/);
    const again = await fetch(url, { headers: { 'If-None-Match': etag } });
    expect(again.status).toBe(304);
  });
});
