// The server's WebSockets: one reconnecting client (ReconnectingSocket) under the job socket
// (/api/v1/ws, JobSocket here) and the replay viewers (/api/v1/replays/{id}/ws, ReplaySocket in replay.ts).

import type { Job, WsMessage } from './types';

export type SocketState = 'connecting' | 'open' | 'closed';

export interface ReconnectingSocketHandlers {
  onState(state: SocketState): void;
  /** A text message (the server's JSON). */
  onText(text: string): void;
  /** A binary message; binary messages are dropped without this handler. */
  onBinary?(data: ArrayBuffer): void;
  /** Whether this close means the resource is gone, so that reconnecting would only hammer the server. */
  isFinal?(ev: CloseEvent): boolean;
}

/**
 * A WebSocket to a same-origin path (ws: or wss: as the page) that reconnects after a close, with backoff
 * 0.5 s, 1 s, 2 s … capped at 15 s, until stop() or a close that `isFinal` calls final. Messages of a
 * socket already replaced or stopped are dropped.
 */
export class ReconnectingSocket {
  private ws: WebSocket | null = null;
  private retry = 0;
  private timer: number | undefined;
  private stopped = false;

  constructor(
    private readonly path: string,
    private readonly handlers: ReconnectingSocketHandlers,
  ) {}

  start(): void {
    this.stopped = false;
    this.connect();
  }

  stop(): void {
    this.stopped = true;
    window.clearTimeout(this.timer);
    this.ws?.close();
    this.ws = null;
  }

  get isOpen(): boolean {
    return this.ws?.readyState === WebSocket.OPEN;
  }

  /** Sends a text message; false (nothing sent) while not open. */
  send(text: string): boolean {
    if (!this.ws || this.ws.readyState !== WebSocket.OPEN) return false;
    this.ws.send(text);
    return true;
  }

  private connect() {
    const url = new URL(this.path, window.location.href);
    url.protocol = url.protocol === 'https:' ? 'wss:' : 'ws:';
    this.handlers.onState('connecting');
    const ws = new WebSocket(url);
    ws.binaryType = 'arraybuffer';
    this.ws = ws;
    ws.onopen = () => {
      this.retry = 0;
      this.handlers.onState('open');
    };
    ws.onmessage = (ev) => {
      if (this.ws !== ws) return;
      if (typeof ev.data === 'string') this.handlers.onText(ev.data);
      else if (ev.data instanceof ArrayBuffer) this.handlers.onBinary?.(ev.data);
    };
    ws.onclose = (ev) => {
      if (this.ws !== ws) return;
      this.ws = null;
      this.handlers.onState('closed');
      if (this.stopped || this.handlers.isFinal?.(ev)) return;
      const delay = Math.min(15000, 500 * 2 ** this.retry++);
      this.timer = window.setTimeout(() => this.connect(), delay);
    };
  }
}

export interface JobSocketHandlers {
  onJob(job: Job): void;
  onState(state: SocketState): void;
}

/** The job WebSocket (/api/v1/ws): every job's progress as `{"type":"job","job":{…}}`. */
export class JobSocket {
  private readonly socket: ReconnectingSocket;
  state: SocketState = 'closed';

  constructor(handlers: JobSocketHandlers) {
    this.socket = new ReconnectingSocket('/api/v1/ws', {
      onState: (s) => {
        this.state = s;
        handlers.onState(s);
      },
      onText: (text) => {
        let msg: WsMessage;
        try {
          msg = JSON.parse(text) as WsMessage;
        } catch {
          return;
        }
        if (msg.type === 'job' && msg.job && typeof msg.job === 'object') handlers.onJob(msg.job as Job);
      },
    });
  }

  start(): void {
    this.socket.start();
  }

  stop(): void {
    this.socket.stop();
  }
}
