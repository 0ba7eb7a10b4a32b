// The URL hash of the two views: "#tracker" or "#tracker?replay=ID&video=V" shows the tracker dashboard;
// anything else is the flight map dashboard (whose hash is its own query string).

export function isTrackerHash(hash: string): boolean {
  return /^#tracker(?:$|[?/&])/.test(hash);
}

/** The tracker's parameters of a "#tracker?…" hash (empty for any other hash). */
export function trackerHashParams(hash: string): URLSearchParams {
  if (!isTrackerHash(hash)) return new URLSearchParams();
  return new URLSearchParams(hash.replace(/^#tracker\/?/, '').replace(/^[?&]/, ''));
}

export function trackerHash(replay: string | null): string {
  return replay ? `#tracker?replay=${encodeURIComponent(replay)}` : '#tracker';
}
