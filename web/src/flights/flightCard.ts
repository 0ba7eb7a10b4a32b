// The info card of the selected flight, over the map.

import type { FlightFeature, FlightRow } from '../api/types';
import { renderLegend, linearTicks } from '../lib/legend';
import { ALTITUDE_STOPS_FT } from '../lib/colors';
import { h, mount } from '../lib/dom';
import { formatAltitude, formatDuration, formatFlightLevel, formatInt, formatSpeed, formatUtcSeconds } from '../lib/format';

export class FlightCard {
  private readonly el: HTMLElement;

  constructor(parent: HTMLElement, private readonly onClose: () => void) {
    this.el = h('section', { class: 'flight-card', 'data-testid': 'flight-card', 'aria-label': 'Selected flight', hidden: true });
    parent.append(this.el);
  }

  hide(): void {
    this.el.hidden = true;
    mount(this.el);
  }

  loading(row: FlightRow): void {
    this.el.hidden = false;
    this.el.dataset.state = 'loading';
    mount(this.el, this.header(row.callsign, row.icao24), h('p', { class: 'muted' }, 'Loading track…'));
  }

  error(row: FlightRow, message: string): void {
    this.el.hidden = false;
    this.el.dataset.state = 'error';
    mount(this.el, this.header(row.callsign, row.icao24), h('p', { class: 'error-text' }, message));
  }

  show(row: FlightRow, f: FlightFeature): void {
    const p = f.properties;
    const times = p.times ?? [];
    const t0 = times.length ? times[0]! : row.t_start;
    const t1 = times.length ? times[times.length - 1]! : row.t_end;
    const alts = (p.altitudes_m ?? []).filter((a): a is number => typeof a === 'number' && Number.isFinite(a));
    const maxAlt = alts.length ? Math.max(...alts) : row.alt_max_m;
    const speeds = (p.speeds_ms ?? []).filter((v): v is number => typeof v === 'number' && Number.isFinite(v));
    const maxSpeed = speeds.length ? Math.max(...speeds) : null;
    this.el.hidden = false;
    this.el.dataset.state = 'ready';
    this.el.dataset.flightId = String(p.id);
    const dl = h('dl', { class: 'kv' });
    const add = (k: string, v: string, testid?: string) => dl.append(h('dt', {}, k), h('dd', { 'data-testid': testid }, v));
    add('First seen', `${formatUtcSeconds(t0)} UTC`, 'card-t-start');
    add('Last seen', `${formatUtcSeconds(t1)} UTC`, 'card-t-end');
    add('Duration (whole flight)', formatDuration(t1 - t0), 'card-duration');
    add('Max altitude', `${formatAltitude(maxAlt)} (${formatFlightLevel(maxAlt)})`, 'card-alt-max');
    if (maxSpeed !== null) add('Max speed', formatSpeed(maxSpeed));
    add('Points', formatInt(f.geometry.coordinates.length));
    mount(
      this.el,
      this.header(p.callsign || row.callsign, p.icao24 || row.icao24),
      dl,
      altitudeLegend(),
    );
  }

  private header(callsign: string, icao24: string): HTMLElement {
    return h(
      'header',
      { class: 'card-head' },
      h('span', { class: 'card-callsign mono', 'data-testid': 'card-callsign' }, callsign || '—'),
      h('span', { class: 'card-icao mono muted', 'data-testid': 'card-icao24', title: 'ICAO 24-bit address' }, icao24 || 'no ICAO24'),
      h('button', { type: 'button', class: 'icon-button', 'aria-label': 'Close flight', title: 'Close (Esc)', onclick: () => this.onClose() }, '×'),
    );
  }
}

/** The track's altitude ramp (ALTITUDE_STOPS_FT) as a legend with flight-level ticks. */
function altitudeLegend(): HTMLElement {
  const el = h('div', { class: 'card-legend' });
  const top = ALTITUDE_STOPS_FT[ALTITUDE_STOPS_FT.length - 1]![0];
  renderLegend(el, {
    title: 'Track colour: altitude',
    stops: ALTITUDE_STOPS_FT.map(([, c]) => c),
    ticks: linearTicks(0, top, 4, (ft) => (ft === 0 ? 'GND' : `FL${String(Math.round(ft / 100)).padStart(3, '0')}`)),
    width: 200,
    testid: 'altitude-legend',
  });
  return el;
}
