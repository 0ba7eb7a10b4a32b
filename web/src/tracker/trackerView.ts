// The tracker dashboard: wiring between a frame source and the linked views. Two sources:
//  - a live replay ("#tracker?replay=ID"): the server owns this viewer's cursor; every view seeks through
//    the WebSocket ({"op":"seek"}), and every frame the server shows moves the cursor of every view. The
//    frame-axis views cover the whole video: frames seen over the socket are kept, and once the replay's
//    run is stored its records are fetched;
//  - a stored run ("#tracker?run=ID&frame=N", storedRun.ts): the cursor is local, the run's records are
//    fetched in pages and the pictures of the cursor frame from the video; no WebSocket.

import { ApiError, isAbort } from '../api/client';
import { ReplaySocket, trackerApi } from '../api/replay';
import type { PlayerState, Replay, ReplayOp, TrackerParam } from '../api/trackerTypes';
import type { FrameMessage } from '../api/tsrf';
import { h } from '../lib/dom';
import { FrameData } from './frameData';
import { FrameStore } from './frameStore';
import { PlayerControls } from './playerControls';
import { parseTrackerRoute, trackerHash, trackerRunHash } from './route';
import { ReplayImages } from './replayImages';
import { SetupPanel } from './setupPanel';
import { StateTimeline } from './stateTimeline';
import { StoredRunSource, type ShownFrame } from './storedRun';
import { Trajectories } from './trajectories';
import './tracker.css';

const POLL_MS = 1000;
/** Frames per request to the run frames route (its kMaxRunFramesPerPage is 1000). */
const RUN_CHUNK = 1000;

export class TrackerView {
  readonly root: HTMLElement;
  private readonly setup: SetupPanel;
  private readonly controls: PlayerControls;
  private readonly images: ReplayImages;
  private readonly timeline: StateTimeline;
  private readonly trajectories: Trajectories;
  private readonly frameData: FrameData;
  private readonly status: HTMLElement;
  private replay: Replay | null = null;
  /** The replay this tab started (released when it starts another and nobody else watches). */
  private own: string | null = null;
  private socket: ReplaySocket | null = null;
  /** The stored run shown instead of a replay (null in replay mode). */
  private stored: StoredRunSource | null = null;
  private store: FrameStore | null = null;
  private state: PlayerState = { playing: false, frame: 0, speed: 1 };
  private current = 0;
  /** A live replay's frame from the URL, sought once its socket says hello. */
  private pendingReplayFrame: number | null = null;
  /** Depth coloured per frame (each frame's own 2nd–98th percentiles) rather than with the video's one range. */
  private depthPerFrame = false;
  private videoDepthRange: [number, number] | undefined = undefined;
  private readonly depthToggle: HTMLInputElement;
  private run: string | null = null;
  private done = false;
  private pollTimer: number | undefined;
  private fetchingRun = false;
  private params: TrackerParam[] = [];
  private ctrl = new AbortController();
  private unsubscribe: (() => void) | null = null;
  private storeDirty = false;

  constructor(host: HTMLElement) {
    this.setup = new SetupPanel({ onStart: (video, params, colormap) => void this.start(video, params, colormap) });
    this.controls = new PlayerControls((op) => this.send(op));
    this.images = new ReplayImages();
    this.timeline = new StateTimeline((f) => this.seek(f));
    this.trajectories = new Trajectories((f) => this.seek(f));
    this.frameData = new FrameData();
    this.status = h('div', { class: 'tracker-status muted small', 'data-testid': 'tracker-status', role: 'status' });
    this.depthToggle = h('input', { type: 'checkbox', 'data-testid': 'depth-per-frame' });
    this.depthToggle.addEventListener('change', () => this.setDepthPerFrame(this.depthToggle.checked));
    const depthOption = h(
      'label',
      { class: 'check small', title: 'Colour each frame’s depth with its own 2nd–98th percentiles (near structures keep their contrast) instead of one range for the whole video' },
      this.depthToggle,
      ' per-frame depth range',
    );
    this.root = h(
      'div',
      { class: 'tracker', 'data-testid': 'tracker', 'data-state': 'idle', tabindex: -1 },
      h('aside', { class: 'tracker-side panel' }, this.setup.root, this.status),
      h('section', { class: 'tracker-main tracker-panel', 'aria-label': 'Replay' }, this.controls.root, depthOption, this.images.root),
      h('aside', { class: 'tracker-data' }, this.frameData.root),
      h('div', { class: 'tracker-bottom' }, this.timeline.root, this.trajectories.root),
    );
    host.append(this.root);
    // Transport keys anywhere in the shown tracker view, except while typing (and Space on a button).
    window.addEventListener('keydown', (e) => {
      if ((!this.replay && !this.stored) || this.root.offsetParent === null || e.ctrlKey || e.metaKey || e.altKey) return;
      const t = e.target as HTMLElement;
      if (t.closest?.('input, select, textarea, [contenteditable]')) return;
      if (e.key === ' ' && t.closest?.('button, summary, a')) return;
      if (this.controls.handleKey(e)) e.preventDefault();
    });
    (window as unknown as { trailscopeTracker: unknown }).trailscopeTracker = this;
  }

  /** Called when the route shows the tracker (first time and after coming back). */
  async activate(hash: string): Promise<void> {
    const q = parseTrackerRoute(hash);
    if (this.params.length === 0) await this.loadLists(q.video);
    if (q.depthPerFrame !== this.depthPerFrame) {
      this.depthPerFrame = q.depthPerFrame;
      this.depthToggle.checked = q.depthPerFrame;
      this.stored?.setDepthRange(q.depthPerFrame ? undefined : this.videoDepthRange);
    }
    if (q.run) {
      if (q.run !== this.stored?.info.run) await this.openRun(q.run, q.frame);
      else if (q.frame !== null && q.frame !== this.current) this.seek(q.frame);
      return;
    }
    const id = q.replay;
    if (id && id !== this.replay?.id) {
      this.pendingReplayFrame = q.frame;
      await this.openById(id);
    } else if (id && q.frame !== null && q.frame !== this.current) this.seek(q.frame);
  }

  /** The stored run this viewer shows (null in replay mode). */
  get runId(): string | null {
    return this.stored?.info.run ?? null;
  }

  /** Frames of the video shown (the cursor's range). */
  private get frameCount(): number {
    return this.replay?.frames ?? this.stored?.info.frames ?? 0;
  }

  /** Opens a stored run at video frame `frame` (its first recorded frame when null). */
  private async openRun(runId: string, frame: number | null) {
    this.close();
    this.replay = null;
    this.run = null;
    this.done = true;
    this.store = null;
    const d = this.root.dataset;
    delete d.replay;
    delete d.connection;
    d.run = runId;
    d.state = 'loading';
    d.complete = 'false';
    this.setup.setError('');
    this.setStatus(`Loading run ${runId}…`);
    const signal = this.ctrl.signal;
    try {
      const row = await trackerApi.run(runId, signal);
      const video = await trackerApi.video(row.video, signal);
      if (signal.aborted) return;
      const frames = video.frame_count;
      this.videoDepthRange = video.depth_range_mm;
      this.depthToggle.disabled = false;
      this.depthToggle.title = '';
      const store = new FrameStore(frames);
      this.store = store;
      this.unsubscribe = store.subscribe(() => this.onStoreChange());
      this.current = -1;
      this.state = { playing: false, frame: 0, speed: 1 };
      this.controls.setTimestamp(null);
      this.images.reset(video.intrinsics?.width ?? 0, video.intrinsics?.height ?? 0);
      this.controls.setFrames(frames);
      this.controls.setState(this.state);
      this.timeline.setStore(store);
      this.trajectories.setStore(store);
      this.frameData.show(0, null, null);
      const params: Record<string, number> = {};
      (row.param_names ?? []).forEach((n, i) => {
        const v = row.params?.[i];
        if (typeof v === 'number') params[n] = v;
      });
      this.setup.selectVideo(row.video);
      this.setup.setParams(this.params, params);
      const logFrames = typeof row.summary?.frames === 'number' ? row.summary.frames : null;
      this.setup.setRun(runId, `${logFrames ?? '?'} frames tracked of ${frames} · video ${video.name || row.video}`);
      const source = new StoredRunSource(
        {
          run: runId,
          video: row.video,
          frames,
          fps: video.fps > 0 ? video.fps : (row.summary?.fps ?? 30),
          logFrames,
          videoHasTruth: video.has_truth !== false,
          colormap: this.setup.colormapValue,
          ...(video.depth_range_mm && !this.depthPerFrame ? { depthRange: video.depth_range_mm } : {}),
        },
        store,
        {
          onState: (s) => this.onState(s),
          onFrame: (f) => this.onStoredFrame(f),
          onPage: (loaded, total) => {
            d.loaded = String(loaded);
            d.complete = String(loaded >= total);
            this.setStatus(loaded >= total ? '' : `Loading run ${runId}: ${loaded} / ${total} frames…`);
          },
          onError: (msg) => this.setStatus(msg, true),
        },
      );
      this.stored = source;
      d.state = 'ready';
      // Without a frame, the source starts at the run's first frame (a run may cover part of its video).
      source.start(frame);
      this.root.focus({ preventScroll: true });
    } catch (e) {
      if (isAbort(e)) return;
      const msg = e instanceof ApiError && e.status === 404 ? `Run ${runId} is not stored on the server.` : e instanceof ApiError ? e.detail : String(e);
      this.setup.setError(msg);
      this.setStatus(msg, true);
      d.state = 'error';
    }
  }

  private onStoredFrame(f: ShownFrame) {
    this.images.show(f);
    if (f.index !== this.current) return;
    this.frameData.show(f.index, f.frame, f.truth);
    if (f.frame) this.controls.setTimestamp(f.frame.timestampS);
  }

  /** The replay this viewer shows (for the browser test and the console). */
  get replayId(): string | null {
    return this.replay?.id ?? null;
  }

  private async loadLists(preferVideo: string | null) {
    try {
      const [videos, params] = await Promise.all([trackerApi.videos(this.ctrl.signal), trackerApi.params(this.ctrl.signal)]);
      this.params = params;
      this.setup.setVideos(videos, preferVideo);
      this.setup.setParams(params);
      this.setStatus(videos.length ? '' : 'No videos yet.');
    } catch (e) {
      if (isAbort(e)) return;
      this.setup.setError(e instanceof ApiError ? e.detail : String(e));
    }
  }

  private async start(video: string, params: Record<string, number>, colormap: string) {
    this.setup.setBusy(true);
    this.setup.setError('');
    try {
      await this.releaseOwn();
      let replay: Replay;
      try {
        replay = await trackerApi.startReplay(video, params, colormap);
      } catch (e) {
        // The server runs a few replays at once: make room by removing one that nobody watches, once.
        if (!(e instanceof ApiError && e.status === 409 && (await this.freeSlot()))) throw e;
        replay = await trackerApi.startReplay(video, params, colormap);
      }
      this.own = replay.id;
      this.open(replay);
    } catch (e) {
      const err = e instanceof ApiError ? e : null;
      this.setup.setError(err ? err.detail : String(e), err?.param);
    } finally {
      this.setup.setBusy(false);
    }
  }

  private async openById(id: string) {
    try {
      this.open(await trackerApi.replay(id));
    } catch (e) {
      const msg = e instanceof ApiError && e.status === 404 ? `Replay ${id} is not on the server (it ended or the server restarted).` : e instanceof ApiError ? e.detail : String(e);
      this.setup.setError(msg);
      this.root.dataset.state = 'error';
    }
  }

  private open(replay: Replay) {
    this.close();
    delete this.root.dataset.run;
    delete this.root.dataset.loaded;
    this.replay = replay;
    this.run = replay.run ?? null;
    this.done = replay.done ?? false;
    this.current = 0;
    this.state = { playing: false, frame: 0, speed: 1 };
    const store = new FrameStore(replay.frames);
    this.store = store;
    this.unsubscribe = store.subscribe(() => this.onStoreChange());
    this.images.reset(replay.width, replay.height);
    this.controls.setFrames(replay.frames);
    this.controls.setState(this.state);
    this.timeline.setStore(store);
    this.trajectories.setStore(store);
    this.frameData.show(0, null, null);
    this.setup.selectVideo(replay.video);
    this.setup.selectColormap(replay.colormap);
    this.setup.setParams(this.params, replay.params ?? {});
    const range = replay.depth_range_mm;
    this.setup.setReplay(replay.id, `${replay.frames} frames${range ? ` · depth ${Math.round(range[0])}–${Math.round(range[1])} mm (${replay.colormap ?? 'colour map'})` : ''}`);
    this.root.dataset.replay = replay.id;
    this.root.dataset.state = 'connecting';
    const next = trackerHash(replay.id, this.pendingReplayFrame);
    if (window.location.hash !== next) history.replaceState(null, '', next);
    // A live replay's pictures come with its one depth range (chosen when it started).
    this.depthToggle.disabled = true;
    this.depthToggle.title = 'A live replay sends its pictures with one depth range; open its stored run for per-frame ranges.';

    const socket = new ReplaySocket(replay.ws, {
      onHello: (m) => {
        this.root.dataset.state = 'ready';
        // A reconnect starts a fresh cursor at frame 0: go back to where this viewer was.
        const resume = this.pendingReplayFrame ?? this.current;
        this.pendingReplayFrame = null;
        this.onState(m.state);
        if (resume > 0 && m.state.frame !== resume) this.seek(resume);
      },
      onState: (s) => this.onState(s),
      onFrame: (m) => this.onFrame(m),
      onRun: (run) => {
        this.run = run;
        this.maybeFetchRun();
      },
      onError: (error, detail) => this.setStatus(`${error}: ${detail}`, true),
      onConnection: (st) => {
        this.root.dataset.connection = st;
        if (st === 'closed') {
          this.setStatus('Replay connection lost; reconnecting…', true);
          void this.checkGone(replay.id);
        } else if (st === 'open') this.setStatus('');
      },
    });
    this.socket = socket;
    socket.open();
    this.poll();
    this.root.focus({ preventScroll: true });
  }

  /** Deletes the replay this tab started last when no other viewer watches it (its run stays stored). */
  private async releaseOwn() {
    const id = this.own;
    if (!id) return;
    this.own = null;
    try {
      const r = await trackerApi.replay(id);
      if ((r.viewers ?? 0) > (this.replay?.id === id ? 1 : 0)) return;
      if (this.replay?.id === id) this.close();
      await trackerApi.deleteReplay(id);
    } catch {
      /* gone already, or the server is away: nothing to release */
    }
  }

  /** Removes the oldest finished replay without viewers; false when there is none. */
  private async freeSlot(): Promise<boolean> {
    try {
      const idle = (await trackerApi.replays()).find((r) => r.done && (r.viewers ?? 0) === 0);
      if (!idle) return false;
      await trackerApi.deleteReplay(idle.id);
      return true;
    } catch {
      return false;
    }
  }

  /** After a lost connection: stop reconnecting when the replay no longer exists (deleted, server restarted). */
  private async checkGone(id: string) {
    try {
      await trackerApi.replay(id, this.ctrl.signal);
    } catch (e) {
      if (e instanceof ApiError && e.status === 404 && this.replay?.id === id) {
        this.socket?.close();
        this.root.dataset.connection = 'gone';
        this.setStatus(`Replay ${id} is not on the server any more: start a new one.`, true);
      }
    }
  }

  private close() {
    this.socket?.close();
    this.socket = null;
    this.stored?.close();
    this.stored = null;
    this.unsubscribe?.();
    this.unsubscribe = null;
    window.clearTimeout(this.pollTimer);
    this.ctrl.abort();
    this.ctrl = new AbortController();
    this.fetchingRun = false;
  }

  private send(op: ReplayOp) {
    if (this.stored) this.stored.send(op);
    else if (!this.socket?.send(op)) this.setStatus('Not connected to a replay.', true);
  }

  private setDepthPerFrame(on: boolean) {
    this.depthPerFrame = on;
    this.root.dataset.depthPerFrame = String(on);
    if (!this.stored) return;
    this.stored.setDepthRange(on ? undefined : this.videoDepthRange);
    const next = trackerRunHash(this.stored.info.run, this.current, on);
    if (window.location.hash !== next) history.replaceState(null, '', next);
  }

  /** Every view's seek. The cursor moves at once; the server's frame follows. */
  private seek(frame: number) {
    const n = this.frameCount;
    if (n === 0) return;
    const f = Math.max(0, Math.min(n - 1, Math.round(frame)));
    this.send({ op: 'seek', frame: f });
    this.setCurrent(f);
  }

  private onState(s: PlayerState) {
    this.state = s;
    if (s.done) this.done = true;
    this.controls.setState(s);
    this.root.dataset.playing = String(s.playing);
    if (s.frame !== this.current) this.setCurrent(s.frame);
    if (!s.playing && (this.stored || this.replay)) {
      // The URL follows the cursor of a stored run or a live replay (not while playing: browsers throttle
      // history updates).
      const next = this.stored ? trackerRunHash(this.stored.info.run, s.frame, this.depthPerFrame) : trackerHash(this.replay!.id, s.frame > 0 ? s.frame : null);
      if (window.location.hash !== next) history.replaceState(null, '', next);
    }
    if (this.done) this.maybeFetchRun();
  }

  private onFrame(m: FrameMessage) {
    if (!this.store) return;
    this.store.put(m.index, m.frame, m.truth);
    this.images.show(m);
    this.state = { ...this.state, frame: m.index };
    this.controls.setState(this.state);
    this.setCurrent(m.index);
    this.controls.setTimestamp(m.timestampS);
  }

  private setCurrent(f: number) {
    this.current = f;
    this.root.dataset.frame = String(f);
    this.timeline.surface.setCursor(f);
    this.trajectories.setCursor(f);
    const rec = this.store?.records[f] ?? null;
    this.frameData.show(f, rec, this.store?.truth[f] ?? null);
    if (rec) this.controls.setTimestamp(rec.timestampS);
  }

  private onStoreChange() {
    // Coalesce: frames arrive up to hundreds per second.
    if (this.storeDirty) return;
    this.storeDirty = true;
    window.setTimeout(() => {
      this.storeDirty = false;
      this.timeline.update();
      this.trajectories.invalidate();
      const s = this.store;
      if (s) this.root.dataset.known = String(s.knownCount);
    }, 100);
  }

  /** Follows the replay's progress until its run is stored (the socket also says so; this is the fallback). */
  private poll() {
    const replay = this.replay;
    if (!replay || (this.done && this.run)) return;
    const signal = this.ctrl.signal;
    this.pollTimer = window.setTimeout(async () => {
      try {
        const r = await trackerApi.replay(replay.id, signal);
        if (this.replay !== replay) return;
        if (r.done) this.done = true;
        if (r.error) {
          this.setStatus(`The tracker run failed: ${r.error.detail}`, true);
          if (r.done) return; // no run will be stored
        }
        if (r.run) this.run = r.run;
        if (typeof r.computed === 'number') this.controls.setState({ ...this.state, computed: r.computed, done: this.done });
        this.maybeFetchRun();
      } catch (e) {
        if (isAbort(e)) return;
      }
      if (this.replay === replay) this.poll();
    }, POLL_MS);
  }

  /** Once the run is stored, fills every frame not seen yet from it, in chunks. */
  private async maybeFetchRun() {
    const store = this.store;
    const run = this.run;
    if (!store || !run || !this.done || this.fetchingRun || store.complete) return;
    this.fetchingRun = true;
    const signal = this.ctrl.signal;
    try {
      let from = store.firstGap();
      while (from < store.frames && this.store === store) {
        const to = Math.min(store.frames, from + RUN_CHUNK); // exclusive, as the route takes it
        const items = await trackerApi.runFrames(run, from, to, signal);
        // Frames already seen over the socket keep their truth; the run's records are the same.
        store.putMany(items.filter((it) => !store.records[it.frame.index]));
        // Go on at the first hole; when the run has nothing for it (a shorter or capped answer), skip the
        // range asked, so the loop always advances.
        const next = store.firstGap(from);
        from = next > from ? next : store.firstGap(to);
      }
      this.onStoreChange();
      this.root.dataset.complete = String(store.complete);
      if (this.store === store) this.setCurrent(this.current);
    } catch (e) {
      if (!isAbort(e)) this.setStatus(`Could not load the run's frames: ${e instanceof ApiError ? e.detail : String(e)}`, true);
    } finally {
      if (this.store === store) this.fetchingRun = false;
    }
  }

  private setStatus(text: string, error = false) {
    this.status.textContent = text;
    this.status.classList.toggle('error-text', error);
  }
}
