// The summary panel: counts, time span, speed statistics, altitude histogram and top callsigns.

import type { AltitudeHistogram, QualityExample, QualityReport, Summary } from '../api/types';
import { h, mount, sectionHead, svg } from '../lib/dom';
import { trimTail } from './histogram';
import { FT_PER_M, KT_PER_MS, formatCompact, formatDuration, formatInt, formatSpeed, formatUtc } from '../lib/format';

export interface SummaryEvents {
  /** The analyst clicked a top callsign: filter by it. */
  onCallsign(callsign: string): void;
  /** The analyst clicked an example of an implausible value: show that flight. */
  onFlight?(id: number, callsign: string): void;
}

function stat(testid: string, label: string, value: string, raw: number | null, title?: string) {
  return h(
    'div',
    { class: 'stat' },
    h('div', { class: 'stat-label' }, label),
    h('div', { class: 'stat-value', 'data-testid': testid, 'data-value': raw === null ? '' : String(raw), title }, value),
  );
}

export class SummaryView {
  private readonly body: HTMLElement;
  private readonly meta: HTMLElement;

  constructor(private readonly root: HTMLElement, private readonly events: SummaryEvents) {
    this.meta = h('span', { class: 'section-meta', 'data-testid': 'summary-elapsed' });
    this.body = h('div', { class: 'summary-body' });
    root.append(sectionHead('Summary', this.meta), this.body);
    this.root.setAttribute('aria-busy', 'false');
    this.setEmpty('Pick a data set.');
  }

  setLoading(): void {
    this.root.dataset.state = 'loading';
    this.root.setAttribute('aria-busy', 'true');
    this.root.classList.add('is-loading');
  }

  setEmpty(message: string): void {
    this.root.dataset.state = 'empty';
    this.root.dataset.query = '';
    this.root.setAttribute('aria-busy', 'false');
    this.root.classList.remove('is-loading');
    this.meta.textContent = '';
    mount(this.body, h('p', { class: 'empty' }, message));
  }

  setError(message: string): void {
    this.root.dataset.state = 'error';
    this.root.setAttribute('aria-busy', 'false');
    this.root.classList.remove('is-loading');
    this.meta.textContent = '';
    mount(this.body, h('p', { class: 'empty error-text' }, message));
  }

  /** Renders a summary; `query` is the exact query string it was fetched with (without `bins`). */
  set(s: Summary, query: string): void {
    this.root.dataset.state = 'ready';
    this.root.dataset.query = query;
    this.root.setAttribute('aria-busy', 'false');
    this.root.classList.remove('is-loading');
    this.meta.textContent = `${s.elapsed_ms.toFixed(1)} ms`;
    this.meta.title = 'Server time for this summary';

    const hasTime = s.points > 0 && s.t_min !== null && s.t_max !== null;
    const span = hasTime
      ? h(
          'div',
          { class: 'stat wide' },
          h('div', { class: 'stat-label' }, 'Time span (UTC)'),
          h(
            'div',
            { class: 'stat-value small', 'data-testid': 'summary-timespan', 'data-t-min': String(s.t_min), 'data-t-max': String(s.t_max) },
            `${formatUtc(s.t_min!)} → ${formatUtc(s.t_max!)}`,
            h('span', { class: 'muted' }, ` · ${formatDuration(s.t_max! - s.t_min!)}`),
          ),
        )
      : null;

    const sp = s.speed;
    const speed =
      sp && s.points > 0 && sp.count !== 0
        ? h(
            'div',
            { class: 'speed-grid', 'aria-label': 'Ground speed' },
            ...(
              [
                ['mean', sp.mean],
                ['p50', sp.p50],
                ['p95', sp.p95],
                ['max', sp.max],
              ] as const
            ).map(([k, v]) =>
              h(
                'div',
                { class: 'speed-cell' },
                h('div', { class: 'stat-label' }, k),
                h('div', { class: 'stat-value small', 'data-testid': `summary-speed-${k}`, 'data-value': String(v), title: `${v.toFixed(1)} m/s` }, formatSpeed(v)),
              ),
            ),
          )
        : null;

    if (s.points === 0) {
      mount(
        this.body,
        h('div', { class: 'stats' }, stat('summary-flights', 'Flights', '0', 0), stat('summary-points', 'Points', '0', 0)),
        h('p', { class: 'empty' }, 'No points match these filters.'),
      );
      return;
    }

    mount(
      this.body,
      h(
        'div',
        { class: 'stats' },
        stat('summary-flights', 'Flights', formatInt(s.flights), s.flights),
        stat('summary-points', 'Points', formatInt(s.points), s.points, `${formatCompact(s.points)} points`),
        span,
      ),
      speed ? h('h3', { class: 'sub-title' }, 'Ground speed') : null,
      speed,
      h('h3', { class: 'sub-title' }, 'Altitude'),
      altitudeChart(s.altitude_histogram),
      h('h3', { class: 'sub-title' }, 'Top callsigns'),
      this.topCallsigns(s),
      s.quality ? this.quality(s.quality) : null,
    );
  }

  /** Data quality: counts of physically implausible values, with the largest examples (click: the flight). */
  private quality(q: QualityReport): HTMLElement {
    const kt = (ms: number) => `${formatInt(ms * KT_PER_MS)} kt`;
    const fl = (m: number) => `FL${formatInt(Math.round((m * FT_PER_M) / 100))}`;
    const kinds: [keyof Pick<QualityReport, 'speed' | 'altitude' | 'jumps'>, string, (e: QualityExample) => string][] = [
      ['speed', `ground speed above ${q.limits?.speed_kt ?? 800} kt`, (e) => kt(e.value)],
      ['altitude', `altitude above FL${q.limits?.altitude_fl ?? 600}`, (e) => fl(e.value)],
      ['jumps', 'position jumps (impossible speed between samples)', (e) => kt(e.value)],
    ];
    const total = kinds.reduce((a, [k]) => a + (q[k]?.count ?? 0), 0);
    return h(
      'section',
      { class: 'quality', 'data-testid': 'summary-quality', 'data-total': String(total) },
      h('h3', { class: 'sub-title' }, 'Data quality', total > 0 ? h('span', { class: 'stale-mark' }, `${formatInt(total)} implausible`) : null),
      ...kinds.map(([k, label, fmt]) => {
        const c = q[k];
        if (!c) return null;
        return h(
          'div',
          { class: 'quality-row', 'data-testid': `quality-${k}`, 'data-count': String(c.count) },
          h('span', { class: 'num' }, formatInt(c.count)),
          ` ${label}`,
          c.examples.length
            ? h(
                'div',
                { class: 'quality-examples small' },
                ...c.examples.slice(0, 3).map((e) =>
                  h(
                    'button',
                    { type: 'button', class: 'link-button mono', title: `${formatUtc(e.t)} UTC`, onclick: () => this.events.onFlight?.(e.flight_id, e.callsign) },
                    `${e.callsign || `#${e.flight_id}`} ${fmt(e)}`,
                  ),
                ),
              )
            : null,
        );
      }),
    );
  }

  private topCallsigns(s: Summary): HTMLElement {
    if (s.top_callsigns.length === 0) return h('p', { class: 'empty' }, 'No callsigns.');
    const max = Math.max(1, ...s.top_callsigns.map((c) => c.points));
    return h(
      'ol',
      { class: 'top-callsigns', 'data-testid': 'summary-top-callsigns' },
      ...s.top_callsigns.slice(0, 8).map((c) =>
        h(
          'li',
          {},
          h(
            'button',
            {
              type: 'button',
              class: 'callsign-row',
              title: `Filter by ${c.callsign}`,
              onclick: () => this.events.onCallsign(c.callsign),
            },
            h('span', { class: 'cs mono' }, c.callsign || '(none)'),
            h('span', { class: 'cs-bar', style: `--w:${((c.points / max) * 100).toFixed(1)}%` }),
            h('span', { class: 'num', 'data-value': String(c.points) }, formatCompact(c.points)),
            h('span', { class: 'num muted' }, `${formatInt(c.flights)} fl`),
          ),
        ),
      ),
    );
  }
}

/** A small vertical bar chart of points per altitude band (x: altitude in ft, y: points). */
function altitudeChart(a: AltitudeHistogram): Element {
  const n = a.counts.length;
  if (n === 0) return h('p', { class: 'empty' }, 'No altitudes.');
  // Drop empty bands and a sparse tail of outliers above the bulk of the traffic.
  const { keep, hidden } = trimTail(a.counts, 0.005);
  const counts = a.counts.slice(0, keep);
  const W = 280;
  const H = 72;
  const AX = 14;
  const max = Math.max(1, ...counts);
  const bw = W / counts.length;
  const unit = a.unit === 'm' ? 'm' : 'ft';
  const bars = counts.map((c, i) => {
    const bh = c > 0 ? Math.max(1, (c / max) * (H - AX - 4)) : 0;
    const lo = a.min + i * a.bin_width;
    return svg(
      'rect',
      { x: i * bw + 0.5, y: H - AX - bh, width: Math.max(0.5, bw - 1), height: bh, class: 'alt-bar' },
      svg('title', {}, `${formatInt(lo)}–${formatInt(lo + a.bin_width)} ${unit}: ${formatInt(c)} points`),
    );
  });
  const top = a.min + counts.length * a.bin_width;
  const mid = a.min + Math.round(counts.length / 2) * a.bin_width;
  const label = (v: number) => (unit === 'ft' && v >= 1000 ? `${formatInt(v / 1000)}k ft` : `${formatInt(v)} ${unit}`);
  const chart = svg(
    'svg',
    { class: 'alt-chart', viewBox: `0 0 ${W} ${H}`, role: 'img', 'aria-label': `Points per ${formatInt(a.bin_width)} ${unit} altitude band`, 'data-testid': 'summary-altitude' },
    ...bars,
    svg('line', { x1: 0, x2: W, y1: H - AX + 0.5, y2: H - AX + 0.5, class: 'axis-line' }),
    svg('text', { x: 0, y: H - 3, class: 'tick-label' }, label(a.min)),
    svg('text', { x: Math.round(counts.length / 2) * bw, y: H - 3, class: 'tick-label', 'text-anchor': 'middle' }, label(mid)),
    svg('text', { x: W, y: H - 3, class: 'tick-label', 'text-anchor': 'end' }, label(top)),
  );
  if (hidden === 0) return chart;
  return h('div', {}, chart, h('div', { class: 'hint', 'data-testid': 'summary-altitude-hidden' }, `+${formatInt(hidden)} points above ${label(top)} not drawn`));
}
