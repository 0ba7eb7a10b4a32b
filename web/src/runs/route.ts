// The runs dashboard's URL hash: "#runs" or "#runs?sweep=ID&sel=r1,r2&metric=track_share&method=pca&frame=12".

export function isRunsHash(hash: string): boolean {
  return /^#runs(?:$|[?/&])/.test(hash);
}

export interface RunsRoute {
  sweep: string | null;
  sel: string[];
  metric: string | null;
  method: string | null;
  frame: number | null;
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
  };
}

export function runsHash(r: Partial<RunsRoute>): string {
  const q = new URLSearchParams();
  if (r.sweep) q.set('sweep', r.sweep);
  if (r.sel && r.sel.length) q.set('sel', r.sel.join(','));
  if (r.metric) q.set('metric', r.metric);
  if (r.method) q.set('method', r.method);
  if (r.frame !== null && r.frame !== undefined) q.set('frame', String(r.frame));
  const s = q.toString().replace(/%2C/g, ',');
  return s ? `#runs?${s}` : '#runs';
}
