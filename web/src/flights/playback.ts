// The flight dashboard's playback view: the moving aircraft (animation/ TrafficAnimation) over the map at
// the clock's instant (clock.ts), with the density or bundled map of the window dimmed behind, and the
// transport (play/pause, steps, speed), trail tails, colour-by with its legend, hover, click to select and
// follow, the keyboard, and optionally the bundles that follow the clock.
//
// The view owns no time: it drives the one Clock and draws what the clock says; the time histogram's cursor
// and any other layer (a congestion panel, the streamed bundles) subscribe to the same clock.

import type * as maplibregl from 'maplibre-gl';
import type { AnimationStats, ColorBy, PickedAircraft, TrafficAnimationApi, TrafficAnimationOptions, TrafficFilter } from './animation/types';
import { Clock, MAX_TAIL_S, SPEEDS, STEP_LARGE_S, STEP_SMALL_S, formatSpeed, type ClockState } from './clock';
import { COLOR_BY_LABELS, legendGradient, legendTicks } from './playbackLegend';
import { PLAYBACK_KEYS, ownsKeys, playbackAction } from './playbackKeys';
import type { BundleStreamHandle } from './bundleStream';
import type { Filters } from '../api/query';
import { normalizeCallsign, normalizeIcao24 } from '../api/query';
import type { BBox } from '../api/types';
import { h, mount } from '../lib/dom';
import { formatBytes, formatDuration, formatFlightLevel, formatInt, formatSpeed as formatGroundSpeed } from '../lib/format';

export type AnimationFactory = (map: maplibregl.Map, datasetId: string, opts: TrafficAnimationOptions) => TrafficAnimationApi;

/** Starts the streamed bundles (bundles that follow the clock) of the last `windowS` seconds (bundleStream.ts). */
export type BundleStreamFactory = (
  map: maplibregl.Map,
  datasetId: string,
  getTime: () => number,
  windowS: number,
  onError: (detail: string) => void,
) => BundleStreamHandle;

export const COLOR_BYS: readonly ColorBy[] = ['altitude', 'speed', 'vrate', 'callsign'];
/** Bundles that follow the clock cover the last N minutes. */
export const BUNDLE_WINDOWS_S: readonly number[] = [600, 1800, 3600];
/** Seconds of data kept loaded ahead of the playhead per unit of speed while playing (2 s of real time). */
const LOOKAHEAD_REAL_S = 2;

export interface PlaybackEvents {
  /** An aircraft was clicked: select that flight (the map follows it). */
  onSelect(flightId: number, callsign: string, icao24: string): void;
  /** Esc while not following: deselect. */
  onDeselect(): void;
  /** Something the URL keeps changed (on, tail, colour-by, follow). */
  onChange(): void;
}

/** The parts of the filters the playback applies on the client (no refetch). */
export function trafficFilter(f: Filters, bbox: BBox | null): TrafficFilter {
  const out: TrafficFilter = {};
  const FT = 0.3048;
  if (f.altMin !== null) out.altMinM = f.altMin * FT;
  if (f.altMax !== null) out.altMaxM = f.altMax * FT;
  // The same callsign pattern and addresses the API's queries get (buildQuery), matched by the API's rule.
  const cs = normalizeCallsign(f.callsign);
  if (cs) out.callsign = cs;
  const icao = normalizeIcao24(f.icao24);
  if (icao) out.icao24 = icao.split(',');
  if (bbox) out.bbox = [bbox[0], bbox[1], bbox[2], bbox[3]];
  return out;
}

/** "2018-01-01 23:59:59.5" (tenths only when the instant has a fraction). */
export function formatInstant(t: number): string {
  if (!Number.isFinite(t)) return '–';
  const whole = Math.floor(t);
  const frac = t - whole;
  const base = new Date(whole * 1000).toISOString().slice(0, 19).replace('T', ' ');
  const tenths = Math.floor(frac * 10 + 1e-6);
  return frac > 0 ? `${base}.${tenths}` : base;
}

export class PlaybackView {
  readonly root: HTMLElement;
  private anim: TrafficAnimationApi | null = null;
  private animDataset: string | null = null;
  private datasetId: string | null = null;
  private datasetSpan: [number, number] | null = null;
  private legendAt = 0;
  private on = false;
  private tail: number;
  private colorBy: ColorBy;
  private filter: TrafficFilter = {};
  private following: number | null = null;
  private selected: number | null = null;
  private bundles: BundleStreamHandle | null = null;
  private bundleWindow = BUNDLE_WINDOWS_S[1]!;
  private bundlesOn = false;
  private pointer: { x: number; y: number } | null = null;
  private hoverFrame = 0;
  private stats: AnimationStats | null = null;

  private readonly toggle: HTMLInputElement;
  private readonly body: HTMLElement;
  private readonly playBtn: HTMLButtonElement;
  private readonly readout: HTMLElement;
  private readonly speedSel: HTMLSelectElement;
  private readonly tailInput: HTMLInputElement;
  private readonly tailReadout: HTMLElement;
  private readonly colorSel: HTMLSelectElement;
  private readonly legend: HTMLElement;
  private readonly statsEl: HTMLElement;
  private readonly followEl: HTMLElement;
  private readonly tooltip: HTMLElement;
  private readonly bundleToggle: HTMLInputElement | null = null;
  private readonly bundleWindowSel: HTMLSelectElement | null = null;
  private readonly errorEl: HTMLElement;

  constructor(
    parent: HTMLElement,
    private readonly map: maplibregl.Map,
    private readonly clock: Clock,
    private readonly createAnimation: AnimationFactory,
    private readonly events: PlaybackEvents,
    initial: { on: boolean; tail: number; colorBy: ColorBy },
    private readonly createBundleStream: BundleStreamFactory | null = null,
  ) {
    this.tail = initial.tail;
    this.colorBy = initial.colorBy;

    this.toggle = h('input', { id: 'playback-on', type: 'checkbox', role: 'switch', 'data-testid': 'playback-toggle' });
    this.toggle.addEventListener('change', () => this.setOn(this.toggle.checked));

    const btn = (label: string, title: string, testid: string, onclick: () => void) =>
      h('button', { type: 'button', class: 'btn small', title, 'aria-label': title, 'data-testid': testid, onclick }, label);
    this.playBtn = btn('▶', 'Play (Space)', 'playback-play', () => this.clock.toggle());
    this.readout = h('span', { class: 'playback-time mono', 'data-testid': 'playback-time', 'aria-live': 'off' });
    this.speedSel = h(
      'select',
      { class: 'playback-speed', 'aria-label': 'Playback speed (+/−)', title: 'Playback speed (+/−)', 'data-testid': 'playback-speed' },
      ...SPEEDS.map((s) => h('option', { value: String(s) }, formatSpeed(s))),
    );
    this.speedSel.addEventListener('change', () => this.clock.setSpeed(Number(this.speedSel.value)));

    this.tailInput = h('input', {
      type: 'range',
      min: 0,
      max: MAX_TAIL_S,
      step: 30,
      value: this.tail,
      'aria-label': 'Trail tail length (seconds)',
      'data-testid': 'playback-tail',
    });
    this.tailReadout = h('span', { class: 'playback-tail-readout mono' });
    this.tailInput.addEventListener('input', () => this.setTail(Number(this.tailInput.value)));

    this.colorSel = h(
      'select',
      { 'aria-label': 'Colour aircraft by', 'data-testid': 'playback-color' },
      ...COLOR_BYS.map((c) => h('option', { value: c }, COLOR_BY_LABELS[c])),
    );
    this.colorSel.value = this.colorBy;
    this.colorSel.addEventListener('change', () => this.setColorBy(this.colorSel.value as ColorBy));
    this.legend = h('div', { class: 'playback-legend', 'data-testid': 'playback-legend' });
    this.statsEl = h('span', { class: 'playback-stats muted', 'data-testid': 'playback-stats' });
    this.followEl = h('span', { class: 'playback-follow', 'data-testid': 'playback-follow', hidden: true });
    this.errorEl = h('div', { class: 'playback-error field-error', role: 'alert', hidden: true });

    const help = h(
      'span',
      { class: 'playback-help', tabindex: 0, 'aria-label': 'Playback keyboard controls', 'data-testid': 'playback-help' },
      '?',
      h(
        'span',
        { class: 'playback-help-box', role: 'tooltip' },
        h('strong', {}, 'Playback keys'),
        h('dl', {}, ...PLAYBACK_KEYS.flatMap(([k, v]) => [h('dt', {}, k), h('dd', {}, v)])),
        h('span', { class: 'muted' }, 'Playback stops at the end of the time window; play again starts it over.'),
      ),
    );

    let bundleRow: HTMLElement | null = null;
    if (this.createBundleStream) {
      this.bundleToggle = h('input', { id: 'playback-bundles', type: 'checkbox', role: 'switch', 'data-testid': 'playback-bundles' });
      this.bundleToggle.addEventListener('change', () => this.setBundles(this.bundleToggle!.checked));
      this.bundleWindowSel = h(
        'select',
        { 'aria-label': 'Bundled minutes before the instant', 'data-testid': 'playback-bundle-window' },
        ...BUNDLE_WINDOWS_S.map((s) => h('option', { value: String(s) }, `last ${formatDuration(s)}`)),
      );
      this.bundleWindowSel.value = String(this.bundleWindow);
      this.bundleWindowSel.addEventListener('change', () => {
        this.bundleWindow = Number(this.bundleWindowSel!.value);
        this.bundles?.setWindow(this.bundleWindow);
      });
      bundleRow = h(
        'div',
        { class: 'playback-row' },
        h('label', { class: 'switch', for: 'playback-bundles' }, this.bundleToggle, h('span', {}, 'Bundles follow the clock')),
        this.bundleWindowSel,
      );
    }

    this.body = h(
      'div',
      { class: 'playback-body' },
      h(
        'div',
        { class: 'playback-row' },
        btn('−1m', `Back ${STEP_LARGE_S} s (Shift+←)`, 'playback-back-min', () => this.clock.step(-STEP_LARGE_S)),
        btn('−1s', `Back ${STEP_SMALL_S} s (←)`, 'playback-back-s', () => this.clock.step(-STEP_SMALL_S)),
        this.playBtn,
        btn('+1s', `Forward ${STEP_SMALL_S} s (→)`, 'playback-fwd-s', () => this.clock.step(STEP_SMALL_S)),
        btn('+1m', `Forward ${STEP_LARGE_S} s (Shift+→)`, 'playback-fwd-min', () => this.clock.step(STEP_LARGE_S)),
        this.readout,
        this.speedSel,
      ),
      h(
        'div',
        { class: 'playback-row' },
        h('label', { class: 'field-label' }, 'Tail'),
        this.tailInput,
        this.tailReadout,
        h('label', { class: 'field-label' }, 'Colour'),
        this.colorSel,
      ),
      this.legend,
      bundleRow,
      h('div', { class: 'playback-row' }, this.statsEl, this.followEl),
      this.errorEl,
    );
    this.root = h(
      'div',
      { class: 'playback', 'data-testid': 'playback', 'data-state': 'off' },
      h('div', { class: 'playback-head' }, h('label', { class: 'switch', for: 'playback-on' }, this.toggle, h('span', {}, 'Traffic in motion')), help),
      this.body,
    );
    parent.append(this.root);

    this.tooltip = h('div', { class: 'aircraft-tooltip', 'data-testid': 'aircraft-tooltip', hidden: true });
    map.getContainer().append(this.tooltip);

    clock.subscribe((s, prev) => this.onClock(s, prev));
    map.on('mousemove', (e) => {
      this.pointer = { x: e.point.x, y: e.point.y };
      this.scheduleHover();
    });
    map.on('mouseout', () => {
      this.pointer = null;
      this.tooltip.hidden = true;
    });
    map.on('click', (e) => this.onClick(e.point));
    // Panning by hand takes the map back from the followed flight.
    map.on('dragstart', () => this.release());
    // Capture: in playback the arrows step the clock even when the time histogram has focus.
    window.addEventListener('keydown', (e) => this.onKey(e), { capture: true });
    // A focused button would take Space's key-up as a click (a second play/pause).
    window.addEventListener(
      'keyup',
      (e) => {
        if (e.key === ' ' && this.on && this.anim && !ownsKeys(e.target)) e.preventDefault();
      },
      { capture: true },
    );

    this.on = initial.on;
    this.toggle.checked = this.on;
    this.syncTail();
    this.syncClock(clock.get());
    this.syncOn();
  }

  // ---------- state the URL keeps ----------
  isOn(): boolean {
    return this.on;
  }
  tailSeconds(): number {
    return this.tail;
  }
  color(): ColorBy {
    return this.colorBy;
  }
  /** The animation layer (null while playback is off): for the console and the browser test. */
  animation(): TrafficAnimationApi | null {
    return this.anim;
  }

  setOn(on: boolean): void {
    if (on === this.on) return;
    this.on = on;
    this.toggle.checked = on;
    if (!on) {
      this.clock.pause();
      this.release();
      this.setBundles(false);
    }
    this.syncOn();
    this.events.onChange();
  }

  /** The data set whose traffic plays (null: none) and its [t_min, t_max]. A new data set starts a new layer. */
  setDataset(id: string | null, span: [number, number] | null): void {
    if (id === this.datasetId) return;
    this.datasetId = id;
    this.datasetSpan = span;
    this.release();
    if (this.bundlesOn) this.restartBundles();
    this.syncOn();
  }

  /** The dashboard's filters as the layer applies them (altitude band, callsign, bbox): no refetch. */
  setFilters(f: Filters, bbox: BBox | null): void {
    this.filter = trafficFilter(f, bbox);
    this.anim?.setFilter(this.filter);
  }

  /** The selected flight (from the list, the card or a click); highlighted, and followed when clicked here. */
  setSelected(id: number | null): void {
    this.selected = id;
    this.anim?.setSelected(id);
    if (id === null || id !== this.following) this.release();
  }

  setTail(seconds: number): void {
    this.tail = Math.min(MAX_TAIL_S, Math.max(0, Math.round(seconds)));
    this.anim?.setTail(this.tail);
    this.syncTail();
    this.events.onChange();
  }

  setColorBy(c: ColorBy): void {
    this.colorBy = c;
    this.colorSel.value = c;
    this.anim?.setColorBy(c);
    this.renderLegend();
    this.events.onChange();
  }

  // ---------- internals ----------
  private syncOn() {
    this.root.dataset.state = this.on ? 'on' : 'off';
    this.body.hidden = !this.on;
    const want = this.on ? this.datasetId : null;
    if (want !== this.animDataset) {
      this.anim?.destroy();
      this.anim = null;
      this.animDataset = want;
      this.stats = null;
      this.tooltip.hidden = true;
      if (want) {
        const a = this.createAnimation(this.map, want, { tailSeconds: this.tail, colorBy: this.colorBy, span: this.datasetSpan });
        this.anim = a;
        a.setFilter(this.filter);
        a.setSelected(this.selected);
        a.onStats((s) => {
          if (this.anim !== a) return;
          this.stats = s;
          this.renderStats();
          // The callsign legend lists the prefixes on screen: refresh it about once a second.
          if (this.colorBy === 'callsign' && performance.now() - this.legendAt > 1000) this.renderLegend();
        });
        a.onError((err) => {
          if (this.anim !== a) return;
          this.errorEl.hidden = false;
          this.errorEl.textContent = err.message;
        });
        const t = this.clock.get().t;
        if (Number.isFinite(t)) a.setTime(t);
        this.syncLookahead(this.clock.get());
      }
    }
    this.errorEl.hidden = true;
    this.renderLegend();
    this.renderStats();
    this.map.getContainer().dataset.playback = String(this.on && this.anim !== null);
  }

  private onClock(s: ClockState, prev: ClockState) {
    if (s.t !== prev.t && this.anim && Number.isFinite(s.t)) {
      this.anim.setTime(s.t);
      this.follow();
      if (this.pointer) this.scheduleHover();
    }
    if (s.playing !== prev.playing || s.speed !== prev.speed) this.syncLookahead(s);
    this.syncClock(s);
  }

  private syncLookahead(s: ClockState) {
    this.anim?.setLookahead(s.playing ? s.speed * LOOKAHEAD_REAL_S : 0);
  }

  private syncClock(s: ClockState) {
    this.readout.textContent = `${formatInstant(s.t)} UTC`;
    this.root.dataset.t = Number.isFinite(s.t) ? String(s.t) : '';
    this.root.dataset.playing = String(s.playing);
    this.root.dataset.speed = String(s.speed);
    this.playBtn.textContent = s.playing ? '❚❚' : '▶';
    const label = s.playing ? 'Pause (Space)' : 'Play (Space)';
    this.playBtn.title = label;
    this.playBtn.setAttribute('aria-label', label);
    this.playBtn.disabled = s.span === null;
    if (this.speedSel.value !== String(s.speed)) this.speedSel.value = String(s.speed);
  }

  private syncTail() {
    this.tailInput.value = String(this.tail);
    this.tailReadout.textContent = this.tail === 0 ? 'off' : formatDuration(this.tail);
    this.root.dataset.tail = String(this.tail);
  }

  private renderLegend() {
    if (!this.anim) {
      mount(this.legend);
      return;
    }
    this.legendAt = performance.now();
    const l = this.anim.legend();
    const ticks = legendTicks(l);
    this.legend.dataset.colorBy = l.colorBy;
    this.root.dataset.colorBy = this.colorBy;
    if (ticks.length > 0 && ticks[0]!.at !== null) {
      mount(
        this.legend,
        h('div', { class: 'playback-legend-bar', style: `background:${legendGradient(ticks)}`, role: 'img', 'aria-label': `${COLOR_BY_LABELS[l.colorBy]} colour scale` }),
        h(
          'div',
          { class: 'playback-legend-ticks' },
          ...ticks.map((t, i) =>
            h(
              'span',
              {
                class: 'playback-legend-tick',
                'data-testid': 'playback-legend-tick',
                // The first and last labels align to the bar's ends so they are never cut.
                style: `left:${((t.at ?? 0) * 100).toFixed(1)}%;transform:translateX(${i === 0 ? 0 : i === ticks.length - 1 ? -100 : -50}%)`,
              },
              t.label,
            ),
          ),
        ),
      );
    } else {
      mount(
        this.legend,
        h(
          'div',
          { class: 'playback-legend-swatches' },
          ...ticks.map((t) =>
            h('span', { class: 'playback-legend-swatch', 'data-testid': 'playback-legend-tick' }, h('i', { style: `background:${t.color}` }), t.label),
          ),
        ),
      );
    }
  }

  private renderStats() {
    const s = this.stats;
    this.statsEl.textContent = s ? `${formatInt(s.aircraft)} aircraft · ${s.chunksInMemory} chunks (${formatBytes(s.bytesInMemory)})${s.pending ? ' · loading…' : ''}` : '';
    this.root.dataset.aircraft = s ? String(s.aircraft) : '';
    this.root.dataset.pending = s ? String(s.pending) : '';
  }

  private scheduleHover() {
    if (this.hoverFrame) return;
    this.hoverFrame = requestAnimationFrame(() => {
      this.hoverFrame = 0;
      this.hover();
    });
  }

  private hover() {
    const p = this.pointer;
    const a = p && this.anim ? this.anim.pick(p) : null;
    this.map.getCanvas().style.cursor = a ? 'pointer' : '';
    if (!a || !p) {
      this.tooltip.hidden = true;
      delete this.tooltip.dataset.flightId;
      return;
    }
    mount(
      this.tooltip,
      h('strong', { class: 'cs' }, a.callsign || a.icao24 || `#${a.flightId}`),
      h('span', {}, formatFlightLevel(a.altM)),
      h('span', {}, formatGroundSpeed(a.speedMs)),
    );
    this.tooltip.dataset.flightId = String(a.flightId);
    this.tooltip.hidden = false;
    const c = this.map.getContainer();
    const x = Math.min(p.x + 14, c.clientWidth - this.tooltip.offsetWidth - 4);
    const y = Math.max(4, p.y - this.tooltip.offsetHeight - 10);
    this.tooltip.style.transform = `translate(${x}px, ${y}px)`;
  }

  private onClick(point: { x: number; y: number }) {
    if (!this.on || !this.anim) return;
    const a = this.anim.pick(point);
    if (!a) return;
    this.startFollowing(a);
    this.events.onSelect(a.flightId, a.callsign, a.icao24);
  }

  private startFollowing(a: PickedAircraft) {
    this.selected = a.flightId;
    this.anim?.setSelected(a.flightId);
    this.following = a.flightId;
    this.followEl.hidden = false;
    this.followEl.textContent = `following ${a.callsign || a.icao24 || `#${a.flightId}`} · Esc releases`;
    this.map.getContainer().dataset.following = String(a.flightId);
    this.follow();
  }

  private follow() {
    if (this.following === null || !this.anim) return;
    const a = this.anim.aircraft(this.following);
    if (a && Number.isFinite(a.lon) && Number.isFinite(a.lat)) this.map.jumpTo({ center: [a.lon, a.lat] });
  }

  /** Stops following (the flight stays selected). */
  release(): boolean {
    if (this.following === null) return false;
    this.following = null;
    this.followEl.hidden = true;
    delete this.map.getContainer().dataset.following;
    return true;
  }

  private onKey(e: KeyboardEvent) {
    if (!this.on || !this.anim || ownsKeys(e.target)) return;
    if (dashboardHidden(this.root)) return;
    const act = playbackAction(e);
    if (!act) return;
    switch (act.kind) {
      case 'toggle':
        this.clock.toggle();
        break;
      case 'step':
        this.clock.step(act.seconds);
        break;
      case 'faster':
        this.clock.faster();
        break;
      case 'slower':
        this.clock.slower();
        break;
      case 'release':
        // Esc: first stop following, then (a second Esc) let the dashboard deselect.
        if (!this.release()) {
          // On the time histogram Esc clears its window (timeBrush.ts), as without playback.
          if (this.selected === null || (e.target instanceof Element && e.target.closest('.brush-plot'))) return;
          this.events.onDeselect();
        }
        break;
    }
    e.preventDefault();
    e.stopPropagation();
  }

  private setBundles(on: boolean) {
    if (!this.createBundleStream || !this.bundleToggle) return;
    this.bundlesOn = on;
    this.bundleToggle.checked = on;
    this.restartBundles();
  }

  private restartBundles() {
    this.bundles?.stop();
    this.bundles = null;
    if (this.bundlesOn && this.on && this.datasetId && this.createBundleStream) {
      this.bundles = this.createBundleStream(this.map, this.datasetId, () => this.clock.get().t, this.bundleWindow, (detail) => {
        this.errorEl.hidden = false;
        this.errorEl.textContent = `Bundles: ${detail}`;
      });
    }
    this.root.dataset.bundles = String(this.bundles !== null);
  }
}

/** Whether another dashboard (tracker, runs) is shown: the flight view's keys are then not its business. */
function dashboardHidden(el: HTMLElement): boolean {
  return el.offsetParent === null && getComputedStyle(el).position !== 'fixed';
}
