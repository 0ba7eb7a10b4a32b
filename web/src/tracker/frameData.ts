// The frame-data view: what the tracker saw and decided in the selected frame — counts, state, model
// metrics (the six pair distances and their errors, costs), each teat's estimate against the truth,
// the candidate table, and the stage times.

import { PAIR_NAMES, TEAT_NAMES, distance3, type FrameRecord, type FrameTruth } from '../api/trackerLog';
import { h, mount, sectionHead } from '../lib/dom';
import { STATE_COLORS, TEAT_COLORS } from './palette';

/** What a frame does not have (a LOST frame's model, an untracked teat's estimate) reads "-", never 0. */
export const MISSING = '-';
const f1 = (v: number, d = 1) => (Number.isFinite(v) ? v.toFixed(d) : MISSING);
const int = (v: number) => (Number.isFinite(v) ? String(Math.round(v)) : MISSING);

/** Whether the frame holds a fitted model (its costs and pair distances mean something). */
export function hasModel(f: Pick<FrameRecord, 'state' | 'model'>): boolean {
  return f.state === 'TRACK' || f.model.teatsMatched > 0;
}

/**
 * A teat's row values (conf, x, y, z, r): "-" when the tracker has no estimate of it (neither seen nor
 * tracked: a LOST or SEARCH frame writes zeros there, which are not measurements).
 */
export function teatValues(t: FrameRecord['teats'][number]): string[] {
  if (!t.visible && !t.tracked) return [MISSING, MISSING, MISSING, MISSING, MISSING];
  return [f1(t.confidence, 2), f1(t.tipMm?.[0] ?? NaN), f1(t.tipMm?.[1] ?? NaN), f1(t.tipMm?.[2] ?? NaN), f1(t.radiusMm)];
}

function table(cls: string, testid: string, head: string[], rows: (string | Node)[][]): HTMLTableElement {
  return h(
    'table',
    { class: `data-table ${cls}`, 'data-testid': testid },
    h('thead', {}, h('tr', {}, ...head.map((c) => h('th', {}, c)))),
    h('tbody', {}, ...rows.map((r) => h('tr', {}, ...r.map((c, i) => h('td', { class: i === 0 ? '' : 'num' }, c))))),
  );
}

function kv(label: string, value: string, testid?: string): HTMLElement {
  return h('div', { class: 'kv' }, h('span', { class: 'kv-label muted' }, label), h('span', { class: 'kv-value mono', 'data-testid': testid ?? null }, value));
}

function teatTag(i: number): HTMLElement {
  if (i < 0 || i > 3) return h('span', { class: 'muted' }, '–');
  return h('span', { class: 'teat-tag', style: `color:${TEAT_COLORS[i]}` }, TEAT_NAMES[i]!);
}

export class FrameData {
  readonly root: HTMLElement;
  private readonly body: HTMLElement;

  constructor() {
    this.body = h('div', { class: 'frame-data-body' }, h('p', { class: 'empty' }, 'Start or open a replay to see the tracker’s per-frame data.'));
    this.root = h(
      'section',
      { class: 'tracker-panel frame-data', 'aria-label': 'Frame data', 'data-testid': 'frame-data', 'data-frame': '-1' },
      sectionHead('Frame data'),
      this.body,
    );
  }

  private pending: [number, FrameRecord | null, FrameTruth | null] | null = null;

  /** Shows a frame at the next animation frame (playback can ask for hundreds a second; only the last counts). */
  show(index: number, f: FrameRecord | null, truth: FrameTruth | null): void {
    const first = this.pending === null;
    this.pending = [index, f, truth];
    if (!first) return;
    const run = () => {
      if (!this.pending) return;
      const [i, rec, tr] = this.pending;
      this.pending = null;
      this.render(i, rec, tr);
    };
    requestAnimationFrame(run);
    window.setTimeout(run, 100); // background tabs do not paint
  }

  private render(index: number, f: FrameRecord | null, truth: FrameTruth | null): void {
    this.root.dataset.frame = String(index);
    if (!f) {
      mount(this.body, h('p', { class: 'empty' }, `Frame ${index} is not computed yet.`));
      return;
    }
    this.root.dataset.state = f.state;
    const model = hasModel(f);
    const state = h('span', { class: 'state-badge', style: `background:${STATE_COLORS[f.state]}`, 'data-testid': 'frame-state' }, f.state);
    const summary = h(
      'div',
      { class: 'kv-grid' },
      kv('frame', `${f.index}`, 'frame-data-index'),
      kv('time', `${f1(f.timestampS, 3)} s`),
      kv('matches', int(f.matches), 'frame-matches'),
      kv('verified', int(f.verified), 'frame-verified'),
      kv('teats matched', int(f.model.teatsMatched)),
      kv('valid px', int(f.validPixels)),
      kv('flying px', int(f.flyingPixels)),
      kv('cost', model ? f1(f.model.cost, 2) : MISSING, 'frame-cost'),
      kv('shape cost', model ? `${f1(f.model.shapeCost, 2)} mm` : MISSING),
      kv('NCC cost', model ? f1(f.model.nccCost, 3) : MISSING),
    );
    const pairs = table('pairs', 'frame-pairs', ['mm', ...PAIR_NAMES], [
      ['distance', ...f.model.pairMm.map((v) => (model ? f1(v) : MISSING))],
      ['error', ...f.model.pairErrorMm.map((v) => (model ? f1(v, 2) : MISSING))],
    ]);
    const teats = table(
      'teats',
      'frame-teats',
      ['teat', 'seen', 'conf', 'x', 'y', 'z', 'r mm', 'err mm'],
      f.teats.map((t, i) => {
        const tr = truth?.teats[i];
        const err = t.tracked && tr?.visible ? distance3(t.tipMm, tr.tipMm) : NaN;
        return [
          teatTag(i),
          t.visible ? 'yes' : t.tracked ? 'pred' : MISSING,
          ...teatValues(t),
          f1(err, 2),
        ];
      }),
    );
    const cands = f.candidates.length
      ? table(
          'candidates',
          'frame-candidates',
          ['#', 'u', 'v', 'NCC', 'r mm', 'rms mm', 'pts', 'ok', 'teat'],
          f.candidates.map((c, i) => [
            String(i),
            f1(c.u),
            f1(c.v),
            f1(c.ncc, 3),
            c.verified ? f1(c.radiusMm) : '–',
            c.verified || c.fitRmsMm ? f1(c.fitRmsMm, 2) : '–',
            int(c.points),
            c.verified ? '✓' : '✗',
            teatTag(c.teat),
          ]),
        )
      : h('p', { class: 'empty', 'data-testid': 'frame-candidates' }, 'No candidates in this frame.');
    const t = f.times;
    const times = h(
      'div',
      { class: 'stage-times mono small', 'data-testid': 'frame-times' },
      `preprocess ${f1(t.preprocessUs, 0)} µs · detect ${f1(t.detectUs, 0)} µs · verify ${f1(t.verifyUs, 0)} µs · model ${f1(t.modelUs, 0)} µs · total ${f1(t.totalUs, 0)} µs`,
    );
    mount(
      this.body,
      h('div', { class: 'frame-data-head' }, state, truth ? h('span', { class: 'muted small' }, 'with ground truth') : null),
      summary,
      h('h3', { class: 'sub-title' }, 'Teats'),
      teats,
      h('h3', { class: 'sub-title' }, 'Model pairs'),
      pairs,
      h('h3', { class: 'sub-title' }, `Candidates (${f.candidates.length})`),
      cands,
      h('h3', { class: 'sub-title' }, 'Stage times'),
      times,
    );
  }
}
