// The comparison of 2..8 runs of one video (POST /api/v1/compare):
//  - aligned timelines, one lane per run: state strip (TRACK blue, LOST red, SEARCH grey), largest 3D
//    error (red marks = a visible teat not reported), matches and model cost, with one frame cursor shared
//    by every lane (click or drag anywhere sets it); each lane's "open" shows the stored run in the
//    tracker view at the cursor frame (#tracker?run=ID&frame=N), its ▶ starts a fresh live replay;
//  - small multiples: the error of each teat per run, on one scale;
//  - the frames where the runs disagree most, ranked (click → cursor there);
//  - the parameters that differ beside the results, the best result of each row marked.

import type { Comparison, CompareSeries } from '../api/runsTypes';
import { h, mount, sectionHead } from '../lib/dom';
import { AxisSurface } from '../tracker/axisSurface';
import { frameLeft, tickStep, xOfFrame } from '../tracker/frameAxis';
import { STATE_COLORS, TEAT_COLORS, UNKNOWN_COLOR } from '../tracker/palette';
import { trackerRunHash } from '../tracker/route';
import { bestIndex, formatMetric, formatNumber, formatParam, metricDef } from './metrics';

const TEATS = ['FL', 'FR', 'RL', 'RR'] as const;
/** Frames where a visible teat was not reported (error +∞). */
const MISSED_COLOR = '#f472b6';

export interface CompareViewOptions {
  onCursor(frame: number): void;
  onReplay?(runId: string): void;
  /** The stale mark's one-click recompute. */
  onRecompute?(): void;
}

/** Shared y ranges of the lanes: error (mm, the 98th percentile of finite values, 10..200), matches, cost. */
export function laneScales(series: readonly CompareSeries[]): { errMax: number; matchMax: number; costMax: number } {
  const errs: number[] = [];
  let matchMax = 1;
  const costs: number[] = [];
  for (const s of series) {
    for (const v of s.maxErrorMm) if (Number.isFinite(v)) errs.push(v);
    for (const v of s.matches) if (Number.isFinite(v)) matchMax = Math.max(matchMax, v);
    for (const v of s.modelCost) if (Number.isFinite(v)) costs.push(v);
  }
  const q = (a: number[], p: number) => {
    if (!a.length) return NaN;
    a.sort((x, y) => x - y);
    return a[Math.min(a.length - 1, Math.round(p * (a.length - 1)))]!;
  };
  const e = q(errs, 0.98);
  const c = q(costs, 0.98);
  return {
    errMax: Number.isFinite(e) ? Math.min(200, Math.max(10, e * 1.1)) : 10,
    matchMax,
    costMax: Number.isFinite(c) && c > 0 ? c * 1.1 : 1,
  };
}

interface Lane {
  surface: AxisSurface;
  series: CompareSeries;
}

export class CompareView {
  readonly root: HTMLElement;
  private readonly head: HTMLElement;
  private readonly lanesEl: HTMLElement;
  private readonly ticks: HTMLElement;
  private readonly multiplesEl: HTMLElement;
  private readonly disagreeEl: HTMLElement;
  private readonly diffEl: HTMLElement;
  private readonly note: HTMLElement;
  private readonly staleBox: HTMLElement;
  private readonly staleText: HTMLElement;
  private cmp: Comparison | null = null;
  private lanes: Lane[] = [];
  private multiples: AxisSurface[] = [];
  private cursor = 0;
  private colors = new Map<string, string>();
  private readonly errScaleLabel = h('span', { class: 'muted' });

  constructor(private readonly opts: CompareViewOptions) {
    this.head = h('span', { class: 'section-meta', 'data-testid': 'compare-meta' });
    this.note = h('p', { class: 'muted small compare-note', 'data-testid': 'compare-note' }, 'Select 2 to 8 runs of one video (table, projection or filter) to compare them.');
    this.staleText = h('span', { class: 'small muted' });
    this.staleBox = h(
      'div',
      { class: 'stale-line', 'data-testid': 'compare-stale', hidden: true, role: 'status' },
      h('span', { class: 'stale-mark' }, 'stale'),
      this.staleText,
      h('button', { type: 'button', class: 'link-button', 'data-testid': 'compare-recompute', onclick: () => this.opts.onRecompute?.() }, 'Recompute'),
    );
    this.lanesEl = h('div', { class: 'lanes', 'data-testid': 'compare-lanes', 'data-lanes': '0' });
    this.ticks = h('div', { class: 'frame-ticks lane-ticks', 'aria-hidden': 'true' });
    this.multiplesEl = h('div', { class: 'multiples', 'data-testid': 'compare-multiples' });
    this.disagreeEl = h('div', { class: 'disagree', 'data-testid': 'disagreements' });
    this.diffEl = h('div', { class: 'diffs', 'data-testid': 'compare-diffs' });
    const key = (label: string, color: string) => h('span', { class: 'legend-item' }, h('span', { class: 'legend-block', style: `background:${color}` }), label);
    this.root = h(
      'section',
      { class: 'runs-panel compare-panel', 'aria-label': 'Comparison of the selected runs', 'data-testid': 'compare', 'data-state': 'empty' },
      sectionHead('Comparison', this.head),
      this.staleBox,
      this.note,
      h(
        'div',
        { class: 'compare-grid' },
        h(
          'div',
          { class: 'compare-timelines' },
          h(
            'div',
            { class: 'lane-legend legend small' },
            key('track', STATE_COLORS.TRACK),
            key('lost', STATE_COLORS.LOST),
            key('search', STATE_COLORS.SEARCH),
            key('teat missed', MISSED_COLOR),
            this.errScaleLabel,
          ),
          this.lanesEl,
          this.ticks,
          h('h3', { class: 'sub-title' }, 'Error per teat'),
          h('div', { class: 'legend small' }, ...TEATS.map((t, i) => key(t, TEAT_COLORS[i]!))),
          this.multiplesEl,
        ),
        h('div', { class: 'compare-side' }, h('h3', { class: 'sub-title' }, 'Where the runs disagree most'), this.disagreeEl),
      ),
      h('h3', { class: 'sub-title' }, 'Parameters that differ · results'),
      this.diffEl,
    );
    new ResizeObserver(() => this.renderTicks()).observe(this.ticks);
    // ← / → step the shared cursor by a frame (Shift: 10 frames), Home / End jump to the ends.
    this.lanesEl.tabIndex = 0;
    this.lanesEl.setAttribute('aria-label', 'Aligned timelines: ← → move the frame cursor, Shift for 10 frames');
    this.lanesEl.addEventListener('keydown', (e) => {
      const cmp = this.cmp;
      if (!cmp) return;
      const step = e.shiftKey ? 10 : 1;
      const next =
        e.key === 'ArrowRight' ? this.cursor + step : e.key === 'ArrowLeft' ? this.cursor - step : e.key === 'Home' ? cmp.firstFrame : e.key === 'End' ? cmp.firstFrame + cmp.frames - 1 : null;
      if (next === null) return;
      e.preventDefault();
      this.seek(next);
    });
  }

  /** Colours of the runs (the projection's metric colours) for the lane labels. */
  setRunColors(colors: Map<string, string>): void {
    this.colors = colors;
  }

  /** Marks the comparison stale (its runs changed on the server since it was made), with why; null clears it. */
  setStale(why: string | null): void {
    this.staleBox.hidden = why === null;
    this.staleText.textContent = why === null ? '' : ` ${why} `;
    this.root.dataset.stale = String(why !== null);
  }

  clear(message: string): void {
    this.cmp = null;
    this.lanes = [];
    this.multiples = [];
    this.root.dataset.state = 'empty';
    this.lanesEl.dataset.lanes = '0';
    this.note.textContent = message;
    this.note.classList.remove('error-text');
    this.head.textContent = '';
    mount(this.lanesEl);
    mount(this.multiplesEl);
    mount(this.disagreeEl);
    mount(this.diffEl);
    mount(this.ticks);
  }

  setLoading(text: string): void {
    this.root.dataset.state = 'loading';
    this.note.textContent = text;
    this.note.classList.remove('error-text');
  }

  setError(text: string): void {
    this.root.dataset.state = 'error';
    this.note.textContent = text;
    this.note.classList.add('error-text');
  }

  /** The frame (video index) under the cursor. */
  get cursorFrame(): number {
    return this.cursor;
  }

  set(cmp: Comparison, note: string, units: Map<string, string>, cursor: number | null): void {
    this.cmp = cmp;
    this.root.dataset.state = 'ready';
    this.note.textContent = note;
    this.note.classList.remove('error-text');
    this.head.textContent = `${cmp.series.length} runs · video ${cmp.video} · frames ${cmp.firstFrame}–${cmp.firstFrame + cmp.frames - 1}`;
    const sc = laneScales(cmp.series);
    this.errScaleLabel.textContent = `· rows: state, largest error (amber, 0–${Math.round(sc.errMax)} mm), matches (blue, 0–${Math.round(sc.matchMax)}), model cost (violet)`;
    this.lanes = cmp.series.map((s, k) => {
      const surface = new AxisSurface({
        label: `Run ${s.id}: state, error, matches and model cost per frame; click to set the frame`,
        testid: `lane-${s.id}`,
        onSeek: (f) => this.seek(cmp.firstFrame + f),
        draw: (ctx, w, hh) => drawLane(ctx, w, hh, s, cmp.frames, sc),
        describe: (f) => describeFrame(cmp, k, f),
      });
      surface.setFrames(cmp.frames);
      return { surface, series: s };
    });
    mount(
      this.lanesEl,
      ...this.lanes.map((l, k) => {
        const run = cmp.runs[k];
        const sum = run?.summary;
        // "open": the stored run in the tracker view at the cursor frame (href follows the cursor);
        // ▶: a fresh live replay of the run's video at its parameters.
        const open = h(
          'a',
          {
            class: 'btn small lane-open',
            href: trackerRunHash(l.series.id, this.cursor),
            'data-testid': `lane-open-${l.series.id}`,
            title: `Open stored run ${l.series.id} in the tracker view at the cursor frame`,
          },
          'open',
        );
        const replay = this.opts.onReplay
          ? h('button', { class: 'icon-button lane-replay', type: 'button', title: `Replay run ${l.series.id} in the tracker view (a fresh live replay)`, 'aria-label': `Replay run ${l.series.id} in the tracker`, onclick: () => this.opts.onReplay?.(l.series.id) }, '▶')
          : null;
        return h(
          'div',
          { class: 'lane', 'data-run': l.series.id },
          h(
            'div',
            { class: 'lane-label' },
            h('span', { class: 'swatch', style: `background:${this.colors.get(l.series.id) ?? 'transparent'}` }),
            h('span', { class: 'lane-id mono' }, l.series.id),
            sum ? h('span', { class: 'muted small' }, `${formatMetric('track_share', sum.track_share)} track`) : null,
            open,
            replay,
          ),
          l.surface.root,
        );
      }),
    );
    this.lanesEl.dataset.lanes = String(this.lanes.length);
    this.lanesEl.dataset.runs = cmp.series.map((s) => s.id).join(',');
    // Small multiples: error per teat, one panel per run, one scale.
    let teatMax = 10;
    for (const s of cmp.series) for (const t of s.teatErrorMm) for (const v of t) if (Number.isFinite(v)) teatMax = Math.max(teatMax, Math.min(200, v));
    this.multiples = cmp.series.map(
      (s) =>
        new AxisSurface({
          label: `Run ${s.id}: 3D error of each teat per frame`,
          testid: `multiple-${s.id}`,
          onSeek: (f) => this.seek(cmp.firstFrame + f),
          draw: (ctx, w, hh) => drawTeatErrors(ctx, w, hh, s, cmp.frames, teatMax),
          describe: (f) =>
            `frame ${cmp.firstFrame + f}: ${TEATS.map((t, i) => `${t} ${fmtErr(s.teatErrorMm[i]?.[f] ?? NaN)}`).join(' · ')}`,
        }),
    );
    mount(
      this.multiplesEl,
      ...this.multiples.map((m, k) => {
        m.setFrames(cmp.frames);
        const id = cmp.series[k]!.id;
        return h(
          'figure',
          { class: 'multiple' },
          h('figcaption', {}, h('span', { class: 'swatch', style: `background:${this.colors.get(id) ?? 'transparent'}` }), id, h('span', { class: 'muted' }, ` 0–${Math.round(teatMax)} mm`)),
          m.root,
        );
      }),
    );
    if (cmp.series.every((s) => s.teatErrorMm.length === 0)) mount(this.multiplesEl, h('p', { class: 'empty' }, 'These runs have no ground truth: no errors to show.'));
    this.renderDisagreements(cmp);
    this.renderDiffs(cmp, units);
    this.renderTicks();
    this.setCursor(cursor !== null && cursor >= cmp.firstFrame && cursor < cmp.firstFrame + cmp.frames ? cursor : (cmp.disagreements[0]?.frame ?? cmp.firstFrame));
  }

  /** Moves the shared cursor to a video frame (no callback). */
  setCursor(frame: number): void {
    const cmp = this.cmp;
    if (!cmp) return;
    const f = Math.max(cmp.firstFrame, Math.min(cmp.firstFrame + cmp.frames - 1, Math.round(frame)));
    this.cursor = f;
    this.root.dataset.cursor = String(f);
    for (const l of this.lanes) l.surface.setCursor(f - cmp.firstFrame);
    for (const m of this.multiples) m.setCursor(f - cmp.firstFrame);
    for (const row of this.disagreeEl.querySelectorAll<HTMLElement>('[data-frame]')) row.classList.toggle('current', Number(row.dataset.frame) === f);
    for (const a of this.lanesEl.querySelectorAll<HTMLAnchorElement>('a.lane-open')) {
      const run = a.closest<HTMLElement>('.lane')?.dataset.run;
      if (run) a.href = trackerRunHash(run, f);
      a.dataset.frame = String(f);
    }
  }

  private seek(frame: number) {
    this.setCursor(frame);
    this.opts.onCursor(this.cursor);
  }

  private renderTicks() {
    const cmp = this.cmp;
    const w = this.ticks.clientWidth;
    if (!cmp || w === 0 || cmp.frames === 0) {
      mount(this.ticks);
      return;
    }
    const step = tickStep(cmp.frames, Math.max(2, Math.floor(w / 80)));
    const out: HTMLElement[] = [];
    for (let f = 0; f < cmp.frames; f += step) out.push(h('span', { class: 'frame-tick', style: `left:${xOfFrame(f, w, cmp.frames).toFixed(1)}px` }, String(cmp.firstFrame + f)));
    mount(this.ticks, ...out);
  }

  private renderDisagreements(cmp: Comparison) {
    if (cmp.disagreements.length === 0) {
      mount(this.disagreeEl, h('p', { class: 'empty' }, 'The runs agree on every frame.'));
      return;
    }
    const rows = cmp.disagreements.map((d, rank) =>
      h(
        'tr',
        {
          'data-frame': d.frame,
          'data-testid': 'disagreement',
          tabindex: 0,
          role: 'button',
          'aria-label': `Frame ${d.frame}, disagreement ${formatNumber(d.scoreMm)} mm: show`,
          onclick: () => this.seek(d.frame),
          onkeydown: (e: Event) => {
            const k = (e as KeyboardEvent).key;
            if (k === 'Enter' || k === ' ') {
              e.preventDefault();
              this.seek(d.frame);
            }
          },
        },
        h('td', { class: 'num muted' }, String(rank + 1)),
        h('td', { class: 'num' }, String(d.frame)),
        h('td', { class: 'num' }, `${formatNumber(d.scoreMm)} mm`),
        h(
          'td',
          { class: 'chips' },
          ...d.states.map((s, k) => h('span', { class: 'state-chip', title: `${cmp.series[k]?.id ?? k}: ${s ?? '?'}`, style: `background:${s ? STATE_COLORS[s] : UNKNOWN_COLOR}` })),
        ),
        h('td', {}, d.worstTeat !== null ? TEATS[d.worstTeat] : ''),
      ),
    );
    mount(
      this.disagreeEl,
      h(
        'table',
        { class: 'disagree-table' },
        h('thead', {}, h('tr', {}, h('th', { class: 'num' }, '#'), h('th', { class: 'num' }, 'frame'), h('th', { class: 'num' }, 'score'), h('th', {}, 'states'), h('th', {}, 'teat'))),
        h('tbody', {}, ...rows),
      ),
      h('p', { class: 'hint' }, 'Score: mean over the teats of the largest distance between two runs’ tips, plus the miss distance × the share of runs that miss a teat others see.'),
    );
  }

  private renderDiffs(cmp: Comparison, units: Map<string, string>) {
    const ids = cmp.series.map((s) => s.id);
    const headRow = () => h('tr', {}, h('th', {}, ''), ...ids.map((id) => h('th', { class: 'num mono' }, id)));
    const differing = cmp.params.filter((p) => p.differs);
    const paramTable = h(
      'table',
      { class: 'diff-table', 'data-testid': 'param-diffs' },
      h('thead', {}, headRow()),
      h(
        'tbody',
        {},
        ...differing.map((p) => h('tr', { 'data-param': p.name }, h('th', { scope: 'row' }, p.name), ...p.values.map((v) => h('td', { class: 'num' }, formatParam(v, units.get(p.name) ?? ''))))),
      ),
    );
    const resultTable = h(
      'table',
      { class: 'diff-table', 'data-testid': 'result-diffs' },
      h('thead', {}, headRow()),
      h(
        'tbody',
        {},
        ...cmp.results.map((r) => {
          const def = metricDef(r.name);
          const best = r.differs ? bestIndex(r.values, def.better) : -1;
          return h(
            'tr',
            { 'data-result': r.name },
            h('th', { scope: 'row', title: `${def.better === 'high' ? 'higher' : 'lower'} is better` }, def.label),
            ...r.values.map((v, i) => h('td', { class: `num${i === best ? ' best' : ''}` }, formatMetric(r.name, v))),
          );
        }),
      ),
    );
    mount(
      this.diffEl,
      h('div', { class: 'diff-half' }, h('div', { class: 'muted small' }, differing.length ? `${differing.length} parameters differ` : 'Every parameter is equal.'), paramTable),
      h('div', { class: 'diff-half' }, h('div', { class: 'muted small' }, 'Results (best marked)'), resultTable),
    );
  }
}

function fmtErr(v: number): string {
  return Number.isNaN(v) ? '–' : v === Infinity ? 'missed' : `${formatNumber(v)} mm`;
}

function describeFrame(cmp: Comparison, k: number, f: number): string {
  const s = cmp.series[k]!;
  return `${s.id} · frame ${cmp.firstFrame + f}: ${s.state[f] ?? '?'} · max err ${fmtErr(s.maxErrorMm[f] ?? NaN)} · ${formatNumber(s.matches[f] ?? NaN)} matches · cost ${formatNumber(s.modelCost[f] ?? NaN)}`;
}

/** One lane: state strip, max error bars, matches bars, model cost line (rows of the lane's height). */
function drawLane(ctx: CanvasRenderingContext2D, w: number, hh: number, s: CompareSeries, n: number, sc: { errMax: number; matchMax: number; costMax: number }) {
  if (n === 0) return;
  const rows = [
    [0, 0.2],
    [0.24, 0.58],
    [0.62, 0.8],
    [0.84, 1],
  ] as const;
  const band = (i: number) => [Math.round(rows[i]![0] * hh), Math.round(rows[i]![1] * hh)] as const;
  // state
  const [s0, s1] = band(0);
  let start = 0;
  for (let i = 1; i <= n; i++) {
    if (i < n && s.state[i] === s.state[start]) continue;
    const st = s.state[start];
    ctx.fillStyle = st ? STATE_COLORS[st] : UNKNOWN_COLOR;
    const x0 = Math.floor(frameLeft(start, w, n));
    const x1 = Math.ceil(frameLeft(i, w, n));
    ctx.fillRect(x0, s0, Math.max(1, x1 - x0), s1 - s0);
    start = i;
  }
  const bars = (i: number, a: Float64Array, max: number, color: string) => {
    const [y0, y1] = band(i);
    ctx.fillStyle = 'rgba(255,255,255,0.04)';
    ctx.fillRect(0, y0, w, y1 - y0);
    for (let f = 0; f < n; f++) {
      const v = a[f]!;
      if (Number.isNaN(v)) continue;
      const x0 = Math.floor(frameLeft(f, w, n));
      const x1 = Math.max(x0 + 1, Math.ceil(frameLeft(f + 1, w, n)));
      if (v === Infinity) {
        // A visible teat not reported: a pink mark along the top of the row.
        ctx.fillStyle = MISSED_COLOR;
        ctx.fillRect(x0, y0, x1 - x0, Math.max(2, Math.round((y1 - y0) * 0.3)));
        continue;
      }
      const t = Math.min(1, Math.max(0, v / max));
      ctx.fillStyle = color;
      ctx.fillRect(x0, y1 - t * (y1 - y0), x1 - x0, Math.max(1, t * (y1 - y0)));
    }
  };
  bars(1, s.maxErrorMm, sc.errMax, '#fbbf24');
  bars(2, s.matches, sc.matchMax, '#60a5fa');
  // model cost as a line
  const [c0, c1] = band(3);
  ctx.fillStyle = 'rgba(255,255,255,0.04)';
  ctx.fillRect(0, c0, w, c1 - c0);
  ctx.strokeStyle = '#c084fc';
  ctx.lineWidth = 1;
  ctx.beginPath();
  let pen = false;
  for (let f = 0; f < n; f++) {
    const v = s.modelCost[f]!;
    if (!Number.isFinite(v)) {
      pen = false;
      continue;
    }
    const x = xOfFrame(f, w, n);
    const y = c1 - Math.min(1, Math.max(0, v / sc.costMax)) * (c1 - c0);
    if (pen) ctx.lineTo(x, y);
    else ctx.moveTo(x, y);
    pen = true;
  }
  ctx.stroke();
}

function drawTeatErrors(ctx: CanvasRenderingContext2D, w: number, hh: number, s: CompareSeries, n: number, max: number) {
  if (n === 0) return;
  ctx.fillStyle = '#0b0f14';
  ctx.fillRect(0, 0, w, hh);
  s.teatErrorMm.forEach((a, t) => {
    ctx.strokeStyle = TEAT_COLORS[t]!;
    ctx.fillStyle = TEAT_COLORS[t]!;
    ctx.lineWidth = 1.2;
    ctx.beginPath();
    let pen = false;
    for (let f = 0; f < n; f++) {
      const v = a[f]!;
      const x = xOfFrame(f, w, n);
      if (v === Infinity) {
        // a visible teat not reported: a tick at the top
        ctx.fillRect(x - 0.5, t * 3, 1.5, 3);
        pen = false;
        continue;
      }
      if (!Number.isFinite(v)) {
        pen = false;
        continue;
      }
      const y = hh - 2 - Math.min(1, v / max) * (hh - 14);
      if (pen) ctx.lineTo(x, y);
      else ctx.moveTo(x, y);
      pen = true;
    }
    ctx.stroke();
  });
}
