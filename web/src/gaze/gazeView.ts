// The gaze dashboard (#gaze): gaze data sets (list, upload with progress, delete), and one stimulus at a
// time with the stimulus-space density tiles, scanpaths, saccades, bundled saccades and areas of interest
// over it, filtered by participant, time window, event types and detector method. The URL hash holds the
// view (gaze/route.ts), AOIs included; every change rewrites it.

import { ApiError, api, isAbort } from '../api/client';
import { gazeApi, gazeStimulusUrl, gazeTileUrl, type GazeTileRender } from '../api/gaze';
import { GAZE_EVENT_TYPES, GAZE_METHODS, type Aoi, type AoiAnswer, type GazeDataset, type GazeEventType, type GazeFilters, type GazeFormat, type GazeMethod, type Scanpath } from '../api/gazeTypes';
import type { Job } from '../api/types';
import { cubuRainbow, LEGEND_STOPS, densityTicks, linearTicks, renderLegend } from '../lib/legend';
import { debounce, h, mount, sectionHead } from '../lib/dom';
import { formatBytes, formatInt } from '../lib/format';
import { decodeTsbl } from '../flights/tsbl';
import { AoiPanel } from './aoiPanel';
import { nextAoiName } from './geometry';
import { FINISHED_STATES, JobWatch } from './jobWatch';
import { AOI_NAME, DEFAULT_TYPES, gazeHash, isGazeHash, parseGazeHash, type GazeRoute } from './route';
import { FIXATION_RAMP, StimulusView, type DrawMode } from './stimulusView';
import './gaze.css';

/** The density tiles' colour map (the server's name). */
const CMAP = 'fire';

const FORMATS: ['' | GazeFormat, string][] = [
  ['', 'Auto (by content)'],
  ['eyelink_asc', 'EyeLink ASC'],
  ['tobii_tsv', 'Tobii TSV/CSV'],
  ['psychopy_tobii', 'PsychoPy Tobii TSV'],
  ['smi_idf_text', 'SMI iView text'],
  ['gazecom_arff', 'GazeCom ARFF'],
  ['dsf_coord', 'DSF coord'],
  ['simple_gaze_tracker', 'SimpleGazeTracker CSV'],
  ['plain', 'time x y [valid]'],
];

function labelled(text: string, control: HTMLElement): HTMLLabelElement {
  return h('label', { class: 'gaze-field' }, h('span', { class: 'gaze-field-label' }, text), control);
}

function numberInput(testid: string, placeholder: string, title: string): HTMLInputElement {
  return h('input', { type: 'number', min: 0, step: 'any', class: 'num-input', placeholder, title, 'aria-label': title, 'data-testid': testid });
}

const numOrNull = (i: HTMLInputElement) => (i.value.trim() !== '' && Number.isFinite(Number(i.value)) ? Number(i.value) : null);

export class GazeView {
  readonly root: HTMLElement;
  private readonly list: HTMLElement;
  private readonly listStatus: HTMLElement;
  private readonly jobsEl: HTMLElement;
  private readonly uploadError: HTMLElement;
  private readonly upFile: HTMLInputElement;
  private readonly upImage: HTMLInputElement;
  private readonly upName: HTMLInputElement;
  private readonly upFormat: HTMLSelectElement;
  private readonly upParticipant: HTMLInputElement;
  private readonly upStimulus: HTMLInputElement;
  private readonly upGeometry: Record<'width_px' | 'height_px' | 'width_cm' | 'height_cm' | 'distance_cm', HTMLInputElement>;
  private readonly stimulusSelect: HTMLSelectElement;
  private readonly participantSelect: HTMLSelectElement;
  private readonly t0Input: HTMLInputElement;
  private readonly t1Input: HTMLInputElement;
  private readonly methodSelect: HTMLSelectElement;
  private readonly typeBoxes = new Map<GazeEventType, HTMLInputElement>();
  private readonly whatSelect: HTMLSelectElement;
  private readonly howSelect: HTMLSelectElement;
  private readonly layerBoxes: Record<'density' | 'scanpaths' | 'saccades' | 'bundles', HTMLInputElement>;
  private readonly eventCounts: HTMLElement;
  private readonly bundleBtn: HTMLButtonElement;
  private readonly bundleStatus: HTMLElement;
  private readonly densityLegend: HTMLElement;
  private readonly fixationLegend: HTMLElement;
  private readonly drawButtons: Record<'rect' | 'polygon', HTMLButtonElement>;
  private readonly title: HTMLElement;
  private readonly aoiName: HTMLInputElement;
  private readonly stage: StimulusView;
  private readonly aoiPanel: AoiPanel;
  private readonly watch: JobWatch;
  private datasets: GazeDataset[] = [];
  private detail: GazeDataset | null = null;
  private route: GazeRoute = parseGazeHash('#gaze');
  private uploads: { name: string; size: number; fraction: number; job: Job | null; abort(): void }[] = [];
  private tileZ = 0;
  private ctrl = new AbortController();
  private aoiCtrl = new AbortController();
  private legendCtrl = new AbortController();
  private selectedAoi: string | null = null;
  private bundleFor = '';
  private readonly reloadLegend = debounce(() => void this.loadLegend(), 150);

  constructor(host: HTMLElement) {
    this.watch = new JobWatch(() => this.renderJobs());
    this.stage = new StimulusView({
      onAoiDrawn: (shape) => this.addAoi(shape),
      onTileZoom: (z) => {
        this.tileZ = z;
        this.reloadLegend();
      },
    });
    this.aoiPanel = new AoiPanel({
      onRemove: (name) => this.setAois(this.route.aois.filter((a) => a.name !== name)),
      onSelect: (name) => {
        this.selectedAoi = this.selectedAoi === name ? null : name;
        this.stage.setAois(this.route.aois, this.selectedAoi);
      },
    });

    // Data sets
    this.listStatus = h('span', { class: 'small muted', 'data-testid': 'gaze-list-status' });
    this.list = h('ul', { class: 'gaze-list', 'data-testid': 'gaze-list' });

    // Upload
    this.upFile = h('input', { type: 'file', class: 'visually-hidden', id: 'gaze-upload-file', 'data-testid': 'gaze-upload-input' });
    this.upImage = h('input', { type: 'file', accept: 'image/png,image/jpeg', 'data-testid': 'gaze-upload-image', 'aria-label': 'Stimulus image (PNG or JPEG)' });
    this.upName = h('input', { type: 'text', placeholder: 'name (a-z 0-9 _ -)', pattern: '[a-z0-9_\\-]{1,64}', 'data-testid': 'gaze-upload-name', 'aria-label': 'Name of the new gaze data set', autocomplete: 'off', spellcheck: 'false' });
    this.upFormat = h('select', { 'aria-label': 'Format', 'data-testid': 'gaze-upload-format' }, ...FORMATS.map(([v, t]) => h('option', { value: v }, t)));
    this.upParticipant = h('input', { type: 'text', placeholder: "file's", 'data-testid': 'gaze-upload-participant', 'aria-label': 'Participant' });
    this.upStimulus = h('input', { type: 'text', placeholder: "file's", 'data-testid': 'gaze-upload-stimulus', 'aria-label': 'Stimulus' });
    this.upGeometry = {
      width_px: numberInput('gaze-upload-width-px', 'px', 'Screen width (px)'),
      height_px: numberInput('gaze-upload-height-px', 'px', 'Screen height (px)'),
      width_cm: numberInput('gaze-upload-width-cm', 'cm', 'Screen width (cm)'),
      height_cm: numberInput('gaze-upload-height-cm', 'cm', 'Screen height (cm)'),
      distance_cm: numberInput('gaze-upload-distance-cm', 'cm', 'Viewing distance (cm)'),
    };
    this.upFile.addEventListener('change', () => {
      const f = this.upFile.files?.[0];
      if (f) this.upload(f);
      this.upFile.value = '';
    });
    this.uploadError = h('div', { class: 'error-text small', 'data-testid': 'gaze-upload-error' });
    this.jobsEl = h('ul', { class: 'job-list', 'data-testid': 'gaze-jobs', 'aria-live': 'polite' });

    // Filters
    this.stimulusSelect = h('select', { 'aria-label': 'Stimulus', 'data-testid': 'gaze-stimulus', onchange: () => this.setRoute({ stimulus: this.stimulusSelect.value || null }) });
    this.participantSelect = h('select', { 'aria-label': 'Participant', 'data-testid': 'gaze-participant', onchange: () => this.setRoute({ participant: this.participantSelect.value || null }) });
    this.t0Input = numberInput('gaze-t0', 'from', 'Window start (ms after each recording starts)');
    this.t1Input = numberInput('gaze-t1', 'to', 'Window end (ms after each recording starts)');
    const onWindow = debounce(() => this.setRoute({ t0: numOrNull(this.t0Input), t1: numOrNull(this.t1Input) }), 300);
    this.t0Input.addEventListener('input', onWindow);
    this.t1Input.addEventListener('input', onWindow);
    this.methodSelect = h(
      'select',
      { 'aria-label': 'Event detector', 'data-testid': 'gaze-method', onchange: () => this.setRoute({ method: this.methodSelect.value as GazeMethod }) },
      ...GAZE_METHODS.map((m) => h('option', { value: m }, { ivt: 'I-VT (velocity)', idt: 'I-DT (dispersion)', adaptive: 'adaptive (Nyström–Holmqvist)' }[m])),
    );
    const typeRow = h('div', { class: 'gaze-types', 'data-testid': 'gaze-types' });
    for (const t of GAZE_EVENT_TYPES) {
      const box = h('input', { type: 'checkbox', value: t, 'data-testid': `gaze-type-${t}`, onchange: () => this.setRoute({ types: GAZE_EVENT_TYPES.filter((k) => this.typeBoxes.get(k)!.checked) }) });
      this.typeBoxes.set(t, box);
      typeRow.append(h('label', { class: 'check' }, box, t));
    }
    this.whatSelect = h(
      'select',
      { 'aria-label': 'Density of', 'data-testid': 'gaze-what', onchange: () => this.setRoute({ what: this.whatSelect.value as GazeRoute['what'] }) },
      h('option', { value: 'fixations' }, 'fixations (by duration)'),
      h('option', { value: 'samples' }, 'samples'),
    );
    this.howSelect = h(
      'select',
      { 'aria-label': 'Density shading', 'data-testid': 'gaze-how', onchange: () => this.setRoute({ how: this.howSelect.value as GazeRoute['how'] }) },
      h('option', { value: 'log' }, 'log'),
      h('option', { value: 'linear' }, 'linear'),
      h('option', { value: 'eq_hist' }, 'histogram-equalised'),
    );
    const layer = (name: string, testid: string, checked: boolean) => {
      const box = h('input', { type: 'checkbox', checked, 'data-testid': testid, onchange: () => this.applyLayers() });
      return [box, h('label', { class: 'check' }, box, name)] as const;
    };
    const [dBox, dLabel] = layer('density', 'gaze-layer-density', true);
    const [sBox, sLabel] = layer('scanpaths', 'gaze-layer-scanpaths', true);
    const [aBox, aLabel] = layer('saccades', 'gaze-layer-saccades', false);
    const [bBox, bLabel] = layer('bundles', 'gaze-layer-bundles', true);
    this.layerBoxes = { density: dBox, scanpaths: sBox, saccades: aBox, bundles: bBox };
    this.eventCounts = h('div', { class: 'small', 'data-testid': 'gaze-event-counts' });

    this.bundleBtn = h('button', { type: 'button', class: 'btn', 'data-testid': 'gaze-bundle', onclick: () => void this.bundle() }, 'Bundle saccades');
    this.bundleStatus = h('span', { class: 'small muted', 'data-testid': 'gaze-bundle-status' });
    this.densityLegend = h('div', { class: 'gaze-legend', 'data-testid': 'gaze-density-legend', hidden: true });
    this.fixationLegend = h('div', { class: 'gaze-legend', 'data-testid': 'gaze-fixation-legend', hidden: true });
    this.drawButtons = {
      rect: h('button', { type: 'button', class: 'btn small', 'data-testid': 'aoi-draw-rect', 'aria-pressed': 'false', onclick: () => this.toggleDraw('rect') }, 'Draw rectangle'),
      polygon: h('button', { type: 'button', class: 'btn small', 'data-testid': 'aoi-draw-polygon', 'aria-pressed': 'false', onclick: () => this.toggleDraw('polygon') }, 'Draw polygon'),
    };
    this.title = h('div', { class: 'gaze-title', 'data-testid': 'gaze-title' });
    this.aoiName = h('input', { type: 'text', placeholder: 'next: AOI n', maxlength: 32, 'data-testid': 'aoi-name', 'aria-label': 'Name of the next area of interest' });

    const sidebar = h(
      'aside',
      { class: 'gaze-sidebar' },
      h('section', { class: 'panel' }, sectionHead('Gaze data sets', this.listStatus), this.list),
      h(
        'section',
        { class: 'panel gaze-upload', 'data-testid': 'gaze-upload' },
        sectionHead('Upload gaze file'),
        h('div', { class: 'gaze-form' }, labelled('Name', this.upName), labelled('Format', this.upFormat), labelled('Participant', this.upParticipant), labelled('Stimulus', this.upStimulus)),
        h(
          'div',
          { class: 'gaze-form gaze-geometry' },
          labelled('Width px', this.upGeometry.width_px),
          labelled('Height px', this.upGeometry.height_px),
          labelled('Width cm', this.upGeometry.width_cm),
          labelled('Height cm', this.upGeometry.height_cm),
          labelled('Distance cm', this.upGeometry.distance_cm),
        ),
        labelled('Stimulus image', this.upImage),
        h('label', { class: 'btn', for: 'gaze-upload-file', title: 'EyeLink ASC, Tobii, SMI, ARFF or plain time x y files' }, 'Upload gaze file…', this.upFile),
        this.uploadError,
        this.jobsEl,
      ),
      h(
        'section',
        { class: 'panel', 'data-testid': 'gaze-filters' },
        sectionHead('Filters'),
        h('div', { class: 'gaze-form' }, labelled('Stimulus', this.stimulusSelect), labelled('Participant', this.participantSelect), labelled('From ms', this.t0Input), labelled('To ms', this.t1Input), labelled('Detector', this.methodSelect)),
        h('div', { class: 'gaze-field-label' }, 'Events'),
        typeRow,
        this.eventCounts,
      ),
      h(
        'section',
        { class: 'panel' },
        sectionHead('Layers'),
        h('div', { class: 'gaze-types' }, dLabel, sLabel, aLabel, bLabel),
        h('div', { class: 'gaze-form' }, labelled('Density of', this.whatSelect), labelled('Shading', this.howSelect)),
        this.densityLegend,
        this.fixationLegend,
        h('div', { class: 'gaze-row' }, this.bundleBtn, this.bundleStatus),
      ),
      h('section', { class: 'panel' }, sectionHead('Areas of interest'), labelled('Name', this.aoiName), h('div', { class: 'gaze-row' }, this.drawButtons.rect, this.drawButtons.polygon), h('div', { class: 'small muted' }, 'Rectangle: drag. Polygon: click the corners, then click the first one or double-click.')),
    );
    const head = h('div', { class: 'gaze-head' }, this.title, h('button', { type: 'button', class: 'btn small', 'data-testid': 'gaze-fit', title: 'Show the whole stimulus', onclick: () => this.stage.fit() }, 'Fit'));
    const main = h('div', { class: 'gaze-main' }, head, this.stage.el, this.aoiPanel.el);
    this.root = h('div', { class: 'gaze-root', 'data-testid': 'gaze', 'data-state': 'idle' }, sidebar, main);
    host.append(this.root);
    window.addEventListener('keydown', (e) => {
      if (e.key === 'Escape' && isGazeHash(window.location.hash)) this.toggleDraw(null);
    });
    (window as unknown as { trailscopeGaze: GazeView }).trailscopeGaze = this;
  }

  /** Shows the view for `hash` (a "#gaze…" hash). */
  async activate(hash: string): Promise<void> {
    // The bare tab link ("#gaze") returns to the view this tab showed last.
    if (/^#gaze\/?$/.test(hash) && this.route.dataset) {
      this.syncHash();
      await this.loadList();
      return;
    }
    const next = parseGazeHash(hash);
    const changedSet = next.dataset !== this.route.dataset || !this.detail;
    this.route = next;
    this.syncControls();
    await this.loadList();
    if (!this.route.dataset && this.datasets.length) {
      this.route.dataset = this.datasets[0]!.id;
      // A default the view chose is in the hash before the view reports ready (the debounced write is for
      // typing): a link copied at once names what is shown.
      this.syncHash();
    }
    if (changedSet) await this.loadDetail();
    else this.reload();
  }

  // ---------- data sets ----------

  private async loadList(): Promise<void> {
    try {
      this.listStatus.textContent = 'loading…';
      this.datasets = (await gazeApi.list()).datasets;
      this.listStatus.textContent = `${this.datasets.length}`;
      this.list.dataset.state = 'ready';
    } catch (e) {
      this.listStatus.textContent = e instanceof ApiError ? e.detail : String(e);
      this.list.dataset.state = 'error';
      this.datasets = [];
    }
    this.renderList();
  }

  private renderList() {
    mount(
      this.list,
      ...this.datasets.map((d) =>
        h(
          'li',
          { class: `gaze-item${d.id === this.route.dataset ? ' selected' : ''}`, 'data-id': d.id, 'data-testid': 'gaze-item' },
          h(
            'button',
            { type: 'button', class: 'gaze-item-main', onclick: () => this.setRoute({ dataset: d.id, stimulus: null, participant: null, aois: [] }) },
            h('span', { class: 'gaze-item-name' }, d.name || d.id),
            h('span', { class: 'small muted' }, `${d.format} · ${d.recordings} rec. · `, h('span', { 'data-testid': 'gaze-samples', 'data-value': d.samples }, `${formatInt(d.samples)} samples`)),
            h('span', { class: 'small muted' }, `${d.participants.length} participant${d.participants.length === 1 ? '' : 's'} · ${d.stimuli.length} stimul${d.stimuli.length === 1 ? 'us' : 'i'}`),
          ),
          h('button', { type: 'button', class: 'link-button', 'data-testid': 'gaze-delete', title: `Delete ${d.id}`, onclick: () => void this.remove(d) }, 'Delete'),
        ),
      ),
    );
    this.list.dataset.count = String(this.datasets.length);
    if (!this.datasets.length) this.list.append(h('li', { class: 'small muted' }, 'No gaze data sets yet: upload one below.'));
  }

  private async remove(d: GazeDataset) {
    if (!window.confirm(`Delete gaze data set "${d.id}"?`)) return;
    try {
      await gazeApi.remove(d.id);
      if (this.route.dataset === d.id) {
        this.route.dataset = null;
        this.detail = null;
      }
      await this.loadList();
      this.setRoute({ dataset: this.datasets[0]?.id ?? null, stimulus: null, participant: null, aois: [] });
    } catch (e) {
      this.listStatus.textContent = e instanceof ApiError ? e.detail : String(e);
    }
  }

  private async loadDetail() {
    this.ctrl.abort();
    this.detail = null;
    const id = this.route.dataset;
    if (!id) {
      this.root.dataset.state = 'idle';
      this.title.textContent = this.datasets.length ? 'Pick a gaze data set' : 'No gaze data sets';
      return;
    }
    this.root.dataset.state = 'loading';
    try {
      this.detail = await gazeApi.get(id);
    } catch (e) {
      this.root.dataset.state = 'error';
      this.title.textContent = e instanceof ApiError ? e.detail : String(e);
      return;
    }
    this.fillFilterOptions();
    this.reload();
  }

  private fillFilterOptions() {
    const d = this.detail;
    if (!d) return;
    mount(this.stimulusSelect, ...d.stimuli.map((s) => h('option', { value: s }, s)));
    if (!d.stimuli.length) this.stimulusSelect.append(h('option', { value: '' }, '(none)'));
    mount(this.participantSelect, h('option', { value: '' }, 'all'), ...d.participants.map((p) => h('option', { value: p }, p)));
    if (!this.route.stimulus || !d.stimuli.includes(this.route.stimulus)) {
      this.route.stimulus = d.stimuli[0] ?? null;
      this.syncHash();
    }
    this.syncControls();
  }

  // ---------- upload ----------

  private upload(file: File) {
    const name = this.upName.value.trim() || file.name.toLowerCase().replace(/\.[^.]*$/, '').replace(/[^a-z0-9_-]+/g, '_').slice(0, 64) || 'gaze';
    const stimulus = this.upStimulus.value.trim();
    const image = this.upImage.files?.[0] ?? null;
    const geometry = Object.fromEntries(Object.entries(this.upGeometry).map(([k, i]) => [k, numOrNull(i) ?? undefined]));
    this.uploadError.textContent = '';
    const handle = gazeApi.upload(file, { name, format: this.upFormat.value as GazeFormat | '', participant: this.upParticipant.value.trim(), stimulus, ...geometry }, (f) => {
      up.fraction = f;
      this.renderJobs();
    });
    const up = { name, size: file.size, fraction: 0, job: null as Job | null, abort: handle.abort };
    this.uploads.push(up);
    this.renderJobs();
    handle.done
      .then(async (job) => {
        up.job = job;
        const end = await this.watch.follow(job, (j) => {
          up.job = j;
          this.renderJobs();
        });
        if (end.state !== 'done') throw new ApiError(0, end.error ?? { error: end.state, detail: `ingest ${end.state}` });
        const id = (end.result as { gaze?: string } | undefined)?.gaze ?? name;
        if (image) {
          const stim = stimulus || (await gazeApi.get(id)).stimuli[0] || '';
          if (stim) await gazeApi.putStimulus(id, stim, image);
        }
        this.upName.value = '';
        await this.loadList();
        this.setRoute({ dataset: id, stimulus: null, participant: null, aois: [] });
      })
      .catch((e: unknown) => {
        if (!isAbort(e)) this.uploadError.textContent = e instanceof ApiError ? `${e.detail}${e.param ? ` (${e.param})` : ''}` : String(e);
      })
      .finally(() => {
        window.setTimeout(() => {
          this.uploads = this.uploads.filter((u) => u !== up);
          this.renderJobs();
        }, 4000);
        this.renderJobs();
      });
  }

  private renderJobs() {
    const bar = (fraction: number, label: string) => {
      const pct = Math.round(Math.min(1, Math.max(0, fraction)) * 100);
      return h('div', { class: 'progress', role: 'progressbar', 'aria-label': label, 'aria-valuemin': 0, 'aria-valuemax': 100, 'aria-valuenow': pct }, h('div', { class: 'progress-fill', style: `width:${pct}%` }));
    };
    mount(
      this.jobsEl,
      ...this.uploads.map((u) => {
        const j = u.job;
        const state = j ? j.state : 'uploading';
        const text = j ? (FINISHED_STATES.has(j.state) ? j.state : `${j.stage || j.state} · ${Math.round(j.progress * 100)}%`) : `uploading · ${formatBytes(u.size)} · ${Math.round(u.fraction * 100)}%`;
        return h(
          'li',
          { class: `job ${state}`, 'data-state': state, 'data-job-id': j?.id ?? '', 'data-testid': 'gaze-job' },
          h('div', { class: 'job-line' }, h('span', { class: 'job-name' }, u.name), h('span', { class: 'job-state' }, text)),
          bar(j ? (j.state === 'done' ? 1 : j.progress) : u.fraction, `Gaze upload ${u.name}`),
          j?.error ? h('div', { class: 'error-text small' }, j.error.detail || j.error.error) : null,
          !j ? h('button', { type: 'button', class: 'link-button', onclick: () => u.abort() }, 'Cancel') : null,
        );
      }),
    );
    this.jobsEl.hidden = this.uploads.length === 0;
  }

  // ---------- route ----------

  private setRoute(patch: Partial<GazeRoute>) {
    const datasetChanged = patch.dataset !== undefined && patch.dataset !== this.route.dataset;
    Object.assign(this.route, patch);
    this.syncHash();
    if (datasetChanged) {
      this.renderList();
      void this.loadDetail();
    } else this.reload();
  }

  private syncHash() {
    // A write after an await (the user may have left for another dashboard meanwhile) must not bring them back.
    if (!isGazeHash(window.location.hash)) return;
    const next = gazeHash(this.route);
    if (window.location.hash !== next) history.replaceState(null, '', next);
  }

  private syncControls() {
    const r = this.route;
    if (r.stimulus !== null) this.stimulusSelect.value = r.stimulus;
    this.participantSelect.value = r.participant ?? '';
    if (numOrNull(this.t0Input) !== r.t0) this.t0Input.value = r.t0 === null ? '' : String(r.t0);
    if (numOrNull(this.t1Input) !== r.t1) this.t1Input.value = r.t1 === null ? '' : String(r.t1);
    this.methodSelect.value = r.method;
    for (const [t, box] of this.typeBoxes) box.checked = r.types.includes(t);
    this.whatSelect.value = r.what;
    this.howSelect.value = r.how;
  }

  private filters(): GazeFilters {
    const r = this.route;
    return { participant: r.participant, stimulus: r.stimulus, t0_ms: r.t0, t1_ms: r.t1, method: r.method };
  }

  private render(): GazeTileRender {
    return { what: this.route.what, how: this.route.how, cmap: CMAP };
  }

  // ---------- the stimulus and its layers ----------

  /**
   * The stimulus's size: the recordings' screen geometry (the pixel space of the gaze positions), else the
   * image's, else the scanpaths' extent.
   */
  private stimulusSize(image: HTMLImageElement | null, paths: readonly Scanpath[]): [number, number] {
    const rec = this.detail?.recording_list?.find((r) => (!this.route.stimulus || r.stimulus === this.route.stimulus) && r.geometry.width_px && r.geometry.height_px);
    if (rec) return [rec.geometry.width_px!, rec.geometry.height_px!];
    if (image && image.naturalWidth) return [image.naturalWidth, image.naturalHeight];
    let w = 1;
    let hh = 1;
    for (const p of paths) for (const f of p.fixations) if (f.x !== null && f.y !== null) (w = Math.max(w, f.x)), (hh = Math.max(hh, f.y));
    return [Math.ceil(w), Math.ceil(hh)];
  }

  private loadImage(url: string, signal: AbortSignal): Promise<HTMLImageElement | null> {
    return new Promise((resolve) => {
      const im = new Image();
      im.onload = () => resolve(im);
      im.onerror = () => resolve(null);
      signal.addEventListener('abort', () => resolve(null));
      im.src = url;
    });
  }

  private reload() {
    const d = this.detail;
    if (!d) return;
    this.ctrl.abort();
    const ctrl = new AbortController();
    this.ctrl = ctrl;
    void this.loadStimulus(d, ctrl.signal);
  }

  private async loadStimulus(d: GazeDataset, signal: AbortSignal) {
    const f = this.filters();
    const stimulus = this.route.stimulus;
    this.root.dataset.state = 'loading';
    this.title.textContent = `${d.name || d.id}${stimulus ? ` · ${stimulus}` : ''}`;
    try {
      const types = this.route.types.length ? this.route.types : [...DEFAULT_TYPES];
      const [image, sp, ev] = await Promise.all([
        // Only a stimulus with an uploaded image is asked for (no 404 for the others).
        stimulus && (d.stimulus_images ?? []).some((i) => i.stimulus === stimulus) ? this.loadImage(gazeStimulusUrl(d.id, stimulus), signal) : Promise.resolve(null),
        gazeApi.scanpaths(d.id, f, signal),
        gazeApi.events(d.id, f, types, signal),
      ]);
      if (signal.aborted) return;
      const [w, hh] = this.stimulusSize(image, sp.scanpaths);
      this.stage.setStimulus(w, hh, image);
      const span = this.stage.setScanpaths(sp.scanpaths);
      this.stage.setSaccades(ev.events);
      this.renderFixationLegend(span, sp.scanpaths.some((p) => p.fixations.length > 0));
      this.eventCounts.dataset.total = String(ev.events.length);
      mount(this.eventCounts, `${ev.method}: `, ...Object.entries(ev.counts).map(([k, v]) => h('span', { class: 'gaze-count', 'data-type': k, 'data-value': v }, `${formatInt(v)} ${k} `)));
      this.root.dataset.scanpaths = String(sp.scanpaths.length);
      this.stage.setDensity(stimulus ? (z, x, y) => gazeTileUrl(d.id, z, x, y, f, this.render()) : null);
      this.applyLayers();
      this.reloadLegend();
      this.stage.setAois(this.route.aois, this.selectedAoi);
      this.root.dataset.state = 'ready';
      if (this.bundleFor && this.bundleFor !== this.bundleKey()) this.clearBundles();
      void this.loadAois();
    } catch (e) {
      if (isAbort(e) || signal.aborted) return;
      this.root.dataset.state = 'error';
      this.title.textContent = `${d.name || d.id}: ${e instanceof ApiError ? e.detail : String(e)}`;
    }
  }

  private applyLayers() {
    const b = this.layerBoxes;
    this.stage.el.querySelector<HTMLElement>('[data-testid="gaze-density"]')!.hidden = !b.density.checked;
    const show = (sel: string, on: boolean) => this.stage.el.querySelector(sel)?.setAttribute('display', on ? 'inline' : 'none');
    show('.gaze-scanpaths', b.scanpaths.checked);
    show('.gaze-saccades', b.saccades.checked && this.route.types.includes('saccade'));
    show('.gaze-bundles', b.bundles.checked);
    this.densityLegend.hidden = !b.density.checked || this.densityLegend.dataset.state !== 'ready';
  }

  private renderFixationLegend(spanMs: number, any: boolean) {
    this.fixationLegend.hidden = !any;
    if (!any) return;
    const s = spanMs / 1000;
    renderLegend(this.fixationLegend, {
      title: 'Fixation start after the path\'s first (circle area ∝ duration)',
      stops: FIXATION_RAMP,
      ticks: linearTicks(0, s, 4, (v) => `${+v.toFixed(2)} s`),
      width: 200,
      testid: 'gaze-fixation-legend',
    });
  }

  private async loadLegend() {
    const d = this.detail;
    this.legendCtrl.abort();
    const ctrl = new AbortController();
    this.legendCtrl = ctrl;
    this.densityLegend.dataset.state = 'loading';
    if (!d || !this.route.stimulus) return;
    try {
      const span = await gazeApi.tilesLegend(d.id, this.filters(), this.tileZ, this.render(), LEGEND_STOPS, ctrl.signal);
      if (span.empty) {
        this.densityLegend.replaceChildren(h('div', { class: 'value-legend-title' }, 'No gaze under these filters'));
      } else {
        renderLegend(this.densityLegend, {
          title: `Density: ${this.route.what === 'fixations' ? 'fixation ms per pixel' : 'samples per pixel'} (z${span.z})`,
          stops: span.stops.map((x) => x.color),
          ticks: densityTicks(span, this.route.how),
          width: 200,
          testid: 'gaze-density-legend',
          note: { log: 'log scale', linear: 'linear scale', eq_hist: 'histogram-equalised: ticks are quantiles of shaded pixels' }[this.route.how],
        });
      }
      this.densityLegend.dataset.state = 'ready';
    } catch (e) {
      if (isAbort(e)) return;
      this.densityLegend.dataset.state = 'error';
      this.densityLegend.dataset.error = e instanceof ApiError ? `${e.status} ${e.detail}` : String(e);
    }
    this.applyLayers();
  }

  // ---------- AOIs ----------

  private toggleDraw(mode: DrawMode | null) {
    const next: DrawMode = mode === null || this.stage.el.dataset.mode === mode ? 'none' : mode;
    this.stage.setMode(next);
    for (const [m, b] of Object.entries(this.drawButtons)) b.setAttribute('aria-pressed', String(m === next));
  }

  private addAoi(shape: { rect: [number, number, number, number] } | { polygon: [number, number][] }) {
    // The name field's name when it is a valid, unused one; else the next "AOI n".
    const asked = this.aoiName.value.trim();
    const name = AOI_NAME.test(asked) && !this.route.aois.some((a) => a.name === asked) ? asked : nextAoiName(this.route.aois.map((a) => a.name));
    this.aoiName.value = '';
    this.toggleDraw(null);
    this.setAois([...this.route.aois, { name, ...shape } as Aoi]);
  }

  private setAois(aois: Aoi[]) {
    this.route.aois = aois;
    this.syncHash();
    this.stage.setAois(aois, this.selectedAoi);
    void this.loadAois();
  }

  private async loadAois() {
    const d = this.detail;
    this.aoiCtrl.abort();
    const ctrl = new AbortController();
    this.aoiCtrl = ctrl;
    if (!d || !this.route.aois.length) {
      this.aoiPanel.show(null);
      this.aoiPanel.setStatus('No areas of interest: draw one on the stimulus.', 'empty');
      return;
    }
    this.aoiPanel.setStatus('computing…', 'loading');
    try {
      const a: AoiAnswer = await gazeApi.aoi(d.id, this.route.aois, this.filters(), ctrl.signal);
      this.aoiPanel.show(a);
      const outside = a.fixations !== undefined && a.outside !== undefined ? `; ${formatInt(a.outside)} of ${formatInt(a.fixations)} fixations in no AOI` : '';
      this.aoiPanel.setStatus(`${a.aois.length} area${a.aois.length === 1 ? '' : 's'} over ${a.recordings} recording${a.recordings === 1 ? '' : 's'} (${this.route.method})${outside}`, 'ready');
    } catch (e) {
      if (isAbort(e)) return;
      this.aoiPanel.show(null);
      this.aoiPanel.setStatus(e instanceof ApiError ? e.detail : String(e), 'error');
    }
  }

  // ---------- bundling ----------

  private bundleKey(): string {
    return `${this.route.dataset}|${JSON.stringify(this.filters())}`;
  }

  private clearBundles() {
    this.bundleFor = '';
    this.stage.setBundles([]);
    this.bundleStatus.textContent = '';
  }

  private async bundle() {
    const d = this.detail;
    if (!d || !this.route.stimulus) return;
    const key = this.bundleKey();
    this.bundleBtn.disabled = true;
    this.bundleStatus.dataset.state = 'running';
    this.bundleStatus.textContent = 'starting…';
    try {
      const acc = await gazeApi.startBundle(d.id, this.filters());
      const onJob = (j: Job) => {
        if (j.id === acc.job.id && !FINISHED_STATES.has(j.state)) this.bundleStatus.textContent = `${j.stage || j.state} · ${Math.round(j.progress * 100)}%`;
      };
      const end = await this.watch.follow(acc.job, onJob);
      if (end.state !== 'done') throw new ApiError(0, end.error ?? { error: end.state, detail: `bundling ${end.state}` });
      const tsbl = decodeTsbl(await api.bundlePolylines(acc.bundle));
      const lines: { points: Float64Array; color: string }[] = [];
      let maxLen = 0;
      for (let i = 0; i < tsbl.n; i++) maxLen = Math.max(maxLen, tsbl.length[i]!);
      for (let i = 0; i < tsbl.n; i++) {
        const a = tsbl.offsets[i]!;
        const b = tsbl.offsets[i + 1]!;
        lines.push({ points: Float64Array.from(tsbl.bundled.subarray(2 * a, 2 * b)), color: cubuRainbow(maxLen > 0 ? tsbl.length[i]! / maxLen : 0) });
      }
      if (key !== this.bundleKey()) return;
      this.stage.setBundles(lines);
      this.bundleFor = key;
      this.bundleStatus.dataset.state = 'done';
      this.bundleStatus.dataset.bundle = acc.bundle;
      this.bundleStatus.textContent = `${tsbl.n} saccades bundled`;
      this.applyLayers();
    } catch (e) {
      this.bundleStatus.dataset.state = 'failed';
      this.bundleStatus.textContent = e instanceof ApiError ? e.detail : String(e);
    } finally {
      this.bundleBtn.disabled = false;
    }
  }
}
