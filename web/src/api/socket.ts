// The job WebSocket (/api/v1/ws): reconnects with backoff and reports its connection state.

import type { Job, WsMessage } from './types';

export type SocketState = 'connecting' | 'open' | 'closed';

export interface JobSocketHandlers {
  onJob(job: Job): void;
  onState(state: SocketState): void;
}

export class JobSocket {
  private ws: WebSocket | null = null;
  private retry = 0;
  private timer: number | undefined;
  private stopped = false;
  state: SocketState = 'closed';

  constructor(private readonly handlers: JobSocketHandlers) {}

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

  private setState(s: SocketState) {
    this.state = s;
    this.handlers.onState(s);
  }

  private connect() {
    const url = new URL('/api/v1/ws', window.location.href);
    url.protocol = url.protocol === 'https:' ? 'wss:' : 'ws:';
    this.setState('connecting');
    const ws = new WebSocket(url);
    this.ws = ws;
    ws.onopen = () => {
      this.retry = 0;
      this.setState('open');
    };
    ws.onmessage = (ev) => {
      if (typeof ev.data !== 'string') return;
      let msg: WsMessage;
      try {
        msg = JSON.parse(ev.data) as WsMessage;
      } catch {
        return;
      }
      if (msg.type === 'job' && msg.job && typeof msg.job === 'object') this.handlers.onJob(msg.job as Job);
    };
    ws.onclose = () => {
      if (this.ws !== ws) return;
      this.ws = null;
      this.setState('closed');
      if (this.stopped) return;
      // 0.5 s, 1 s, 2 s … capped at 15 s.
      const delay = Math.min(15000, 500 * 2 ** this.retry++);
      this.timer = window.setTimeout(() => this.connect(), delay);
    };
  }
}
