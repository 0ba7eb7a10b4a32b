import { afterEach, describe, expect, it, vi } from 'vitest';
import { gazeApi, gazeBodyFilters, gazeQuery, gazeStimulusUrl, gazeTileUrl, gazeUploadQuery } from './gaze';

afterEach(() => vi.unstubAllGlobals());

/** Stubs fetch with one JSON answer and records the requests. */
function stubFetch(status: number, body: unknown) {
  const calls: { url: string; init: RequestInit }[] = [];
  vi.stubGlobal('fetch', async (url: string, init: RequestInit = {}) => {
    calls.push({ url, init });
    return new Response(status === 204 ? null : JSON.stringify(body), { status, headers: { 'Content-Type': 'application/json' } });
  });
  return calls;
}

describe('gaze filters', () => {
  it('leave out what is unset, keep zero', () => {
    expect(gazeQuery({}).toString()).toBe('');
    expect(gazeQuery({ participant: '', stimulus: null, t0_ms: 0, t1_ms: Number.NaN, method: 'idt' }).toString()).toBe('t0_ms=0&method=idt');
    expect(gazeQuery({ stimulus: 'Europe', recording: 2 }, { type: 'fixation,saccade', z: null }).toString()).toBe('stimulus=Europe&recording=2&type=fixation%2Csaccade');
  });

  it('become JSON members with numbers as numbers', () => {
    expect(gazeBodyFilters({ stimulus: 'S', t0_ms: 10, t1_ms: 500, recording: 0, method: 'adaptive' })).toEqual({ stimulus: 'S', recording: 0, t0_ms: 10, t1_ms: 500, method: 'adaptive' });
  });

  it('make tile, stimulus and upload URLs', () => {
    expect(gazeTileUrl('my set', 2, 1, 3, { stimulus: 'Europe', participant: 'TH34' }, { what: 'fixations', how: 'log', cmap: 'fire' })).toBe(
      '/api/v1/gaze/my%20set/tiles/2/1/3.png?participant=TH34&stimulus=Europe&what=fixations&how=log&cmap=fire',
    );
    expect(gazeStimulusUrl('g1', 'Europe 1')).toBe('/api/v1/gaze/g1/stimulus?stimulus=Europe+1');
    expect(gazeUploadQuery({ name: 'lund', participant: 'TH34', stimulus: 'Europe', width_px: 1024, height_px: 768, width_cm: 38, height_cm: 30, distance_cm: 67, format: '' }).toString()).toBe(
      'name=lund&participant=TH34&stimulus=Europe&width_px=1024&height_px=768&width_cm=38&height_cm=30&distance_cm=67',
    );
    expect(gazeUploadQuery({ name: 'x', width_px: Number.NaN, height_cm: 0 }).toString()).toBe('name=x');
  });
});

describe('gaze API calls', () => {
  it('GET /gaze', async () => {
    const calls = stubFetch(200, { datasets: [] });
    expect(await gazeApi.list()).toEqual({ datasets: [] });
    expect(calls[0]!.url).toBe('/api/v1/gaze');
  });

  it('events carry the filters and the types', async () => {
    const calls = stubFetch(200, { events: [], counts: {}, method: 'ivt' });
    await gazeApi.events('g', { stimulus: 'S', t1_ms: 1000 }, ['fixation', 'saccade']);
    expect(calls[0]!.url).toBe('/api/v1/gaze/g/events?stimulus=S&t1_ms=1000&type=fixation%2Csaccade');
  });

  it('AOIs are POSTed with the filters beside them', async () => {
    const calls = stubFetch(200, { aois: [], transitions: { names: [], counts: [] }, recordings: 0 });
    await gazeApi.aoi('g', [{ name: 'a', rect: [0, 0, 10, 10] }], { stimulus: 'S', method: 'idt' });
    expect(calls[0]!.url).toBe('/api/v1/gaze/g/aoi');
    expect(calls[0]!.init.method).toBe('POST');
    expect(JSON.parse(String(calls[0]!.init.body))).toEqual({ aois: [{ name: 'a', rect: [0, 0, 10, 10] }], stimulus: 'S', method: 'idt' });
  });

  it('bundling sends the filters as fields and the bundling parameters under params', async () => {
    const calls = stubFetch(202, { job: { id: 'j1' }, bundle: 'b1' });
    await gazeApi.startBundle('g', { stimulus: 'S', t0_ms: 0 });
    expect(JSON.parse(String(calls[0]!.init.body))).toEqual({ stimulus: 'S', t0_ms: 0 });
    await gazeApi.startBundle('g', { stimulus: 'S' }, { iterations: 10 });
    expect(JSON.parse(String(calls[1]!.init.body))).toEqual({ stimulus: 'S', params: { iterations: 10 } });
  });

  it('DELETE answers 204, errors carry the server\'s body', async () => {
    const calls = stubFetch(204, null);
    await expect(gazeApi.remove('g')).resolves.toBeUndefined();
    expect(calls[0]!.init.method).toBe('DELETE');
    stubFetch(404, { error: 'not_found', detail: 'no gaze data set "g"', param: 'id' });
    await expect(gazeApi.get('g')).rejects.toMatchObject({ status: 404, code: 'not_found', detail: 'no gaze data set "g"', param: 'id' });
  });
});
