// What the client knows about one replay's frames: the tracker record and the ground truth of every frame
// seen over the WebSocket or fetched from the stored run. Views read it; it tells them when it grew.

import type { FrameRecord, FrameTruth, TrackerState } from '../api/trackerLog';

export const STATE_CODE: Record<TrackerState, number> = { SEARCH: 1, TRACK: 2, LOST: 3 };
export const CODE_STATE: (TrackerState | null)[] = [null, 'SEARCH', 'TRACK', 'LOST'];

export class FrameStore {
  readonly records: (FrameRecord | undefined)[];
  readonly truth: (FrameTruth | null | undefined)[];
  /** 0 = unknown, else STATE_CODE. */
  readonly states: Uint8Array;
  private known = 0;
  private listeners = new Set<() => void>();
  /** Bumped on every change, so views can skip redraws. */
  version = 0;

  constructor(readonly frames: number) {
    this.records = new Array<FrameRecord | undefined>(frames);
    this.truth = new Array<FrameTruth | null | undefined>(frames);
    this.states = new Uint8Array(frames);
  }

  get knownCount(): number {
    return this.known;
  }

  get complete(): boolean {
    return this.frames > 0 && this.known >= this.frames;
  }

  /** Adds one frame; `truth` undefined keeps what is known. Returns false for an index outside the video. */
  put(index: number, record: FrameRecord, truth?: FrameTruth | null, notify = true): boolean {
    if (!Number.isInteger(index) || index < 0 || index >= this.frames) return false;
    if (!this.records[index]) this.known++;
    this.records[index] = record;
    this.states[index] = STATE_CODE[record.state];
    if (truth !== undefined && (truth !== null || this.truth[index] === undefined)) this.truth[index] = truth;
    this.version++;
    if (notify) this.emit();
    return true;
  }

  putMany(items: { frame: FrameRecord; truth: FrameTruth | null }[]): number {
    let n = 0;
    for (const it of items) if (this.put(it.frame.index, it.frame, it.truth, false)) n++;
    if (n) this.emit();
    return n;
  }

  /** Counts of frames per state (unknown frames not counted). */
  stateCounts(): Record<TrackerState, number> {
    const c = { SEARCH: 0, TRACK: 0, LOST: 0 };
    for (const s of this.states) {
      const st = CODE_STATE[s];
      if (st) c[st]++;
    }
    return c;
  }

  /** First frame not yet known at or after `from` (frames when none). */
  firstGap(from = 0): number {
    for (let i = Math.max(0, from); i < this.frames; i++) if (!this.records[i]) return i;
    return this.frames;
  }

  subscribe(l: () => void): () => void {
    this.listeners.add(l);
    return () => this.listeners.delete(l);
  }

  private emit() {
    for (const l of this.listeners) l();
  }
}
