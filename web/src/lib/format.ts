// Number, time and unit formatting for the dashboard. All times are shown in UTC, as in aviation.

export const FT_PER_M = 1 / 0.3048;
export const KT_PER_MS = 3600 / 1852;

const intFmt = new Intl.NumberFormat('en-US', { maximumFractionDigits: 0 });

/** 11043 → "11,043"; non-finite → "–". */
export function formatInt(n: number | null | undefined): string {
  return n === null || n === undefined || !Number.isFinite(n) ? '–' : intFmt.format(Math.round(n));
}

/** 950 → "950", 12_700 → "12.7k", 15_000_000 → "15.0M". */
export function formatCompact(n: number | null | undefined): string {
  if (n === null || n === undefined || !Number.isFinite(n)) return '–';
  const a = Math.abs(n);
  if (a < 1000) return intFmt.format(Math.round(n));
  const [div, suffix] = a < 1e6 ? [1e3, 'k'] : a < 1e9 ? [1e6, 'M'] : [1e9, 'G'];
  const v = n / div;
  // Keep three significant digits, and roll 999.95k over to 1.00M.
  if (Math.abs(v) >= 999.5 && suffix !== 'G') return formatCompact(Math.sign(n) * div * 1000);
  return `${v.toFixed(Math.abs(v) < 10 ? 2 : Math.abs(v) < 100 ? 1 : 0)}${suffix}`;
}

function iso(ts: number): string {
  return new Date(Math.round(ts) * 1000).toISOString();
}

/** Unix seconds → "2018-01-01 06:15:00". */
export function formatUtcSeconds(ts: number): string {
  return Number.isFinite(ts) ? iso(ts).slice(0, 19).replace('T', ' ') : '–';
}

/** Unix seconds → "2018-01-01 06:15". */
export function formatUtc(ts: number): string {
  return Number.isFinite(ts) ? iso(ts).slice(0, 16).replace('T', ' ') : '–';
}

/** Unix seconds → "06:15". */
export function formatUtcTime(ts: number): string {
  return Number.isFinite(ts) ? iso(ts).slice(11, 16) : '–';
}

/** Seconds → "2 d 3 h", "6 h 15 min", "45 min", "12 s". */
export function formatDuration(seconds: number): string {
  if (!Number.isFinite(seconds) || seconds < 0) return '–';
  const s = Math.round(seconds);
  if (s < 60) return `${s} s`;
  const m = Math.round(s / 60);
  if (m < 60) return `${m} min`;
  const h = Math.floor(m / 60);
  const rm = m % 60;
  if (h < 48) return rm ? `${h} h ${rm} min` : `${h} h`;
  const d = Math.floor(h / 24);
  const rh = h % 24;
  return rh ? `${d} d ${rh} h` : `${d} d`;
}

/** Seconds → "1:26" (hours:minutes), for dense tables. */
export function formatHoursMinutes(seconds: number): string {
  if (!Number.isFinite(seconds) || seconds < 0) return '–';
  const m = Math.round(seconds / 60);
  return `${Math.floor(m / 60)}:${String(m % 60).padStart(2, '0')}`;
}

/** A half-open window [t0, t1) → "2018-01-01 06:00 → 12:00 UTC" (date repeated only when it changes). */
export function formatWindow(t0: number, t1: number): string {
  const a = formatUtc(t0);
  const b = formatUtc(t1);
  const sameDay = a.slice(0, 10) === b.slice(0, 10);
  return `${a} → ${sameDay ? b.slice(11) : b} UTC`;
}

/** Metres → "37,000 ft" (rounded to 100 ft). */
export function formatAltitude(m: number | null | undefined): string {
  if (m === null || m === undefined || !Number.isFinite(m)) return '–';
  return `${formatInt(Math.round((m * FT_PER_M) / 100) * 100)} ft`;
}

/** Metres → flight level "FL370" (hundreds of feet). */
export function formatFlightLevel(m: number | null | undefined): string {
  if (m === null || m === undefined || !Number.isFinite(m)) return '–';
  return `FL${String(Math.max(0, Math.round((m * FT_PER_M) / 100))).padStart(3, '0')}`;
}

/** m/s → "452 kt". */
export function formatSpeed(ms: number | null | undefined): string {
  if (ms === null || ms === undefined || !Number.isFinite(ms)) return '–';
  return `${formatInt(ms * KT_PER_MS)} kt`;
}

/** Bytes → "4.4 MB" (SI units, as file managers show them). */
export function formatBytes(n: number): string {
  if (!Number.isFinite(n) || n < 0) return '–';
  if (n < 1000) return `${n} B`;
  const units = ['kB', 'MB', 'GB', 'TB'];
  let v = n / 1000;
  let i = 0;
  while (v >= 1000 && i < units.length - 1) {
    v /= 1000;
    i++;
  }
  return `${v.toFixed(v < 10 ? 1 : 0)} ${units[i]}`;
}
