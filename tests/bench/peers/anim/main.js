// The animation benchmark page: one MapLibre map (1280×720, a plain background, no network) and one of
// two layers fed the SAME seeded synthetic trips, chosen by the query string:
//   ?mode=trailscope&n=25000&tail=120   TrailScope's layer (web/src/flights/animation): TSAN chunks of
//                                       300 s, encoded in the page from the trips before the clock starts
//                                       (the server's part), served to the layer through its fetch option
//   ?mode=deckchunks&n=25000&tail=120  the same chunks and CPU positions as TrailScope's layer, drawn with
//                                       deck.gl layers instead of the custom layer: one TripsLayer per
//                                       chunk (binary attributes, chunk-relative times) and a
//                                       ScatterplotLayer of the aircraft (the alternative to the custom layer)
//   ?mode=empty                         the map alone (the frame loop's ceiling)
//   ?mode=trips&n=25000&tail=120        deck.gl's TripsLayer fed the usual way: every trip loaded at once
//                                       (path + timestamps, relative seconds), currentTime and trailLength,
//                                       through @deck.gl/mapbox's MapboxOverlay interleaved with MapLibre
// window.benchRun({seconds}) plays the clock at 10× (see below) and resolves to
//   {mode, n, tail, samples, ttff_ms, frames, seconds, fps, heap_mb, drawn}.
import * as maplibregl from 'maplibre-gl';
import workerUrl from 'maplibre-gl/dist/maplibre-gl-worker.mjs?url';
import 'maplibre-gl/dist/maplibre-gl.css';
import { TrafficAnimation } from '../../../../web/src/flights/animation';
import { MapboxOverlay } from '@deck.gl/mapbox';
import { TripsLayer } from '@deck.gl/geo-layers';
import { ScatterplotLayer } from '@deck.gl/layers';
import { decodeTsan } from '../../../../web/src/flights/animation/tsan';
import { frameAt } from '../../../../web/src/flights/animation/frame';
import { compileFilter } from '../../../../web/src/flights/animation/filter';
import { mercXToLon, mercYToLat } from '../../../../web/src/flights/animation/interp';

maplibregl.setWorkerUrl(workerUrl);

const q = new URLSearchParams(location.search);
const MODE = q.get('mode') ?? 'trailscope';
const N = Number(q.get('n') ?? 5000);
const TAIL = Number(q.get('tail') ?? 120);
const STEP = 20; // seconds between samples
const SPAN = 1500; // seconds every trip covers: [T0 - STEP, T0 + SPAN]
const CHUNK = 300;
// 20:00 UTC on 2018-01-01: late in a day, where float32 epoch seconds are 8 s apart.
const T0 = 1514764800 + 72000;
const PLAY_FROM = T0 + 600;
const SPEED = 10;

// ---------- seeded trips (mulberry32), columns of N × P samples ----------
function rng(seed) {
  return () => {
    seed |= 0;
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
const P = Math.floor(SPAN / STEP) + 2;
function makeTrips(n) {
  const r = rng(20180101);
  const t = new Float64Array(n * P), lon = new Float32Array(n * P), lat = new Float32Array(n * P);
  const alt = new Float32Array(n * P), speed = new Float32Array(n * P), track = new Float32Array(n * P), vrate = new Float32Array(n * P);
  for (let i = 0; i < n; i++) {
    const phase = r() * STEP;
    let x = -10 + r() * 40, y = 36 + r() * 24, h = r() * 360, a = 3000 + r() * 9000;
    const v = 180 + r() * 70, turn = (r() - 0.5) * 0.3, vr = (r() - 0.5) * 10;
    for (let k = 0; k < P; k++) {
      const o = i * P + k;
      t[o] = T0 - phase + k * STEP;
      lon[o] = x; lat[o] = y; alt[o] = a; speed[o] = v; track[o] = h; vrate[o] = vr;
      const d = v * STEP, hr = (h * Math.PI) / 180;
      y += (d * Math.cos(hr)) / 111320;
      x += (d * Math.sin(hr)) / (111320 * Math.cos((y * Math.PI) / 180));
      h = (h + turn * STEP + 360) % 360;
      a = Math.max(300, Math.min(12500, a + vr * STEP));
    }
  }
  return { n, t, lon, lat, alt, speed, track, vrate };
}

// ---------- TSAN encoding of a chunk (proto/animation_chunks.md), the server's part ----------
const R = 6378137;
const mx = (l) => (R * l * Math.PI) / 180;
const my = (l) => R * Math.asinh(Math.tan((l * Math.PI) / 180));
function encodeChunk(tr, s, d, originLon, originLat) {
  const ranges = [];
  let total = 0;
  for (let i = 0; i < tr.n; i++) {
    const b = i * P, e = b + P - 1;
    if (!(tr.t[b] < s + d && tr.t[e] >= s)) continue;
    let k0 = b; while (k0 < e && tr.t[k0 + 1] < s) k0++; // last before s (or first)
    if (tr.t[k0] >= s) k0 = b;
    let k1 = k0; while (k1 < e && tr.t[k1] < s + d) k1++; // first at or after s + d (or last)
    ranges.push(i, k0, k1 - k0 + 1);
    total += k1 - k0 + 1;
  }
  const F = ranges.length / 3, Np = total, p8 = (v) => (v + 7) & ~7, C = p8(4 * Np);
  const strBytes = 7 * F; // callsigns "TSxxxxx"
  const size = 64 + 24 * F + 7 * C + p8(Np) + p8(strBytes);
  const buf = new ArrayBuffer(size), dv = new DataView(buf), u8 = new Uint8Array(buf);
  u8.set([84, 83, 65, 78]);
  dv.setUint16(4, 1, true);
  dv.setFloat64(8, s, true);
  dv.setFloat64(16, d, true);
  const ox = mx(originLon), oy = my(originLat);
  dv.setFloat64(24, ox, true);
  dv.setFloat64(32, oy, true);
  dv.setUint32(40, F, true);
  dv.setUint32(44, Np, true);
  dv.setUint32(48, strBytes, true);
  const table = new Uint32Array(buf, 64, 6 * F);
  const col = (c) => new Float32Array(buf, 64 + 24 * F + c * C, Np);
  const [ct, cx, cy, ca, cs, ck, cv] = [0, 1, 2, 3, 4, 5, 6].map(col);
  const strAt = 64 + 24 * F + 7 * C + p8(Np);
  const prefixes = ['DLH', 'BAW', 'AFR', 'RYR', 'EZY', 'KLM', 'SWR', 'IBE', 'THY', 'SAS', 'AUA', 'TAP', 'WZZ', 'VLG'];
  let k = 0;
  for (let f = 0; f < F; f++) {
    const i = ranges[3 * f], k0 = ranges[3 * f + 1], cnt = ranges[3 * f + 2];
    table.set([i, k, cnt, (0x400000 + i) & 0xffffff, 7 * f, 7], 6 * f);
    const cs7 = prefixes[i % prefixes.length] + String(i % 10000).padStart(4, '0');
    for (let c = 0; c < 7; c++) u8[strAt + 7 * f + c] = cs7.charCodeAt(c);
    for (let j = 0; j < cnt; j++, k++) {
      const o = k0 + j;
      ct[k] = tr.t[o] - s; cx[k] = mx(tr.lon[o]) - ox; cy[k] = my(tr.lat[o]) - oy;
      ca[k] = tr.alt[o]; cs[k] = tr.speed[o]; ck[k] = tr.track[o]; cv[k] = tr.vrate[o];
    }
  }
  return buf;
}

// ---------- the page ----------
const map = new maplibregl.Map({
  container: 'map',
  style: { version: 8, sources: {}, layers: [{ id: 'bg', type: 'background', paint: { 'background-color': '#0b0f14' } }] },
  center: [12, 48.5],
  zoom: Number(q.get('zoom') ?? 3.55),
  renderWorldCopies: false,
  attributionControl: false,
  fadeDuration: 0,
});
const loaded = new Promise((r) => map.once('load', r));
window.map = map;
// @deck.gl/mapbox 9.4 reads MapLibre's private `map.transform` (MapLibre <= 5); MapLibre 6 keeps the
// camera's transform at `map._camera.transform`. This shim gives the overlay what it reads, unchanged.
if (!('transform' in map)) Object.defineProperty(map, 'transform', { get: () => map._camera.transform });

function altColor(a) {
  const w = Math.min(1, Math.max(0, a / 12500));
  return [Math.round(61 + 183 * w), Math.round(220 - 106 * w), Math.round(132 + 50 * w)];
}

window.benchRun = async ({ seconds = 6 } = {}) => {
  await loaded;
  const trips = makeTrips(N);
  let t = PLAY_FROM;
  let frames = 0, drawn = 0;
  let first = null;
  let ttff = NaN;
  let tick;
  let stop = false;
  if (MODE === 'trailscope') {
    const chunks = new Map();
    for (let s = Math.floor((T0 - STEP) / CHUNK) * CHUNK; s < T0 + SPAN; s += CHUNK) chunks.set(s, encodeChunk(trips, s, CHUNK, 10, 48));
    const fetchChunk = async (url) => {
      const s = Number(new URL(url, location.href).searchParams.get('t'));
      const b = chunks.get(s);
      return b ? new Response(b.slice(0), { status: 200 }) : new Response('{"error":"not_found","detail":"no chunk"}', { status: 404 });
    };
    const t0 = performance.now();
    const anim = new TrafficAnimation(map, 'bench', { chunkSeconds: CHUNK, tailSeconds: TAIL, fetch: fetchChunk, span: [T0 - STEP, T0 + SPAN] });
    window.anim = anim;
    first = new Promise((resolve) => anim.onStats((s) => {
      if (s.aircraft > 0 && Number.isNaN(ttff)) {
        ttff = performance.now() - t0;
        resolve();
      }
      drawn = s.aircraft;
    }));
    anim.setTime(t);
    await anim.ready(t);
    map.triggerRepaint();
    tick = (dt) => {
      t += dt * SPEED;
      anim.setTime(t);
    };
  } else if (MODE === 'deckchunks') {
    const encoded = [];
    for (let s = Math.floor((T0 - STEP) / CHUNK) * CHUNK; s < T0 + SPAN; s += CHUNK) encoded.push(encodeChunk(trips, s, CHUNK, 10, 48));
    const t0 = performance.now();
    // What the cache would hold: the decoded chunks (all of them here: the window is 25 minutes).
    const chunks = encoded.map((b) => decodeTsan(b.slice(0)));
    const filter = compileFilter({});
    const tripsData = new Map();
    const tripsOf = (c) => {
      let d = tripsData.get(c);
      if (!d) {
        const path = new Float64Array(2 * c.nSamples);
        for (let i = 0; i < c.nSamples; i++) {
          path[2 * i] = mercXToLon(c.originX + c.x[i]);
          path[2 * i + 1] = mercYToLat(c.originY + c.y[i]);
        }
        const colors = new Uint8Array(4 * c.nSamples);
        for (let i = 0; i < c.nSamples; i++) colors.set([...altColor(c.alt[i]), 255], 4 * i);
        d = { length: c.nFlights, startIndices: c.first, attributes: { getPath: { value: path, size: 2 }, getTimestamps: { value: c.t, size: 1 }, getColor: { value: colors, size: 4, normalized: true } } };
        tripsData.set(c, d);
      }
      return d;
    };
    const layers = (tt) => {
      const out = [];
      for (const c of chunks) {
        if (c.tStart > tt || c.tStart + c.duration <= tt - TAIL) continue;
        out.push(new TripsLayer({ id: `trips-${c.tStart}`, data: tripsOf(c), _pathType: 'open', widthMinPixels: 2, fadeTrail: true, trailLength: TAIL, currentTime: tt - c.tStart, capRounded: false, jointRounded: false }));
      }
      const c = chunks.find((x) => x.tStart <= tt && tt < x.tStart + x.duration);
      const fr = frameAt(c, tt, filter);
      const pos = new Float64Array(2 * fr.n);
      for (let i = 0; i < fr.n; i++) {
        pos[2 * i] = fr.lon[i];
        pos[2 * i + 1] = fr.lat[i];
      }
      drawn = fr.n;
      out.push(new ScatterplotLayer({ id: 'aircraft', data: { length: fr.n, attributes: { getPosition: { value: pos, size: 2 } } }, getFillColor: [167, 139, 250], radiusMinPixels: 3, radiusMaxPixels: 3 }));
      return out;
    };
    let resolveFirst;
    first = new Promise((r) => (resolveFirst = r));
    const overlay = new MapboxOverlay({
      interleaved: true,
      layers: layers(t),
      onAfterRender: () => {
        if (Number.isNaN(ttff)) {
          ttff = performance.now() - t0;
          resolveFirst();
        }
      },
    });
    map.addControl(overlay);
    tick = (dt) => {
      t += dt * SPEED;
      overlay.setProps({ layers: layers(t) });
    };
  } else if (MODE === 'empty') {
    // The map alone: what the browser's frame loop gives with no layer (a ceiling for both).
    first = Promise.resolve();
    ttff = 0;
    tick = (dt) => {
      t += dt * SPEED;
    };
  } else {
    const t0 = performance.now();
    const data = new Array(trips.n);
    for (let i = 0; i < trips.n; i++) {
      const path = new Float64Array(2 * P), ts = new Array(P);
      for (let k = 0; k < P; k++) {
        path[2 * k] = trips.lon[i * P + k];
        path[2 * k + 1] = trips.lat[i * P + k];
        ts[k] = trips.t[i * P + k] - T0; // seconds relative to the data's start, the usual way
      }
      data[i] = { path, timestamps: ts, color: altColor(trips.alt[i * P]) };
    }
    const layer = (ct) =>
      new TripsLayer({
        id: 'trips', data, getPath: (d) => d.path, positionFormat: 'XY', getTimestamps: (d) => d.timestamps,
        getColor: (d) => d.color, widthMinPixels: 2, fadeTrail: true, trailLength: TAIL, currentTime: ct,
        capRounded: false, jointRounded: false,
      });
    let resolveFirst;
    first = new Promise((r) => (resolveFirst = r));
    const overlay = new MapboxOverlay({
      interleaved: true,
      layers: [layer(t - T0)],
      onAfterRender: () => {
        if (Number.isNaN(ttff)) {
          ttff = performance.now() - t0;
          resolveFirst();
        }
      },
    });
    map.addControl(overlay);
    drawn = trips.n;
    tick = (dt) => {
      t += dt * SPEED;
      overlay.setProps({ layers: [layer(t - T0)] });
    };
  }
  await first;
  // Play: every frame advances the clock by the wall time since the last one, at 10x. Frames/s is
  // measured between the first and the last rendered frame of the run, which lasts `seconds` and at least
  // three frames (at most 100 s), so slow layers are not rounded to a frame or two. A layer that draws
  // fewer than two frames in 100 s gets the upper bound 1 / (time since its first frame), marked so.
  const stamps = [];
  map.on('render', () => {
    if (!stop) stamps.push(performance.now());
  });
  await new Promise((resolve) => {
    let last = performance.now();
    const start = last;
    const loop = () => {
      const now = performance.now();
      if ((now - start >= seconds * 1000 && stamps.length >= 3) || now - start >= 100_000) {
        stop = true;
        resolve();
        return;
      }
      tick((now - last) / 1000);
      last = now;
      map.triggerRepaint();
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
  });
  frames = stamps.length;
  const upper = stamps.length < 2;
  const secondsRun = upper ? (performance.now() - (stamps[0] ?? performance.now())) / 1000 : (stamps[stamps.length - 1] - stamps[0]) / 1000;
  const heap = performance.memory ? performance.memory.usedJSHeapSize / 2 ** 20 : NaN;
  return {
    mode: MODE, n: N, tail: TAIL, samples: N * P, ttff_ms: Math.round(ttff), frames, seconds: Math.round(secondsRun * 100) / 100,
    fps: upper ? 1 / secondsRun : (frames - 1) / secondsRun, heap_mb: Math.round(heap * 10) / 10, drawn,
    ...(upper ? { fps_bound: 'upper' } : {}),
  };
};
window.benchReady = true;
