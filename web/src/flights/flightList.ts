// The paged flight list, sorted on the server by any column (a header click; again reverses). Start, the
// first duration and the highest level are "in window": they cover only the flight's points passing the
// time window and filters; the second duration is the whole flight's. A row click selects the flight
// (flightsView.ts loads and draws its track).

import type { FlightPage, FlightRow, FlightSort, SortOrder } from '../api/types';
import { h, mount, sectionHead } from '../lib/dom';
import { formatFlightLevel, formatHoursMinutes, formatInt, formatUtc, formatUtcTime } from '../lib/format';

export interface FlightListEvents {
  onPage(page: number): void;
  onSelect(row: FlightRow): void;
  /** A header asked for another order (the page goes back to the first). */
  onSort(sort: FlightSort, order: SortOrder): void;
}

/** The list's columns: label, sort key, tooltip, and whether it is a number (right-aligned). */
const COLUMNS: { label: string; sort: FlightSort; title: string; num: boolean }[] = [
  { label: 'Callsign', sort: 'callsign', title: 'Callsign (ICAO24 in the row tooltip)', num: false },
  { label: 'Start', sort: 't_start', title: 'In window: first point passing the window and filters (UTC)', num: false },
  { label: 'In win.', sort: 'duration_s', title: 'In window: time between the first and last point passing the window and filters (h:mm)', num: true },
  { label: 'Flight', sort: 'flight_duration_s', title: 'Whole flight: first to last point, whatever the filters (h:mm)', num: true },
  { label: 'Max', sort: 'alt_max_m', title: 'In window: highest flight level of the points passing the filters', num: true },
];

export class FlightList {
  private readonly list: HTMLElement;
  private readonly count: HTMLElement;
  private readonly pager: HTMLElement;
  private selected: number | null = null;
  private multiDay = false;
  private sort: FlightSort = 't_start';
  private order: SortOrder = 'asc';
  private readonly head: HTMLElement;

  constructor(private readonly root: HTMLElement, private readonly events: FlightListEvents) {
    this.count = h('span', { class: 'section-meta', 'data-testid': 'flights-total', 'aria-live': 'polite' });
    this.pager = h('div', { class: 'pager' });
    this.list = h('ol', { class: 'flight-list', 'data-testid': 'flight-list', 'aria-label': 'Flights' });
    this.list.addEventListener('keydown', (e) => this.onKey(e));
    this.head = h('div', { class: 'flight-head', role: 'row', 'data-testid': 'flight-head' });
    this.renderHead();
    root.append(
      sectionHead('Flights', this.count),
      h(
        'div',
        { class: 'flight-groups', 'aria-hidden': 'true' },
        h('span', {}, ''),
        h('span', { class: 'grp' }, 'in window'),
        h('span', { class: 'grp whole' }, 'whole'),
        h('span', { class: 'grp' }, 'in win.'),
      ),
      this.head,
      this.list,
      this.pager,
    );
    this.setEmpty('Pick a data set.');
  }

  setLoading(): void {
    this.root.dataset.state = 'loading';
    this.root.classList.add('is-loading');
  }

  setEmpty(message: string): void {
    this.showMessage('empty', message);
  }

  setError(message: string): void {
    this.showMessage('error', message);
  }

  /** A message in place of the list (no count, no pager). */
  private showMessage(state: 'empty' | 'error', message: string) {
    this.root.dataset.state = state;
    this.root.classList.remove('is-loading');
    this.count.textContent = '';
    mount(this.list, h('li', { class: state === 'error' ? 'empty error-text' : 'empty' }, message));
    mount(this.pager);
  }

  /** The order shown (from the URL or the server's answer); does not emit. */
  setSort(sort: FlightSort, order: SortOrder): void {
    this.sort = sort;
    this.order = order;
    this.renderHead();
  }

  private renderHead() {
    this.root.dataset.sort = this.sort;
    this.root.dataset.order = this.order;
    mount(
      this.head,
      ...COLUMNS.map((c) => {
        const on = c.sort === this.sort;
        const b = h(
          'button',
          {
            type: 'button',
            class: `flight-sort${c.num ? ' num' : ''}${on ? ' on' : ''}`,
            title: `${c.title} · click to sort${on ? ', again to reverse' : ''}`,
            'aria-sort': on ? (this.order === 'asc' ? 'ascending' : 'descending') : 'none',
            'data-testid': `flight-sort-${c.sort}`,
            onclick: () => this.events.onSort(c.sort, on && this.order === 'asc' ? 'desc' : 'asc'),
          },
          c.label,
          on ? (this.order === 'asc' ? ' ▲' : ' ▼') : '',
        );
        return b;
      }),
    );
  }

  /** Whether start times need their date (the data set spans more than one UTC day). */
  setMultiDay(multiDay: boolean): void {
    this.multiDay = multiDay;
  }

  setSelected(id: number | null): void {
    this.selected = id;
    for (const b of this.list.querySelectorAll<HTMLButtonElement>('button.flight-row')) {
      const on = b.dataset.flightId === String(id);
      b.classList.toggle('selected', on);
      b.setAttribute('aria-pressed', String(on));
    }
  }

  set(p: FlightPage): void {
    this.root.dataset.state = 'ready';
    this.root.classList.remove('is-loading');
    this.count.textContent = `${formatInt(p.total)} total`;
    if (p.flights.length === 0) {
      mount(this.list, h('li', { class: 'empty' }, p.total === 0 ? 'No flights match these filters.' : 'No flights on this page.'));
    } else {
      mount(this.list, ...p.flights.map((f) => h('li', {}, this.row(f))));
    }
    this.renderPager(p);
  }

  private row(f: FlightRow): HTMLButtonElement {
    const on = f.id === this.selected;
    return h(
      'button',
      {
        type: 'button',
        class: on ? 'flight-row selected' : 'flight-row',
        'data-flight-id': String(f.id),
        'data-testid': 'flight-row',
        'aria-pressed': String(on),
        title: rowTitle(f),
        onclick: () => this.events.onSelect(f),
      },
      h('span', { class: 'mono cs' }, f.callsign || '—'),
      h('span', { class: 'mono', 'data-col': 't_start' }, this.multiDay ? `${formatUtc(f.t_start).slice(5, 10)} ${formatUtcTime(f.t_start)}` : formatUtcTime(f.t_start)),
      h('span', { class: 'num', 'data-col': 'duration_s' }, formatHoursMinutes(f.duration_s ?? f.t_end - f.t_start)),
      h('span', { class: 'num whole', 'data-col': 'flight_duration_s' }, f.flight_duration_s === undefined ? '–' : formatHoursMinutes(f.flight_duration_s)),
      h('span', { class: 'num', 'data-col': 'alt_max_m' }, formatFlightLevel(f.alt_max_m)),
    );
  }

  private renderPager(p: FlightPage) {
    const pages = Math.max(1, Math.ceil(p.total / p.page_size));
    const from = p.total === 0 ? 0 : p.page * p.page_size + 1;
    const to = Math.min(p.total, (p.page + 1) * p.page_size);
    mount(
      this.pager,
      h('button', { type: 'button', class: 'btn small', disabled: p.page <= 0, 'aria-label': 'Previous page', onclick: () => this.events.onPage(p.page - 1) }, '‹'),
      h('span', { class: 'pager-text' }, `${formatInt(from)}–${formatInt(to)} of ${formatInt(p.total)}`),
      h('button', { type: 'button', class: 'btn small', disabled: p.page + 1 >= pages, 'aria-label': 'Next page', onclick: () => this.events.onPage(p.page + 1) }, '›'),
    );
  }

  /** ↑/↓ move focus between rows. */
  private onKey(e: KeyboardEvent) {
    if (e.key !== 'ArrowDown' && e.key !== 'ArrowUp') return;
    const rows = [...this.list.querySelectorAll<HTMLButtonElement>('button.flight-row')];
    const i = rows.indexOf(document.activeElement as HTMLButtonElement);
    const next = rows[Math.min(rows.length - 1, Math.max(0, i + (e.key === 'ArrowDown' ? 1 : -1)))];
    if (next) {
      e.preventDefault();
      next.focus();
    }
  }
}

/** A row's tooltip: who, the part in the window and the whole flight. */
function rowTitle(f: FlightRow): string {
  const who = `${f.callsign || '—'} (${f.icao24 || 'no ICAO24'})`;
  const win = `in window ${formatUtc(f.t_start)} → ${formatUtc(f.t_end)} UTC, ${formatInt(f.points)} points`;
  const whole =
    f.flight_t_start !== undefined && f.flight_t_end !== undefined
      ? ` · whole flight ${formatUtc(f.flight_t_start)} → ${formatUtc(f.flight_t_end)} UTC${f.flight_points !== undefined ? `, ${formatInt(f.flight_points)} points` : ''}`
      : '';
  return `${who} · ${win}${whole}`;
}
