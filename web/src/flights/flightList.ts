// The paged flight list. A row click selects the flight (flightsView.ts loads and draws its track).

import type { FlightPage, FlightRow } from '../api/types';
import { h, mount, sectionHead } from '../lib/dom';
import { formatFlightLevel, formatHoursMinutes, formatInt, formatUtc, formatUtcTime } from '../lib/format';

export interface FlightListEvents {
  onPage(page: number): void;
  onSelect(row: FlightRow): void;
}

export class FlightList {
  private readonly list: HTMLElement;
  private readonly count: HTMLElement;
  private readonly pager: HTMLElement;
  private selected: number | null = null;
  private multiDay = false;

  constructor(private readonly root: HTMLElement, private readonly events: FlightListEvents) {
    this.count = h('span', { class: 'section-meta', 'data-testid': 'flights-total', 'aria-live': 'polite' });
    this.pager = h('div', { class: 'pager' });
    this.list = h('ol', { class: 'flight-list', 'data-testid': 'flight-list', 'aria-label': 'Flights' });
    this.list.addEventListener('keydown', (e) => this.onKey(e));
    root.append(
      sectionHead('Flights', this.count),
      h(
        'div',
        { class: 'flight-head', 'aria-hidden': 'true' },
        h('span', {}, 'Callsign'),
        h('span', {}, 'ICAO24'),
        h('span', {}, 'Start (UTC)'),
        h('span', { class: 'num', title: 'Duration (h:mm)' }, 'Dur.'),
        h('span', { class: 'num', title: 'Highest flight level' }, 'Max'),
      ),
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
        title: `${f.callsign || f.icao24} · ${formatUtc(f.t_start)} → ${formatUtc(f.t_end)} UTC · ${formatInt(f.points)} points`,
        onclick: () => this.events.onSelect(f),
      },
      h('span', { class: 'mono cs' }, f.callsign || '—'),
      h('span', { class: 'mono muted' }, f.icao24 || '—'),
      h('span', { class: 'mono' }, this.multiDay ? `${formatUtc(f.t_start).slice(5, 10)} ${formatUtcTime(f.t_start)}` : formatUtcTime(f.t_start)),
      h('span', { class: 'num' }, formatHoursMinutes(f.t_end - f.t_start)),
      h('span', { class: 'num' }, formatFlightLevel(f.alt_max_m)),
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
