// The runs table: one row per run with its varying parameters and result figures; sortable columns
// (click or Enter on a header), selection by click (only this run), ctrl/cmd-click or the checkbox
// (toggle) and shift-click (range from the last clicked run).

import type { RunRow } from '../api/runsTypes';
import { h, mount, sectionHead } from '../lib/dom';
import type { ColorScale } from './colorScale';
import { formatMetric, formatParam, metricValue, paramValue } from './metrics';
import { clickSelect } from './selection';

export interface TableColumn {
  key: string;
  label: string;
  title?: string;
  kind: 'id' | 'video' | 'sweep' | 'param' | 'metric';
  unit?: string;
}

export const RESULT_COLUMNS: readonly TableColumn[] = [
  { key: 'track_share', label: 'track', title: 'Share of frames in TRACK', kind: 'metric' },
  { key: 'accuracy.median_error_mm', label: 'med err', title: 'Median 3D error over reported visible teats', kind: 'metric' },
  { key: 'accuracy.frames_all_within', label: 'within', title: 'Share of frames with every visible teat within the radius', kind: 'metric' },
  { key: 'lost_episodes', label: 'lost', title: 'Lost episodes', kind: 'metric' },
];

function cellValue(r: RunRow, c: TableColumn): number | string {
  switch (c.kind) {
    case 'id':
      return r.id;
    case 'video':
      return r.video;
    case 'sweep':
      return r.sweep ?? '';
    case 'param':
      return paramValue(r, c.key);
    case 'metric':
      return metricValue(r, c.key);
  }
}

/** Sorts rows by a column; NaN and empty last in either direction; ties by id (numeric-aware). */
export function sortRows(rows: readonly RunRow[], c: TableColumn, dir: 1 | -1): RunRow[] {
  const byId = (a: RunRow, b: RunRow) => a.id.localeCompare(b.id, 'en', { numeric: true });
  return [...rows].sort((a, b) => {
    const va = cellValue(a, c);
    const vb = cellValue(b, c);
    if (typeof va === 'number' && typeof vb === 'number') {
      const na = Number.isNaN(va);
      const nb = Number.isNaN(vb);
      if (na || nb) return na && nb ? byId(a, b) : na ? 1 : -1;
      return (va - vb) * dir || byId(a, b);
    }
    const sa = String(va);
    const sb = String(vb);
    return sa.localeCompare(sb, 'en', { numeric: true }) * dir || byId(a, b);
  });
}

export interface RunsTableOptions {
  onSelect(ids: string[]): void;
}

export class RunsTable {
  readonly root: HTMLElement;
  private readonly body: HTMLElement;
  private readonly head: HTMLElement;
  private readonly count: HTMLElement;
  private rows: RunRow[] = [];
  private order: string[] = [];
  private columns: TableColumn[] = [];
  private sortKey = 'id';
  private sortDir: 1 | -1 = 1;
  private selected: string[] = [];
  private anchor: string | null = null;
  private highlight: Set<string> | null = null;
  private scale: ColorScale | null = null;
  private colorKey = 'track_share';
  private trByID = new Map<string, HTMLTableRowElement>();

  constructor(private readonly opts: RunsTableOptions) {
    this.head = h('thead');
    this.body = h('tbody');
    this.count = h('span', { class: 'section-meta', 'data-testid': 'runs-count' });
    this.root = h(
      'section',
      { class: 'runs-panel runs-table-panel', 'aria-label': 'Runs table' },
      sectionHead(
        'Runs',
        this.count,
        h('button', { class: 'btn btn-small', type: 'button', 'data-testid': 'runs-clear', onclick: () => this.opts.onSelect([]) }, 'Clear selection'),
      ),
      h(
        'div',
        { class: 'runs-table-wrap' },
        h('table', { class: 'runs-table', 'data-testid': 'runs-table', 'aria-multiselectable': 'true', role: 'grid' }, this.head, this.body),
      ),
      h('p', { class: 'hint' }, 'Click a run to select it, Ctrl/⌘-click or the box to add or remove one, Shift-click for a range.'),
    );
  }

  setRows(rows: RunRow[], keyParams: string[], units: Map<string, string>): void {
    this.rows = rows;
    this.columns = [
      { key: 'id', label: 'run', kind: 'id' },
      { key: 'video', label: 'video', kind: 'video' },
      { key: 'sweep', label: 'sweep', kind: 'sweep' },
      ...keyParams.map((p): TableColumn => ({ key: p, label: p, title: `Parameter ${p}${units.get(p) ? ` (${units.get(p)})` : ''}`, kind: 'param', unit: units.get(p) ?? '' })),
      ...RESULT_COLUMNS,
    ];
    if (!this.columns.some((c) => c.key === this.sortKey)) {
      this.sortKey = 'id';
      this.sortDir = 1;
    }
    this.render();
  }

  setSelection(ids: readonly string[]): void {
    this.selected = [...ids];
    const set = new Set(ids);
    for (const [id, tr] of this.trByID) {
      const on = set.has(id);
      tr.setAttribute('aria-selected', String(on));
      const box = tr.querySelector('input');
      if (box) box.checked = on;
    }
    this.root.dataset.selected = String(set.size);
    this.updateCount();
  }

  /** Runs passing the parallel-coordinate brushes (null = no brush): others are dimmed. */
  setHighlight(ids: Set<string> | null): void {
    this.highlight = ids;
    for (const [id, tr] of this.trByID) tr.classList.toggle('dim', ids !== null && !ids.has(id));
    this.updateCount();
  }

  setColor(scale: ColorScale | null, key: string): void {
    this.scale = scale;
    this.colorKey = key;
    for (const [id, tr] of this.trByID) {
      const r = this.rows.find((x) => x.id === id);
      const sw = tr.querySelector<HTMLElement>('.swatch');
      if (r && sw) sw.style.background = scale ? scale.color(metricValue(r, key)) : 'transparent';
    }
  }

  /** Scrolls a run's row into view. */
  reveal(id: string): void {
    this.trByID.get(id)?.scrollIntoView({ block: 'nearest' });
  }

  /** Row ids in displayed order (for shift ranges and the test). */
  get displayOrder(): string[] {
    return this.order;
  }

  private updateCount() {
    const hl = this.highlight ? ` · ${this.highlight.size} in filter` : '';
    this.count.textContent = `${this.rows.length} runs · ${this.selected.length} selected${hl}`;
  }

  private sortBy(key: string) {
    if (this.sortKey === key) this.sortDir = this.sortDir === 1 ? -1 : 1;
    else {
      this.sortKey = key;
      const c = this.columns.find((x) => x.key === key);
      this.sortDir = c?.kind === 'metric' && (key === 'track_share' || key === 'accuracy.frames_all_within') ? -1 : 1;
    }
    this.render();
  }

  private render() {
    const col = this.columns.find((c) => c.key === this.sortKey) ?? this.columns[0]!;
    const sorted = sortRows(this.rows, col, this.sortDir);
    this.order = sorted.map((r) => r.id);
    const ths = this.columns.map((c) => {
      const active = c.key === this.sortKey;
      return h(
        'th',
        { scope: 'col', class: c.kind === 'param' || c.kind === 'metric' ? 'num' : '', 'aria-sort': active ? (this.sortDir === 1 ? 'ascending' : 'descending') : 'none', title: c.title ?? null },
        h('button', { class: 'th-sort', type: 'button', 'data-sort': c.key, onclick: () => this.sortBy(c.key) }, c.label, active ? (this.sortDir === 1 ? ' ▲' : ' ▼') : ''),
      );
    });
    mount(this.head, h('tr', {}, h('th', { scope: 'col', class: 'cb' }, h('span', { class: 'visually-hidden' }, 'selected')), h('th', { class: 'sw' }), ...ths));
    this.trByID.clear();
    const sel = new Set(this.selected);
    const trs = sorted.map((r) => {
      const box = h('input', { type: 'checkbox', 'aria-label': `Select run ${r.id}` });
      box.checked = sel.has(r.id);
      box.addEventListener('click', (e) => {
        e.stopPropagation();
        this.click(r.id, e.shiftKey ? 'range' : 'toggle');
      });
      const tds = this.columns.map((c) => {
        const v = cellValue(r, c);
        const text = typeof v === 'string' ? v : c.kind === 'param' ? formatParam(v, c.unit) : formatMetric(c.key, v);
        return h('td', { class: typeof v === 'number' ? 'num' : '' }, text);
      });
      const sw = h('span', { class: 'swatch' });
      if (this.scale) sw.style.background = this.scale.color(metricValue(r, this.colorKey));
      const tr = h('tr', { 'data-run': r.id, 'aria-selected': String(sel.has(r.id)), tabindex: 0 }, h('td', { class: 'cb' }, box), h('td', { class: 'sw' }, sw), ...tds);
      if (this.highlight && !this.highlight.has(r.id)) tr.classList.add('dim');
      // Shift-click selects a range of runs, not the text between.
      tr.addEventListener('mousedown', (e) => {
        if (e.shiftKey) e.preventDefault();
      });
      tr.addEventListener('click', (e) => this.click(r.id, e.shiftKey ? 'range' : e.ctrlKey || e.metaKey ? 'toggle' : 'replace'));
      tr.addEventListener('keydown', (e) => {
        if (e.key === 'Enter' || e.key === ' ') {
          e.preventDefault();
          this.click(r.id, e.shiftKey ? 'range' : e.ctrlKey || e.metaKey || e.key === ' ' ? 'toggle' : 'replace');
        } else if (e.key === 'ArrowDown' || e.key === 'ArrowUp') {
          e.preventDefault();
          const next = (e.key === 'ArrowDown' ? tr.nextElementSibling : tr.previousElementSibling) as HTMLElement | null;
          next?.focus();
        }
      });
      this.trByID.set(r.id, tr);
      return tr;
    });
    mount(this.body, ...trs);
    if (trs.length === 0) mount(this.body, h('tr', {}, h('td', { colspan: this.columns.length + 2, class: 'empty' }, 'No runs: start a sweep (POST /api/v1/sweeps) or track a video.')));
    this.updateCount();
  }

  private click(id: string, mode: 'replace' | 'toggle' | 'range') {
    const next = clickSelect(this.selected, this.order, this.anchor, id, mode);
    if (mode !== 'range') this.anchor = id;
    this.opts.onSelect(next);
  }
}
