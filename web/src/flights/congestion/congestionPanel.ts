// The congestion panel of the flight dashboard: runs a congestion analysis (POST /api/v1/congestion, a
// job followed over the job WebSocket) for the current time window and filters, on the grid of the map
// view or an uploaded sector set; draws the volumes coloured by occupancy against their thresholds at the
// current instant (the playback clock's while the playback view is open, else the largest over the time
// histogram's window); the selected volume's occupancy and entry series; the ranked hotspots (click: the
// map fits the volume, the time window becomes the hotspot's, the involved flights are drawn); the
// separation events as a list and as markers (click: the clock jumps to the closest point of approach).

import { ApiError, api, fetchOk, isAbort } from '../../api/client';
import type { Job } from '../../api/types';
import { h, mount, sectionHead } from '../../lib/dom';
import { formatAltitude, formatDuration, formatFlightLevel, formatInt, formatUtc, formatUtcTime } from '../../lib/format';
import type { Clock } from '../clock';
import type { MapView } from '../map';
import type { Store } from '../state';
import { congestionApi } from './api';
import { validateFilters } from '../../api/query';
import { CongestionLayer } from './congestionLayer';
import {
  CLASS_STYLE,
  footprintStates,
  rankHotspots,
  stepAt,
  stepsInWindow,
  volumeState,
  type CongestionModel,
  type Hotspot,
  type HotspotOrder,
  type Volume,
  cpaPoint,
  gridFootprints,
  sectorFootprints,
  type Footprint,
} from './model';
import { parseResult } from './model';
import { SeriesChart } from './seriesChart';
import type { Compute, CongestionBody, Method } from './types';
import { congestionBody, congestionTileTemplate } from './request';
import './congestion.css';

const FINISHED = new Set(['done', 'failed', 'cancelled']);
const COMPUTE: { value: Compute; label: string; checked: boolean; title: string }[] = [
  { value: 'occupancy', label: 'occupancy', checked: true, title: 'Flights in each volume per counting period' },
  { value: 'entries', label: 'entries', checked: true, title: 'Entries into each volume per rolling window' },
  { value: 'hotspots', label: 'hotspots', checked: true, title: 'Runs of periods above the peak or sustained threshold' },
  { value: 'complexity', label: 'complexity', checked: false, title: 'The PRU complexity score per volume-hour' },
  { value: 'separation', label: 'separation', checked: true, title: 'Losses of separation (5 NM, 1,000 ft; 2,000 ft above FL410)' },
];
/** Hotspots and separation events listed (the API returns more; the CSV tables hold them all). */
const MAX_LISTED = 100;
/** Flight tracks of a hotspot fetched to draw on the map (the list names them all). */
const MAX_TRACKS = 40;

export interface CongestionPanelDeps {
  store: Store;
  map: MapView;
  clock: Clock;
  /** Whether the playback view is open (the clock's instant rules); else the time window does. */
  playbackOn(): boolean;
  /** Selects one flight in the dashboard (its card, its track, the playback's selection). */
  onSelectFlight(id: number, callsign: string, icao24: string): void;
}

interface NumField {
  name: string;
  label: string;
  el: HTMLInputElement;
  hint: string;
}

export class CongestionPanel {
  private readonly root: HTMLElement;
  private readonly layer: CongestionLayer;
  private readonly chart: SeriesChart;
  private readonly volumeMode: Record<'grid' | 'sectors', HTMLInputElement>;
  private readonly sectorSelect: HTMLSelectElement;
  private readonly sectorBox: HTMLElement;
  private readonly computeInputs = new Map<Compute, HTMLInputElement>();
  private readonly fields: NumField[] = [];
  private readonly method: HTMLSelectElement;
  private readonly startBtn: HTMLButtonElement;
  private readonly errorBox: HTMLElement;
  private readonly status: HTMLElement;
  private readonly resultBox: HTMLElement;
  private readonly instantLabel: HTMLElement;
  private readonly volumeBox: HTMLElement;
  private readonly hotspotList: HTMLElement;
  private readonly hotspotOrder: HTMLSelectElement;
  private readonly flightsBox: HTMLElement;
  private readonly sepList: HTMLElement;
  private job: Job | null = null;
  private model: CongestionModel | null = null;
  private volumeIndex: number | null = null;
  private hotspot: Hotspot | null = null;
  private rangeKey = '';
  private activeKey = '';
  private readonly mapBox: HTMLElement;
  private readonly mapToggle: HTMLInputElement;
  private readonly mapThreshold: HTMLInputElement;
  private readonly mapError: HTMLElement;
  private loadCtrl: AbortController | null = null;
  private tracksCtrl: AbortController | null = null;

  constructor(
    root: HTMLElement,
    private readonly deps: CongestionPanelDeps,
  ) {
    this.root = root;
    root.dataset.state = 'idle';
    this.layer = new CongestionLayer(deps.map.map, {
      onVolumeClick: (fp) => this.onFootprintClick(fp),
      onEventClick: (i) => this.selectEvent(i),
      onTilesError: (detail) => {
        this.mapError.textContent = `Congestion map: ${detail}`;
        this.mapError.hidden = false;
      },
    });
    this.chart = new SeriesChart((t) => this.seek(t));

    const radio = (m: 'grid' | 'sectors') => {
      const el = h('input', { type: 'radio', name: 'cong-volumes', value: m, id: `cong-volumes-${m}`, 'data-testid': `cong-volumes-${m}` });
      el.addEventListener('change', () => this.syncForm());
      return el;
    };
    this.volumeMode = { grid: radio('grid'), sectors: radio('sectors') };
    this.volumeMode.grid.checked = true;
    this.sectorSelect = h('select', { id: 'cong-sector-set', 'aria-label': 'Sector set', 'data-testid': 'cong-sector-set', 'data-param': 'sectors' });
    const fileInput = h('input', { type: 'file', accept: '.geojson,.json,application/geo+json', class: 'visually-hidden', id: 'cong-sector-file', 'data-testid': 'cong-sector-file' });
    fileInput.addEventListener('change', () => {
      const f = fileInput.files?.[0];
      fileInput.value = '';
      if (f) void this.uploadSectors(f);
    });
    const delBtn = h('button', { type: 'button', class: 'btn small', 'data-testid': 'cong-sector-delete', title: 'Delete the selected sector set' }, 'Delete');
    delBtn.addEventListener('click', () => void this.deleteSectors());
    this.sectorBox = h(
      'div',
      { class: 'cong-sectors', hidden: true },
      this.sectorSelect,
      h('label', { class: 'btn small', for: 'cong-sector-file', title: 'GeoJSON FeatureCollection of Polygon features with name, lower_fl, upper_fl and optional peak, sustained' }, 'Upload…', fileInput),
      delBtn,
    );

    for (const c of COMPUTE) {
      const el = h('input', { type: 'checkbox', value: c.value, checked: c.checked, 'data-testid': `cong-compute-${c.value}`, 'data-param': 'compute' });
      this.computeInputs.set(c.value, el);
    }
    const field = (name: string, label: string, hint: string, placeholder: string) => {
      const el = h('input', { type: 'text', inputmode: 'decimal', id: `cong-${name}`, placeholder, autocomplete: 'off', 'data-param': name, 'data-testid': `cong-${name}` });
      this.fields.push({ name, label, el, hint });
      return h('div', { class: 'field', title: hint }, h('label', { class: 'field-label', for: `cong-${name}` }, label), el);
    };
    this.method = h(
      'select',
      { id: 'cong-method', 'data-param': 'method', 'data-testid': 'cong-method' },
      h('option', { value: 'interpolated' }, 'interpolated'),
      h('option', { value: 'samples' }, 'samples'),
    );
    this.startBtn = h('button', { type: 'button', class: 'btn primary', 'data-testid': 'cong-start', disabled: true }, 'Analyse this window');
    this.startBtn.addEventListener('click', () => void this.start());
    this.errorBox = h('div', { class: 'field-error', role: 'alert', hidden: true, 'data-testid': 'cong-error' });
    this.status = h('div', { class: 'bundle-status', 'aria-live': 'polite', 'data-testid': 'cong-status' });
    this.resultBox = h('div', { class: 'cong-result', 'data-testid': 'cong-result' });
    this.instantLabel = h('div', { class: 'cong-instant small muted', 'data-testid': 'cong-instant' });
    this.volumeBox = h('div', { class: 'cong-volume', 'data-testid': 'cong-volume' });
    this.hotspotOrder = h(
      'select',
      { 'aria-label': 'Rank hotspots by', 'data-testid': 'cong-hotspot-order', class: 'cong-order' },
      h('option', { value: 'excess' }, 'by excess'),
      h('option', { value: 'duration' }, 'by duration'),
    );
    this.hotspotOrder.addEventListener('change', () => this.renderHotspots());
    this.hotspotList = h('ol', { class: 'cong-list', 'data-testid': 'cong-hotspots' });
    this.flightsBox = h('div', { class: 'cong-flights', 'data-testid': 'cong-flights' });
    this.sepList = h('ol', { class: 'cong-list', 'data-testid': 'cong-separation' });
    this.mapToggle = h('input', { type: 'checkbox', id: 'cong-map', 'data-testid': 'cong-map-toggle' });
    this.mapThreshold = h('input', { type: 'text', inputmode: 'decimal', id: 'cong-map-threshold', value: '1', 'aria-label': 'Congestion map threshold (aircraft per pixel)', 'data-testid': 'cong-map-threshold', class: 'cong-map-threshold' });
    this.mapToggle.addEventListener('change', () => void this.checkTiles());
    this.mapError = h('div', { class: 'error-text small', hidden: true, 'data-testid': 'cong-map-error' });
    this.mapThreshold.addEventListener('change', () => this.syncTiles());
    this.mapBox = h(
      'div',
      { class: 'cong-map-row small', title: 'The congestion map: aircraft per pixel at the clock (playback) or averaged over the time window, below the threshold transparent' },
      h('label', { for: 'cong-map' }, this.mapToggle, ' Congestion map, from'),
      this.mapThreshold,
      h('span', { class: 'muted' }, 'aircraft / px'),
    );

    root.append(
      sectionHead('Congestion', h('span', { class: 'section-meta' }, 'occupancy · hotspots · separation')),
      h(
        'div',
        { class: 'segmented', role: 'radiogroup', 'aria-label': 'Volumes' },
        h('label', { for: 'cong-volumes-grid', title: '20 NM × 20 NM × 3,000 ft cells over the map view and the altitude filter' }, this.volumeMode.grid, h('span', {}, 'Grid (map view)')),
        h('label', { for: 'cong-volumes-sectors', title: 'An uploaded sector set' }, this.volumeMode.sectors, h('span', {}, 'Sectors')),
      ),
      this.sectorBox,
      this.mapBox,
      this.mapError,
      h('div', { class: 'cong-compute', role: 'group', 'aria-label': 'Compute' }, ...COMPUTE.map((c) => h('label', { title: c.title }, this.computeInputs.get(c.value)!, ` ${c.label}`))),
      h(
        'div',
        { class: 'bundle-grid' },
        field('step', 'step s', 'Seconds between counting periods (1 to 3600)', '60'),
        field('duration', 'period s', 'Length of a counting period in seconds (60 to 3600)', '60'),
        h('div', { class: 'field', title: 'interpolated: the trajectory between samples; samples: only reported positions' }, h('label', { class: 'field-label', for: 'cong-method' }, 'method'), this.method),
        field('peak', 'peak', 'Peak threshold (flights): a period above it is a hotspot; sectors with their own keep theirs', ''),
        field('sustained', 'sustained', 'Sustained threshold (flights): N consecutive periods above it are a hotspot', ''),
        field('sustained_steps', 'N periods', 'Consecutive periods a sustained hotspot lasts at least', '3'),
      ),
      h('div', { class: 'bundle-actions' }, this.startBtn),
      this.errorBox,
      this.status,
      this.resultBox,
    );
    this.fields.find((f) => f.name === 'peak')!.el.value = '10';
    this.fields.find((f) => f.name === 'sustained')!.el.value = '8';

    deps.store.subscribe((s, prev) => {
      if (s.datasetId !== prev.datasetId) this.reset();
      if (s.filters.t0 !== prev.filters.t0 || s.filters.t1 !== prev.filters.t1) this.refreshInstant();
      this.syncForm();
      if (s.datasetId !== prev.datasetId || s.filters !== prev.filters) this.syncTiles();
    });
    deps.clock.subscribe((c, prev) => {
      if (c.t !== prev.t || c.span !== prev.span) this.refreshInstant();
      if (c.t !== prev.t || c.playing !== prev.playing) this.syncTiles();
    });
    void this.loadSets();
    this.syncForm();
  }

  // ---------- form ----------

  private usesSectors(): boolean {
    return this.volumeMode.sectors.checked;
  }

  private syncForm() {
    this.sectorBox.hidden = !this.usesSectors();
    const running = this.job !== null && !FINISHED.has(this.job.state);
    this.startBtn.disabled = running || this.deps.store.dataset() === null || (this.usesSectors() && !this.sectorSelect.value);
  }

  private async loadSets(select?: string) {
    try {
      const { sectors } = await congestionApi.sectorSets();
      const keep = select ?? this.sectorSelect.value;
      mount(this.sectorSelect, ...sectors.map((s) => h('option', { value: s.id, selected: s.id === keep }, `${s.name} (${s.sectors})`)));
      if (sectors.length === 0) mount(this.sectorSelect, h('option', { value: '' }, 'no sector sets: upload one'));
    } catch (e) {
      this.showError(e);
    }
    this.syncForm();
  }

  private async uploadSectors(f: File) {
    this.clearError();
    try {
      const meta = await congestionApi.uploadSectors(f, f.name.replace(/\.(geo)?json$/i, ''));
      await this.loadSets(meta.id);
    } catch (e) {
      this.showError(e);
    }
  }

  private async deleteSectors() {
    const id = this.sectorSelect.value;
    if (!id) return;
    this.clearError();
    try {
      await congestionApi.deleteSectors(id);
      await this.loadSets();
    } catch (e) {
      this.showError(e);
    }
  }

  private showError(e: unknown) {
    if (isAbort(e)) return;
    const err = e instanceof ApiError ? e : new ApiError(0, { error: 'client', detail: String(e) });
    this.errorBox.textContent = err.param ? `${err.param}: ${err.detail}` : err.detail;
    this.errorBox.hidden = false;
    for (const el of this.root.querySelectorAll<HTMLElement>('[aria-invalid]')) el.removeAttribute('aria-invalid');
    if (err.param) for (const el of this.root.querySelectorAll<HTMLElement>(`[data-param="${CSS.escape(err.param)}"]`)) el.setAttribute('aria-invalid', 'true');
  }

  private clearError() {
    this.errorBox.hidden = true;
    this.errorBox.textContent = '';
    for (const el of this.root.querySelectorAll<HTMLElement>('[aria-invalid]')) el.removeAttribute('aria-invalid');
  }

  /** The request for the current data set, time window and filters (request.ts). */
  private body(): CongestionBody | null {
    const d = this.deps.store.dataset();
    if (!d) return null;
    const s = this.deps.store.get();
    return congestionBody({
      dataset: d,
      filters: s.filters,
      mapBBox: s.mapBBox,
      sectors: this.usesSectors() ? this.sectorSelect.value : null,
      compute: COMPUTE.map((c) => c.value).filter((c) => this.computeInputs.get(c)!.checked),
      method: this.method.value as Method,
      fields: Object.fromEntries(this.fields.map((f) => [f.name, f.el.value])),
    });
  }

  private async start() {
    const body = this.body();
    if (!body) return;
    const problem = validateFilters(this.deps.store.get().filters);
    if (problem) {
      this.showError(new ApiError(400, { error: 'invalid_argument', ...problem })); // never sent
      return;
    }
    this.clearError();
    this.startBtn.disabled = true;
    try {
      const accepted = await congestionApi.start(body);
      this.job = null;
      this.update(accepted.job, true);
      // Events sent before this answer arrived were not ours yet: catch up once.
      this.update(await api.job(accepted.job.id));
    } catch (e) {
      this.showError(e);
      this.syncForm();
    }
  }

  // ---------- the job ----------

  /** A job event (the job WebSocket, or polling): only this panel's current job is followed. */
  update(job: Job, started = false): void {
    if (!started && (!this.job || job.id !== this.job.id)) return;
    if (this.job && (FINISHED.has(this.job.state) || (job.state === this.job.state && job.progress < this.job.progress))) return;
    this.job = job;
    this.root.dataset.state = job.state === 'done' ? 'loading' : job.state;
    this.root.dataset.job = job.id;
    const pct = Math.round(Math.min(1, Math.max(0, job.state === 'done' ? 1 : job.progress)) * 100);
    const cancel = h('button', { type: 'button', class: 'link-button', 'data-testid': 'cong-cancel' }, 'Cancel');
    cancel.addEventListener('click', () => void api.cancelJob(job.id).catch(() => undefined));
    mount(
      this.status,
      h('div', { class: 'job-line' }, h('span', {}, `Congestion ${job.id}`), h('span', { class: 'job-state' }, FINISHED.has(job.state) ? job.state : `${job.stage || job.state} · ${pct}%`)),
      h(
        'div',
        { class: 'progress', role: 'progressbar', 'aria-label': 'Congestion analysis progress', 'aria-valuemin': 0, 'aria-valuemax': 100, 'aria-valuenow': pct, 'data-testid': 'cong-progress' },
        h('div', { class: 'progress-fill', style: `width:${pct}%` }),
      ),
      job.error ? h('div', { class: 'error-text small' }, job.error.detail || job.error.error) : null,
      FINISHED.has(job.state) ? null : cancel,
    );
    this.syncForm();
    if (job.state === 'done') void this.load(job.id);
  }

  private async load(job: string) {
    this.loadCtrl?.abort();
    const ctrl = new AbortController();
    this.loadCtrl = ctrl;
    try {
      const wire = await congestionApi.result(job, ctrl.signal);
      const model = parseResult(wire, job);
      let footprints: Footprint[];
      if (model.grid) footprints = gridFootprints(model.volumes);
      else {
        const set = 'sectors' in wire.volumes ? wire.volumes.sectors : '';
        footprints = sectorFootprints(await congestionApi.sectorGeojson(set, ctrl.signal), model.volumes);
      }
      if (ctrl.signal.aborted) return;
      this.show(model, footprints);
      this.root.dataset.state = 'done';
    } catch (e) {
      if (isAbort(e)) return;
      this.root.dataset.state = 'failed';
      this.showError(e);
    }
  }

  // ---------- the result ----------

  private show(m: CongestionModel, footprints: Footprint[]) {
    this.model = m;
    this.volumeIndex = null;
    this.hotspot = null;
    this.rangeKey = '';
    this.activeKey = '';
    this.layer.setFootprints(footprints);
    this.layer.setEvents(m.separation);
    this.layer.setFlights([]);
    const kv = (k: string, v: string, testid: string) => h('div', { class: 'kv' }, h('span', { class: 'muted' }, k), h('span', { class: 'mono', 'data-testid': testid }, v));
    const p = m.periods;
    const links = (['series', 'hotspots', 'separation'] as const)
      .filter((t) => (t === 'separation' ? m.separation !== null : m.volumes.length > 0))
      .map((t) => h('a', { href: congestionApi.csvUrl(m.job, t), download: `congestion-${m.job}-${t}.csv`, class: 'link-button' }, t));
    mount(
      this.resultBox,
      kv('Window', `${formatUtc(p.t0)} – ${formatUtcTime(p.t1)}`, 'cong-window'),
      kv('Flights', formatInt(m.flights), 'cong-flight-count'),
      kv(m.grid ? 'Cells with traffic' : 'Sectors', formatInt(m.volumes.length), 'cong-volume-count'),
      kv('Periods', `${formatInt(p.steps)} × ${formatDuration(p.duration)}, every ${formatDuration(p.step)}`, 'cong-periods'),
      kv('Hotspots', formatInt(m.hotspotsTotal), 'cong-hotspot-count'),
      m.separation ? kv('Losses of separation', formatInt(m.separation.length), 'cong-separation-count') : null,
      h('div', { class: 'cong-legend', 'data-testid': 'cong-legend' }, ...CLASS_STYLE.map((s) => h('span', { class: 'cong-legend-item', 'data-class': s.cls }, h('i', { style: `background:${s.color}` }), s.label))),
      this.instantLabel,
      this.volumeBox,
      this.chart.el,
      h('div', { class: 'sub-title cong-sub' }, h('span', {}, 'Hotspots'), this.hotspotOrder),
      this.hotspotList,
      this.flightsBox,
      m.separation ? h('div', { class: 'sub-title' }, 'Losses of separation') : null,
      m.separation ? this.sepList : null,
      links.length ? h('div', { class: 'cong-links small' }, 'CSV: ', ...links) : null,
    );
    mount(this.flightsBox);
    this.renderHotspots();
    this.renderEvents();
    // Start on the worst hotspot's volume, else the busiest volume.
    const first = rankHotspots(m.hotspots, 'excess')[0];
    let busiest = -1;
    m.volumes.forEach((v, i) => (busiest < 0 || v.maxOccupancy > m.volumes[busiest]!.maxOccupancy) && (busiest = i));
    this.selectVolume(first ? first.volumeIndex : busiest >= 0 ? busiest : null, false);
    this.refreshInstant();
  }

  private renderHotspots() {
    const m = this.model;
    if (!m) return;
    const ranked = rankHotspots(m.hotspots, this.hotspotOrder.value as HotspotOrder).slice(0, MAX_LISTED);
    if (ranked.length === 0) {
      mount(this.hotspotList, h('li', { class: 'empty' }, m.volumes.some((v) => v.peak !== null || v.sustained !== null) ? 'No volume exceeds its thresholds.' : 'Set a peak or sustained threshold to find hotspots.'));
      return;
    }
    mount(
      this.hotspotList,
      ...ranked.map((hs, i) => {
        const v = m.volumes[hs.volumeIndex]!;
        const li = h(
          'li',
          {
            class: `cong-hotspot${hs === this.hotspot ? ' selected' : ''}`,
            tabindex: 0,
            'data-testid': 'cong-hotspot',
            'data-rank': i + 1,
            'data-volume': hs.volume,
            'data-kind': hs.kind,
            'data-start': hs.start,
            'data-end': hs.end,
            'data-peak': hs.peak,
            'data-excess': hs.excess,
            'data-flights': hs.flights.length,
          },
          h('div', { class: 'cong-row' }, h('span', { class: 'mono' }, `${i + 1}. ${hs.volume}`), h('span', { class: `cong-kind ${hs.kind}` }, hs.kind)),
          h(
            'div',
            { class: 'cong-row small muted' },
            h('span', { 'data-testid': 'cong-hotspot-time' }, `${formatUtcTime(hs.start)}–${formatUtcTime(hs.end)}`),
            h('span', { class: 'mono', 'data-testid': 'cong-hotspot-numbers' }, `peak ${hs.peak} > ${hs.threshold} (+${hs.excess}) · ${hs.flights.length} fl`),
          ),
          h('div', { class: 'small muted' }, volumeLevels(v)),
        );
        li.addEventListener('click', () => this.selectHotspot(hs));
        li.addEventListener('keydown', (e) => e.key === 'Enter' && this.selectHotspot(hs));
        return li;
      }),
    );
  }

  private renderEvents() {
    const m = this.model;
    if (!m?.separation) return;
    if (m.separation.length === 0) {
      mount(this.sepList, h('li', { class: 'empty' }, 'No loss of separation in this window.'));
      return;
    }
    mount(
      this.sepList,
      ...m.separation.slice(0, MAX_LISTED).map((e, i) => {
        const li = h(
          'li',
          { class: 'cong-event', tabindex: 0, 'data-testid': 'cong-event', 'data-index': i, 'data-cpa-t': e.cpa.t },
          h('div', { class: 'cong-row' }, h('span', { class: 'mono' }, `${e.callsign_a || e.icao24_a || e.flight_a} · ${e.callsign_b || e.icao24_b || e.flight_b}`), h('span', { class: 'small muted' }, formatUtcTime(e.cpa.t))),
          h('div', { class: 'small muted mono' }, `CPA ${(e.cpa.horizontal_m / 1852).toFixed(2)} NM, ${formatInt(Math.round(e.cpa.vertical_m / 0.3048))} ft · ${formatDuration(e.duration_s)}`),
        );
        li.addEventListener('click', () => this.selectEvent(i));
        li.addEventListener('keydown', (ev) => ev.key === 'Enter' && this.selectEvent(i));
        return li;
      }),
    );
  }

  // ---------- selection ----------

  private onFootprintClick(fp: string) {
    const m = this.model;
    if (!m) return;
    const range = this.range().range;
    const st = footprintStates(m, range).get(fp);
    const idx = st ? st.volume : m.volumes.findIndex((v) => v.footprint === fp);
    if (idx >= 0) this.selectVolume(idx, false);
  }

  private selectVolume(i: number | null, fit: boolean) {
    const m = this.model;
    this.volumeIndex = i;
    const v = m && i !== null ? m.volumes[i]! : null;
    this.layer.setSelected(v ? v.footprint : null);
    this.chart.set(m, v);
    this.rangeKey = '';
    this.refreshInstant();
    if (v && fit) {
      const [w, s, e, n] = v.bbox;
      this.deps.map.map.fitBounds(
        [
          [w, s],
          [e, n],
        ],
        { padding: 80, maxZoom: 8, duration: 500 },
      );
    }
  }

  /** A hotspot: the map fits its volume, the time window becomes its interval, the clock its peak. */
  private selectHotspot(hs: Hotspot) {
    this.hotspot = hs;
    this.deps.store.setFilters({ t0: hs.start, t1: hs.end });
    this.deps.clock.seek(hs.peak_time);
    this.selectVolume(hs.volumeIndex, true);
    this.root.dataset.hotspot = `${hs.volume}/${hs.kind}/${hs.start}`;
    this.renderHotspots();
    this.showFlights(hs);
  }

  private showFlights(hs: Hotspot) {
    const d = this.deps.store.dataset();
    mount(
      this.flightsBox,
      h('div', { class: 'sub-title' }, `Flights in ${hs.volume}, ${formatUtcTime(hs.start)}–${formatUtcTime(hs.end)}`),
      h(
        'div',
        { class: 'cong-chips' },
        ...hs.flights.map((f) => {
          const b = h('button', { type: 'button', class: 'cong-chip mono', 'data-testid': 'cong-flight', 'data-flight': f.id, title: `${f.icao24} · flight ${f.id}` }, f.callsign || f.icao24 || String(f.id));
          b.addEventListener('click', () => this.deps.onSelectFlight(f.id, f.callsign, f.icao24));
          return b;
        }),
      ),
    );
    this.tracksCtrl?.abort();
    this.layer.setFlights([]);
    if (!d) return;
    const ctrl = new AbortController();
    this.tracksCtrl = ctrl;
    // The involved flights' tracks during the hotspot (a little before and after, to show the way in).
    const from = hs.start - 300;
    const to = hs.end + 300;
    void Promise.all(
      hs.flights.slice(0, MAX_TRACKS).map((f) =>
        api.flight(d.id, f.id, ctrl.signal).then(
          (feat) => {
            const times = feat.properties.times;
            const coords = feat.geometry.coordinates.filter((_, i) => times[i]! >= from && times[i]! <= to).map((c) => [c[0], c[1]] as [number, number]);
            return { id: f.id, coords };
          },
          () => ({ id: f.id, coords: [] as [number, number][] }),
        ),
      ),
    ).then((lines) => {
      if (ctrl.signal.aborted) return;
      this.layer.setFlights(lines);
      this.flightsBox.dataset.tracks = String(lines.filter((l) => l.coords.length >= 2).length);
    });
  }

  /** A separation event: the clock jumps to its closest point of approach, the map centres there. */
  private selectEvent(i: number) {
    const e = this.model?.separation?.[i];
    if (!e) return;
    const span = this.deps.clock.get().span;
    if (span && (e.cpa.t < span.start || e.cpa.t > span.end)) {
      // The window does not hold the event: widen it to the analysis' window.
      this.deps.store.setFilters({ t0: this.model!.periods.t0, t1: this.model!.periods.t1 });
    }
    this.deps.clock.seek(e.cpa.t);
    this.root.dataset.event = String(i);
    for (const li of this.sepList.querySelectorAll('li')) li.classList.toggle('selected', li.dataset.index === String(i));
    this.deps.map.map.easeTo({ center: cpaPoint(e), zoom: Math.max(this.deps.map.map.getZoom(), 7), duration: 500 });
  }

  /** The playback view opened or closed: the instant's source changed. */
  refresh(): void {
    this.rangeKey = '';
    this.refreshInstant();
    this.syncTiles();
  }

  // ---------- the congestion map ----------

  /**
   * Turning the congestion map on asks for one tile first: MapLibre drops a tile's 404 silently, and an
   * API error (a bad threshold, a server without the route) belongs next to the control.
   */
  private async checkTiles() {
    this.mapError.hidden = true;
    this.syncTiles();
    const template = this.mapToggle.checked ? this.layer.congestionTiles() : null;
    if (!template) return;
    try {
      await fetchOk(template.replace('{z}/{x}/{y}', '0/0/0'));
    } catch (e) {
      if (this.layer.congestionTiles() !== template) return;
      this.mapToggle.checked = false;
      this.syncTiles();
      this.mapError.textContent = `Congestion map: ${e instanceof ApiError ? (e.status === 404 && e.param === 'path' ? 'not served by this server' : e.detail) : String(e)}`;
      this.mapError.hidden = false;
    }
  }

  /**
   * The congestion map's tiles: at the clock while the playback view is open (whole minutes while it
   * plays, so tiles are not asked for every frame), else over the time window (the data set's range
   * without one).
   */
  private syncTiles() {
    const d = this.deps.store.dataset();
    const threshold = Number(this.mapThreshold.value);
    // Filters the dashboard flags as invalid are never sent (the query's inline error says why).
    const ok = d !== null && this.mapToggle.checked && threshold > 0 && validateFilters(this.deps.store.get().filters) === null;
    this.mapThreshold.toggleAttribute('aria-invalid', !(threshold > 0));
    if (!ok) {
      this.layer.setCongestionTiles(null);
      return;
    }
    const f = this.deps.store.get().filters;
    const c = this.deps.clock.get();
    let t: number | null = null;
    const filters = { ...f };
    if (this.deps.playbackOn() && Number.isFinite(c.t)) t = c.playing ? Math.floor(c.t / 60) * 60 : c.t;
    else if (f.t0 === null || f.t1 === null) {
      filters.t0 = Math.floor(d.t_min);
      filters.t1 = Math.floor(d.t_max) + 1;
    }
    this.layer.setCongestionTiles(congestionTileTemplate(window.location.origin, d.id, filters, t, threshold));
  }

  private seek(t: number) {
    this.deps.clock.seek(t);
  }

  // ---------- the instant ----------

  /** The periods shown now: the clock's while the playback view is open, else the time window's. */
  private range(): { range: [number, number] | null; k: number; label: string } {
    const m = this.model!;
    const p = m.periods;
    const t = this.deps.clock.get().t;
    if (this.deps.playbackOn()) {
      const k = stepAt(p, t);
      return { range: k >= 0 ? [k, k] : null, k, label: k >= 0 ? `At ${formatUtc(t)} (period ${k + 1} of ${p.steps})` : `At ${formatUtc(t)}: outside the analysed window` };
    }
    const f = this.deps.store.get().filters;
    const k = stepAt(p, t);
    if (f.t0 !== null && f.t1 !== null) {
      const r = stepsInWindow(p, f.t0, f.t1);
      return { range: r, k, label: r ? `Largest over ${formatUtcTime(f.t0)}–${formatUtcTime(f.t1)} (periods ${r[0] + 1}–${r[1] + 1})` : 'The time window misses the analysed window' };
    }
    return { range: p.steps > 0 ? [0, p.steps - 1] : null, k, label: 'Largest over the analysed window' };
  }

  private refreshInstant() {
    const m = this.model;
    if (!m) return;
    const { range, k, label } = this.range();
    const t = this.deps.clock.get().t;
    const key = range ? range.join('-') : '';
    this.chart.setCursor(t, k);
    const f = this.deps.store.get().filters;
    this.chart.setWindow(f.t0 !== null && f.t1 !== null ? { start: f.t0, end: f.t1 } : null);
    if (key !== this.rangeKey) {
      this.rangeKey = key;
      this.instantLabel.textContent = label;
      this.root.dataset.range = key;
      this.layer.setStates(footprintStates(m, range));
      this.renderVolume(range);
    }
    if (m.separation) {
      const playing = this.deps.playbackOn();
      const active = new Set<number>();
      m.separation.forEach((e, i) => {
        const on = playing ? e.t_start <= t && t <= e.t_end : range !== null && e.t_start < periodEndOf(m, range[1]) && e.t_end >= m.periods.t0 + range[0] * m.periods.step;
        if (on) active.add(i);
      });
      const akey = [...active].join(',');
      if (akey !== this.activeKey) {
        this.activeKey = akey;
        this.layer.setActiveEvents(active);
        for (const li of this.sepList.querySelectorAll<HTMLElement>('li[data-index]')) li.classList.toggle('active', active.has(Number(li.dataset.index)));
      }
    }
  }

  private renderVolume(range: [number, number] | null) {
    const m = this.model!;
    const v = this.volumeIndex === null ? null : m.volumes[this.volumeIndex]!;
    if (!v) {
      mount(this.volumeBox, h('p', { class: 'empty' }, 'Click a volume on the map or a hotspot.'));
      return;
    }
    const st = volumeState(v, range);
    const style = CLASS_STYLE.find((s) => s.cls === st.cls);
    this.volumeBox.dataset.volume = v.id;
    this.volumeBox.dataset.occupancy = String(st.occupancy);
    this.volumeBox.dataset.class = st.cls;
    mount(
      this.volumeBox,
      h('div', { class: 'cong-row' }, h('span', { class: 'mono', 'data-testid': 'cong-volume-id' }, v.id), h('span', { class: 'small muted' }, volumeLevels(v))),
      h(
        'div',
        { class: 'cong-row' },
        h('span', {}, 'Occupancy ', h('b', { class: 'mono', 'data-testid': 'cong-volume-occupancy' }, String(st.occupancy)), style ? h('i', { class: 'cong-swatch', style: `background:${style.color}`, title: style.label }) : null),
        h('span', { class: 'small muted mono', 'data-testid': 'cong-volume-thresholds' }, `peak ${v.peak ?? '–'} · sustained ${v.sustained ?? '–'}`),
      ),
      h('div', { class: 'small muted' }, `max ${v.maxOccupancy} · ${formatInt(v.totalEntries)} entries`),
    );
  }

  private reset() {
    this.loadCtrl?.abort();
    this.tracksCtrl?.abort();
    this.model = null;
    this.job = null;
    this.hotspot = null;
    this.volumeIndex = null;
    this.root.dataset.state = 'idle';
    delete this.root.dataset.job;
    this.layer.setFootprints(null);
    this.layer.setEvents(null);
    this.layer.setFlights([]);
    this.chart.set(null, null);
    mount(this.status);
    mount(this.resultBox);
  }
}

function periodEndOf(m: CongestionModel, k: number): number {
  return Math.min(m.periods.t0 + k * m.periods.step + m.periods.duration, m.periods.t1);
}

function volumeLevels(v: Volume): string {
  return `${formatFlightLevel(v.lowerM)}–${formatFlightLevel(v.upperM)} (${formatAltitude(v.lowerM)}–${formatAltitude(v.upperM)})`;
}
