// Signing in (access control, README "Access control"): the browser holds a session cookie
// (trailscope_session, HttpOnly: scripts never see it) that POST /api/v1/session sets, either for the
// one-time code of the URL `trailscope serve` prints (`/?login=CODE`) or for a pasted API token. Same-origin
// fetches, images, tiles and WebSockets all carry the cookie, so nothing else in the app handles credentials.
// A 401 from any request is announced (onUnauthorized) so that the sign-in panel can open.

/** Roles, least first (proto/openapi.yaml x-role). */
export type Role = 'anyone' | 'reader' | 'writer' | 'admin';

/** GET /api/v1/session. */
export interface SessionState {
  owner: string;
  role: Role;
  signed_in: boolean;
  public_reads: boolean;
}

/** POST /api/v1/session's answer. */
export interface SignedIn {
  owner: string;
  role: Role;
}

/** What POST /api/v1/session takes: the sign-in URL's code, or a token. */
export type Credential = { login: string } | { token: string };

const TOKEN_RE = /^tsk_[0-9a-f]{12}_[0-9a-f]{64}$/;

/**
 * The one-time sign-in code of `href` (its `login` query parameter) and the same URL without it (what the
 * address bar should show, so the used code is neither bookmarked nor shared); null when there is none.
 */
export function takeLoginCode(href: string): { code: string; cleanUrl: string } | null {
  const url = new URL(href);
  const code = url.searchParams.get('login');
  if (code === null) return null;
  url.searchParams.delete('login');
  return { code: code.trim(), cleanUrl: url.pathname + url.search + url.hash };
}

/**
 * The token in what the user pasted (surrounding blanks and a leading "Bearer " are forgiven), or the
 * reason it cannot be one.
 */
export function parseTokenInput(text: string): { token: string } | { error: string } {
  let t = text.trim();
  if (/^bearer\s+/i.test(t)) t = t.replace(/^bearer\s+/i, '');
  if (t === '') return { error: 'Paste a token (tsk_…), or open the sign-in URL the server printed.' };
  if (!TOKEN_RE.test(t)) return { error: 'A token looks like tsk_ followed by 12 and 64 hex digits.' };
  return { token: t };
}

/** The top bar's words for who is signed in. */
export function sessionLabel(s: SessionState): string {
  if (s.signed_in) return `${s.owner} · ${s.role}`;
  return s.public_reads ? 'Not signed in (public reads)' : 'Not signed in';
}

/** Whether `have` may do what needs `need` (anyone < reader < writer < admin). */
export function roleAtLeast(have: Role, need: Role): boolean {
  const order: Role[] = ['anyone', 'reader', 'writer', 'admin'];
  return order.indexOf(have) >= order.indexOf(need);
}

type Listener = () => void;
const listeners = new Set<Listener>();

/** Calls `fn` whenever a request is answered 401; returns the unsubscribe function. */
export function onUnauthorized(fn: Listener): () => void {
  listeners.add(fn);
  return () => listeners.delete(fn);
}

/** Announces a 401 (api/client.ts calls it for every request it makes). */
export function notifyUnauthorized(): void {
  for (const fn of listeners) fn();
}

/** The API error body's detail, or the status line. */
async function detailOf(res: Response): Promise<string> {
  try {
    const body = (await res.json()) as { detail?: string };
    if (body.detail) return body.detail;
  } catch {
    /* not JSON */
  }
  return `${res.status} ${res.statusText}`.trim();
}

/** Who is signed in (anyone may ask). */
export async function getSession(fetchImpl: typeof fetch = fetch): Promise<SessionState> {
  const res = await fetchImpl('/api/v1/session', { headers: { Accept: 'application/json' } });
  if (!res.ok) throw new Error(await detailOf(res));
  return (await res.json()) as SessionState;
}

/** Signs this browser in; rejects with the server's reason (a used code, a revoked token, 429 …). */
export async function signIn(credential: Credential, fetchImpl: typeof fetch = fetch): Promise<SignedIn> {
  const res = await fetchImpl('/api/v1/session', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', Accept: 'application/json' },
    body: JSON.stringify(credential),
  });
  if (!res.ok) throw new Error(await detailOf(res));
  return (await res.json()) as SignedIn;
}

/** Ends this browser's session. */
export async function signOut(fetchImpl: typeof fetch = fetch): Promise<void> {
  const res = await fetchImpl('/api/v1/session', { method: 'DELETE' });
  if (!res.ok && res.status !== 204) throw new Error(await detailOf(res));
}
