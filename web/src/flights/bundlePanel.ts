// Bundling panel: CUBu parameters (from the API's own list), "Bundle this window" for the current data set,
// time window, filters and map view, a progress bar fed by the job WebSocket, the quality figures, and the
// raw/bundled toggle with a relaxation slider that blends on the client (no recomputation). The shown
// bundle, its mode, relaxation and colouring are in the URL (flightsView.ts writes them: bundle, bview,
// brelax, bcolor), so a shared link shows the same bundle, marked stale if the link's window is not its own.

import { ApiError, api, bundleTileTemplate, isAbort } from '../api/client';
import { buildQuery, parseFilters, validateFilters, type Filters } from '../api/query';
import type { Bundle, BundleParamInfo, Job } from '../api/types';
import { debounce, h, mount, sectionHead } from '../lib/dom';
import { blendSource, decodeTsbl } from './tsbl';
import { BUNDLE_COLORS, bundleLegend, kmPerMercatorDegree, renderLegend, type BundleColor, type LegendSpec } from '../lib/legend';
import { COLORMAP_STOPS } from '../lib/colors';
import type { BundleOverlay } from './bundleOverlay';
import type { Store } from './state';
import type { ErrorSlots } from './errors';
import type { MapView } from './map';

/** Shown up front; the rest sit under "More parameters". */
const MAIN_PARAMS = ['size', 'h', 'iterations', 'eps', 'lambda', 'spl', 'profile', 'directional'];
const FINISHED = new Set(['done', 'failed', 'cancelled']);

export type BundleMode = 'raw' | 'bundled';

/** A shown bundle as the URL keeps it. */
export interface BundleView {
  id: string;
  mode: BundleMode;
  /** 0 = bundled .. 1 = raw trails. */
  relaxation: number;
  color: BundleColor;
}

/** The bundle view in a URL hash's parameters (bundle, bview, brelax, bcolor), or null without `bundle`. */
export function parseBundleView(q: URLSearchParams): BundleView | null {
  const id = q.get('bundle');
  if (!id || !/^[A-Za-z0-9_-]{1,64}$/.test(id)) return null;
  const relax = Number(q.get('brelax') ?? '0');
  return {
    id,
    mode: q.get('bview') === 'raw' ? 'raw' : 'bundled',
    relaxation: Number.isFinite(relax) ? Math.min(1, Math.max(0, relax)) : 0,
    color: BUNDLE_COLORS.find((c) => c === q.get('bcolor')) ?? 'length',
  };
}

/** Writes `v` into hash parameters `p` (defaults left out: bundled, relaxation 0, colour by length). */
export function writeBundleView(p: URLSearchParams, v: BundleView | null): void {
  if (!v) return;
  p.set('bundle', v.id);
  if (v.mode !== 'bundled') p.set('bview', v.mode);
  if (v.relaxation > 0) p.set('brelax', v.relaxation.toFixed(2));
  if (v.color !== 'length') p.set('bcolor', v.color);
}

export class BundlePanel {
  private readonly root: HTMLElement;
  private readonly paramsBox: HTMLElement;
  private readonly inputs = new Map<string, { info: BundleParamInfo; el: HTMLInputElement | HTMLSelectElement }>();
  private readonly startBtn: HTMLButtonElement;
  private readonly status: HTMLElement;
  private readonly result: HTMLElement;
  private readonly viewBox: HTMLElement;
  private readonly slider: HTMLInputElement;
  private readonly sliderValue: HTMLElement;
  private readonly modeInputs: Record<BundleMode, HTMLInputElement>;
  private job: Job | null = null;
  /** The inputs (data set, filters without the view box, parameters) the current bundle was made from. */
  private madeFrom: string | null = null;
  private readonly staleBox: HTMLElement;
  private readonly legendBox: HTMLElement;
  private readonly colorSelect: HTMLSelectElement;
  private color: BundleColor = 'length';
  /** The loaded bundle's trail lengths (TSBL, Mercator degrees), for the length legend. */
  private lengths: ArrayLike<number> = [];
  /** The bundle legend shown (the PNG export draws it in bundled mode). */
  legendSpec: LegendSpec | null = null;
  private pendingBundle: string | null = null;
  private pendingInputs: string | null = null;
  private bundle: Bundle | null = null;
  private mode: BundleMode = 'raw';
  private relaxation = 0;
  private loadCtrl: AbortController | null = null;
  private readonly applyTilesSoon = debounce(() => this.applyLayers(), 250);
  /** Settles once the parameter list is loaded (a restored bundle fills its fields from it). */
  private readonly paramsLoaded: Promise<void>;

  constructor(
    root: HTMLElement,
    private readonly store: Store,
    private readonly map: MapView,
    private readonly overlay: BundleOverlay,
    private readonly errors: ErrorSlots,
    /** Called when what view() returns changed (the URL follows). */
    private readonly onViewChange: () => void = () => undefined,
  ) {
    this.root = root;
    root.dataset.state = 'idle';
    this.paramsBox = h('div', { class: 'bundle-params' }, h('p', { class: 'empty' }, 'Loading parameters…'));
    this.startBtn = h('button', { type: 'button', class: 'btn primary', 'data-testid': 'bundle-start', disabled: true }, 'Bundle this window');
    this.startBtn.addEventListener('click', () => void this.start());
    this.status = h('div', { class: 'bundle-status', 'aria-live': 'polite', 'data-testid': 'bundle-status' });
    this.result = h('div', { class: 'bundle-result', 'data-testid': 'bundle-result' });

    const modeInput = (m: BundleMode) => {
      const el = h('input', { type: 'radio', name: 'bundle-mode', value: m, id: `bundle-mode-${m}`, 'data-testid': `bundle-mode-${m}` });
      el.addEventListener('change', () => el.checked && this.setMode(m));
      return el;
    };
    this.modeInputs = { raw: modeInput('raw'), bundled: modeInput('bundled') };
    this.modeInputs.raw.checked = true;
    this.slider = h('input', {
      type: 'range',
      id: 'bundle-relaxation',
      min: 0,
      max: 1,
      step: 0.01,
      value: 0,
      'aria-label': 'Relaxation: 0 = bundled, 1 = raw trails',
      'data-testid': 'bundle-relaxation',
    });
    this.sliderValue = h('span', { class: 'mono small' }, '0.00');
    // The overlay follows the slider at once (client blend); tiles follow when it rests (a server render).
    this.slider.addEventListener('input', () => {
      this.relaxation = Number(this.slider.value);
      this.sliderValue.textContent = this.relaxation.toFixed(2);
      this.overlay.setRelaxation(this.relaxation);
      this.applyTilesSoon();
      this.onViewChange();
    });
    this.legendBox = h('div', { class: 'bundle-legend' });
    this.colorSelect = h(
      'select',
      { id: 'bundle-color', 'data-testid': 'bundle-color', 'aria-label': 'Colour bundled trails by' },
      ...BUNDLE_COLORS.map((c) => h('option', { value: c }, c === 'flat' ? 'flat (one colour)' : c)),
    );
    // The tiles colour on the server (the color parameter of the bundle tiles); the legend follows at once.
    this.colorSelect.addEventListener('change', () => {
      this.setColor(this.colorSelect.value as BundleColor);
      this.showLegend();
      this.applyLayers();
      this.onViewChange();
    });
    this.viewBox = h(
      'div',
      { class: 'bundle-view', hidden: true },
      h(
        'div',
        { class: 'segmented', role: 'radiogroup', 'aria-label': 'Map shows' },
        h('label', { for: 'bundle-mode-raw' }, this.modeInputs.raw, h('span', {}, 'Raw')),
        h('label', { for: 'bundle-mode-bundled' }, this.modeInputs.bundled, h('span', {}, 'Bundled')),
      ),
      h('label', { class: 'field-label', for: 'bundle-relaxation' }, 'Relaxation', h('span', { class: 'hint' }, 'bundled → raw'), this.sliderValue),
      this.slider,
      h('label', { class: 'field-label', for: 'bundle-color' }, 'Colour by'),
      this.colorSelect,
      this.legendBox,
    );
    const recompute = h('button', { type: 'button', class: 'link-button', 'data-testid': 'bundle-recompute' }, 'Recompute');
    recompute.addEventListener('click', () => void this.start());
    this.staleBox = h(
      'div',
      { class: 'stale-line', 'data-testid': 'bundle-stale', hidden: true, role: 'status' },
      h('span', { class: 'stale-mark' }, 'stale'),
      h('span', { class: 'small muted' }, ' the time window, filters or parameters changed since this bundle was made '),
      recompute,
    );
    const errorSlot = h('div', { id: 'bundle-error' });
    root.append(
      sectionHead('Bundling', h('span', { class: 'section-meta' }, 'CUBu')),
      this.paramsBox,
      h('div', { class: 'bundle-actions' }, this.startBtn),
      errorSlot,
      this.staleBox,
      this.status,
      this.result,
      this.viewBox,
    );
    errors.register(['source', 'body', 'query'], errorSlot);
    this.paramsLoaded = this.loadParams();
    store.subscribe((s, prev) => {
      if (s.datasetId !== prev.datasetId) this.reset();
      this.startBtn.disabled = !this.canStart();
      this.syncStale();
    });
  }

  private async loadParams() {
    try {
      const { params } = await api.bundleParams();
      const main: HTMLElement[] = [];
      const more: HTMLElement[] = [];
      for (const info of params) (MAIN_PARAMS.includes(info.name) ? main : more).push(this.paramField(info));
      mount(
        this.paramsBox,
        h('div', { class: 'bundle-grid' }, ...main),
        h('details', { class: 'bundle-more' }, h('summary', {}, 'More parameters'), h('div', { class: 'bundle-grid' }, ...more)),
      );
      this.startBtn.disabled = !this.canStart();
    } catch (e) {
      mount(this.paramsBox, h('p', { class: 'error-text small' }, e instanceof ApiError ? e.detail : String(e)));
    }
  }

  private paramField(info: BundleParamInfo): HTMLElement {
    const id = `bundle-param-${info.name}`;
    let el: HTMLInputElement | HTMLSelectElement;
    if (info.type === 'enum' || info.type === 'boolean') {
      const options = info.type === 'boolean' ? ['true', 'false'] : info.range.split(',').map((o) => o.trim());
      el = h('select', { id, 'data-param': info.name, 'data-testid': id }, ...options.map((o) => h('option', { value: o, selected: o === info.default }, o)));
    } else {
      el = h('input', { id, type: 'text', inputmode: 'decimal', placeholder: info.default, autocomplete: 'off', 'data-param': info.name, 'data-testid': id });
    }
    el.addEventListener('input', () => this.syncStale());
    el.addEventListener('change', () => this.syncStale());
    const err = h('div', { id: `${id}-error` });
    this.errors.register([info.name], err);
    this.inputs.set(info.name, { info, el });
    return h(
      'div',
      { class: 'field', title: `${info.help} (${info.range}; default ${info.default})` },
      h('label', { class: 'field-label', for: id }, info.name.replace(/_/g, ' ')),
      el,
      err,
    );
  }

  /** Parameters that differ from their defaults, as text (BundleParams::set reads them). */
  private params(): Record<string, string> {
    const out: Record<string, string> = {};
    for (const [name, { info, el }] of this.inputs) {
      const v = el.value.trim();
      if (v !== '' && v !== info.default) out[name] = v;
    }
    return out;
  }

  /** What a bundle started now would be made from (the view box aside: panning shows, not changes, it). */
  private inputsKey(): string {
    return this.keyOf(this.store.dataset()?.id ?? '', this.store.effectiveFilters());
  }

  private keyOf(dataset: string, filters: Filters): string {
    return `${dataset}?${buildQuery({ ...filters, bbox: null }).toString()}#${JSON.stringify(this.params())}`;
  }

  /** Marks the shown bundle stale once its inputs differ from the dashboard's (one click recomputes). */
  private syncStale() {
    const stale = this.madeFrom !== null && this.bundle !== null && this.madeFrom !== this.inputsKey();
    this.staleBox.hidden = !stale;
    this.root.dataset.stale = String(stale);
  }

  private canStart(): boolean {
    return this.inputs.size > 0 && this.store.dataset() !== null && !(this.job && !FINISHED.has(this.job.state));
  }

  private async start() {
    const d = this.store.dataset();
    if (!d) return;
    // The window as the dashboard shows it, in the view's extent: bundling happens in the view's pixels.
    const s = this.store.get();
    const filters = { ...this.store.effectiveFilters(), bbox: s.mapBBox ?? this.store.effectiveFilters().bbox };
    const problem = validateFilters(filters);
    if (problem) {
      // Never sent: the filter's own inline error already says what to fix.
      this.errors.show('bundle', new ApiError(400, { error: 'invalid_argument', ...problem }));
      return;
    }
    this.errors.clear('bundle');
    this.startBtn.disabled = true;
    const made = this.inputsKey();
    try {
      const accepted = await api.startBundle(d.id, buildQuery(filters), this.params());
      this.pendingInputs = made;
      this.pendingBundle = accepted.bundle;
      this.job = null;
      this.update(accepted.job, true);
      // Events sent before this response arrived were dropped (the job id was unknown): catch up once.
      this.update(await api.job(accepted.job.id));
    } catch (e) {
      const err = e instanceof ApiError ? e : new ApiError(0, { error: 'client', detail: String(e) });
      this.errors.show('bundle', err);
      this.startBtn.disabled = !this.canStart();
    }
  }

  /** A job event (WebSocket or polling): only this panel's current job is followed. */
  update(job: Job, started = false): void {
    if (!started && (!this.job || job.id !== this.job.id)) return;
    // Events can arrive out of order; a job never goes back.
    if (this.job && (FINISHED.has(this.job.state) || (job.state === this.job.state && job.progress < this.job.progress))) return;
    this.job = job;
    this.root.dataset.state = job.state;
    this.root.dataset.job = job.id;
    const pct = Math.round(Math.min(1, Math.max(0, job.state === 'done' ? 1 : job.progress)) * 100);
    const cancel = h('button', { type: 'button', class: 'link-button', 'data-testid': 'bundle-cancel' }, 'Cancel');
    cancel.addEventListener('click', () => void api.cancelJob(job.id).catch(() => undefined));
    mount(
      this.status,
      h('div', { class: 'job-line' }, h('span', {}, `Bundle ${this.pendingBundle ?? ''}`), h('span', { class: 'job-state' }, FINISHED.has(job.state) ? job.state : `${job.stage || job.state} · ${pct}%`)),
      h(
        'div',
        { class: 'progress', role: 'progressbar', 'aria-label': 'Bundling progress', 'aria-valuemin': 0, 'aria-valuemax': 100, 'aria-valuenow': pct, 'data-testid': 'bundle-progress' },
        h('div', { class: 'progress-fill', style: `width:${pct}%` }),
      ),
      job.error ? h('div', { class: 'error-text small' }, job.error.detail || job.error.error) : null,
      FINISHED.has(job.state) ? null : cancel,
    );
    this.startBtn.disabled = !this.canStart();
    if (job.state === 'done') void this.load((job.result as Bundle | null)?.id ?? this.pendingBundle ?? '');
  }

  /**
   * Shows stored bundle `v.id` as a link gave it: its parameters fill the fields, and it is marked stale
   * when the dashboard's window or filters are not the ones it was made from. A bundle of another data set,
   * or one no longer on the server, is not shown; the panel says why.
   */
  async restore(v: BundleView): Promise<void> {
    await this.paramsLoaded;
    this.setColor(v.color);
    this.relaxation = v.relaxation;
    this.slider.value = String(v.relaxation);
    this.sliderValue.textContent = v.relaxation.toFixed(2);
    this.overlay.setRelaxation(v.relaxation);
    await this.load(v.id, v.mode);
  }

  /** The shown bundle's view (null when none is shown). */
  view(): BundleView | null {
    return this.bundle ? { id: this.bundle.id, mode: this.mode, relaxation: this.relaxation, color: this.color } : null;
  }

  private setColor(c: BundleColor) {
    this.color = c;
    this.colorSelect.value = c;
    this.root.dataset.color = c;
  }

  /**
   * Fetches the result's meta and its TSBL polylines (once: the slider blends them locally). `restored`:
   * the mode a link asked for; the bundle's own inputs then say what it was made from.
   */
  private async load(id: string, restored: BundleMode | null = null) {
    this.loadCtrl?.abort();
    const ctrl = new AbortController();
    this.loadCtrl = ctrl;
    try {
      const [meta, buf] = await Promise.all([api.bundle(id, ctrl.signal), api.bundlePolylines(id, ctrl.signal)]);
      const shown = this.store.dataset()?.id;
      if (restored && meta.source.dataset !== shown) {
        mount(this.result, h('p', { class: 'error-text small', 'data-testid': 'bundle-restore-error' }, `Bundle ${id} is of ${meta.source.dataset ? `data set ${meta.source.dataset}` : 'a graph'}, not of ${shown ?? 'the data set shown'}.`));
        return;
      }
      if (restored) {
        // A finished bundle, though no job of this page made it.
        this.root.dataset.state = 'done';
        this.fillParams(meta.params);
        this.pendingInputs = this.keyOf(meta.source.dataset ?? '', parseFilters(new URLSearchParams(meta.source.query ?? {})));
        this.pendingBundle = meta.id;
      }
      this.bundle = meta;
      this.madeFrom = this.pendingInputs;
      this.syncStale();
      const tsbl = decodeTsbl(buf);
      this.overlay.setSource(blendSource(tsbl));
      this.lengths = tsbl.length;
      this.showLegend();
      this.showResult(meta);
      this.root.dataset.bundle = meta.id;
      this.viewBox.hidden = false;
      this.setMode(restored ?? 'bundled');
    } catch (e) {
      if (isAbort(e)) return;
      const why = e instanceof ApiError ? e.detail : String(e);
      mount(this.result, h('p', { class: 'error-text small', 'data-testid': restored ? 'bundle-restore-error' : null }, restored ? `Bundle ${id} from the link: ${why}` : why));
    }
  }

  /** The parameter fields as bundle `params` had them (a field at its default is left empty). */
  private fillParams(params: Record<string, string>) {
    for (const [name, { info, el }] of this.inputs) {
      const v = params[name];
      el.value = v === undefined || v === info.default ? (info.type === 'enum' || info.type === 'boolean' ? info.default : '') : v;
    }
  }

  /**
   * The legend of the bundle tiles' colour mode (lib/legend.ts bundleLegend): by length CUBu's rainbow from
   * the shortest to the longest trail of the bundle, in km (TSBL lengths are Mercator degrees: scaled at the
   * view's latitude, hence "≈"); by direction the bearings; by density and displacement the colour map over
   * their normalised ranges; flat none.
   */
  private showLegend() {
    const lengths = this.lengths;
    let lo = Infinity;
    let hi = -Infinity;
    for (let i = 0; i < lengths.length; i++) {
      const v = lengths[i]!;
      if (Number.isFinite(v)) {
        lo = Math.min(lo, v);
        hi = Math.max(hi, v);
      }
    }
    const k = kmPerMercatorDegree(this.map.map.getCenter().lat);
    const md = Number(this.bundle?.params['max_displacement'] ?? this.inputs.get('max_displacement')?.el.value ?? NaN);
    this.legendSpec = bundleLegend(this.color, { loKm: lo * k, hiKm: hi * k, maxDisplacement: md, cmap: COLORMAP_STOPS.viridis, width: 200 });
    this.legendBox.dataset.color = this.color;
    if (!this.legendSpec) {
      mount(this.legendBox);
      delete this.legendBox.dataset.testid;
      this.legendBox.classList.remove('value-legend');
      return;
    }
    renderLegend(this.legendBox, this.legendSpec);
    this.legendBox.dataset.loKm = String(lo * k);
    this.legendBox.dataset.hiKm = String(hi * k);
  }

  private showResult(b: Bundle) {
    const q = b.quality;
    const row = (k: string, v: string, testid: string) => h('div', { class: 'kv' }, h('span', { class: 'muted' }, k), h('span', { class: 'mono', 'data-testid': testid }, v));
    mount(
      this.result,
      row('Trails', `${b.polylines.toLocaleString('en-US')} (${b.points.toLocaleString('en-US')} points)`, 'bundle-trails'),
      row('Ink reduction', `${(100 * q.ink_reduction).toFixed(1)} %`, 'bundle-ink'),
      row('Displacement', `mean ${q.mean_displacement_px.toFixed(1)} px, max ${q.max_displacement_px.toFixed(1)} px`, 'bundle-displacement'),
      row('Time', `${b.times_ms.total.toFixed(0)} ms on ${b.path}${b.device ? ` (${b.device})` : ''}`, 'bundle-time'),
    );
  }

  private setMode(m: BundleMode) {
    this.mode = m;
    this.modeInputs[m].checked = true;
    this.root.dataset.mode = m;
    this.applyLayers();
    this.onViewChange();
  }

  /** Raw: the density tiles. Bundled: the bundle's tiles at the slider's relaxation, and the overlay. */
  private applyLayers() {
    const d = this.store.dataset();
    const bundled = this.mode === 'bundled' && this.bundle !== null && d !== null && this.bundle.source.dataset === d.id;
    this.map.setDensityShown(!bundled);
    this.map.setBundleTiles(bundled ? bundleTileTemplate(window.location.origin, d!.id, this.bundle!.id, this.relaxation, this.color) : null);
    this.overlay.setVisible(bundled);
  }

  /** Another data set: its bundles do not apply. */
  private reset() {
    this.loadCtrl?.abort();
    this.bundle = null;
    this.job = null;
    this.pendingBundle = null;
    this.madeFrom = this.pendingInputs = null;
    this.syncStale();
    this.overlay.setSource(null);
    this.root.dataset.state = 'idle';
    delete this.root.dataset.bundle;
    mount(this.status);
    mount(this.result);
    this.viewBox.hidden = true;
    this.setMode('raw');
  }
}
