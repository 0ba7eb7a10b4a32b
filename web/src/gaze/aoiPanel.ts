// The areas of interest's numbers (POST /gaze/{id}/aoi): a table (fixations, dwell, first fixation, mean
// fixation, visitors) and the transition matrix between consecutive fixations' AOIs, its cells shaded by
// count (d3-scale).

import { scaleLinear } from 'd3-scale';
import type { AoiAnswer } from '../api/gazeTypes';
import { h, mount } from '../lib/dom';
import { formatInt } from '../lib/format';

export interface AoiPanelEvents {
  onRemove(name: string): void;
  onSelect(name: string): void;
}

/** Milliseconds as the table shows them ("–" when undefined). */
export function ms(v: number | null | undefined): string {
  return v === null || v === undefined || !Number.isFinite(v) ? '–' : `${formatInt(Math.round(v))} ms`;
}

/** The transition matrix's cell colour scale: 0 → the panel, the largest count → the accent. */
export function transitionShade(counts: readonly (readonly number[])[]): (v: number) => string {
  const max = Math.max(1, ...counts.flat());
  return scaleLinear<string>().domain([0, max]).range(['#161b22', '#ff8a1f']).clamp(true);
}

export class AoiPanel {
  readonly el: HTMLElement;
  private readonly table: HTMLElement;
  private readonly matrix: HTMLElement;
  private readonly status: HTMLElement;

  constructor(private readonly events: AoiPanelEvents) {
    this.status = h('div', { class: 'small muted', 'data-testid': 'aoi-status' });
    this.table = h('div', { class: 'aoi-table-wrap' });
    this.matrix = h('div', { class: 'aoi-matrix-wrap' });
    this.el = h('section', { class: 'panel gaze-aoi-panel', 'data-testid': 'aoi-panel', 'aria-label': 'Areas of interest' }, this.status, h('div', { class: 'aoi-grid' }, this.table, this.matrix));
  }

  setStatus(text: string, state: string): void {
    this.status.textContent = text;
    this.el.dataset.state = state;
  }

  show(a: AoiAnswer | null): void {
    if (!a || a.aois.length === 0) {
      mount(this.table);
      mount(this.matrix);
      this.el.dataset.rows = '0';
      return;
    }
    this.el.dataset.rows = String(a.aois.length);
    this.el.dataset.recordings = String(a.recordings);
    const head = ['AOI', 'Fixations', 'Dwell', 'Visitors', 'First fix. (median)', 'First fix. (min)', 'Mean fix.', ''];
    mount(
      this.table,
      h(
        'table',
        { class: 'data-table aoi-table', 'data-testid': 'aoi-table' },
        h('thead', {}, h('tr', {}, ...head.map((t) => h('th', { scope: 'col' }, t)))),
        h(
          'tbody',
          {},
          ...a.aois.map((r) =>
            h(
              'tr',
              { 'data-name': r.name, onclick: () => this.events.onSelect(r.name) },
              h('th', { scope: 'row' }, r.name),
              h('td', { 'data-col': 'fixations', 'data-value': r.fixations }, formatInt(r.fixations)),
              h('td', { 'data-col': 'dwell_ms', 'data-value': r.dwell_ms }, ms(r.dwell_ms)),
              h('td', { 'data-col': 'visitors', 'data-value': r.visitors }, `${r.visitors} / ${a.recordings}`),
              h('td', { 'data-col': 'first_median', 'data-value': r.first_fixation_ms.median ?? '' }, ms(r.first_fixation_ms.median)),
              h('td', { 'data-col': 'first_min', 'data-value': r.first_fixation_ms.min ?? '' }, ms(r.first_fixation_ms.min)),
              h('td', { 'data-col': 'mean_fixation_ms', 'data-value': r.mean_fixation_ms ?? '' }, ms(r.mean_fixation_ms)),
              h('td', {}, h('button', { type: 'button', class: 'link-button', title: `Remove ${r.name}`, onclick: (e: Event) => (e.stopPropagation(), this.events.onRemove(r.name)) }, 'Remove')),
            ),
          ),
        ),
      ),
    );
    const { names, counts } = a.transitions;
    const shade = transitionShade(counts);
    mount(
      this.matrix,
      h(
        'table',
        { class: 'aoi-matrix', 'data-testid': 'aoi-matrix', 'aria-label': 'Transitions: row = from, column = to' },
        h('caption', {}, 'Transitions (row → column)'),
        h('thead', {}, h('tr', {}, h('th', {}, ''), ...names.map((n) => h('th', { scope: 'col' }, n)))),
        h(
          'tbody',
          {},
          ...names.map((from, i) =>
            h(
              'tr',
              {},
              h('th', { scope: 'row' }, from),
              ...names.map((to, j) => {
                const v = counts[i]?.[j] ?? 0;
                return h('td', { 'data-from': from, 'data-to': to, 'data-value': v, style: `background:${shade(v)}`, title: `${from} → ${to}: ${v}` }, String(v));
              }),
            ),
          ),
        ),
      ),
    );
  }
}
