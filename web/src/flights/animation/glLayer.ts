// The WebGL2 drawing of the animation (a MapLibre custom layer's body): per chunk, the segments between
// consecutive samples live on the GPU once (a float texture), bucketed by start time, so a frame draws
// only the segments that can touch [t - tail, t] in ONE draw per chunk; the vertex shader clips each
// segment to the tail window and to the chunk's own [0, duration) (neighbouring chunks share the
// bracketing segment; each draws its own part) and fades it by age. The aircraft are ONE draw of arrow
// glyphs at positions computed on the CPU in float64 (frame.ts). Both draws pull their data from textures
// by gl_VertexID through a shared index buffer (4 vertices, 2 triangles per item; no instancing): software
// WebGL (SwiftShader) pays a fixed cost per instance that made instanced tails 5-10x slower there, its
// vertex cache only works for indexed draws, and vertex pulling costs nothing extra on a real GPU. Every time the GPU sees is chunk-relative float32
// seconds (a few thousand at most), and every position is float32 metres relative to the chunk origin
// through a matrix composed in float64, so there is no float32 epoch jitter at any time of day.

import type { TsanChunk } from './tsan';
import type { Frame } from './frame';
import type { CompiledFilter } from './filter';
import { WORLD_M, lonToMercX, latToMercY } from './interp';
import { flightPasses } from './filter';
import { PALETTE, RAMPS, callsignPrefix, paletteTexels, prefixCategory, rampTexels } from './colors';
import type { ColorBy } from './types';

/** Floats per segment (3 RGBA32F texels): ta, tb, xa, ya | xb, yb, alt, speed | vrate, flight index, 0, 0. */
const SEG_FLOATS = 12;
/** Width of the data textures (texels). */
const DATA_TEX_W = 4096;
/** Width of the per-flight texture. */
const FLIGHT_TEX_W = 1024;
/** Floats per glyph (one RGBA32F texel): x, y, heading (rad; + 100 when selected), colour value. */
const GLYPH_FLOATS = 4;
/** Stand-in for an unknown value on the GPU (NaN compares unreliably in GLSL). */
export const UNKNOWN = -1e30;

const TAIL_VS = `#version 300 es
precision highp float;
uniform highp sampler2D u_segs;
uniform int u_first;
uniform mat4 u_m;
uniform float u_t, u_tail, u_dur, u_width;
uniform vec2 u_px;
uniform int u_colorBy;
uniform vec2 u_domain;
uniform vec3 u_alt;   // min, max, on
uniform vec4 u_bbox;  // west, south, east, north: absolute EPSG:3857 metres
uniform float u_bboxOn;
uniform vec2 u_origin;
uniform float u_world;
uniform sampler2D u_flights, u_ramp;
out vec4 v_color;

bool inBox(vec2 p) {
  float x = u_origin.x + p.x, y = u_origin.y + p.y;
  x = x - u_world * floor((x + 0.5 * u_world) / u_world);
  bool inX = u_bbox.x <= u_bbox.z ? (x >= u_bbox.x && x <= u_bbox.z) : (x >= u_bbox.x || x <= u_bbox.z);
  return inX && y >= u_bbox.y && y <= u_bbox.w;
}

vec4 seg(int i) { return texelFetch(u_segs, ivec2(i % ${DATA_TEX_W}, i / ${DATA_TEX_W}), 0); }

void main() {
  // Indexed: vertex 4s + corner (0, 1 at the older end, 2, 3 at the newer; triangles 0 1 2, 2 1 3).
  int s = u_first + gl_VertexID / 4;
  int vid = gl_VertexID % 4;
  vec4 a_t4 = seg(3 * s), b4 = seg(3 * s + 1), c4 = seg(3 * s + 2);
  vec4 a_xy = vec4(a_t4.zw, b4.xy);
  vec4 a_val = vec4(b4.zw, c4.xy);
  float ta = a_t4.x, tb = a_t4.y;
  float t0 = max(max(ta, u_t - u_tail), 0.0);
  float t1 = min(min(tb, u_t), u_dur);
  int idx = int(a_val.w + 0.5);
  vec4 fl = texelFetch(u_flights, ivec2(idx % ${FLIGHT_TEX_W}, idx / ${FLIGHT_TEX_W}), 0);
  float v = u_colorBy == 0 ? a_val.x : u_colorBy == 1 ? a_val.y : a_val.z;
  bool altOk = u_alt.z < 0.5 || (a_val.x >= u_alt.x && a_val.x <= u_alt.y);
  vec2 p0 = mix(a_xy.xy, a_xy.zw, (t0 - ta) / max(tb - ta, 1e-6));
  vec2 p1 = mix(a_xy.xy, a_xy.zw, (t1 - ta) / max(tb - ta, 1e-6));
  bool boxOk = u_bboxOn < 0.5 || (inBox(p0) && inBox(p1));
  if (!(t1 > t0) || fl.r < 0.5 || !altOk || !boxOk) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    v_color = vec4(0.0);
    return;
  }
  vec4 c0 = u_m * vec4(p0, 0.0, 1.0);
  vec4 c1 = u_m * vec4(p1, 0.0, 1.0);
  vec2 s0 = c0.xy / c0.w, s1 = c1.xy / c1.w;
  vec2 d = (s1 - s0) / u_px;
  float len = length(d);
  vec2 n = len > 1e-6 ? vec2(-d.y, d.x) / len : vec2(0.0, 1.0);
  bool sel = fl.g > 0.5;
  float w = (sel ? 2.2 : 1.0) * u_width * 0.5;
  bool head = vid >= 2;
  vec2 sp = head ? s1 : s0;
  float side = (vid == 0 || vid == 2) ? -1.0 : 1.0;
  gl_Position = vec4(sp + side * n * w * u_px, 0.0, 1.0);
  float age = u_t - (head ? t1 : t0);
  float alpha = u_tail > 0.0 ? clamp(1.0 - age / u_tail, 0.0, 1.0) : 1.0;
  vec3 rgb;
  if (u_colorBy == 3) {
    float cat = fl.b * 255.0;
    rgb = cat > 254.0 ? vec3(0.61, 0.64, 0.69) : texture(u_ramp, vec2((cat + 0.5) / ${PALETTE.length}.0, 0.5)).rgb;
  } else {
    rgb = v < -1e29 ? vec3(0.61, 0.64, 0.69) : texture(u_ramp, vec2(clamp((v - u_domain.x) / (u_domain.y - u_domain.x), 0.0, 1.0), 0.5)).rgb;
  }
  if (sel) { rgb = vec3(1.0); alpha = max(alpha, 0.35); }
  float a = alpha * 0.85;
  v_color = vec4(rgb * a, a);
}`;

const GLYPH_VS = `#version 300 es
precision highp float;
uniform highp sampler2D u_glyphs; // x, y, heading (+100 when selected), value
uniform mat4 u_m;
uniform vec2 u_px;
uniform float u_size;
uniform int u_colorBy;
uniform vec2 u_domain;
uniform sampler2D u_ramp;
out vec4 v_color;
// Nose, left wing tip, notch, right wing tip; indexed as triangles 0 1 2, 0 2 3.
const vec2 SHAPE[4] = vec2[4](vec2(0.0, 1.0), vec2(-0.62, -0.72), vec2(0.0, -0.35), vec2(0.62, -0.72));
void main() {
  int i = gl_VertexID / 4;
  vec4 g = texelFetch(u_glyphs, ivec2(i % ${DATA_TEX_W}, i / ${DATA_TEX_W}), 0);
  vec2 l = SHAPE[gl_VertexID % 4];
  bool sel = g.z > 50.0;
  float h = sel ? g.z - 100.0 : g.z;
  vec2 a_pos = g.xy;
  float size = u_size * (sel ? 1.8 : 1.0);
  vec2 fwd = vec2(sin(h), cos(h)), right = vec2(cos(h), -sin(h));
  vec2 off = (l.x * right + l.y * fwd) * size;
  vec4 c = u_m * vec4(a_pos, 0.0, 1.0);
  gl_Position = vec4(c.xy / c.w + off * u_px, 0.0, 1.0);
  float v = g.w;
  vec3 rgb;
  if (v < -1e29) rgb = vec3(0.61, 0.64, 0.69);
  else if (u_colorBy == 3) rgb = texture(u_ramp, vec2((v + 0.5) / ${PALETTE.length}.0, 0.5)).rgb;
  else rgb = texture(u_ramp, vec2(clamp((v - u_domain.x) / (u_domain.y - u_domain.x), 0.0, 1.0), 0.5)).rgb;
  if (sel) rgb = vec3(1.0);
  v_color = vec4(rgb, 1.0);
}`;

const FS = `#version 300 es
precision mediump float;
in vec4 v_color;
out vec4 o;
void main() { o = v_color; }`;

/** A chunk's GPU side. */
interface ChunkGpu {
  chunk: TsanChunk;
  segTex: WebGLTexture;
  segments: number;
  /** bucketStart[k]: first segment whose clipped start lies in second k or later (k = 0..nb). */
  bucketStart: Uint32Array;
  /** Longest clipped segment (s). */
  maxDur: number;
  flightTex: WebGLTexture;
  flightTexH: number;
  /** What the flight texture was last filled for. */
  flightKey: string;
  bytes: number;
}

function compile(gl: WebGL2RenderingContext, vs: string, fs: string): WebGLProgram {
  const p = gl.createProgram()!;
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]] as const) {
    const s = gl.createShader(type)!;
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(`animation shader: ${gl.getShaderInfoLog(s)}`);
    gl.attachShader(p, s);
  }
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(`animation program: ${gl.getProgramInfoLog(p)}`);
  return p;
}

/** Segments of a chunk, clipped to its span and bucketed by clipped start second (a counting sort). */
export function buildSegments(c: TsanChunk): { data: Float32Array; segments: number; bucketStart: Uint32Array; maxDur: number } {
  const dur = c.duration;
  const nb = Math.ceil(dur) + 1;
  const counts = new Uint32Array(nb + 1);
  let n = 0;
  const keep = (a: number) => {
    const ta = c.t[a]!, tb = c.t[a + 1]!;
    return tb > ta && tb > 0 && ta < dur;
  };
  const bucketOf = (ta: number) => Math.min(nb - 1, Math.floor(Math.max(ta, 0)));
  for (let f = 0; f < c.nFlights; f++) {
    const e = c.first[f]! + c.count[f]! - 1;
    for (let a = c.first[f]!; a < e; a++) if (keep(a)) counts[bucketOf(c.t[a]!) + 1]!++, n++;
  }
  const bucketStart = new Uint32Array(nb + 1);
  for (let k = 1; k <= nb; k++) bucketStart[k] = bucketStart[k - 1]! + counts[k]!;
  const fill = bucketStart.slice(0, nb);
  // Whole texture rows (3 texels per segment, DATA_TEX_W texels per row).
  const rows = Math.max(1, Math.ceil((3 * n) / DATA_TEX_W));
  const data = new Float32Array(rows * DATA_TEX_W * 4);
  let maxDur = 0;
  const val = (v: number) => (v === v ? v : UNKNOWN);
  for (let f = 0; f < c.nFlights; f++) {
    const e = c.first[f]! + c.count[f]! - 1;
    for (let a = c.first[f]!; a < e; a++) {
      if (!keep(a)) continue;
      const ta = c.t[a]!, tb = c.t[a + 1]!;
      const o = fill[bucketOf(ta)]!++ * SEG_FLOATS;
      let xb = c.x[a + 1]!;
      const dx = xb - c.x[a]!;
      if (Math.abs(dx) > WORLD_M / 2) xb += dx > 0 ? -WORLD_M : WORLD_M; // the short way across 180°
      data[o] = ta;
      data[o + 1] = tb;
      data[o + 2] = c.x[a]!;
      data[o + 3] = c.y[a]!;
      data[o + 4] = xb;
      data[o + 5] = c.y[a + 1]!;
      data[o + 6] = val(c.alt[a]!);
      data[o + 7] = val(c.speed[a]!);
      data[o + 8] = val(c.vrate[a]!);
      data[o + 9] = f;
      maxDur = Math.max(maxDur, Math.min(tb, dur) - Math.max(ta, 0));
    }
  }
  return { data, segments: n, bucketStart, maxDur };
}

/** Column-major 4×4 product a·b (float64). */
function mul(a: ArrayLike<number>, b: ArrayLike<number>): Float64Array {
  const o = new Float64Array(16);
  for (let c = 0; c < 4; c++)
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r]! * b[c * 4 + k]!;
      o[c * 4 + r] = s;
    }
  return o;
}

/**
 * The matrix from metres relative to (ox, oy) (EPSG:3857, y north) to clip space, given MapLibre's
 * matrix of unit Mercator coordinates (x east from 180°W, y south from the north edge), in float64.
 */
export function metresMatrix(unitMatrix: ArrayLike<number>, ox: number, oy: number): Float64Array {
  const a = new Float64Array(16);
  a[0] = 1 / WORLD_M;
  a[5] = -1 / WORLD_M;
  a[10] = 1;
  a[12] = ox / WORLD_M + 0.5;
  a[13] = 0.5 - oy / WORLD_M;
  a[15] = 1;
  return mul(unitMatrix, a);
}

export interface DrawParams {
  /** float64 Unix seconds. */
  t: number;
  tail: number;
  chunks: TsanChunk[];
  frame: Frame | null;
  /** Heading per frame aircraft (radians), computed by the owner. */
  headings: Float32Array | null;
  colorBy: ColorBy;
  filter: CompiledFilter;
  filterKey: string;
  selected: number | null;
  /** CSS pixel size of the canvas. */
  width: number;
  height: number;
  /** MapLibre's matrix of unit Mercator coordinates → clip. */
  unitMatrix: ArrayLike<number>;
}

/** A float texture of `texels` RGBA32F texels in rows of DATA_TEX_W. */
function floatTexture(gl: WebGL2RenderingContext, data: Float32Array | null, rows: number): WebGLTexture {
  const tex = gl.createTexture()!;
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, DATA_TEX_W, rows, 0, gl.RGBA, gl.FLOAT, data);
  for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
  return tex;
}

export class TrafficGl {
  private tailProg!: WebGLProgram;
  private glyphProg!: WebGLProgram;
  private readonly gpu = new Map<TsanChunk, ChunkGpu>();
  private glyphTex: WebGLTexture | null = null;
  private glyphRows = 0;
  private glyphData = new Float32Array(0);
  private rampTex!: WebGLTexture;
  private rampFor: ColorBy | null = null;
  private vao!: WebGLVertexArrayObject;
  /** Index buffers of quads (0 1 2, 2 1 3 per item) and glyphs (0 1 2, 0 2 3), grown on demand. */
  private readonly quadIdx: { buf: WebGLBuffer | null; items: number } = { buf: null, items: 0 };
  private readonly glyphIdx: { buf: WebGLBuffer | null; items: number } = { buf: null, items: 0 };
  private loc: Record<string, WebGLUniformLocation | null> = {};
  private gloc: Record<string, WebGLUniformLocation | null> = {};
  tailWidth = 2;
  glyphSize = 5;
  /** Segments drawn in the last frame (for tests and benchmarks). */
  lastSegments = 0;

  constructor(private readonly gl: WebGL2RenderingContext) {
    this.tailProg = compile(gl, TAIL_VS, FS);
    this.glyphProg = compile(gl, GLYPH_VS, FS);
    for (const u of ['u_segs', 'u_first', 'u_m', 'u_t', 'u_tail', 'u_dur', 'u_width', 'u_px', 'u_colorBy', 'u_domain', 'u_alt', 'u_bbox', 'u_bboxOn', 'u_origin', 'u_world', 'u_flights', 'u_ramp'])
      this.loc[u] = gl.getUniformLocation(this.tailProg, u);
    for (const u of ['u_glyphs', 'u_m', 'u_px', 'u_size', 'u_colorBy', 'u_domain', 'u_ramp']) this.gloc[u] = gl.getUniformLocation(this.glyphProg, u);
    this.rampTex = gl.createTexture()!;
    this.vao = gl.createVertexArray()!;
  }

  /** GPU bytes held for chunks. */
  gpuBytes(): number {
    let b = 0;
    for (const g of this.gpu.values()) b += g.bytes;
    return b;
  }

  /** Frees the GPU side of chunks no longer in `keep`. */
  retain(keep: TsanChunk[]): void {
    const set = new Set(keep);
    for (const [c, g] of this.gpu) {
      if (set.has(c)) continue;
      this.gl.deleteTexture(g.segTex);
      this.gl.deleteTexture(g.flightTex);
      this.gpu.delete(c);
    }
  }

  private upload(c: TsanChunk): ChunkGpu {
    const gl = this.gl;
    const s = buildSegments(c);
    const rows = s.data.length / (4 * DATA_TEX_W);
    const segTex = floatTexture(gl, s.data, rows);
    const tex = gl.createTexture()!;
    const h = Math.max(1, Math.ceil(c.nFlights / FLIGHT_TEX_W));
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, FLIGHT_TEX_W, h, 0, gl.RGBA, gl.UNSIGNED_BYTE, null);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    const g: ChunkGpu = {
      chunk: c, segTex, segments: s.segments, bucketStart: s.bucketStart, maxDur: s.maxDur, flightTex: tex, flightTexH: h, flightKey: '',
      bytes: s.data.byteLength + FLIGHT_TEX_W * h * 4,
    };
    this.gpu.set(c, g);
    return g;
  }

  /** Per flight: passes the flight-level filters (callsign, icao24), selected, callsign category (255 = none). */
  private fillFlights(g: ChunkGpu, filter: CompiledFilter, selected: number | null) {
    const c = g.chunk;
    const px = new Uint8Array(FLIGHT_TEX_W * g.flightTexH * 4);
    for (let f = 0; f < c.nFlights; f++) {
      const cs = c.callsign[f]!;
      px[4 * f] = !filter.byFlight || flightPasses(filter, cs, c.icao24[f]!) ? 255 : 0;
      px[4 * f + 1] = selected !== null && c.flightId[f] === selected ? 255 : 0;
      const cat = prefixCategory(callsignPrefix(cs));
      px[4 * f + 2] = cat < 0 ? 255 : cat;
      px[4 * f + 3] = 255;
    }
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, g.flightTex);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, FLIGHT_TEX_W, g.flightTexH, gl.RGBA, gl.UNSIGNED_BYTE, px);
  }

  private ramp(colorBy: ColorBy) {
    const gl = this.gl;
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, this.rampTex);
    if (this.rampFor !== colorBy) {
      this.rampFor = colorBy;
      const px = colorBy === 'callsign' ? paletteTexels() : rampTexels(RAMPS[colorBy]);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, 256, 1, 0, gl.RGBA, gl.UNSIGNED_BYTE, px);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, colorBy === 'callsign' ? gl.NEAREST : gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, colorBy === 'callsign' ? gl.NEAREST : gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    }
  }

  /** Binds (in the bound VAO) an index buffer covering `items` items of `pattern`. */
  private bindIndices(ib: { buf: WebGLBuffer | null; items: number }, pattern: readonly number[], items: number) {
    const gl = this.gl;
    if (!ib.buf || ib.items < items) {
      if (ib.buf) gl.deleteBuffer(ib.buf);
      const n = Math.max(1024, Math.ceil(items * 1.25));
      const idx = new Uint32Array(6 * n);
      for (let i = 0; i < n; i++) for (let k = 0; k < 6; k++) idx[6 * i + k] = 4 * i + pattern[k]!;
      ib.buf = gl.createBuffer()!;
      ib.items = n;
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib.buf);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, idx, gl.STATIC_DRAW);
    } else {
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib.buf);
    }
  }

  private static domain(colorBy: ColorBy): [number, number] {
    if (colorBy === 'callsign') return [0, PALETTE.length];
    const s = RAMPS[colorBy].stops;
    return [s[0]![0], s[s.length - 1]![0]];
  }

  draw(p: DrawParams): void {
    const gl = this.gl;
    const colorMode = ['altitude', 'speed', 'vrate', 'callsign'].indexOf(p.colorBy);
    const dom = TrafficGl.domain(p.colorBy);
    const px: [number, number] = [2 / Math.max(1, p.width), 2 / Math.max(1, p.height)];
    gl.bindVertexArray(this.vao);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    gl.disable(gl.DEPTH_TEST);
    gl.disable(gl.CULL_FACE);
    this.ramp(p.colorBy);
    const selKey = `${p.filterKey}|${p.selected}`;
    this.lastSegments = 0;

    // ---- tails: one draw per chunk overlapping [t - tail, t], 4 vertices per segment
    if (p.tail > 0) {
      gl.useProgram(this.tailProg);
      const L = this.loc;
      gl.uniform1f(L.u_tail!, p.tail);
      gl.uniform1f(L.u_width!, this.tailWidth);
      gl.uniform2f(L.u_px!, px[0], px[1]);
      gl.uniform1i(L.u_colorBy!, colorMode);
      gl.uniform2f(L.u_domain!, dom[0], dom[1]);
      const f = p.filter;
      gl.uniform3f(L.u_alt!, f.hasAlt ? Math.max(f.altMin, -3e38) : 0, f.hasAlt ? Math.min(f.altMax, 3e38) : 0, f.hasAlt ? 1 : 0);
      if (f.bbox) {
        const [w, s, e, n] = f.bbox;
        gl.uniform4f(L.u_bbox!, lonToMercX(w), latToMercY(Math.max(-85.05, s)), lonToMercX(e), latToMercY(Math.min(85.05, n)));
      }
      gl.uniform1f(L.u_bboxOn!, f.bbox ? 1 : 0);
      gl.uniform1f(L.u_world!, WORLD_M);
      gl.uniform1i(L.u_flights!, 0);
      gl.uniform1i(L.u_ramp!, 1);
      gl.uniform1i(L.u_segs!, 2);
      for (const c of p.chunks) {
        if (c.tStart > p.t || c.tStart + c.duration <= p.t - p.tail) continue;
        const g = this.gpu.get(c) ?? this.upload(c);
        if (g.flightKey !== selKey) {
          this.fillFlights(g, p.filter, p.selected);
          g.flightKey = selKey;
        }
        const tRel = p.t - c.tStart; // float64, then a small float32
        const nb = g.bucketStart.length - 1;
        const lo = g.bucketStart[Math.max(0, Math.min(nb, Math.floor(tRel - p.tail - g.maxDur)))]!;
        const hi = g.bucketStart[Math.max(0, Math.min(nb, Math.floor(tRel) + 1))]!;
        if (hi <= lo) continue;
        gl.uniformMatrix4fv(L.u_m!, false, Float32Array.from(metresMatrix(p.unitMatrix, c.originX, c.originY)));
        gl.uniform1f(L.u_t!, tRel);
        gl.uniform1f(L.u_dur!, c.duration);
        gl.uniform2f(L.u_origin!, c.originX, c.originY);
        gl.uniform1i(L.u_first!, lo);
        gl.activeTexture(gl.TEXTURE0);
        gl.bindTexture(gl.TEXTURE_2D, g.flightTex);
        gl.activeTexture(gl.TEXTURE2);
        gl.bindTexture(gl.TEXTURE_2D, g.segTex);
        this.bindIndices(this.quadIdx, [0, 1, 2, 2, 1, 3], hi - lo);
        gl.drawElements(gl.TRIANGLES, 6 * (hi - lo), gl.UNSIGNED_INT, 0);
        this.lastSegments += hi - lo;
      }
    }

    // ---- aircraft: one draw of glyphs, 4 vertices each
    const fr = p.frame;
    if (fr && fr.n > 0 && p.headings) {
      const c = fr.chunk;
      const rows = Math.ceil(fr.n / DATA_TEX_W);
      if (this.glyphData.length < rows * DATA_TEX_W * GLYPH_FLOATS) this.glyphData = new Float32Array(Math.ceil(rows * 1.25) * DATA_TEX_W * GLYPH_FLOATS);
      const d = this.glyphData;
      let selIndex = -1;
      for (let i = 0; i < fr.n; i++) {
        const o = i * GLYPH_FLOATS, f = fr.flight[i]!;
        const sel = p.selected !== null && c.flightId[f] === p.selected;
        d[o] = fr.x[i]!;
        d[o + 1] = fr.y[i]!;
        d[o + 2] = p.headings[i]! + (sel ? 100 : 0);
        let v: number;
        if (colorMode === 3) {
          const cat = prefixCategory(callsignPrefix(c.callsign[f]!));
          v = cat < 0 ? UNKNOWN : cat;
        } else {
          v = colorMode === 0 ? fr.alt[i]! : colorMode === 1 ? fr.speed[i]! : fr.vrate[i]!;
          if (v !== v) v = UNKNOWN;
        }
        d[o + 3] = v;
        if (sel) selIndex = i;
      }
      // The selected aircraft is drawn last, on top.
      if (selIndex >= 0 && selIndex !== fr.n - 1) {
        const a = selIndex * GLYPH_FLOATS, b = (fr.n - 1) * GLYPH_FLOATS;
        for (let k = 0; k < GLYPH_FLOATS; k++) {
          const tmp = d[a + k]!;
          d[a + k] = d[b + k]!;
          d[b + k] = tmp;
        }
      }
      gl.activeTexture(gl.TEXTURE2);
      const capRows = d.length / (DATA_TEX_W * GLYPH_FLOATS);
      if (!this.glyphTex || this.glyphRows < capRows) {
        if (this.glyphTex) gl.deleteTexture(this.glyphTex);
        this.glyphTex = floatTexture(gl, null, capRows);
        this.glyphRows = capRows;
      }
      gl.bindTexture(gl.TEXTURE_2D, this.glyphTex);
      gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, DATA_TEX_W, rows, gl.RGBA, gl.FLOAT, d, 0);
      gl.useProgram(this.glyphProg);
      const G = this.gloc;
      gl.uniformMatrix4fv(G.u_m!, false, Float32Array.from(metresMatrix(p.unitMatrix, c.originX, c.originY)));
      gl.uniform2f(G.u_px!, px[0], px[1]);
      gl.uniform1f(G.u_size!, this.glyphSize);
      gl.uniform1i(G.u_colorBy!, colorMode);
      gl.uniform2f(G.u_domain!, dom[0], dom[1]);
      gl.uniform1i(G.u_ramp!, 1);
      gl.uniform1i(G.u_glyphs!, 2);
      this.bindIndices(this.glyphIdx, [0, 1, 2, 0, 2, 3], fr.n);
      gl.drawElements(gl.TRIANGLES, 6 * fr.n, gl.UNSIGNED_INT, 0);
    }
    gl.activeTexture(gl.TEXTURE0);
    gl.bindVertexArray(null);
  }

  destroy(): void {
    this.retain([]);
    const gl = this.gl;
    if (this.glyphTex) gl.deleteTexture(this.glyphTex);
    for (const ib of [this.quadIdx, this.glyphIdx]) if (ib.buf) gl.deleteBuffer(ib.buf);
    gl.deleteTexture(this.rampTex);
    gl.deleteVertexArray(this.vao);
    gl.deleteProgram(this.tailProg);
    gl.deleteProgram(this.glyphProg);
  }
}
