import { describe, expect, it, vi } from 'vitest';
import {
  getSession,
  notifyUnauthorized,
  onUnauthorized,
  parseTokenInput,
  roleAtLeast,
  sessionLabel,
  signIn,
  signOut,
  takeLoginCode,
} from './session';

const TOKEN = `tsk_0123456789ab_${'f'.repeat(64)}`;

describe('takeLoginCode', () => {
  it('takes the code and keeps the rest of the URL', () => {
    expect(takeLoginCode('http://127.0.0.1:8080/?login=abc123')).toEqual({ code: 'abc123', cleanUrl: '/' });
    expect(takeLoginCode('http://127.0.0.1:8080/?x=1&login=abc&y=2#tracker?run=r1')).toEqual({
      code: 'abc',
      cleanUrl: '/?x=1&y=2#tracker?run=r1',
    });
  });
  it('finds none in a URL without one, even in the hash', () => {
    expect(takeLoginCode('http://127.0.0.1:8080/#dataset=europe')).toBeNull();
    expect(takeLoginCode('http://127.0.0.1:8080/#runs?login=abc')).toBeNull();
  });
});

describe('parseTokenInput', () => {
  it('accepts a token, with blanks and a Bearer prefix forgiven', () => {
    expect(parseTokenInput(TOKEN)).toEqual({ token: TOKEN });
    expect(parseTokenInput(`  Bearer ${TOKEN}\n`)).toEqual({ token: TOKEN });
    expect(parseTokenInput(`bearer   ${TOKEN}`)).toEqual({ token: TOKEN });
  });
  it('refuses what cannot be a token, saying why', () => {
    expect(parseTokenInput('  ')).toEqual({ error: 'Paste a token (tsk_…), or open the sign-in URL the server printed.' });
    const bad = { error: 'A token looks like tsk_ followed by 12 and 64 hex digits.' };
    expect(parseTokenInput('tsk_0123456789ab_abc')).toEqual(bad);
    expect(parseTokenInput(TOKEN.toUpperCase())).toEqual(bad);
    expect(parseTokenInput(`${TOKEN}x`)).toEqual(bad);
  });
});

describe('labels and roles', () => {
  it('names who is signed in', () => {
    expect(sessionLabel({ owner: 'local', role: 'admin', signed_in: true, public_reads: false })).toBe('local · admin');
    expect(sessionLabel({ owner: '', role: 'anyone', signed_in: false, public_reads: false })).toBe('Not signed in');
    expect(sessionLabel({ owner: '', role: 'anyone', signed_in: false, public_reads: true })).toBe(
      'Not signed in (public reads)',
    );
  });
  it('orders the roles', () => {
    expect(roleAtLeast('admin', 'writer')).toBe(true);
    expect(roleAtLeast('writer', 'writer')).toBe(true);
    expect(roleAtLeast('reader', 'writer')).toBe(false);
    expect(roleAtLeast('anyone', 'reader')).toBe(false);
  });
});

describe('the session requests', () => {
  const json = (status: number, body: unknown) =>
    new Response(JSON.stringify(body), { status, headers: { 'Content-Type': 'application/json' } });

  it('signs in with a code or a token, as JSON', async () => {
    const f = vi.fn(async () => json(200, { owner: 'local', role: 'admin' }));
    await expect(signIn({ login: 'c0de' }, f)).resolves.toEqual({ owner: 'local', role: 'admin' });
    await signIn({ token: TOKEN }, f);
    expect(f.mock.calls.map((c) => c as unknown[])).toEqual([
      ['/api/v1/session', expect.objectContaining({ method: 'POST', body: '{"login":"c0de"}' })],
      ['/api/v1/session', expect.objectContaining({ method: 'POST', body: JSON.stringify({ token: TOKEN }) })],
    ]);
  });
  it("rejects with the server's detail", async () => {
    const f = vi.fn(async () =>
      json(401, { error: 'unauthorized', detail: 'the sign-in code is not valid', param: 'authorization' }),
    );
    await expect(signIn({ login: 'used' }, f)).rejects.toThrow('the sign-in code is not valid');
    const g = vi.fn(async () => new Response('nope', { status: 429, statusText: 'Too Many Requests' }));
    await expect(signIn({ login: 'x' }, g)).rejects.toThrow('429 Too Many Requests');
  });
  it('asks who is signed in, and signs out', async () => {
    const state = { owner: 'rita', role: 'reader', signed_in: true, public_reads: false };
    await expect(getSession(vi.fn(async () => json(200, state)))).resolves.toEqual(state);
    const del = vi.fn(async () => new Response(null, { status: 204 }));
    await signOut(del);
    expect(del).toHaveBeenCalledWith('/api/v1/session', { method: 'DELETE' });
  });
});

describe('401 announcements', () => {
  it('reach every listener until it unsubscribes', () => {
    const a = vi.fn();
    const b = vi.fn();
    const offA = onUnauthorized(a);
    const offB = onUnauthorized(b);
    notifyUnauthorized();
    offA();
    notifyUnauthorized();
    offB();
    notifyUnauthorized();
    expect(a).toHaveBeenCalledTimes(1);
    expect(b).toHaveBeenCalledTimes(2);
  });
});
