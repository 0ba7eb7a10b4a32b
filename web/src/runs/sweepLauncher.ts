// A small sweep launcher (POST /api/v1/sweeps): videos, a random or grid sample over a few parameter
// ranges, then the job's progress until its runs are stored.

import { ApiError } from '../api/client';
import { runsApi } from '../api/runs';
import type { SweepAxisSpec, SweepSpecBody } from '../api/runsTypes';
import type { TrackerParam, Video } from '../api/trackerTypes';
import { h, mount } from '../lib/dom';

export interface SweepLauncherOptions {
  /** The sweep's job finished (done, failed or cancelled). */
  onDone(sweep: string, state: string): void;
}

interface AxisRow {
  row: HTMLElement;
  param: HTMLSelectElement;
  min: HTMLInputElement;
  max: HTMLInputElement;
}

/** The request body of the form's values; throws Error naming the field at fault. */
export function sweepBody(
  videos: string[],
  mode: 'random' | 'grid',
  samples: number,
  steps: number,
  seed: number,
  axes: { param: string; min: number; max: number }[],
): { videos: string[]; sweep: SweepSpecBody } {
  if (videos.length === 0) throw new Error('videos: choose at least one video');
  if (axes.length === 0) throw new Error('axes: add at least one parameter range');
  const seen = new Set<string>();
  const out: SweepAxisSpec[] = axes.map((a) => {
    if (seen.has(a.param)) throw new Error(`axes: ${a.param} is swept twice`);
    seen.add(a.param);
    if (!Number.isFinite(a.min) || !Number.isFinite(a.max) || a.min > a.max) throw new Error(`${a.param}: min must be a number ≤ max`);
    return mode === 'grid' ? { param: a.param, min: a.min, max: a.max, steps } : { param: a.param, min: a.min, max: a.max };
  });
  if (mode === 'random' && !(Number.isInteger(samples) && samples >= 1)) throw new Error('samples: a whole number ≥ 1');
  if (mode === 'grid' && !(Number.isInteger(steps) && steps >= 2 && steps <= 100)) throw new Error('steps: a whole number 2..100');
  const sweep: SweepSpecBody = { mode, seed: Math.max(0, Math.floor(seed) || 0), axes: out };
  if (mode === 'random') sweep.samples = samples;
  return { videos, sweep };
}

export class SweepLauncher {
  readonly root: HTMLElement;
  private readonly videosEl: HTMLElement;
  private readonly axesEl: HTMLElement;
  private readonly mode: HTMLSelectElement;
  private readonly samples: HTMLInputElement;
  private readonly steps: HTMLInputElement;
  private readonly seed: HTMLInputElement;
  private readonly start: HTMLButtonElement;
  private readonly status: HTMLElement;
  private params: TrackerParam[] = [];
  private axes: AxisRow[] = [];

  constructor(private readonly opts: SweepLauncherOptions) {
    this.videosEl = h('div', { class: 'launch-videos', 'data-testid': 'launch-videos' });
    this.axesEl = h('div', { class: 'launch-axes' });
    this.mode = h('select', { 'aria-label': 'Sampling', 'data-testid': 'launch-mode' }, h('option', { value: 'random' }, 'random'), h('option', { value: 'grid' }, 'grid'));
    this.samples = h('input', { type: 'number', min: 1, value: 50, 'aria-label': 'Random points', 'data-testid': 'launch-samples' });
    this.steps = h('input', { type: 'number', min: 2, max: 100, value: 5, 'aria-label': 'Grid steps per parameter' });
    this.seed = h('input', { type: 'number', min: 0, value: 1, 'aria-label': 'Seed' });
    this.start = h('button', { class: 'btn btn-small', type: 'button', 'data-testid': 'launch-start', onclick: () => void this.launch() }, 'Start sweep');
    this.status = h('div', { class: 'small muted', role: 'status', 'data-testid': 'launch-status' });
    const add = h('button', { class: 'btn btn-small', type: 'button', onclick: () => this.addAxis() }, '+ parameter');
    this.root = h(
      'details',
      { class: 'runs-side-section launcher', 'data-testid': 'sweep-launcher' },
      h('summary', { class: 'sub-title' }, 'New sweep'),
      h('div', { class: 'field-label' }, 'Videos'),
      this.videosEl,
      h('div', { class: 'field-label' }, 'Parameter ranges'),
      this.axesEl,
      add,
      h(
        'div',
        { class: 'launch-grid' },
        h('label', {}, 'sampling ', this.mode),
        h('label', {}, 'points ', this.samples),
        h('label', {}, 'grid steps ', this.steps),
        h('label', {}, 'seed ', this.seed),
      ),
      this.start,
      this.status,
    );
  }

  setChoices(videos: Video[], params: TrackerParam[]): void {
    this.params = params;
    mount(
      this.videosEl,
      ...videos.map((v) =>
        h('label', { class: 'check small' }, h('input', { type: 'checkbox', value: v.id, 'data-video': v.id }), `${v.id} · ${v.name} (${v.frame_count} frames)`),
      ),
    );
    if (videos.length === 0) mount(this.videosEl, h('p', { class: 'empty' }, 'No videos on the server.'));
    if (this.axes.length === 0 && params.some((p) => p.name === 'ncc_min')) this.addAxis('ncc_min');
  }

  private addAxis(name?: string) {
    const param = h('select', { 'aria-label': 'Parameter', 'data-testid': 'launch-param' }, ...this.params.map((p) => h('option', { value: p.name }, p.unit ? `${p.name} (${p.unit})` : p.name)));
    const used = new Set(this.axes.map((a) => a.param.value));
    param.value = name ?? this.params.find((p) => !used.has(p.name))?.name ?? '';
    const min = h('input', { type: 'number', step: 'any', 'aria-label': 'Minimum', placeholder: 'min', 'data-testid': 'launch-min' });
    const max = h('input', { type: 'number', step: 'any', 'aria-label': 'Maximum', placeholder: 'max', 'data-testid': 'launch-max' });
    const fill = () => {
      const p = this.params.find((x) => x.name === param.value);
      if (!p) return;
      // Default range: half to twice the default, inside the parameter's own range.
      const d = p.default_value;
      // Four significant digits: the field shows the whole number.
      min.value = String(+Math.max(p.min, d > 0 ? d / 2 : p.min).toPrecision(4));
      max.value = String(+Math.min(p.max, d > 0 ? d * 2 : p.max).toPrecision(4));
    };
    param.addEventListener('change', fill);
    fill();
    const row: AxisRow = { row: h('div', { class: 'launch-axis' }), param, min, max };
    const remove = h('button', { class: 'icon-button', type: 'button', 'aria-label': 'Remove this range', onclick: () => this.removeAxis(row) }, '×');
    row.row.append(param, min, max, remove);
    this.axes.push(row);
    this.axesEl.append(row.row);
  }

  private removeAxis(row: AxisRow) {
    this.axes = this.axes.filter((a) => a !== row);
    row.row.remove();
  }

  private setStatus(text: string, error = false) {
    this.status.textContent = text;
    this.status.classList.toggle('error-text', error);
  }

  private async launch() {
    let body: ReturnType<typeof sweepBody>;
    try {
      body = sweepBody(
        [...this.videosEl.querySelectorAll<HTMLInputElement>('input:checked')].map((i) => i.value),
        this.mode.value === 'grid' ? 'grid' : 'random',
        Number(this.samples.value),
        Number(this.steps.value),
        Number(this.seed.value),
        this.axes.map((a) => ({ param: a.param.value, min: Number(a.min.value), max: Number(a.max.value) })),
      );
    } catch (e) {
      this.setStatus(e instanceof Error ? e.message : String(e), true);
      return;
    }
    this.start.disabled = true;
    try {
      const r = await runsApi.startSweep(body.videos, body.sweep);
      this.setStatus(`Sweep ${r.sweep.id}: ${r.sweep.total ?? '?'} runs queued…`);
      this.root.dataset.sweep = r.sweep.id;
      const end = await this.follow(r.job.id, r.sweep.id);
      this.opts.onDone(r.sweep.id, end);
    } catch (e) {
      this.setStatus(e instanceof ApiError ? e.detail : String(e), true);
    } finally {
      this.start.disabled = false;
    }
  }

  /** Polls the job until it ends; returns its final state. */
  private async follow(job: string, sweep: string): Promise<string> {
    for (;;) {
      const j = await runsApi.job(job);
      if (j.state === 'done' || j.state === 'failed' || j.state === 'cancelled') {
        this.setStatus(j.state === 'done' ? `Sweep ${sweep} done.` : `Sweep ${sweep} ${j.state}${j.error ? `: ${j.error.detail}` : ''}`, j.state !== 'done');
        return j.state;
      }
      this.setStatus(`Sweep ${sweep}: ${Math.round((j.progress ?? 0) * 100)} %`);
      await new Promise((r) => window.setTimeout(r, 700));
    }
  }
}
