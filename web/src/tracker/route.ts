// The tracker dashboard's URL hash: "#tracker", "#tracker?replay=ID&video=V" or "#tracker?run=ID&frame=N"
// (src/route.ts gives every other hash to the runs or the flight dashboard).

export function isTrackerHash(hash: string): boolean {
  return /^#tracker(?:$|[?/&])/.test(hash);
}

/** The tracker's parameters of a "#tracker?…" hash (empty for any other hash). */
export function trackerHashParams(hash: string): URLSearchParams {
  if (!isTrackerHash(hash)) return new URLSearchParams();
  return new URLSearchParams(hash.replace(/^#tracker\/?/, '').replace(/^[?&]/, ''));
}

/** "#tracker?replay=ID&frame=N": a live replay, at frame N once it rests there. */
export function trackerHash(replay: string | null, frame?: number | null): string {
  if (!replay) return '#tracker';
  const f = frame !== undefined && frame !== null && Number.isInteger(frame) && frame >= 0 ? `&frame=${frame}` : '';
  return `#tracker?replay=${encodeURIComponent(replay)}${f}`;
}

/** "#tracker?run=ID&frame=N[&depth=frame]": a stored run opened at video frame N (depth=frame: per-frame depth range). */
export function trackerRunHash(run: string, frame?: number | null, depthPerFrame = false): string {
  const q = new URLSearchParams({ run });
  if (frame !== undefined && frame !== null && Number.isInteger(frame) && frame >= 0) q.set('frame', String(frame));
  if (depthPerFrame) q.set('depth', 'frame');
  return `#tracker?${q.toString()}`;
}

export interface TrackerRoute {
  replay: string | null;
  run: string | null;
  /** The video frame to show (a non-negative integer), or null when absent or malformed. */
  frame: number | null;
  video: string | null;
  /** Depth coloured with each frame's own range (`depth=frame`) instead of the video's one range. */
  depthPerFrame: boolean;
}

export function parseTrackerRoute(hash: string): TrackerRoute {
  const q = trackerHashParams(hash);
  const str = (k: string) => {
    const v = q.get(k);
    return v && v.trim() ? v.trim() : null;
  };
  const f = str('frame');
  const frame = f !== null && /^\d+$/.test(f) ? Number(f) : null;
  return {
    replay: str('replay'),
    run: str('run'),
    frame: frame !== null && Number.isSafeInteger(frame) ? frame : null,
    video: str('video'),
    depthPerFrame: q.get('depth') === 'frame',
  };
}
