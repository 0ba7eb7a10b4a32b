// Video and tracker-parameter choice, and the button that starts a replay. The parameter form is built
// from GET /api/v1/tracker/params; blank fields keep the server's defaults, only changed values are sent.

import type { TrackerParam, Video } from '../api/trackerTypes';
import { h, mount, sectionHead } from '../lib/dom';
import { trackerHash } from './route';

export interface SetupEvents {
  onStart(video: string, params: Record<string, number>, colormap: string): void;
}

/** Depth colour maps the server knows (the density maps); the first is its default. */
const COLORMAPS = ['viridis', 'inferno', 'magma', 'fire', 'gray'] as const;

/** Checks a typed value against a parameter's range; returns a message or null. */
export function paramProblem(p: TrackerParam, text: string): string | null {
  if (text.trim() === '') return null;
  const v = Number(text);
  if (!Number.isFinite(v)) return `${p.name} must be a number`;
  if (p.integer && !Number.isInteger(v)) return `${p.name} must be a whole number`;
  if (v < p.min || v > p.max) return `${p.name} must lie in [${p.min}, ${p.max}]`;
  return null;
}

export class SetupPanel {
  readonly root: HTMLElement;
  private readonly videoSelect: HTMLSelectElement;
  private readonly videoInfo: HTMLElement;
  private readonly paramsBox: HTMLElement;
  private readonly startBtn: HTMLButtonElement;
  private readonly colormap: HTMLSelectElement;
  private readonly error: HTMLElement;
  private readonly replayInfo: HTMLElement;
  private videos: Video[] = [];
  private params: TrackerParam[] = [];
  private inputs = new Map<string, HTMLInputElement>();

  constructor(private readonly events: SetupEvents) {
    this.videoSelect = h('select', { id: 'tracker-video', 'data-testid': 'tracker-video', 'aria-label': 'Video' });
    this.videoSelect.addEventListener('change', () => this.showVideoInfo());
    this.videoInfo = h('div', { class: 'hint', 'data-testid': 'tracker-video-info' });
    this.paramsBox = h('div', { class: 'tracker-params', 'data-testid': 'tracker-params' }, h('p', { class: 'empty' }, 'Loading parameters…'));
    this.colormap = h('select', { id: 'tracker-colormap', 'data-testid': 'tracker-colormap' }, ...COLORMAPS.map((c) => h('option', { value: c }, c)));
    this.startBtn = h('button', { class: 'btn primary', type: 'button', 'data-testid': 'replay-start', disabled: true }, 'Start replay');
    this.startBtn.addEventListener('click', () => this.start());
    this.error = h('div', { class: 'error-text small', role: 'alert', 'data-testid': 'tracker-error' });
    this.replayInfo = h('div', { class: 'hint replay-info', 'data-testid': 'replay-info' });
    this.root = h(
      'div',
      { class: 'tracker-setup' },
      sectionHead('Replay'),
      h('div', { class: 'field' }, h('label', { class: 'field-label', for: 'tracker-video' }, 'Video'), this.videoSelect, this.videoInfo),
      h('div', { class: 'field' }, h('label', { class: 'field-label', for: 'tracker-colormap' }, 'Depth colours'), this.colormap),
      h('details', { class: 'tracker-params-details' }, h('summary', {}, 'Tracker parameters'), this.paramsBox),
      h('div', { class: 'field' }, this.startBtn),
      this.error,
      this.replayInfo,
    );
  }

  setVideos(videos: Video[], prefer?: string | null): void {
    this.videos = videos;
    mount(
      this.videoSelect,
      ...videos.map((v) => h('option', { value: v.id }, `${v.name || v.id}${v.source?.scenario ? ` (${v.source.scenario})` : ''}`)),
    );
    const pick = videos.find((v) => v.id === prefer || v.name === prefer) ?? videos[0];
    if (pick) this.videoSelect.value = pick.id;
    this.startBtn.disabled = videos.length === 0;
    if (videos.length === 0) this.videoInfo.textContent = 'No videos on the server (trailscope serve --demo adds two).';
    else this.showVideoInfo();
  }

  selectColormap(name: string | undefined): void {
    if (name && (COLORMAPS as readonly string[]).includes(name)) this.colormap.value = name;
  }

  selectVideo(id: string): void {
    if (this.videos.some((v) => v.id === id)) {
      this.videoSelect.value = id;
      this.showVideoInfo();
    }
  }

  setParams(params: TrackerParam[], values: Record<string, number> = {}): void {
    this.params = params;
    this.inputs.clear();
    mount(
      this.paramsBox,
      ...params.map((p) => {
        const id = `tp-${p.name}`;
        const input = h('input', {
          type: 'number',
          id,
          step: p.integer ? 1 : 'any',
          min: p.min,
          max: p.max,
          placeholder: String(p.default_value),
          'data-testid': `tracker-param-${p.name}`,
          'data-param': p.name,
        });
        const v = values[p.name];
        if (v !== undefined && v !== p.default_value) input.value = String(v);
        input.addEventListener('input', () => this.validate());
        this.inputs.set(p.name, input);
        return h(
          'div',
          { class: 'param-row', title: p.help },
          h('label', { for: id, class: 'param-name mono' }, p.name),
          input,
          h('span', { class: 'param-unit muted' }, p.unit),
        );
      }),
    );
  }

  setError(message: string, param?: string): void {
    this.error.textContent = message;
    for (const [name, input] of this.inputs) input.toggleAttribute('aria-invalid', param === name);
  }

  setBusy(busy: boolean): void {
    this.startBtn.disabled = busy || this.videos.length === 0;
    this.startBtn.textContent = busy ? 'Starting…' : 'Start replay';
  }

  setReplay(id: string | null, detail = ''): void {
    if (!id) {
      mount(this.replayInfo);
      return;
    }
    const link = h('a', { href: trackerHash(id), target: '_blank', rel: 'noopener', 'data-testid': 'replay-link' }, 'open another viewer');
    mount(this.replayInfo, 'replay ', h('code', { 'data-testid': 'replay-id' }, id), ' · ', link, detail ? ` · ${detail}` : '');
  }

  /** Shows the stored run on view (instead of a replay). */
  setRun(id: string, detail = ''): void {
    mount(this.replayInfo, 'stored run ', h('code', { 'data-testid': 'run-id' }, id), detail ? ` · ${detail}` : '');
  }

  /** The depth colour map picked. */
  get colormapValue(): string {
    return this.colormap.value;
  }

  private showVideoInfo() {
    const v = this.videos.find((x) => x.id === this.videoSelect.value);
    this.videoInfo.textContent = v
      ? `${v.frame_count} frames · ${v.fps} fps · ${v.intrinsics?.width ?? '?'}×${v.intrinsics?.height ?? '?'} px · ${v.has_truth ? 'ground truth' : 'no truth'}`
      : '';
  }

  private validate(): Record<string, number> | null {
    let values: Record<string, number> | null = {};
    let first: [string, string] | null = null;
    for (const p of this.params) {
      const input = this.inputs.get(p.name)!;
      const problem = paramProblem(p, input.value);
      input.toggleAttribute('aria-invalid', problem !== null);
      if (problem) {
        first ??= [problem, p.name];
        values = null;
      } else if (values && input.value.trim() !== '') {
        const v = Number(input.value);
        if (v !== p.default_value) values[p.name] = v;
      }
    }
    this.error.textContent = first ? first[0] : '';
    return values;
  }

  private start() {
    const values = this.validate();
    if (!values || !this.videoSelect.value) return;
    this.events.onStart(this.videoSelect.value, values, this.colormap.value);
  }
}
