// The runs dashboard's URL hash: "#runs" or
// "#runs?sweep=ID&sel=r1,r2&metric=track_share&method=tsne&perp=5&pc=param:sigma:0.5:2&frame=12".

export function isRunsHash(hash: string): boolean {
  return /^#runs(?:$|[?/&])/.test(hash);
}

export interface RunsRoute {
  sweep: string | null;
  sel: string[];
  metric: string | null;
  method: string | null;
  frame: number | null;
  /** The t-SNE perplexity asked for (`perp`). */
  perp: number | null;
  /** The parallel-coordinate filters (`pc=axis:lo:hi;axis:lo:hi`), by axis key. */
  pc: [string, [number, number]][];
}

/** "param:sigma:0.5:2;metric:x:1:3" → [["param:sigma", [0.5, 2]], …]: the key is all but the last two fields. */
export function parsePcFilters(text: string | null): [string, [number, number]][] {
  const out: [string, [number, number]][] = [];
  for (const part of (text ?? '').split(';')) {
    const f = part.split(':');
    if (f.length < 3) continue;
    const lo = Number(f[f.length - 2]);
    const hi = Number(f[f.length - 1]);
    const key = f.slice(0, -2).join(':');
    if (key && Number.isFinite(lo) && Number.isFinite(hi) && lo <= hi) out.push([key, [lo, hi]]);
  }
  return out;
}

export function formatPcFilters(pc: readonly [string, [number, number]][]): string {
  return pc.map(([k, [lo, hi]]) => `${k}:${+lo.toPrecision(6)}:${+hi.toPrecision(6)}`).join(';');
}

export function parseRunsHash(hash: string): RunsRoute {
  const q = isRunsHash(hash) ? new URLSearchParams(hash.replace(/^#runs\/?/, '').replace(/^[?&]/, '')) : new URLSearchParams();
  const frame = Number(q.get('frame'));
  return {
    sweep: q.get('sweep') || null,
    sel: (q.get('sel') ?? '').split(',').map((s) => s.trim()).filter(Boolean),
    metric: q.get('metric') || null,
    method: q.get('method') || null,
    frame: q.has('frame') && Number.isInteger(frame) && frame >= 0 ? frame : null,
    perp: q.has('perp') && Number.isFinite(Number(q.get('perp'))) && Number(q.get('perp')) > 0 ? Number(q.get('perp')) : null,
    pc: parsePcFilters(q.get('pc')),
  };
}

export function runsHash(r: Partial<RunsRoute>): string {
  const q = new URLSearchParams();
  if (r.sweep) q.set('sweep', r.sweep);
  if (r.sel && r.sel.length) q.set('sel', r.sel.join(','));
  if (r.metric) q.set('metric', r.metric);
  if (r.method) q.set('method', r.method);
  if (r.frame !== null && r.frame !== undefined) q.set('frame', String(r.frame));
  if (r.perp !== null && r.perp !== undefined) q.set('perp', String(r.perp));
  if (r.pc && r.pc.length) q.set('pc', formatPcFilters(r.pc));
  const s = q.toString().replace(/%2C/g, ',').replace(/%3A/g, ':').replace(/%3B/g, ';');
  return s ? `#runs?${s}` : '#runs';
}
