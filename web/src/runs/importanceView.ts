// Parameter importance for the chosen metric (GET /api/v1/importance): signed Pearson and Spearman
// correlations (bars left/right of zero) and the random forest's impurity-decrease importance, with the
// forest's out-of-bag R². Parameters that do not vary (no correlation and no importance) are left out.

import type { Importance } from '../api/runsTypes';
import { h, mount } from '../lib/dom';
import { metricDef } from './metrics';

function signedBar(v: number | null, cls: string): HTMLElement {
  const bar = h('span', { class: `imp-signed ${cls}` });
  if (v === null || !Number.isFinite(v)) {
    bar.append(h('span', { class: 'imp-na muted' }, '–'));
    return bar;
  }
  const w = Math.min(1, Math.abs(v)) * 50;
  bar.append(h('span', { class: `imp-fill ${v < 0 ? 'neg' : 'pos'}`, style: v < 0 ? `right:50%;width:${w}%` : `left:50%;width:${w}%` }));
  bar.title = `${cls === 'pearson' ? 'Pearson' : 'Spearman'} ${v.toFixed(2)}`;
  return bar;
}

export class ImportanceView {
  readonly root: HTMLElement;
  private readonly body: HTMLElement;
  private readonly meta: HTMLElement;

  constructor() {
    this.body = h('div', { class: 'imp-body', 'data-testid': 'importance' });
    this.meta = h('div', { class: 'muted small', 'data-testid': 'importance-meta' });
    this.root = h(
      'section',
      { class: 'runs-side-section', 'aria-label': 'Parameter importance' },
      h('h3', { class: 'sub-title' }, 'Parameter importance'),
      this.meta,
      h(
        'div',
        { class: 'imp-head muted small' },
        h('span', {}, 'parameter'),
        h('span', {}, 'Pearson'),
        h('span', {}, 'Spearman'),
        h('span', {}, 'forest'),
      ),
      this.body,
    );
  }

  setMessage(text: string, error = false): void {
    this.meta.textContent = text;
    this.meta.classList.toggle('error-text', error);
    if (error) mount(this.body);
  }

  set(imp: Importance): void {
    const def = metricDef(imp.metric);
    const r2 = imp.forest_r2;
    this.meta.textContent = `${def.label} · ${imp.samples} runs · forest R² ${r2 === null || !Number.isFinite(r2) ? '–' : r2.toFixed(2)}`;
    this.meta.classList.remove('error-text');
    const rows = imp.inputs
      .filter((i) => (i.forest ?? 0) > 0 || (i.pearson !== null && Number.isFinite(i.pearson)))
      .sort((a, b) => (b.forest ?? 0) - (a.forest ?? 0) || Math.abs(b.spearman ?? 0) - Math.abs(a.spearman ?? 0));
    const maxForest = Math.max(1e-9, ...rows.map((r) => r.forest ?? 0));
    mount(
      this.body,
      ...rows.map((i) =>
        h(
          'div',
          { class: 'imp-row', 'data-param': i.name, title: `${i.name}: Pearson ${fmt(i.pearson)}, Spearman ${fmt(i.spearman)}, forest ${fmt(i.forest)}` },
          h('span', { class: 'imp-name' }, i.name),
          signedBar(i.pearson, 'pearson'),
          signedBar(i.spearman, 'spearman'),
          h('span', { class: 'imp-forest' }, h('span', { class: 'imp-fill forest', style: `width:${(((i.forest ?? 0) / maxForest) * 100).toFixed(1)}%` }), h('span', { class: 'imp-num' }, fmt(i.forest))),
        ),
      ),
    );
    if (rows.length === 0) mount(this.body, h('p', { class: 'empty' }, 'No parameter varies over these runs.'));
  }
}

function fmt(v: number | null): string {
  return v === null || !Number.isFinite(v) ? '–' : v.toFixed(2);
}
