// Shows an API error next to the control its `param` names, or in a general banner otherwise.

import type { ApiError } from '../api/client';

export class ErrorSlots {
  private slots = new Map<string, HTMLElement>();
  private active = new Map<string, Set<HTMLElement>>();

  constructor(private readonly banner: HTMLElement) {}

  /** Registers the element that shows errors about any of `params`. */
  register(params: string[], el: HTMLElement): void {
    el.classList.add('field-error');
    el.setAttribute('role', 'alert');
    el.hidden = true;
    for (const p of params) this.slots.set(p, el);
  }

  /** Shows `err` for `source` (e.g. "summary", "tiles"): next to its parameter's control when known. */
  show(source: string, err: ApiError): void {
    this.clear(source);
    const el = (err.param && this.slots.get(err.param)) || this.banner;
    const text = err.param && el === this.banner ? `${err.param}: ${err.detail}` : err.detail;
    el.textContent = text;
    el.dataset.param = err.param ?? '';
    el.hidden = false;
    this.active.set(source, new Set([el]));
    // Mark the control itself invalid for assistive tech.
    if (err.param) {
      for (const input of document.querySelectorAll<HTMLElement>(`[data-param~="${CSS.escape(err.param)}"]`)) {
        input.setAttribute('aria-invalid', 'true');
        input.setAttribute('aria-errormessage', el.id);
      }
    }
  }

  /** Clears what `source` showed (after its next request succeeds). */
  clear(source: string): void {
    const els = this.active.get(source);
    if (!els) return;
    this.active.delete(source);
    const stillShown = new Set([...this.active.values()].flatMap((s) => [...s]));
    for (const el of els) {
      if (stillShown.has(el)) continue;
      const param = el.dataset.param;
      el.hidden = true;
      el.textContent = '';
      if (param) {
        for (const input of document.querySelectorAll<HTMLElement>(`[data-param~="${CSS.escape(param)}"]`)) {
          input.removeAttribute('aria-invalid');
          input.removeAttribute('aria-errormessage');
        }
      }
    }
  }
}
