import { describe, expect, it } from 'vitest';
import type { Job } from '../api/types';
import { isNewer } from './jobWatch';

const job = (state: Job['state'], progress: number, stage = 'parse'): Job => ({ id: 'j', kind: 'gaze_ingest', state, progress, stage, dataset: 'g', error: null });

describe('job events', () => {
  it('never go back', () => {
    expect(isNewer(undefined, job('queued', 0))).toBe(true);
    expect(isNewer(job('running', 0.5), job('queued', 0))).toBe(false);
    expect(isNewer(job('running', 0.5), job('running', 0.4))).toBe(false);
    expect(isNewer(job('running', 0.5), job('running', 0.6))).toBe(true);
    expect(isNewer(job('running', 0.9, 'parse'), job('running', 0.1, 'store'))).toBe(true);
    expect(isNewer(job('running', 0.9), job('done', 1))).toBe(true);
    expect(isNewer(job('done', 1), job('done', 1))).toBe(false);
    expect(isNewer(job('done', 1), job('running', 0.2))).toBe(false);
  });
});
