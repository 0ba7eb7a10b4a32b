// The top bar's "who is signed in" with its sign-out button, and the sign-in panel (paste a token) that
// opens on any 401. The logic (the URL's one-time code, token checks, labels) is in api/session.ts.
import {
  getSession,
  onUnauthorized,
  parseTokenInput,
  sessionLabel,
  signIn,
  signOut,
  takeLoginCode,
  type SessionState,
} from '../api/session';
import { h, mount } from '../lib/dom';

export class SessionUi {
  private state: SessionState | null = null;
  private panel: HTMLDivElement | null = null;

  /** `slot`: the top bar's element that shows who is signed in. */
  constructor(private readonly slot: HTMLElement) {
    onUnauthorized(() => this.openPanel('This needs signing in: paste an API token.'));
  }

  /**
   * Exchanges the URL's one-time code (`/?login=CODE`, printed by `trailscope serve`) for a session and
   * removes it from the address bar; then shows who is signed in. Call before the dashboards load.
   */
  async start(): Promise<void> {
    const login = takeLoginCode(window.location.href);
    if (login) {
      window.history.replaceState(window.history.state, '', login.cleanUrl);
      try {
        await signIn({ login: login.code });
      } catch (e) {
        this.openPanel(`The sign-in link did not work: ${e instanceof Error ? e.message : String(e)}`);
      }
    }
    await this.refresh();
  }

  async refresh(): Promise<void> {
    try {
      this.state = await getSession();
    } catch {
      this.state = null;
    }
    this.render();
  }

  private render() {
    const s = this.state;
    this.slot.dataset.signedIn = String(Boolean(s?.signed_in));
    if (!s) {
      mount(this.slot);
      return;
    }
    const who = h('span', { class: 'session-who', 'data-testid': 'session-who', title: 'Signed in as' }, sessionLabel(s));
    const button = s.signed_in
      ? h('button', { class: 'btn small', type: 'button', 'data-testid': 'sign-out', onclick: () => void this.signOut() }, 'Sign out')
      : h('button', { class: 'btn small', type: 'button', 'data-testid': 'sign-in', onclick: () => this.openPanel() }, 'Sign in');
    mount(this.slot, who, button);
  }

  private async signOut() {
    try {
      await signOut();
    } finally {
      window.location.reload();
    }
  }

  /** Opens the sign-in panel (once), saying `reason`. */
  openPanel(reason = 'Paste an API token (trailscope token create).') {
    if (this.panel) {
      this.panel.querySelector<HTMLElement>('[data-testid="signin-reason"]')!.textContent = reason;
      return;
    }
    const input = h('input', {
      type: 'password',
      autocomplete: 'off',
      spellcheck: 'false',
      placeholder: 'tsk_…',
      'aria-label': 'API token',
      'data-testid': 'signin-token',
    });
    const error = h('p', { class: 'field-error', 'data-testid': 'signin-error', hidden: true });
    const submit = h('button', { class: 'btn primary', type: 'submit', 'data-testid': 'signin-submit' }, 'Sign in');
    const close = () => {
      this.panel?.remove();
      this.panel = null;
    };
    const form = h(
      'form',
      { class: 'signin', 'aria-labelledby': 'signin-title' },
      h('h2', { id: 'signin-title', class: 'section-title' }, 'Sign in to TrailScope'),
      h('p', { 'data-testid': 'signin-reason' }, reason),
      input,
      error,
      h('div', { class: 'signin-actions' }, submit, h('button', { class: 'btn', type: 'button', onclick: close }, 'Cancel')),
      h('p', { class: 'signin-hint' }, 'Or open the one-time sign-in URL that trailscope serve printed.'),
    );
    form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      const parsed = parseTokenInput(input.value);
      const fail = (msg: string) => {
        error.textContent = msg;
        error.hidden = false;
        input.setAttribute('aria-invalid', 'true');
      };
      if ('error' in parsed) return fail(parsed.error);
      submit.disabled = true;
      signIn({ token: parsed.token })
        .then(() => window.location.reload())
        .catch((e: unknown) => {
          submit.disabled = false;
          fail(e instanceof Error ? e.message : String(e));
        });
    });
    this.panel = h('div', { class: 'signin-backdrop', role: 'dialog', 'aria-modal': 'true', 'data-testid': 'signin-panel' }, form);
    document.body.append(this.panel);
    input.focus();
  }
}
