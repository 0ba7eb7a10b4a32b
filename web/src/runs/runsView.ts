// The runs dashboard (#runs): a sweep's runs as a table, a projection scatter coloured by a metric,
// parallel coordinates of the varying parameters and the metrics, parameter importance, and the
// comparison of the selected runs. One selection links them all: brushing the projection, clicking the
// table or filtering the parallel coordinates selects runs, and the selection's runs open in the
// comparison (aligned timelines with one frame cursor).

import { ApiError, isAbort } from '../api/client';
import { trackerApi } from '../api/replay';
import { runsApi } from '../api/runs';
import { PROJECTION_METHODS, type Comparison, type Projection, type ProjectionMethod, type RunRow, type Sweep } from '../api/runsTypes';
import { debounce, h, mount, sectionHead } from '../lib/dom';
import { trackerHash } from '../tracker/route';
import { colorScale, type ColorScale } from './colorScale';
import { CompareView } from './compareView';
import { ImportanceView } from './importanceView';
import { METRICS, formatMetric, metricDef, metricValue, paramValue, varyingParams } from './metrics';
import { ParallelCoords, type PcRow } from './parallelCoords';
import { axisDomain, type PcAxis } from './parcoordsScale';
import { ProjectionView, type ScatterPoint } from './projectionView';
import { isRunsHash, parseRunsHash, runsHash } from './route';
import { DEFAULT_PERPLEXITY, choosePerplexity } from './tsne';
import { RunsTable } from './runsTable';
import { pickCompare, type ComparePick } from './selection';
import { SweepLauncher } from './sweepLauncher';
import '../tracker/tracker.css';
import './runs.css';

/** Metrics offered as parallel-coordinate axes (when they vary). */
const PC_METRICS = ['track_share', 'accuracy.frames_all_within', 'accuracy.median_error_mm', 'accuracy.p95_error_mm', 'lost_episodes'];
const KEY_PARAMS = 5;

function select(label: string, testid: string, options: [string, string][], onChange: (v: string) => void): HTMLSelectElement {
  const s = h('select', { 'aria-label': label, 'data-testid': testid, onchange: () => onChange(s.value) }, ...options.map(([v, t]) => h('option', { value: v }, t)));
  return s;
}

/** How often the runs view asks whether its projection and comparison still match the server (ms). */
const FRESH_CHECK_MS = 15_000;

export class RunsView {
  readonly root: HTMLElement;
  private readonly table: RunsTable;
  private readonly projection: ProjectionView;
  private readonly pc: ParallelCoords;
  private readonly importance: ImportanceView;
  private readonly compare: CompareView;
  private readonly sweepSelect: HTMLSelectElement;
  private readonly metricSelect: HTMLSelectElement;
  private readonly methodSelect: HTMLSelectElement;
  private readonly includeSelect: HTMLSelectElement;
  private readonly quality: HTMLElement;
  private readonly sweepInfo: HTMLElement;
  private readonly status: HTMLElement;
  private readonly launcher: SweepLauncher;
  private allRuns: RunRow[] = [];
  private sweeps: Sweep[] = [];
  private rows: RunRow[] = [];
  private rowMap = new Map<string, RunRow>();
  private units = new Map<string, string>();
  private sweep: string | null = null;
  private metric = 'track_share';
  private method: ProjectionMethod = 'pca';
  /** The t-SNE perplexity asked for (capped to the table by choosePerplexity). */
  private perplexity = DEFAULT_PERPLEXITY;
  private readonly perplexityInput: HTMLInputElement;
  private readonly perplexityNote: HTMLElement;
  private readonly perplexityBox: HTMLElement;
  /** Parallel-coordinate filters from the URL, applied once the sweep's axes exist. */
  private pendingPc: [string, [number, number]][] | null = null;
  private selection: string[] = [];
  private filter: Set<string> | null = null;
  private scale: ColorScale | null = null;
  private proj: Projection | null = null;
  /** The runs (ids, sorted) and options the shown projection was made from (staleKey). */
  private projectedKey = '';
  private freshCtrl = new AbortController();
  private pick: ComparePick | null = null;
  /** The selection (ids joined) the pick was made from. */
  private pickFor = '';
  /**
   * The compared runs (ids joined) the comparison shows; null forces the next loadCompare to redo it (an
   * empty pick's key is '' too, so '' could not say "redo": a sweep reloaded down to one run kept the old
   * comparison on screen).
   */
  private comparedKey: string | null = null;
  private cmp: Comparison | null = null;
  private cursor: number | null = null;
  private loaded = false;
  private readonly projCtrl = { c: new AbortController() };
  private readonly impCtrl = { c: new AbortController() };
  private readonly cmpCtrl = { c: new AbortController() };
  private readonly scheduleCompare = debounce(() => void this.loadCompare(), 150);
  private readonly writeHash = debounce(() => this.syncHash(), 200);

  constructor(host: HTMLElement) {
    this.table = new RunsTable({ onSelect: (ids) => this.setSelection(ids, false) });
    this.sweepSelect = select('Sweep', 'sweep-select', [], (v) => void this.setSweep(v || null, true));
    this.metricSelect = select(
      'Colour and importance metric',
      'metric-select',
      METRICS.map((m) => [m.key, m.label]),
      (v) => this.setMetric(v),
    );
    this.methodSelect = select(
      'Projection method',
      'method-select',
      PROJECTION_METHODS.map((m) => [m, { pca: 'PCA', mds: 'MDS', tsne: 't-SNE', lamp: 'LAMP', force: 'Force scheme' }[m]]),
      (v) => {
        this.method = v as ProjectionMethod;
        void this.project();
        this.writeHash();
      },
    );
    this.includeSelect = select(
      'Projected columns',
      'include-select',
      [
        ['params,metrics', 'parameters + results'],
        ['params', 'parameters only'],
        ['metrics', 'results only'],
      ],
      () => void this.project(),
    );
    this.perplexityInput = h('input', {
      type: 'number',
      min: 1,
      max: 100,
      step: 1,
      value: DEFAULT_PERPLEXITY,
      class: 'num-input',
      'aria-label': 't-SNE perplexity',
      'data-testid': 'perplexity-input',
    });
    this.perplexityInput.addEventListener('change', () => {
      const v = Number(this.perplexityInput.value);
      if (!(v >= 1 && v <= 100)) {
        this.perplexityNote.textContent = 'perplexity: a number from 1 to 100';
        this.perplexityInput.setAttribute('aria-invalid', 'true');
        return; // never sent
      }
      this.perplexityInput.removeAttribute('aria-invalid');
      this.perplexity = v;
      this.writeHash();
      void this.project();
    });
    this.perplexityNote = h('span', { class: 'muted small', 'data-testid': 'perplexity-note' });
    this.perplexityBox = h('label', { class: 'perplexity', hidden: true }, h('span', { class: 'small' }, 'perplexity'), this.perplexityInput, this.perplexityNote);
    const projectBtn = h('button', { class: 'btn btn-small', type: 'button', 'data-testid': 'project-button', onclick: () => void this.project() }, 'Project');
    this.projection = new ProjectionView(
      { onSelect: (ids, add) => this.setSelection(ids, add), onRecompute: () => void this.reload() },
      h('div', { class: 'proj-controls' }, this.methodSelect, this.includeSelect, this.perplexityBox, projectBtn),
    );
    this.pc = new ParallelCoords({
      onBrush: () => this.onFilter(),
      onSelect: (ids) => this.setSelection(ids, false),
    });
    this.importance = new ImportanceView();
    this.compare = new CompareView({
      onCursor: (f) => {
        this.cursor = f;
        this.writeHash();
      },
      onReplay: (id) => void this.replay(id),
      onRecompute: () => void this.reload(),
    });
    this.quality = h('dl', { class: 'kv quality', 'data-testid': 'projection-quality' });
    this.sweepInfo = h('div', { class: 'muted small', 'data-testid': 'sweep-info' });
    this.status = h('div', { class: 'muted small', role: 'status', 'data-testid': 'runs-status' });
    this.launcher = new SweepLauncher({
      onDone: (sweep) =>
        void (async () => {
          await this.loadLists();
          await this.setSweep(sweep, true);
        })(),
    });
    const side = h(
      'aside',
      { class: 'runs-side panel' },
      sectionHead('Runs', h('button', { class: 'btn btn-small', type: 'button', onclick: () => void this.reload() }, 'Reload')),
      h('label', { class: 'field' }, h('span', { class: 'field-label' }, 'Sweep'), this.sweepSelect),
      this.sweepInfo,
      h('label', { class: 'field' }, h('span', { class: 'field-label' }, 'Colour by'), this.metricSelect),
      h('section', { class: 'runs-side-section', 'aria-label': 'Projection quality' }, h('h3', { class: 'sub-title' }, 'Projection quality'), this.quality),
      this.importance.root,
      this.launcher.root,
      this.status,
    );
    this.root = h(
      'div',
      { class: 'runs', 'data-testid': 'runs-view', 'data-state': 'idle' },
      side,
      h(
        'div',
        { class: 'runs-main' },
        h('div', { class: 'runs-top' }, this.projection.root, this.table.root),
        this.pc.root,
        this.compare.root,
      ),
    );
    host.append(this.root);
    window.addEventListener('focus', () => void this.checkFresh());
    document.addEventListener('visibilitychange', () => document.visibilityState === 'visible' && void this.checkFresh());
    window.setInterval(() => document.visibilityState === 'visible' && void this.checkFresh(), FRESH_CHECK_MS);
    (window as unknown as { __trailscopeRuns: unknown }).__trailscopeRuns = {
      state: () => this.debugState(),
      view: this,
    };
  }

  /** Called when the route shows the runs view (first time and after every hash change). */
  async activate(hash: string): Promise<void> {
    if (!isRunsHash(hash)) return;
    const r = parseRunsHash(hash);
    if (r.metric && METRICS.some((m) => m.key === r.metric)) this.metric = r.metric;
    this.metricSelect.value = this.metric;
    if (r.method && (PROJECTION_METHODS as readonly string[]).includes(r.method)) this.method = r.method as ProjectionMethod;
    this.methodSelect.value = this.method;
    if (r.frame !== null) this.cursor = r.frame;
    if (r.perp !== null && r.perp >= 1 && r.perp <= 100) {
      this.perplexity = r.perp;
      this.perplexityInput.value = String(r.perp);
    }
    if (r.pc.length) this.pendingPc = r.pc;
    if (!this.loaded) {
      this.loaded = true;
      await this.loadLists();
      const sweep = r.sweep ?? this.sweeps.filter((s) => s.runs.length > 1).at(-1)?.id ?? null;
      await this.setSweep(sweep, false, r.sel);
    } else if (!r.sweep && r.sel.length === 0) {
      // The bare tab link (#runs): keep what the view shows and put it back in the URL.
      this.syncHash();
    } else if ((r.sweep ?? null) !== this.sweep && r.sweep) {
      // A sweep made since the lists were loaded (a link from elsewhere): load them again first.
      if (!this.sweeps.some((x) => x.id === r.sweep)) await this.loadLists();
      await this.setSweep(r.sweep, false, r.sel);
    } else if (r.sel.join(',') !== this.selection.join(',')) {
      this.setSelection(r.sel, false);
    }
  }

  private async loadLists() {
    this.root.dataset.state = 'loading';
    try {
      const [runs, sweeps, params, videos] = await Promise.all([
        runsApi.runs(),
        runsApi.sweeps(),
        trackerApi.params().catch(() => []),
        trackerApi.videos().catch(() => []),
      ]);
      this.allRuns = runs;
      this.sweeps = sweeps;
      this.units = new Map(params.map((p) => [p.name, p.unit]));
      this.launcher.setChoices(videos, params);
      mount(
        this.sweepSelect,
        h('option', { value: '' }, `All runs (${runs.length})`),
        ...sweeps.map((s) => h('option', { value: s.id }, `${s.id} · ${s.runs.length}${s.total ? `/${s.total}` : ''} runs${s.state && s.state !== 'done' ? ` · ${s.state}` : ''}`)),
      );
      this.setStatus('');
    } catch (e) {
      this.root.dataset.state = 'error';
      this.setStatus(e instanceof ApiError ? e.detail : String(e), true);
    }
  }

  private async reload() {
    await this.loadLists();
    await this.setSweep(this.sweep, false, this.selection);
    this.compare.setStale(null);
  }

  /** What a projection is made of: the runs it projects (ids, sorted), the method, the columns and perplexity. */
  private staleKey(rows: readonly RunRow[]): string {
    const ids = rows.map((r) => r.id).sort();
    return JSON.stringify([ids, this.method, this.includeSelect.value, this.method === 'tsne' ? this.perplexity : null]);
  }

  /**
   * Asks the server for its runs and marks the projection and the comparison stale when theirs changed since
   * they were made: a sweep still running (or another client's) added runs to the projected set, or a compared
   * run is gone. They are not recomputed behind the analyst's back (a projection of hundreds of runs takes a
   * while and would move every point under the cursor); the mark's Recompute reloads and recomputes.
   * Called when the window gains focus or becomes visible, while a sweep launched here runs, and every
   * FRESH_CHECK_MS while the runs view shows.
   */
  async checkFresh(): Promise<void> {
    if (!this.loaded || !isRunsHash(window.location.hash)) return;
    this.freshCtrl.abort();
    const ctrl = new AbortController();
    this.freshCtrl = ctrl;
    let runs: RunRow[];
    try {
      runs = await runsApi.runs(ctrl.signal);
    } catch {
      return; // a failed check changes nothing
    }
    if (ctrl.signal.aborted) return;
    const now = this.sweep ? runs.filter((r) => r.sweep === this.sweep) : runs;
    if (this.proj && this.projectedKey && this.staleKey(now) !== this.projectedKey) {
      const had = this.proj.rows;
      this.projection.setStale(`${now.length} runs on the server now, ${had} projected;`);
    }
    if (this.cmp) {
      const ids = new Set(runs.map((r) => r.id));
      const gone = this.cmp.series.map((s) => s.id).filter((id) => !ids.has(id));
      if (gone.length) this.compare.setStale(`compared run${gone.length === 1 ? '' : 's'} ${gone.join(', ')} no longer on the server;`);
    }
  }

  private async setSweep(sweep: string | null, user: boolean, sel: string[] = []) {
    this.sweep = sweep && this.sweeps.some((s) => s.id === sweep) ? sweep : null;
    this.sweepSelect.value = this.sweep ?? '';
    if (sweep && !this.sweep) this.setStatus(`Sweep ${sweep} is not on the server; showing all runs.`, true);
    this.rows = this.sweep ? this.allRuns.filter((r) => r.sweep === this.sweep) : [...this.allRuns];
    this.rowMap = new Map(this.rows.map((r) => [r.id, r]));
    const s = this.sweeps.find((x) => x.id === this.sweep);
    const videos = [...new Set(this.rows.map((r) => r.video))];
    this.sweepInfo.textContent = s
      ? `${s.spec?.mode ?? ''} sweep over ${s.spec?.axes.map((a) => a.param).join(', ') ?? '?'} · ${this.rows.length} runs on ${videos.join(', ')}`
      : `${this.rows.length} runs on ${videos.length} videos`;
    this.proj = null;
    this.filter = null;
    this.comparedKey = null;
    const varying = varyingParams(this.rows);
    this.table.setRows(this.rows, varying.slice(0, KEY_PARAMS), this.units);
    this.buildParallel(varying);
    if (this.pendingPc) {
      this.pc.setBrushes(this.pendingPc);
      this.pendingPc = null;
      this.onFilter();
    }
    this.updateColors();
    this.selection = [];
    this.setSelection(
      sel.filter((id) => this.rowMap.has(id)),
      false,
    );
    this.root.dataset.state = 'ready';
    this.root.dataset.sweep = this.sweep ?? '';
    if (user) this.cursor = null;
    this.writeHash();
    void this.loadImportance();
    await this.project();
  }

  private buildParallel(varying: string[]) {
    const metrics = PC_METRICS.filter((m) => {
      const vals = this.rows.map((r) => metricValue(r, m)).filter(Number.isFinite);
      return vals.length > 0 && vals.some((v) => v !== vals[0]);
    });
    const axes: PcAxis[] = [
      ...varying.map((p) => {
        const [lo, hi] = axisDomain(this.rows.map((r) => paramValue(r, p)));
        const unit = this.units.get(p);
        return { key: `param:${p}`, label: unit ? `${p} (${unit})` : p, lo, hi };
      }),
      ...metrics.map((m) => {
        const [lo, hi] = axisDomain(this.rows.map((r) => metricValue(r, m)));
        const d = metricDef(m);
        return { key: `metric:${m}`, label: `${d.short}${d.unit === 'mm' ? ' (mm)' : ''}`, lo, hi };
      }),
    ];
    const pcRows: PcRow[] = this.rows.map((r) => ({
      id: r.id,
      values: new Map(axes.map((a) => [a.key, a.key.startsWith('param:') ? paramValue(r, a.key) : metricValue(r, a.key)])),
      colorValue: metricValue(r, this.metric),
    }));
    this.pc.setData(axes, pcRows);
  }

  private setMetric(key: string) {
    this.metric = key;
    this.updateColors();
    this.buildParallel(varyingParams(this.rows));
    this.pc.setSelection(this.selection);
    void this.loadImportance();
    this.comparedKey = null;
    this.scheduleCompare();
    this.writeHash();
  }

  private updateColors() {
    const def = metricDef(this.metric);
    this.scale = colorScale(
      this.rows.map((r) => metricValue(r, this.metric)),
      { reversed: def.better === 'low' },
    );
    this.table.setColor(this.scale, this.metric);
    this.pc.setColor(this.scale);
    this.projection.setColor(this.scale, def.label, (v) => formatMetric(this.metric, v));
    this.compare.setRunColors(new Map(this.rows.map((r) => [r.id, this.scale!.color(metricValue(r, this.metric))])));
    this.setPoints();
  }

  private setPoints() {
    const p = this.proj;
    if (!p) {
      this.projection.setPoints([]);
      return;
    }
    const ids = p.row_ids ?? this.rows.map((r) => r.id);
    const pts: ScatterPoint[] = [];
    p.coordinates.forEach((c, i) => {
      const id = ids[i];
      const r = id ? this.rowMap.get(id) : undefined;
      if (!id || !r) return;
      const v = metricValue(r, this.metric);
      pts.push({ id, x: c[0], y: c[1], value: v, label: `${id} · ${r.video} · ${metricDef(this.metric).label} ${formatMetric(this.metric, v)}` });
    });
    this.projection.setPoints(pts);
  }

  private async project() {
    this.projection.setStale(null);
    this.projCtrl.c.abort();
    const ctrl = new AbortController();
    this.projCtrl.c = ctrl;
    if (this.rows.length < 3) {
      this.proj = null;
      this.setPoints();
      this.projection.setState('empty', this.rows.length ? 'Too few runs to project.' : 'No runs.');
      mount(this.quality);
      return;
    }
    const include = this.includeSelect.value.split(',') as ('params' | 'metrics')[];
    // t-SNE: the perplexity capped to the table (tsne.ts), or not offered at all below 4 runs.
    const perp = choosePerplexity(this.perplexity, this.rows.length);
    const tsneOption = this.methodSelect.querySelector<HTMLOptionElement>('option[value="tsne"]');
    if (tsneOption) {
      tsneOption.disabled = perp.value === null;
      tsneOption.title = perp.value === null ? perp.note : '';
    }
    this.perplexityBox.hidden = this.method !== 'tsne';
    this.perplexityNote.textContent = perp.note;
    this.perplexityBox.dataset.capped = String(perp.capped);
    this.perplexityBox.dataset.value = perp.value === null ? '' : String(perp.value);
    if (this.method === 'tsne' && perp.value === null) {
      this.proj = null;
      this.setPoints();
      this.projection.setState('empty', perp.note);
      mount(this.quality);
      return;
    }
    this.projection.setState('loading', `Projecting ${this.rows.length} runs (${this.method})…`);
    try {
      const body = {
        runs: this.sweep ? { sweep: this.sweep, include } : { include },
        method: this.method,
        seed: 42,
        ...(this.method === 'tsne' ? { perplexity: perp.value! } : {}),
      };
      const t0 = performance.now();
      const p = await runsApi.projection(body, ctrl.signal);
      if (ctrl.signal.aborted) return;
      this.proj = p;
      this.projectedKey = this.staleKey(this.rows);
      this.projection.setStale(null);
      this.setPoints();
      this.projection.setState('ready');
      this.renderQuality(p, performance.now() - t0);
    } catch (e) {
      if (isAbort(e)) return;
      this.proj = null;
      this.setPoints();
      const msg = e instanceof ApiError ? (e.status === 404 || e.status === 405 ? 'This server has no projection route (POST /api/v1/projections).' : e.detail) : String(e);
      this.projection.setState('error', msg);
      mount(this.quality);
    }
  }

  private renderQuality(p: Projection, ms: number) {
    const q = p.quality ?? {};
    const f = (v: number | null | undefined, d = 3) => (v === null || v === undefined || !Number.isFinite(v) ? '–' : v.toFixed(d));
    const kv = (k: string, v: string, title?: string) => [h('dt', { title: title ?? null }, k), h('dd', { class: 'num' }, v)];
    const t = p.timings_ms ?? {};
    const parts = Object.values(t);
    const total = typeof t.total === 'number' ? t.total : parts.length ? parts.reduce((a, b) => a + b, 0) : NaN;
    mount(
      this.quality,
      ...kv('method', `${p.method}${p.variant ? ` (${p.variant})` : ''}`),
      ...kv('trustworthiness', f(q.trustworthiness), `Are the ${q.k ?? 'k'} nearest neighbours in the plot neighbours in the data? (1 = all)`),
      ...kv('continuity', f(q.continuity), 'Are the data neighbours kept near in the plot? (1 = all)'),
      ...kv('neighbourhood', f(q.neighborhood_preservation), 'Share of k-nearest neighbours kept'),
      ...kv('stress', f(q.stress), 'Normalised stress (0 = distances kept)'),
      ...kv('Shepard', f(q.shepard), 'Rank correlation of data and plot distances'),
      ...kv('k', q.k !== undefined ? String(q.k) : '–'),
      ...kv('columns', String(p.columns.length), p.columns.join(', ')),
      ...kv('computed', `${p.path ?? '?'} · ${Number.isFinite(total) ? `${total < 10 ? total.toFixed(2) : Math.round(total)} ms` : '–'} (${Math.round(ms)} ms round trip)`),
    );
    this.quality.dataset.trustworthiness = f(q.trustworthiness, 4);
    if (p.dropped_columns?.length) this.quality.title = `Dropped: ${p.dropped_columns.map((d) => `${d.name} (${d.why})`).join(', ')}`;
  }

  private async loadImportance() {
    this.impCtrl.c.abort();
    const ctrl = new AbortController();
    this.impCtrl.c = ctrl;
    // The server needs at least 4 runs with a value of the metric (422 otherwise).
    const finite = this.rows.filter((r) => Number.isFinite(metricValue(r, this.metric))).length;
    if (finite < 4) {
      this.importance.setMessage(`Importance needs at least 4 runs with a ${metricDef(this.metric).label.toLowerCase()} (${finite} here).`);
      return;
    }
    this.importance.setMessage('Loading…');
    try {
      const imp = await runsApi.importance(this.metric, this.sweep, ctrl.signal);
      if (!ctrl.signal.aborted) this.importance.set(imp);
    } catch (e) {
      if (isAbort(e)) return;
      this.importance.setMessage(e instanceof ApiError ? e.detail : String(e), true);
    }
  }

  private onFilter() {
    const b = this.pc.brushState;
    this.filter = b.size ? new Set(this.pc.filtered()) : null;
    this.table.setHighlight(this.filter);
    this.projection.setHighlight(this.filter);
    this.writeHash();
  }

  /** The one selection of the view. `add` merges into the current one (Shift-brush). */
  setSelection(ids: readonly string[], add: boolean): void {
    const known = ids.filter((id) => this.rowMap.has(id));
    const next = add ? [...this.selection, ...known.filter((id) => !this.selection.includes(id))] : [...new Set(known)];
    this.selection = next;
    this.table.setSelection(next);
    this.projection.setSelection(next);
    this.pc.setSelection(next);
    if (next.length === 1) this.table.reveal(next[0]!);
    this.root.dataset.selected = String(next.length);
    this.writeHash();
    this.scheduleCompare();
  }

  private async loadCompare() {
    const pick = pickCompare(this.selection, this.rowMap, this.metric);
    this.pick = pick;
    this.pickFor = this.selection.join(',');
    const key = pick.ids.join(',');
    if (key === this.comparedKey) return;
    this.comparedKey = key;
    this.cmpCtrl.c.abort();
    const ctrl = new AbortController();
    this.cmpCtrl.c = ctrl;
    if (pick.ids.length < 2) {
      this.cmp = null;
      this.compare.clear(
        pick.selected === 0
          ? 'Select 2 to 8 runs of one video (table, projection or filter) to compare them.'
          : pick.selected === 1
            ? 'Select at least 2 runs.'
            : `The selection has fewer than 2 runs of any one video (runs are compared on one video).`,
      );
      return;
    }
    const others = pick.selected - pick.ofVideo;
    const otherText = others ? `; ${others} selected run${others === 1 ? '' : 's'} of other videos not shown` : '';
    const note =
      pick.ofVideo > pick.ids.length
        ? `${pick.ids.length} of the ${pick.ofVideo} selected runs on video ${pick.video}, spread over their ${metricDef(this.metric).label.toLowerCase()} (best first)${otherText}.`
        : `${pick.ids.length} selected runs on video ${pick.video}, best ${metricDef(this.metric).label.toLowerCase()} first${otherText}.`;
    this.compare.setLoading(`Comparing ${pick.ids.join(', ')}…`);
    try {
      const cmp = await runsApi.compare({ runs: pick.ids, top: 20 }, ctrl.signal);
      if (ctrl.signal.aborted) return;
      this.cmp = cmp;
      this.compare.set(cmp, note, this.units, this.cursor);
      this.cursor = this.compare.cursorFrame;
      this.writeHash();
    } catch (e) {
      if (isAbort(e)) return;
      this.cmp = null;
      this.comparedKey = null;
      const msg = e instanceof ApiError ? (e.status === 404 && e.param !== 'runs' && !e.detail.includes('run') ? 'This server has no comparison route (POST /api/v1/compare).' : e.detail) : String(e);
      this.compare.setError(msg);
    }
  }

  /** Starts a live replay of a run's video at its parameters and opens it in the tracker view. */
  private async replay(id: string) {
    const r = this.rowMap.get(id);
    if (!r) return;
    const params: Record<string, number> = {};
    r.param_names.forEach((n, i) => (params[n] = r.params[i]!));
    try {
      const replay = await trackerApi.startReplay(r.video, params);
      window.location.hash = trackerHash(replay.id);
    } catch (e) {
      this.setStatus(`Could not start a replay of ${id}: ${e instanceof ApiError ? e.detail : String(e)}`, true);
    }
  }

  private syncHash() {
    if (!isRunsHash(window.location.hash)) return;
    const next = runsHash({
      sweep: this.sweep,
      sel: this.selection.length <= 40 ? this.selection : [],
      metric: this.metric !== 'track_share' ? this.metric : null,
      method: this.method !== 'pca' ? this.method : null,
      frame: this.cmp ? this.cursor : null,
      perp: this.method === 'tsne' && this.perplexity !== DEFAULT_PERPLEXITY ? this.perplexity : null,
      pc: [...this.pc.brushState],
    });
    if (window.location.hash !== next) history.replaceState(null, '', next);
  }

  private setStatus(text: string, error = false) {
    this.status.textContent = text;
    this.status.classList.toggle('error-text', error);
  }

  /** Read-only snapshot for the browser test and the console (window.__trailscopeRuns.state()). */
  debugState() {
    return {
      sweep: this.sweep,
      rows: this.rows.length,
      metric: this.metric,
      method: this.method,
      projection: this.proj
        ? { method: this.proj.method, columns: this.proj.columns, quality: this.proj.quality ?? null, rows: this.proj.rows }
        : null,
      points: this.projection.clientPoints(),
      selection: [...this.selection],
      tableSelected: [...this.table.root.querySelectorAll<HTMLElement>('tr[aria-selected="true"]')].map((tr) => tr.dataset.run ?? ''),
      filter: this.filter ? [...this.filter] : null,
      compare: this.pick && this.pickFor === this.selection.join(',') ? { video: this.pick.video, ids: this.pick.ids, ofVideo: this.pick.ofVideo } : null,
      lanes: this.cmp ? this.cmp.series.map((s) => s.id) : [],
      cursor: this.cmp ? this.compare.cursorFrame : null,
      disagreements: this.cmp ? this.cmp.disagreements.map((d) => ({ frame: d.frame, score: d.scoreMm })) : [],
    };
  }
}
