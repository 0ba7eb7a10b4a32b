// Transport controls of one viewer: play/pause, step ±1, seek slider, speed, and the frame readout.
// The server owns the cursor: controls send operations and show the state the server reports.
// Keyboard (on the tracker view): Space play/pause, ←/→ step, Shift+←/→ step 10, Home/End.

import { SPEED_MAX, SPEED_MIN, type PlayerState, type ReplayOp } from '../api/trackerTypes';
import { h } from '../lib/dom';

const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 4, 8, 16].filter((s) => s >= SPEED_MIN && s <= SPEED_MAX);

export class PlayerControls {
  readonly root: HTMLElement;
  private readonly play: HTMLButtonElement;
  private readonly slider: HTMLInputElement;
  private readonly speed: HTMLSelectElement;
  private readonly counter: HTMLElement;
  private readonly time: HTMLElement;
  private readonly computed: HTMLElement;
  private frames = 0;
  private state: PlayerState = { playing: false, frame: 0, speed: 1 };
  private dragging = false;
  private seekTimer: number | undefined;

  constructor(private readonly send: (op: ReplayOp) => void) {
    const btn = (label: string, title: string, testid: string, op: () => ReplayOp) => {
      const b = h('button', { class: 'btn small', type: 'button', title, 'aria-label': title, 'data-testid': testid }, label);
      b.addEventListener('click', () => this.send(op()));
      return b;
    };
    this.play = h('button', { class: 'btn small primary play-button', type: 'button', 'data-testid': 'replay-play' }, '▶');
    this.play.addEventListener('click', () => this.send({ op: this.state.playing ? 'pause' : 'play' }));
    this.slider = h('input', { type: 'range', min: 0, max: 0, step: 1, value: 0, class: 'seek-slider', 'aria-label': 'Frame', 'data-testid': 'replay-seek' });
    this.slider.addEventListener('input', () => {
      this.dragging = true;
      this.counter.textContent = this.counterText(Number(this.slider.value));
      window.clearTimeout(this.seekTimer);
      this.seekTimer = window.setTimeout(() => this.send({ op: 'seek', frame: Number(this.slider.value) }), 40);
    });
    this.slider.addEventListener('change', () => {
      window.clearTimeout(this.seekTimer);
      this.send({ op: 'seek', frame: Number(this.slider.value) });
      this.dragging = false;
    });
    this.speed = h('select', { 'aria-label': 'Playback speed', 'data-testid': 'replay-speed' }, ...SPEEDS.map((s) => h('option', { value: s }, `${s}×`)));
    this.speed.value = '1';
    this.speed.addEventListener('change', () => this.send({ op: 'speed', value: Number(this.speed.value) }));
    this.counter = h('span', { class: 'frame-counter mono', 'data-testid': 'replay-frame', 'data-frame': '0' });
    this.time = h('span', { class: 'frame-time mono muted', 'data-testid': 'replay-time' });
    this.computed = h('span', { class: 'frame-computed muted small', 'data-testid': 'replay-computed' });
    this.root = h(
      'div',
      { class: 'player-controls', 'data-testid': 'replay-controls' },
      btn('|◀', 'First frame (Home)', 'replay-first', () => ({ op: 'seek', frame: 0 })),
      btn('−1', 'Step back (←)', 'replay-step-back', () => ({ op: 'step', delta: -1 })),
      this.play,
      btn('+1', 'Step forward (→)', 'replay-step', () => ({ op: 'step', delta: 1 })),
      this.slider,
      this.counter,
      this.time,
      h('label', { class: 'speed-label' }, 'speed ', this.speed),
      this.computed,
    );
    this.render();
  }

  setFrames(n: number): void {
    this.frames = n;
    this.slider.max = String(Math.max(0, n - 1));
    this.render();
  }

  setState(s: PlayerState): void {
    this.state = s;
    this.render();
  }

  setTimestamp(t: number | null): void {
    this.time.textContent = t === null || !Number.isFinite(t) ? '' : `t = ${t.toFixed(3)} s`;
  }

  /** Keyboard shortcuts; returns true when the key was used. */
  handleKey(e: KeyboardEvent): boolean {
    const step = e.shiftKey ? 10 : 1;
    let op: ReplayOp | null = null;
    if (e.key === ' ') op = { op: this.state.playing ? 'pause' : 'play' };
    else if (e.key === 'ArrowRight') op = { op: 'step', delta: step };
    else if (e.key === 'ArrowLeft') op = { op: 'step', delta: -step };
    else if (e.key === 'Home') op = { op: 'seek', frame: 0 };
    else if (e.key === 'End') op = { op: 'seek', frame: Math.max(0, this.frames - 1) };
    if (op) this.send(op);
    return op !== null;
  }

  private counterText(frame: number) {
    return `frame ${frame} / ${Math.max(0, this.frames - 1)}`;
  }

  private render() {
    const s = this.state;
    this.play.textContent = s.playing ? '❚❚' : '▶';
    this.play.title = s.playing ? 'Pause (Space)' : 'Play (Space)';
    this.play.setAttribute('aria-label', this.play.title);
    this.play.dataset.playing = String(s.playing);
    if (!this.dragging) this.slider.value = String(s.frame);
    this.counter.textContent = this.counterText(s.frame);
    this.counter.dataset.frame = String(s.frame);
    if (document.activeElement !== this.speed) {
      const v = String(s.speed);
      if (![...this.speed.options].some((o) => o.value === v)) this.speed.append(h('option', { value: v }, `${v}×`));
      this.speed.value = v;
    }
    const c = s.computed;
    this.computed.textContent = s.done ? 'all frames computed' : c !== undefined && this.frames ? `computed ${c} / ${this.frames}` : '';
    this.root.dataset.playing = String(s.playing);
    this.root.dataset.speed = String(s.speed);
  }
}
