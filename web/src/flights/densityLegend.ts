// The density map's legend, on the map: the colour map as a bar of real width with ticks in the data's
// units, read from the legend of the current zoom's tiles (GET .../density/legend: the span they are shaded
// with and the colours they use, the minimum level included), so it follows the query, the value, the
// shading and the zoom (eq_hist: quartiles of the shaded pixels).

import { api, isAbort } from '../api/client';
import type { RenderOptions } from '../api/query';
import { LEGEND_STOPS, densityTicks, densityUnit, renderLegend, type DensityLegendAnswer, type LegendSpec } from '../lib/legend';
import { h } from '../lib/dom';

/** The legend bar's width in CSS pixels. */
export const DENSITY_LEGEND_WIDTH = 220;
/** The density source's highest zoom (map.ts): tiles above it are overzoomed z14 tiles. */
const MAX_TILE_ZOOM = 14;

const HOW_NOTES: Record<RenderOptions['how'], string> = {
  linear: 'linear scale',
  log: 'log scale',
  eq_hist: 'histogram-equalised: ticks are quantiles (0/25/50/75/100 %) of shaded pixels',
};

export class DensityLegend {
  readonly el: HTMLElement;
  private ctrl: AbortController | null = null;
  private key = '';
  /** What the legend shows now (the PNG export draws the same), null when nothing. */
  spec: LegendSpec | null = null;

  constructor(parent: HTMLElement) {
    this.el = h('div', { class: 'map-legend', 'data-testid': 'density-legend', hidden: true });
    parent.append(this.el);
  }

  /**
   * The zoom of the 256-px density tiles MapLibre requests at map zoom `zoom`: its zoom counts 512-px
   * tiles, so 256-px tiles are one level deeper, and raster sources round (SourceCache's covering tiles
   * with roundZoom).
   */
  static tileZoom(zoom: number): number {
    return Math.max(0, Math.min(MAX_TILE_ZOOM, Math.round(zoom + 1)));
  }

  /** Shows the legend of dataset `dataset` under `query` (without bbox) and `render` at map zoom `zoom`. */
  update(dataset: string | null, query: URLSearchParams | null, render: RenderOptions, zoom: number): void {
    if (!dataset || !query) {
      this.ctrl?.abort();
      this.key = '';
      this.el.hidden = true;
      this.spec = null;
      return;
    }
    const z = DensityLegend.tileZoom(zoom);
    const key = `${dataset}?${query.toString()}&z=${z}&value=${render.value}&how=${render.how}&cmap=${render.cmap}`;
    if (key === this.key) return;
    this.key = key;
    this.ctrl?.abort();
    const ctrl = new AbortController();
    this.ctrl = ctrl;
    this.el.dataset.state = 'loading';
    api
      .densityLegend(dataset, query, z, render, LEGEND_STOPS, ctrl.signal)
      .then((span) => this.show(span, render))
      .catch((e: unknown) => {
        if (isAbort(e)) return;
        this.key = '';
        this.el.dataset.state = 'error';
      });
  }

  private show(span: DensityLegendAnswer, render: RenderOptions) {
    this.el.hidden = false;
    this.el.dataset.state = 'ready';
    this.el.dataset.z = String(span.z);
    this.el.dataset.lo = String(span.lo);
    this.el.dataset.hi = String(span.hi);
    this.el.dataset.how = render.how;
    this.el.dataset.value = render.value;
    this.el.dataset.minLevel = String(span.min_level);
    if (span.empty) {
      this.el.replaceChildren(h('div', { class: 'value-legend-title' }, 'No traffic under these filters'));
      this.el.dataset.ticks = '';
      this.spec = null;
      return;
    }
    this.spec = {
      title: `Density: ${densityUnit(render.value)} (z${span.z})`,
      // The tiles' own colours (with the minimum level that keeps faint traffic off black).
      stops: span.stops.map((x) => x.color),
      ticks: densityTicks(span, render.how),
      width: DENSITY_LEGEND_WIDTH,
      testid: 'density-legend',
      note: HOW_NOTES[render.how],
    };
    renderLegend(this.el, this.spec);
  }
}
