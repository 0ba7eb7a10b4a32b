// Sidebar controls: data set picker, filters and density rendering options.

import { COLORMAPS, DENSITY_HOWS, DENSITY_VALUES, EMPTY_FILTERS, normalizeBBox, type OnGround } from '../api/query';
import type { Colormap, Dataset, DensityHow, DensityValue } from '../api/types';
import type { AppState, Store } from './state';
import { debounce, h, mount, sectionHead } from '../lib/dom';
import { formatCompact, formatInt, formatUtc } from '../lib/format';
import type { ErrorSlots } from './errors';

const VALUE_LABELS: Record<DensityValue, string> = { count: 'Count', altitude: 'Altitude', speed: 'Speed' };
const HOW_LABELS: Record<DensityHow, string> = { linear: 'Linear', log: 'Log', eq_hist: 'Eq. hist' };
const CMAP_LABELS: Record<Colormap, string> = { fire: 'Fire', viridis: 'Viridis', inferno: 'Inferno', magma: 'Magma', gray: 'Gray' };

function field(label: string, control: HTMLElement, errorId: string, hint?: string): HTMLElement {
  return h(
    'div',
    { class: 'field' },
    h('label', { class: 'field-label', for: control.id }, label, hint ? h('span', { class: 'hint' }, hint) : null),
    control,
    h('div', { id: errorId }),
  );
}

function parseNum(v: string): number | null {
  if (v.trim() === '') return null;
  const n = Number(v);
  return Number.isFinite(n) ? n : null;
}

export class Controls {
  private readonly datasetSelect: HTMLSelectElement;
  private readonly datasetMeta: HTMLElement;
  private readonly altMin: HTMLInputElement;
  private readonly altMax: HTMLInputElement;
  private readonly callsign: HTMLInputElement;
  private readonly icao24: HTMLInputElement;
  private readonly onGround: HTMLSelectElement;
  private readonly useMapView: HTMLInputElement;
  private readonly bboxReadout: HTMLElement;
  private readonly value: HTMLSelectElement;
  private readonly how: HTMLSelectElement;
  private readonly cmap: HTMLSelectElement;
  private readonly legend: HTMLElement;

  constructor(
    datasetRoot: HTMLElement,
    filterRoot: HTMLElement,
    renderRoot: HTMLElement,
    store: Store,
    errors: ErrorSlots,
  ) {
    // Data set
    this.datasetSelect = h('select', { id: 'dataset', 'data-testid': 'dataset-select', 'data-param': 'dataset' });
    this.datasetSelect.addEventListener('change', () => store.set({ datasetId: this.datasetSelect.value || null, selectedFlight: null }));
    this.datasetMeta = h('div', { class: 'dataset-meta', 'data-testid': 'dataset-meta' });
    datasetRoot.append(field('Data set', this.datasetSelect, 'dataset-error'), this.datasetMeta);

    // Filters
    const commitAlt = () => store.setFilters({ altMin: parseNum(this.altMin.value), altMax: parseNum(this.altMax.value) });
    const commitAltSoon = debounce(commitAlt, 500);
    const altInput = (id: string, label: string, param: string) => {
      const el = h('input', {
        id,
        type: 'number',
        inputmode: 'numeric',
        min: -2000,
        max: 60000,
        step: 500,
        placeholder: label,
        'aria-label': `Altitude ${label} (feet)`,
        'data-testid': id,
        'data-param': param,
      });
      el.addEventListener('input', () => commitAltSoon());
      el.addEventListener('change', () => commitAltSoon.flush());
      return el;
    };
    this.altMin = altInput('alt-min', 'from', 'alt_min alt_unit');
    this.altMax = altInput('alt-max', 'to', 'alt_max alt_unit');

    // A text filter: its value (trimmed) is committed 350 ms after typing stops, or at once on change.
    const textFilter = (id: 'callsign' | 'icao24', placeholder: string) => {
      const el = h('input', { id, type: 'search', placeholder, autocomplete: 'off', spellcheck: 'false', 'data-testid': id, 'data-param': id });
      const commit = debounce(() => store.setFilters({ [id]: el.value.trim() }), 350);
      el.addEventListener('input', () => commit());
      el.addEventListener('change', () => commit.flush());
      return el;
    };
    this.callsign = textFilter('callsign', 'AFR, BAW1*');
    this.icao24 = textFilter('icao24', '4ca7b5');

    this.onGround = h(
      'select',
      { id: 'on-ground', 'data-testid': 'on-ground', 'data-param': 'on_ground' },
      h('option', { value: 'any' }, 'All'),
      h('option', { value: 'false' }, 'Airborne'),
      h('option', { value: 'true' }, 'On ground'),
    );
    this.onGround.addEventListener('change', () => store.setFilters({ onGround: this.onGround.value as OnGround }));

    this.useMapView = h('input', { id: 'use-map-view', type: 'checkbox', role: 'switch', 'data-testid': 'use-map-view', 'data-param': 'bbox' });
    this.useMapView.addEventListener('change', () => store.set({ useMapView: this.useMapView.checked }));
    this.bboxReadout = h('div', { class: 'hint mono', 'data-testid': 'bbox-readout' });

    const reset = h('button', { type: 'button', class: 'link-button', 'data-testid': 'reset-filters' }, 'Reset');
    reset.addEventListener('click', () => store.set({ filters: { ...EMPTY_FILTERS }, useMapView: false }));

    filterRoot.append(
      sectionHead('Filters', reset),
      h(
        'div',
        { class: 'field' },
        h('span', { class: 'field-label', id: 'alt-label' }, 'Altitude band', h('span', { class: 'hint' }, 'ft, barometric')),
        h('div', { class: 'range-row', role: 'group', 'aria-labelledby': 'alt-label' }, this.altMin, h('span', { class: 'muted' }, '–'), this.altMax),
        h('div', { id: 'alt-error' }),
      ),
      h(
        'div',
        { class: 'field-row' },
        field('Callsign', this.callsign, 'callsign-error', 'prefix, *'),
        field('ICAO24', this.icao24, 'icao24-error', 'hex list'),
      ),
      h(
        'div',
        { class: 'field-row' },
        field('Ground state', this.onGround, 'on-ground-error'),
        h(
          'div',
          { class: 'field' },
          h('span', { class: 'field-label' }, 'Area'),
          h('label', { class: 'switch', for: 'use-map-view' }, this.useMapView, h('span', {}, 'Map view only')),
          this.bboxReadout,
          h('div', { id: 'bbox-error' }),
        ),
      ),
    );

    // Density rendering
    const select = <T extends string>(id: string, options: readonly T[], labels: Record<T, string>, param: string, on: (v: T) => void) => {
      const el = h('select', { id, 'data-testid': id, 'data-param': param }, ...options.map((o) => h('option', { value: o }, labels[o])));
      el.addEventListener('change', () => on(el.value as T));
      return el;
    };
    this.value = select('density-value', DENSITY_VALUES, VALUE_LABELS, 'value', (value) => store.setRender({ value }));
    this.how = select('density-how', DENSITY_HOWS, HOW_LABELS, 'how', (how) => store.setRender({ how }));
    this.cmap = select('density-cmap', COLORMAPS, CMAP_LABELS, 'cmap', (cmap) => store.setRender({ cmap }));
    this.legend = h('div', { class: 'legend' });
    renderRoot.append(
      sectionHead('Density'),
      h(
        'div',
        { class: 'render-grid' },
        field('Value', this.value, 'value-error'),
        field('Scale', this.how, 'how-error'),
        field('Colours', this.cmap, 'cmap-error'),
      ),
      this.legend,
      h('div', { id: 'render-error' }),
    );

    errors.register(['dataset'], document.getElementById('dataset-error')!);
    errors.register(['alt_min', 'alt_max', 'alt_unit'], document.getElementById('alt-error')!);
    errors.register(['callsign'], document.getElementById('callsign-error')!);
    errors.register(['icao24'], document.getElementById('icao24-error')!);
    errors.register(['on_ground'], document.getElementById('on-ground-error')!);
    errors.register(['bbox'], document.getElementById('bbox-error')!);
    errors.register(['value'], document.getElementById('value-error')!);
    errors.register(['how'], document.getElementById('how-error')!);
    errors.register(['cmap'], document.getElementById('cmap-error')!);
    errors.register(['size', 'z', 'x', 'y'], document.getElementById('render-error')!);

    store.subscribe((s, prev) => this.sync(s, prev));
    this.sync(store.get(), null);
  }

  private sync(s: AppState, prev: AppState | null) {
    if (!prev || s.datasets !== prev.datasets || s.datasetId !== prev.datasetId) this.syncDatasets(s);
    if (!prev || s.filters !== prev.filters) {
      const f = s.filters;
      setIfIdle(this.altMin, f.altMin === null ? '' : String(f.altMin));
      setIfIdle(this.altMax, f.altMax === null ? '' : String(f.altMax));
      setIfIdle(this.callsign, f.callsign);
      setIfIdle(this.icao24, f.icao24);
      this.onGround.value = f.onGround;
    }
    this.useMapView.checked = s.useMapView;
    this.bboxReadout.textContent = s.useMapView && s.mapBBox ? normalizeBBox(s.mapBBox).map((v) => v.toFixed(2)).join(', ') : '';
    if (!prev || s.render !== prev.render) {
      this.value.value = s.render.value;
      this.how.value = s.render.how;
      this.cmap.value = s.render.cmap;
      // The legend that reads values sits on the map (densityLegend.ts): it needs the zoom's span.
      mount(this.legend, h('span', { class: 'hint' }, `${CMAP_LABELS[s.render.cmap]}, ${HOW_LABELS[s.render.how]}: values in the legend on the map`));
    }
  }

  private syncDatasets(s: AppState) {
    const sel = this.datasetSelect;
    if (s.datasets.length === 0) {
      mount(sel, h('option', { value: '' }, 'No data sets yet'));
      sel.disabled = true;
      mount(this.datasetMeta, h('p', { class: 'empty' }, 'Upload a file below, or run ', h('code', {}, 'trailscope ingest FILE --name NAME'), '.'));
      return;
    }
    sel.disabled = false;
    mount(
      sel,
      s.datasetId ? null : h('option', { value: '' }, 'Choose a data set…'),
      ...s.datasets.map((d) => h('option', { value: d.id }, `${d.name} · ${formatCompact(d.flights)} flights`)),
    );
    sel.value = s.datasetId ?? '';
    const d = s.datasets.find((x) => x.id === s.datasetId);
    mount(this.datasetMeta, d ? datasetMeta(d) : null);
  }
}

function datasetMeta(d: Dataset): HTMLElement {
  return h(
    'div',
    { title: `${formatInt(d.flights)} flights, ${formatInt(d.points)} points, ${formatUtc(d.t_min)} → ${formatUtc(d.t_max)} UTC` },
    `${d.format} · ${formatInt(d.flights)} flights · ${formatCompact(d.points)} points`,
    h('br'),
    `${formatUtc(d.t_min)} → ${formatUtc(d.t_max)} UTC`,
    ingestQuality(d),
  );
}

/** The ingest report's data-quality line: implausible values found and flights split between legs and at teleports. */
function ingestQuality(d: Dataset): HTMLElement | null {
  const q = (d.ingest as { quality?: Record<string, { count?: number } | undefined> } | undefined)?.quality;
  if (!q) return null;
  const n = (k: string) => q[k]?.count ?? 0;
  const parts = [
    [n('speed'), 'speeds'],
    [n('altitude'), 'altitudes'],
    [n('jumps'), 'jumps'],
    [n('jump_splits'), 'split at teleports'],
    [n('leg_splits'), 'split between legs'],
  ].filter(([c]) => (c as number) > 0);
  return h(
    'div',
    { class: 'hint', 'data-testid': 'dataset-quality', 'data-speed': String(n('speed')), 'data-altitude': String(n('altitude')), 'data-jumps': String(n('jumps')), 'data-splits': String(n('jump_splits')), 'data-leg-splits': String(n('leg_splits')) },
    parts.length ? `Ingest flagged: ${parts.map(([c, l]) => `${formatInt(c as number)} ${l}`).join(' · ')}` : 'Ingest: no implausible values',
  );
}

/** Updates an input from state unless the analyst is typing in it. */
function setIfIdle(el: HTMLInputElement, v: string) {
  if (document.activeElement !== el && el.value !== v) el.value = v;
}
