// The flight map dashboard: wires its store (state.ts), the API and its panels together.

import { ApiError, api, isAbort } from '../api/client';
import { buildQuery, densityTileTemplate, parseFilters, parseRender, validateFilters } from '../api/query';
import { JobSocket } from '../api/socket';
import { FLIGHT_SORTS, type Dataset, type FlightRow, type FlightSort, type Job, type SortOrder, type Summary } from '../api/types';
import { byId, debounce, h } from '../lib/dom';
import { Store, type AppState } from './state';
import { Controls } from './controls';
import { ErrorSlots } from './errors';
import { FlightCard } from './flightCard';
import { FlightList } from './flightList';
import { JobsView } from './jobs';
import { BundlePanel, parseBundleView, writeBundleView, type BundleView } from './bundlePanel';
import { FlowPanel } from './flow/flowPanel';
import { BundleOverlay } from './bundleOverlay';
import { MapView } from './map';
import { SummaryView } from './summary';
import { DensityLegend } from './densityLegend';
import { Picking } from './picking';
import { download, mapPng } from './exportPng';
import { formatUtcSeconds } from '../lib/format';
import { TimeBrush } from './timeBrush';
import { Clock, parsePlayback, writePlayback } from './clock';
import { COLOR_BYS, PlaybackView } from './playback';
import { TrafficAnimation } from './animation';
import { startBundleStream } from './bundleStream';
import type { ColorBy } from './animation/types';
import { dashboardOf } from '../route';
import { CongestionPanel } from './congestion/congestionPanel';

const SUMMARY_BINS = 96;
const PAGE_SIZE = 50;
/** The server's largest export (limits kMaxExportPoints): the links are disabled beyond it. */
const MAX_EXPORT_POINTS = 10_000_000;

/** Latest-wins request channel: starting a new request aborts the previous one. */
class Channel {
  private ctrl: AbortController | null = null;
  next(): AbortSignal {
    this.ctrl?.abort();
    this.ctrl = new AbortController();
    return this.ctrl.signal;
  }
  cancel() {
    this.ctrl?.abort();
    this.ctrl = null;
  }
}

interface HashState {
  datasetId: string | null;
  view: { lng: number; lat: number; zoom: number } | null;
  flight: number | null;
  /** The flight list's order and page (`fsort`, `forder`, `fpage`). */
  flightSort: { sort: FlightSort; order: SortOrder };
  flightPage: number | null;
  /** The time axis's zoomed view (`tview=start,end`), null for the whole data set. */
  timeView: { start: number; end: number } | null;
  /** The playback instant (`at`: the playback view is open), speed, tail and colour-by. */
  playback: ReturnType<typeof parsePlayback> & { colorBy: ColorBy };
  /** The shown bundle (`bundle`, `bview`, `brelax`, `bcolor`: bundlePanel.ts). */
  bundle: BundleView | null;
}

function readHash(): { state: Partial<AppState>; extra: HashState } {
  const q = new URLSearchParams(window.location.hash.replace(/^#/, ''));
  const filters = parseFilters(q);
  const useMapView = filters.bbox !== null || q.get('mapview') === '1';
  filters.bbox = null;
  const view = q.get('view')?.split(',').map(Number);
  const flight = Number(q.get('flight'));
  const color = q.get('color');
  const tview = q.get('tview')?.split(',').map(Number);
  return {
    state: { filters, render: parseRender(q), useMapView },
    extra: {
      datasetId: q.get('dataset'),
      view: view && view.length === 3 && view.every(Number.isFinite) ? { lng: view[0]!, lat: view[1]!, zoom: view[2]! } : null,
      flight: q.has('flight') && Number.isInteger(flight) ? flight : null,
      flightSort: {
        sort: FLIGHT_SORTS.find((c) => c === q.get('fsort')) ?? 't_start',
        order: q.get('forder') === 'desc' ? 'desc' : 'asc',
      },
      flightPage: /^\d+$/.test(q.get('fpage') ?? '') ? Number(q.get('fpage')) : null,
      timeView: tview && tview.length === 2 && tview.every(Number.isFinite) && tview[1]! > tview[0]! ? { start: tview[0]!, end: tview[1]! } : null,
      playback: { ...parsePlayback(q), colorBy: COLOR_BYS.find((c) => c === color) ?? 'altitude' },
      bundle: parseBundleView(q),
    },
  };
}

export class FlightsView {
  private readonly store: Store;
  private readonly errors: ErrorSlots;
  private readonly map: MapView;
  private readonly summary: SummaryView;
  private readonly brush: TimeBrush;
  private readonly flights: FlightList;
  private readonly card: FlightCard;
  private readonly jobs: JobsView;
  private readonly bundles: BundlePanel;
  private readonly legend: DensityLegend;
  private readonly exportBar: HTMLElement;
  private readonly exportLinks: Record<'geojson' | 'csv' | 'summaryJson' | 'summaryCsv', HTMLAnchorElement>;
  /** The last query the server accepted (tiles and the legend follow it), without bbox. */
  private acceptedQuery: URLSearchParams | null = null;
  /** The one time cursor of the dashboard (clock.ts): playback, the histogram's cursor and every time layer. */
  readonly clock: Clock;
  private readonly playback: PlaybackView;
  private readonly congestion: CongestionPanel;
  private readonly summaryCh = new Channel();
  private readonly histCh = new Channel();
  private readonly flightsCh = new Channel();
  private readonly trackCh = new Channel();
  private summaryKey = '';
  private histKey = '';
  private flightsKey = '';
  private flightPage = 0;
  /** The flight list's order (`fsort`, `forder` in the hash) and a page from the hash, used once. */
  private flightSort: { sort: FlightSort; order: SortOrder } = { sort: 't_start', order: 'asc' };
  private initialPage: number | null = null;
  /** Matching points of the last accepted summary (null before one). */
  private lastPoints: number | null = null;
  private initialView: HashState['view'];
  private initialFlight: number | null;
  /** A bundle from the URL, shown once its data set is (used once). */
  private initialBundle: BundleView | null;
  private readonly scheduleRefresh = debounce(() => this.refresh(), 60);
  private readonly writeHash = debounce(() => this.syncHash(), 300);

  constructor() {
    const { state, extra } = readHash();
    this.store = new Store(state);
    this.initialView = extra.view;
    this.initialFlight = extra.flight;
    this.initialBundle = extra.bundle;
    this.flightSort = extra.flightSort;
    this.initialPage = extra.flightPage;
    this.errors = new ErrorSlots(byId('banner'));

    this.map = new MapView(byId('map'), {
      onViewChange: (bbox) => {
        this.store.set({ mapBBox: bbox });
        this.updateLegend();
        this.writeHash();
      },
      onTileError: (err) => this.errors.show('tiles', err),
      onTilesOk: () => this.errors.clear('tiles'),
    });
    this.legend = new DensityLegend(byId('map-area'));
    this.exportBar = h('div', { class: 'map-tools', role: 'toolbar', 'aria-label': 'Export' });
    const pngBtn = h('button', { type: 'button', class: 'btn btn-small', 'data-testid': 'export-png', title: 'The map view with its legend as PNG' }, 'PNG');
    pngBtn.addEventListener('click', () => void this.exportPng());
    // The window's flights (GeoJSON, CSV: streamed by the server) and the summary (JSON, CSV): links the
    // browser downloads itself, pointed at the query the server last accepted.
    const link = (testid: string, label: string, title: string) =>
      h('a', { class: 'btn btn-small', 'data-testid': testid, title, 'aria-disabled': 'true' }, label);
    this.exportLinks = {
      geojson: link('export-geojson', 'GeoJSON', "The window's flights, their matching points only (GeoJSON FeatureCollection)"),
      csv: link('export-csv', 'CSV', "The window's points, one row per point (CSV)"),
      summaryJson: link('export-summary-json', 'Summary JSON', 'The summary of the window (JSON)'),
      summaryCsv: link('export-summary-csv', 'Summary CSV', 'The summary totals of the window (CSV)'),
    };
    this.exportBar.append(h('span', { class: 'small muted' }, 'Export'), pngBtn, ...Object.values(this.exportLinks));
    byId('map-area').append(this.exportBar);
    this.clock = new Clock({ t: extra.playback.at ?? NaN, speed: extra.playback.speed });

    new Controls(byId('dataset-section'), byId('filter-section'), byId('render-section'), this.store, this.errors);
    this.summary = new SummaryView(byId('summary-section'), {
      onCallsign: (callsign) => this.store.setFilters({ callsign }),
      onFlight: (id, callsign) => this.selectFlight({ id, icao24: '', callsign, t_start: NaN, t_end: NaN, points: 0, alt_max_m: NaN }),
    });
    this.brush = new TimeBrush(byId('timeline'), {
      onWindow: (w) => this.store.setFilters({ t0: w?.start ?? null, t1: w?.end ?? null }),
      onCursor: (t) => this.clock.seek(t),
      onView: () => {
        this.syncHistogram();
        this.writeHash();
      },
    });
    if (extra.timeView) this.brush.setView(extra.timeView);
    const timeError = h('div', { id: 'time-error' });
    byId('timeline').querySelector('.brush-head')!.append(timeError);
    this.errors.register(['t0', 't1', 'bins'], timeError);

    this.flights = new FlightList(byId('flights-section'), {
      onPage: (p) => {
        this.flightPage = p;
        this.loadFlights();
      },
      onSelect: (row) => this.selectFlight(row),
      onSort: (sort, order) => {
        this.flightSort = { sort, order };
        this.flights.setSort(sort, order);
        this.flightPage = 0;
        this.loadFlights();
        this.writeHash();
      },
    });
    this.flights.setSort(this.flightSort.sort, this.flightSort.order);
    this.card = new FlightCard(byId('map-overlay'), () => this.store.set({ selectedFlight: null }));
    this.jobs = new JobsView(byId('jobs-section'), {
      onJobDone: (job, mine) => this.onJobDone(job, mine),
      onUploadError: (err) => this.errors.show('upload', err),
    });
    this.errors.register(['name', 'format'], byId('upload-error'));
    this.bundles = new BundlePanel(byId('bundle-section'), this.store, this.map, new BundleOverlay(this.map.map), this.errors, () => this.writeHash());
    new FlowPanel(byId('flow-section'), this.store, this.map.map, this.errors); // flow layer (flow/flowPanel.ts)

    this.playback = new PlaybackView(
      byId('map-area'),
      this.map.map,
      this.clock,
      (map, id, opts) => new TrafficAnimation(map, id, opts),
      {
        onSelect: (id, callsign, icao24) =>
          this.selectFlight({ id, icao24, callsign, t_start: NaN, t_end: NaN, points: 0, alt_max_m: NaN }, false),
        onDeselect: () => this.store.set({ selectedFlight: null }),
        onChange: () => this.onPlaybackChange(),
      },
      { on: extra.playback.at !== null, tail: extra.playback.tail, colorBy: extra.playback.colorBy },
      (map, id, getTime, windowS, onError) => startBundleStream(map, id, getTime, { windowS, onError: (e) => onError(e.detail) }),
    );
    this.clock.subscribe((c, prev) => {
      if (c.t !== prev.t) this.brush.setCursor(this.playback.isOn() ? c.t : null);
      // The URL follows the clock when it rests (not on every frame of playback).
      if (!c.playing || c.speed !== prev.speed) this.writeHash();
    });
    this.map.setDimmed(this.playback.isOn());
    this.congestion = new CongestionPanel(byId('congestion-section'), {
      store: this.store,
      map: this.map,
      clock: this.clock,
      playbackOn: () => this.playback.isOn(),
      onSelectFlight: (id, callsign, icao24) => this.selectFlight({ id, icao24, callsign, t_start: NaN, t_end: NaN, points: 0, alt_max_m: NaN }),
    });
    // Hover and click on the density map pick the flights drawn under the cursor (picking.ts).
    new Picking(byId('map'), {
      map: this.map.map,
      target: () => {
        const d = this.store.dataset();
        return d && this.acceptedQuery ? { dataset: d.id, query: this.acceptedQuery } : null;
      },
      enabled: () => !this.playback.isOn() && this.map.map.getContainer().dataset.densityShown !== 'false',
      onSelect: (f) => this.selectFlight({ id: f.id, icao24: f.icao24, callsign: f.callsign, t_start: NaN, t_end: NaN, points: 0, alt_max_m: NaN }),
    });
    const playback = this.playback;
    (window as unknown as { trailscope: unknown }).trailscope = {
      map: this.map.map,
      store: this.store,
      clock: this.clock,
      get animation() {
        return playback.animation();
      },
    };

    this.store.subscribe((s, prev) => this.onState(s, prev));
    window.addEventListener('keydown', (e) => {
      if (e.key === 'Escape' && this.store.get().selectedFlight !== null && !(e.target as HTMLElement).closest('.brush-plot')) {
        this.store.set({ selectedFlight: null });
      }
    });

    this.brush.setWindow(spanOf(this.store.get()));
    this.brush.setCursor(this.playback.isOn() ? this.clock.get().t : null);
    void this.loadHealth();
    void this.loadDatasets(extra.datasetId);
    const socket = new JobSocket({
      onJob: (job) => {
        this.jobs.update(job);
        this.bundles.update(job);
        this.congestion.update(job);
      },
      onState: (st) => {
        this.jobs.setSocketOpen(st === 'open');
        const dot = byId('ws-status');
        dot.dataset.state = st;
        dot.title = st === 'open' ? 'Live job updates connected' : st === 'connecting' ? 'Connecting to job updates…' : 'Job updates disconnected; retrying';
      },
    });
    socket.start();
  }

  private onState(s: AppState, prev: AppState) {
    if (s.datasetId !== prev.datasetId) this.onDatasetChange(s, prev);
    if (s.filters.t0 !== prev.filters.t0 || s.filters.t1 !== prev.filters.t1) {
      this.brush.setWindow(spanOf(s));
      this.syncClockSpan();
    }
    if (s.filters !== prev.filters || s.useMapView !== prev.useMapView || (s.useMapView && s.mapBBox !== prev.mapBBox)) {
      this.playback.setFilters(s.filters, this.store.effectiveFilters().bbox);
    }
    if (s.selectedFlight !== prev.selectedFlight) {
      this.flights.setSelected(s.selectedFlight);
      this.playback.setSelected(s.selectedFlight);
      if (s.selectedFlight === null) {
        this.trackCh.cancel();
        this.card.hide();
        this.map.showTrack(null);
      }
    }
    const queryChanged =
      s.datasetId !== prev.datasetId ||
      s.filters !== prev.filters ||
      s.render !== prev.render ||
      s.useMapView !== prev.useMapView ||
      (s.useMapView && s.mapBBox !== prev.mapBBox);
    if (queryChanged) this.scheduleRefresh();
    this.writeHash();
  }

  private onDatasetChange(s: AppState, prev: AppState) {
    const d = this.store.dataset();
    byId('dataset-title').textContent = d ? d.name : '';
    this.flights.setMultiDay(d !== null && Math.floor(d.t_min / 86400) !== Math.floor(d.t_max / 86400));
    // A time window belongs to one data set's time range.
    if (prev.datasetId !== null && (s.filters.t0 !== null || s.filters.t1 !== null)) {
      this.store.setFilters({ t0: null, t1: null });
    }
    this.summaryKey = this.histKey = this.flightsKey = '';
    this.syncClockSpan();
    this.playback.setDataset(s.datasetId, d ? [d.t_min, d.t_max] : null);
    if (this.initialView) {
      this.map.map.jumpTo({ center: [this.initialView.lng, this.initialView.lat], zoom: this.initialView.zoom });
      this.initialView = null;
    } else if (d) {
      this.map.fitBBox(d.bbox, prev.datasetId !== null);
    }
  }

  private async loadHealth() {
    const el = byId('health');
    try {
      const hl = await api.health();
      const cl = hl.opencl?.available ? `OpenCL: ${hl.opencl.device ?? 'yes'}` : 'CPU (no OpenCL)';
      el.textContent = `v${hl.version} · ${cl}`;
      el.title = `Server ${hl.status}, ${cl}`;
      el.dataset.state = hl.status === 'ok' ? 'ok' : 'warn';
    } catch (e) {
      el.textContent = 'server unreachable';
      el.dataset.state = 'error';
      if (e instanceof ApiError) this.errors.show('health', e);
    }
  }

  private async loadDatasets(prefer?: string | null) {
    try {
      const { datasets } = await api.datasets();
      this.errors.clear('datasets');
      const current = this.store.get().datasetId;
      const pick = (id: string | null | undefined) => (id ? datasets.find((d) => d.id === id || d.name === id) : undefined);
      const chosen = pick(prefer) ?? pick(current) ?? datasets[0] ?? null;
      this.store.set({ datasets, datasetId: chosen?.id ?? null });
      if (!chosen) this.showNoData('No data sets yet: upload one (left) or run trailscope ingest.');
      else if (this.initialBundle) {
        void this.bundles.restore(this.initialBundle);
        this.initialBundle = null;
      }
    } catch (e) {
      if (e instanceof ApiError) {
        this.errors.show('datasets', e);
        this.showNoData(e.detail);
      }
    }
  }

  private showNoData(message: string) {
    this.summary.setEmpty(message);
    this.flights.setEmpty(message);
    this.brush.setMessage('empty', message);
    this.acceptedQuery = null;
    this.updateLegend();
    this.map.setDensity(null);
  }

  private onJobDone(job: Job, mine: boolean) {
    // Only ingest jobs add data sets; a bundle job's result is the bundling panel's business.
    if (job.kind === 'bundle' || job.kind === 'congestion') return;
    if (job.state === 'done') void this.loadDatasets(mine ? job.dataset : undefined);
    else if (mine && job.state === 'failed' && job.error) {
      this.errors.show('upload', new ApiError(400, { error: job.error.error, detail: `Ingest of ${job.dataset} failed: ${job.error.detail}`, param: 'name' }));
    }
  }

  /**
   * Re-issues what the current state needs. The summary goes first and acts as the query's check:
   * only once the server accepts a query are tiles, the brush histogram and the flight list asked for
   * (an invalid filter would otherwise fail every visible tile). Render-only changes swap tiles at once.
   */
  private refresh() {
    const d = this.store.dataset();
    if (!d) return;
    const s = this.store.get();
    const eff = this.store.effectiveFilters();
    if (s.useMapView && !eff.bbox) return; // the map has not reported its view yet
    const problem = validateFilters(eff);
    if (problem) {
      this.summaryCh.cancel();
      this.summaryKey = '';
      const err = new ApiError(400, { error: 'invalid_argument', ...problem });
      this.errors.show('query', err);
      this.summary.setError('Fix the highlighted filter to update the view.');
      return;
    }
    const q = buildQuery(eff);
    const key = `${d.id}?${q.toString()}`;
    if (key === this.summaryKey) {
      this.afterSummary(d);
      return;
    }
    this.summaryKey = key;
    void this.loadSummary(d, q);
  }

  /** The requests that follow an accepted query (each skipped when its own key is unchanged). */
  private afterSummary(d: Dataset, summary?: Summary) {
    const s = this.store.get();
    const eff = this.store.effectiveFilters();
    this.acceptedQuery = buildQuery(eff, { withoutBBox: true });
    this.updateExports(d, buildQuery(eff), summary);
    this.map.setDensity(densityTileTemplate(window.location.origin, d.id, this.acceptedQuery, s.render));
    this.updateLegend();
    const q = buildQuery(eff);
    const key = `${d.id}?${q.toString()}`;
    this.syncHistogram(summary);
    if (key !== this.flightsKey) {
      this.flightsKey = key;
      // A new query starts at the first page, except the page a shared link names (once).
      this.flightPage = this.initialPage ?? 0;
      this.initialPage = null;
      this.loadFlights();
    }
  }

  /** What the view shows, for exported files: data set, window (or all times) and shading. */
  private caption(): string {
    const s = this.store.get();
    const w = spanOf(s);
    const when = w ? `${formatUtcSeconds(w.start)} → ${formatUtcSeconds(w.end)} UTC` : 'all times';
    return `${s.datasetId ?? ''} · ${when} · ${s.render.value}, ${s.render.how}, ${s.render.cmap}`;
  }

  /** A file name stem for exports: data set and window. */
  private fileStem(): string {
    const s = this.store.get();
    const w = spanOf(s);
    return `trailscope-${s.datasetId ?? 'map'}${w ? `-${Math.floor(w.start)}-${Math.ceil(w.end)}` : ''}`;
  }

  /** Points the export links at the accepted query (with the map-view box when on). */
  private updateExports(d: Dataset, q: URLSearchParams, summary?: Summary) {
    const base = `/api/v1/datasets/${encodeURIComponent(d.id)}`;
    const stem = this.fileStem();
    const set = (a: HTMLAnchorElement, path: string, extra: Record<string, string>, file: string, tooMany = false) => {
      const p = new URLSearchParams(q);
      for (const [k, v] of Object.entries(extra)) p.set(k, v);
      if (tooMany) {
        a.removeAttribute('href');
        a.setAttribute('aria-disabled', 'true');
        a.title = `The window holds more than ${MAX_EXPORT_POINTS.toLocaleString('en-US')} points: narrow the window or the filters.`;
        return;
      }
      a.href = `${base}/${path}?${p.toString()}`;
      a.download = file;
      a.removeAttribute('aria-disabled');
    };
    const points = summary?.points ?? this.lastPoints;
    if (summary) this.lastPoints = summary.points;
    const tooMany = points !== null && points > MAX_EXPORT_POINTS;
    set(this.exportLinks.geojson, 'export', { format: 'geojson' }, `${stem}.geojson`, tooMany);
    set(this.exportLinks.csv, 'export', { format: 'csv' }, `${stem}.csv`, tooMany);
    set(this.exportLinks.summaryJson, 'summary', { format: 'json', bins: String(SUMMARY_BINS) }, `${stem}-summary.json`);
    set(this.exportLinks.summaryCsv, 'summary', { format: 'csv', table: 'totals' }, `${stem}-summary.csv`);
  }

  private async exportPng() {
    const bundled = this.map.map.getContainer().dataset.densityShown === 'false';
    const blob = await mapPng(this.map.map, bundled ? this.bundles.legendSpec : this.legend.spec, this.caption());
    download(blob, `${this.fileStem()}.png`);
  }

  /** The density legend of the accepted query at the map's zoom. */
  private updateLegend() {
    const d = this.store.dataset();
    this.legend.update(d?.id ?? null, d ? this.acceptedQuery : null, this.store.get().render, this.map.map.getZoom());
  }

  private async loadSummary(d: Dataset, q: URLSearchParams) {
    const signal = this.summaryCh.next();
    this.summary.setLoading();
    try {
      const s = await api.summary(d.id, q, SUMMARY_BINS, signal);
      this.errors.clear('query');
      this.summary.set(s, q.toString());
      this.afterSummary(d, s);
    } catch (e) {
      if (isAbort(e)) return;
      this.summaryKey = ''; // let the same query be retried
      const err = e instanceof ApiError ? e : new ApiError(0, { error: 'client', detail: String(e) });
      this.errors.show('query', err);
      this.summary.setError(err.param ? 'Fix the highlighted filter to update the view.' : err.detail);
    }
  }

  /**
   * The brush's histogram: of everything but time over the axis's view (the whole data set unless zoomed),
   * asked for again when the filters or the view change.
   */
  private syncHistogram(summary?: Summary) {
    const d = this.store.dataset();
    if (!d || this.acceptedQuery === null) return;
    const eff = this.store.effectiveFilters();
    const key = `${d.id}?${buildQuery(eff).toString()}`;
    const qHist = buildQuery(eff, { withoutTime: true });
    const view = this.brush.getView();
    if (view) {
      qHist.set('t0', String(Math.floor(view.start)));
      qHist.set('t1', String(Math.ceil(view.end)));
    }
    const histKey = `${d.id}?${qHist.toString()}`;
    if (histKey === this.histKey) return;
    this.histKey = histKey;
    // Without a time window or zoom the summary's own histogram is the brush's histogram.
    if (summary && histKey === key) {
      this.histCh.cancel();
      this.brush.setData(summary.time_histogram, d.t_min, d.t_max);
    } else {
      void this.loadHistogram(d, qHist);
    }
  }

  private async loadHistogram(d: Dataset, q: URLSearchParams) {
    const signal = this.histCh.next();
    this.brush.setLoading();
    try {
      const s = await api.summary(d.id, q, SUMMARY_BINS, signal);
      this.brush.setData(s.time_histogram, d.t_min, d.t_max);
    } catch (e) {
      if (isAbort(e)) return;
      this.histKey = '';
      this.brush.setMessage('error', e instanceof ApiError ? e.detail : String(e));
    }
  }

  private loadFlights() {
    const d = this.store.dataset();
    if (!d) return;
    const q = buildQuery(this.store.effectiveFilters());
    const signal = this.flightsCh.next();
    this.flights.setLoading();
    api
      .flights(d.id, q, this.flightPage, PAGE_SIZE, signal, this.flightSort)
      .then((p) => {
        this.flights.set(p);
        this.writeHash();
        this.flights.setSelected(this.store.get().selectedFlight);
        if (this.initialFlight !== null) {
          // A shared link names a flight that may sit on another page: open it anyway.
          const id = this.initialFlight;
          this.initialFlight = null;
          this.selectFlight(
            p.flights.find((f) => f.id === id) ?? { id, icao24: '', callsign: '', t_start: NaN, t_end: NaN, points: 0, alt_max_m: NaN },
          );
        }
      })
      .catch((e: unknown) => {
        if (isAbort(e)) return;
        this.flightsKey = '';
        this.flights.setError(e instanceof ApiError ? e.detail : String(e));
      });
  }

  /** The clock plays the time window, or the whole data set without one. */
  private syncClockSpan() {
    const s = this.store.get();
    const d = this.store.dataset();
    const w = spanOf(s);
    this.clock.setSpan(w ?? (d ? { start: d.t_min, end: d.t_max } : null));
  }

  private onPlaybackChange() {
    const on = this.playback.isOn();
    this.map.setDimmed(on);
    this.brush.setCursor(on ? this.clock.get().t : null);
    this.congestion?.refresh(); // (the playback view may report before the panel exists)
    this.writeHash();
  }

  /** Selects a flight: its card and track (`fit`: zoom to the track; off when the map follows the flight). */
  private selectFlight(row: FlightRow, fit = true) {
    const d = this.store.dataset();
    if (!d) return;
    this.store.set({ selectedFlight: row.id });
    this.card.loading(row);
    const signal = this.trackCh.next();
    api
      .flight(d.id, row.id, signal)
      .then((f) => {
        if (this.store.get().selectedFlight !== row.id) return;
        this.map.showTrack(f, fit);
        this.card.show(row, f);
      })
      .catch((e: unknown) => {
        if (isAbort(e)) return;
        this.card.error(row, e instanceof ApiError ? e.detail : String(e));
      });
  }

  /** The map view is shown again (after the tracker or runs view): restore its URL and size. */
  show(): void {
    this.map.map.resize();
    this.syncHash();
  }

  private syncHash() {
    // The tracker and runs views own the URL while they are shown (#tracker…, #runs…).
    if (dashboardOf(window.location.hash) !== 'map') return;
    const s = this.store.get();
    if (!s.datasetId) return;
    const q = buildQuery({ ...s.filters, bbox: null });
    const p = new URLSearchParams({ dataset: s.datasetId });
    for (const [k, v] of q) p.set(k, v);
    if (s.useMapView) p.set('mapview', '1');
    p.set('value', s.render.value);
    p.set('how', s.render.how);
    p.set('cmap', s.render.cmap);
    const c = this.map.map.getCenter();
    p.set('view', `${c.lng.toFixed(4)},${c.lat.toFixed(4)},${this.map.map.getZoom().toFixed(2)}`);
    if (s.selectedFlight !== null) p.set('flight', String(s.selectedFlight));
    if (this.flightSort.sort !== 't_start' || this.flightSort.order !== 'asc') {
      p.set('fsort', this.flightSort.sort);
      p.set('forder', this.flightSort.order);
    }
    if (this.flightPage > 0) p.set('fpage', String(this.flightPage));
    const tv = this.brush.getView();
    if (tv) p.set('tview', `${Math.floor(tv.start)},${Math.ceil(tv.end)}`);
    const c0 = this.clock.get();
    writePlayback(p, { at: this.playback.isOn() ? c0.t : null, speed: c0.speed, tail: this.playback.tailSeconds() });
    if (this.playback.isOn()) p.set('color', this.playback.color());
    writeBundleView(p, this.bundles.view());
    const next = `#${p.toString()}`;
    if (window.location.hash !== next) history.replaceState(null, '', next);
  }
}

function spanOf(s: AppState) {
  const { t0, t1 } = s.filters;
  return t0 !== null && t1 !== null ? { start: t0, end: t1 } : null;
}
