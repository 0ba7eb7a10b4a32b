// Following the gaze dashboard's own jobs (gaze ingest, saccade bundling): progress from the job
// WebSocket (/api/v1/ws, api/socket.ts), polling GET /jobs/{id} each second while the socket is down, and
// a promise per job that settles when it finishes.

import { api } from '../api/client';
import { JobSocket } from '../api/socket';
import type { Job } from '../api/types';

export const FINISHED_STATES: ReadonlySet<Job['state']> = new Set(['done', 'failed', 'cancelled']);

const rank = (s: Job['state']) => (s === 'queued' ? 0 : s === 'running' ? 1 : 2);

/** Whether `next` is news about a job last seen as `prev`: events may arrive out of order, a job never goes back. */
export function isNewer(prev: Job | undefined, next: Job): boolean {
  if (!prev) return true;
  if (rank(next.state) !== rank(prev.state)) return rank(next.state) > rank(prev.state);
  if (FINISHED_STATES.has(prev.state)) return false;
  return next.stage !== prev.stage || next.progress >= prev.progress;
}

export class JobWatch {
  private readonly jobs = new Map<string, Job>();
  private readonly waiters = new Map<string, { resolve(j: Job): void; onJob?: ((j: Job) => void) | undefined }[]>();
  private readonly socket: JobSocket;
  private open = false;
  private timer: number | undefined;

  constructor(private readonly onUpdate: (job: Job) => void) {
    this.socket = new JobSocket({
      onJob: (j) => this.update(j),
      onState: (s) => {
        this.open = s === 'open';
        this.schedulePoll();
      },
    });
    this.socket.start();
  }

  /** Follows `job` (as accepted), telling `onJob` each news of it; resolves with its final state. */
  follow(job: Job, onJob?: (j: Job) => void): Promise<Job> {
    const p = new Promise<Job>((resolve) => {
      const list = this.waiters.get(job.id) ?? [];
      list.push({ resolve, onJob });
      this.waiters.set(job.id, list);
    });
    this.update(job);
    // A job that finished before we asked is only seen by polling it once.
    void api.job(job.id).then((j) => this.update(j), () => undefined);
    return p;
  }

  update(job: Job): void {
    if (!this.waiters.has(job.id) && !this.jobs.has(job.id)) return; // not one of ours
    if (!isNewer(this.jobs.get(job.id), job)) return;
    this.jobs.set(job.id, job);
    this.onUpdate(job);
    for (const w of this.waiters.get(job.id) ?? []) w.onJob?.(job);
    if (FINISHED_STATES.has(job.state)) {
      for (const w of this.waiters.get(job.id) ?? []) w.resolve(job);
      this.waiters.delete(job.id);
    }
    this.schedulePoll();
  }

  private schedulePoll() {
    window.clearTimeout(this.timer);
    const pending = [...this.jobs.values()].filter((j) => !FINISHED_STATES.has(j.state));
    if (this.open || pending.length === 0) return;
    this.timer = window.setTimeout(() => {
      for (const j of pending) void api.job(j.id).then((n) => this.update(n), () => this.schedulePoll());
    }, 1000);
  }
}
