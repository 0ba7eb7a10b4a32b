// The tracker API: videos, parameters, replays and stored runs (REST), and one replay WebSocket viewer.

import { fetchOk, request } from './client';
import { ReconnectingSocket, type SocketState } from './socket';
import type { RunRow } from './runsTypes';
import { decodeRunFrames, decodeTruth, toNumber, type FrameRecord, type FrameTruth } from './trackerLog';
import type { PlayerState, Replay, ReplayOp, TrackerParam, Video } from './trackerTypes';
import { parseFrameMessage, type FrameMessage } from './tsrf';


/** A list answered bare or wrapped ({videos: [...]}, {params: [...]}, ...). */
function listOf<T>(body: unknown, key: string): T[] {
  if (Array.isArray(body)) return body as T[];
  if (body && typeof body === 'object') {
    const v = (body as Record<string, unknown>)[key];
    if (Array.isArray(v)) return v as T[];
  }
  return [];
}

const enc = encodeURIComponent;

/** A parameter description as the server lists it (`default` or `default_value`). */
export function normalizeParam(p: Record<string, unknown>): TrackerParam {
  const n = (v: unknown, d: number) => (typeof v === 'number' && Number.isFinite(v) ? v : d);
  return {
    name: String(p.name ?? ''),
    unit: typeof p.unit === 'string' ? p.unit : '',
    default_value: n(p.default_value ?? p.default, NaN),
    min: n(p.min, -Infinity),
    max: n(p.max, Infinity),
    integer: p.integer === true,
    help: typeof p.help === 'string' ? p.help : '',
  };
}

export const trackerApi = {
  videos: async (signal?: AbortSignal) => listOf<Video>(await request<unknown>('/api/v1/videos', { signal }), 'videos'),

  params: async (signal?: AbortSignal) =>
    listOf<Record<string, unknown>>(await request<unknown>('/api/v1/tracker/params', { signal }), 'params').map(normalizeParam),

  /** Starts a replay; empty `params` and no `colormap` keep the server's defaults. */
  startReplay(video: string, params: Record<string, number>, colormap?: string) {
    const body: Record<string, unknown> = { video };
    if (Object.keys(params).length) body.params = params;
    if (colormap) body.colormap = colormap;
    return request<Replay>('/api/v1/replays', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(body),
    });
  },

  replay: (id: string, signal?: AbortSignal) => request<Replay>(`/api/v1/replays/${enc(id)}`, { signal }),

  replays: async (signal?: AbortSignal) => listOf<Replay>(await request<unknown>('/api/v1/replays', { signal }), 'replays'),

  /** Stops a replay and closes its viewers (its run, once stored, stays). */
  async deleteReplay(id: string): Promise<void> {
    // 404: already gone, which is what was asked.
    await fetchOk(`/api/v1/replays/${enc(id)}`, { method: 'DELETE' }, (res) => res.ok || res.status === 404);
  },

  /** Frame records [from, to) of a stored run, with their truth when the run has it (at most 1000 a page). */
  async runFrames(run: string, from: number, to: number, signal?: AbortSignal): Promise<{ frame: FrameRecord; truth: FrameTruth | null }[]> {
    const q = new URLSearchParams({ from: String(from), to: String(to) });
    return decodeRunFrames(await request<unknown>(`/api/v1/runs/${enc(run)}/frames?${q.toString()}`, { signal }), from);
  },

  /** One page [from, to) of a stored run's frames with its envelope (log positions, not video indices); `to` null: the server's default page. */
  async runFramesPage(run: string, from: number, to: number | null, signal?: AbortSignal): Promise<RunFramesPage> {
    const q = new URLSearchParams({ from: String(from) });
    if (to !== null) q.set('to', String(to));
    return decodeRunFramesPage(await request<unknown>(`/api/v1/runs/${enc(run)}/frames?${q.toString()}`, { signal }), from);
  },

  /** A stored run's row (GET /api/v1/runs/{run}: the list row plus its log header). */
  run: (id: string, signal?: AbortSignal) => request<RunRow & { header?: Record<string, unknown> }>(`/api/v1/runs/${enc(id)}`, { signal }),

  video: (id: string, signal?: AbortSignal) => request<Video>(`/api/v1/videos/${enc(id)}`, { signal }),

  /** The ground truth of one video frame (null when the video has none). */
  async videoFrameTruth(video: string, index: number, signal?: AbortSignal): Promise<FrameTruth | null> {
    const body = await request<{ truth?: unknown }>(`/api/v1/videos/${enc(video)}/frames/${index}`, { signal });
    return decodeTruth(body?.truth);
  },

  /**
   * A video frame's picture: depth (in `colormap`, over `range` mm — the video's one range, so colours do not
   * flicker — or else the frame's own) or amplitude, as PNG bytes.
   */
  async framePng(
    video: string,
    index: number,
    kind: 'depth' | 'amplitude',
    colormap?: string,
    signal?: AbortSignal,
    range?: [number, number],
  ): Promise<Uint8Array> {
    const p = new URLSearchParams();
    if (kind === 'depth' && colormap) p.set('colormap', colormap);
    if (kind === 'depth' && range) p.set('min', String(range[0])), p.set('max', String(range[1]));
    const q = p.toString() ? `?${p.toString()}` : '';
    const res = await fetchOk(`/api/v1/videos/${enc(video)}/frames/${index}/${kind}.png${q}`, { signal });
    return new Uint8Array(await res.arrayBuffer());
  },
};

/** A decoded page of GET /api/v1/runs/{run}/frames. */
export interface RunFramesPage {
  /** Log positions [from, to) of the page, and the run's frame count. */
  from: number;
  to: number;
  total: number;
  items: { frame: FrameRecord; truth: FrameTruth | null }[];
  /** False when the run stores no ground truth ("truth": null). */
  hasTruth: boolean;
}

export function decodeRunFramesPage(raw: unknown, from: number): RunFramesPage {
  const body = raw && typeof raw === 'object' && !Array.isArray(raw) ? (raw as Record<string, unknown>) : {};
  const items = decodeRunFrames(raw, from);
  const f = toNumber(body.from, from);
  return {
    from: f,
    to: toNumber(body.to, f + items.length),
    total: toNumber(body.total, NaN),
    items,
    hasTruth: Array.isArray(body.truth),
  };
}

export interface HelloMessage {
  replay: Partial<Replay>;
  header: Record<string, unknown> | null;
  state: PlayerState;
}

export interface ReplaySocketHandlers {
  onHello(msg: HelloMessage): void;
  onState(state: PlayerState): void;
  onFrame(msg: FrameMessage): void;
  onRun(run: string): void;
  onError(error: string, detail: string): void;
  onConnection(state: SocketState): void;
}

function playerState(o: Record<string, unknown>, prev?: PlayerState): PlayerState {
  const n = (k: string, d: number) => (typeof o[k] === 'number' ? (o[k] as number) : d);
  const s: PlayerState = {
    playing: typeof o.playing === 'boolean' ? o.playing : (prev?.playing ?? false),
    frame: n('frame', prev?.frame ?? 0),
    speed: n('speed', prev?.speed ?? 1),
  };
  const computed = typeof o.computed === 'number' ? o.computed : prev?.computed;
  const done = typeof o.done === 'boolean' ? o.done : prev?.done;
  if (computed !== undefined) s.computed = computed;
  if (done !== undefined) s.done = done;
  return s;
}

/** One viewer of a replay: its own cursor on the server. Reconnects with backoff while not closed. */
export class ReplaySocket {
  private readonly socket: ReconnectingSocket;
  private last: PlayerState | undefined;

  constructor(path: string, private readonly handlers: ReplaySocketHandlers) {
    this.socket = new ReconnectingSocket(path, {
      onState: (st) => handlers.onConnection(st),
      onText: (text) => this.onText(text),
      onBinary: (data) => {
        try {
          handlers.onFrame(parseFrameMessage(data));
        } catch (e) {
          handlers.onError('bad_frame', String(e instanceof Error ? e.message : e));
        }
      },
      // 4xxx / 1008 (policy) from the server mean "this replay is gone": do not hammer it.
      isFinal: (ev) => ev.code === 1008 || (ev.code >= 4000 && ev.code < 5000),
    });
  }

  open(): void {
    this.socket.start();
  }

  close(): void {
    this.socket.stop();
  }

  get isOpen(): boolean {
    return this.socket.isOpen;
  }

  send(op: ReplayOp): boolean {
    return this.socket.send(JSON.stringify(op));
  }

  private onText(text: string) {
    let msg: Record<string, unknown>;
    try {
      const parsed: unknown = JSON.parse(text);
      if (!parsed || typeof parsed !== 'object') return;
      msg = parsed as Record<string, unknown>;
    } catch {
      return;
    }
    const obj = (v: unknown) => (v && typeof v === 'object' && !Array.isArray(v) ? (v as Record<string, unknown>) : null);
    switch (msg.type) {
      case 'hello': {
        this.last = playerState(obj(msg.state) ?? {});
        this.handlers.onHello({ replay: (obj(msg.replay) ?? {}) as Partial<Replay>, header: obj(msg.header), state: this.last });
        break;
      }
      case 'state':
        this.last = playerState(msg, this.last);
        this.handlers.onState(this.last);
        break;
      case 'run':
        if (typeof msg.run === 'string' && msg.run) this.handlers.onRun(msg.run);
        break;
      case 'error':
        this.handlers.onError(String(msg.error ?? 'error'), String(msg.detail ?? ''));
        break;
      default:
        break;
    }
  }
}
