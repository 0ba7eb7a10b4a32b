// Minimal DOM construction helpers (the UI is small enough not to need a framework).

type Child = Node | string | number | null | undefined | false;
type AttrValue = string | number | boolean | null | undefined | EventListener;
export type Attrs = Record<string, AttrValue>;

function apply(el: Element, attrs: Attrs | undefined) {
  if (!attrs) return;
  for (const [k, v] of Object.entries(attrs)) {
    if (v === null || v === undefined || v === false) continue;
    if (k.startsWith('on') && typeof v === 'function') {
      el.addEventListener(k.slice(2), v);
    } else if (k === 'class') {
      el.setAttribute('class', String(v));
    } else {
      el.setAttribute(k, v === true ? '' : String(v));
    }
  }
}

function append(el: Element, children: Child[]) {
  for (const c of children) {
    if (c === null || c === undefined || c === false) continue;
    el.append(typeof c === 'object' ? c : String(c));
  }
}

/** h('button', {class: 'x', onclick: f}, 'Label') */
export function h<K extends keyof HTMLElementTagNameMap>(tag: K, attrs?: Attrs, ...children: Child[]): HTMLElementTagNameMap[K] {
  const el = document.createElement(tag);
  apply(el, attrs);
  append(el, children);
  return el;
}

const SVG_NS = 'http://www.w3.org/2000/svg';

export function svg<K extends keyof SVGElementTagNameMap>(tag: K, attrs?: Attrs, ...children: Child[]): SVGElementTagNameMap[K] {
  const el = document.createElementNS(SVG_NS, tag);
  apply(el, attrs);
  append(el, children);
  return el;
}

/** A panel's heading row: the title (an h2) and whatever sits beside it (counts, buttons, a legend). */
export function sectionHead(title: string, ...extras: Child[]): HTMLDivElement {
  return h('div', { class: 'section-head' }, h('h2', { class: 'section-title' }, title), ...extras);
}

/** Replaces all children of el. */
export function mount(el: Element, ...children: Child[]) {
  el.replaceChildren();
  append(el, children);
}

export function byId<T extends HTMLElement = HTMLElement>(id: string): T {
  const el = document.getElementById(id);
  if (!el) throw new Error(`#${id} missing from index.html`);
  return el as T;
}

/** Calls fn at most once per `ms` after the last call (trailing edge). */
export function debounce<A extends unknown[]>(fn: (...args: A) => void, ms: number): ((...args: A) => void) & { cancel(): void; flush(): void } {
  let timer: number | undefined;
  let last: A | null = null;
  const run = () => {
    timer = undefined;
    if (last) {
      const a = last;
      last = null;
      fn(...a);
    }
  };
  const d = (...args: A) => {
    last = args;
    window.clearTimeout(timer);
    timer = window.setTimeout(run, ms);
  };
  d.cancel = () => {
    window.clearTimeout(timer);
    last = null;
  };
  d.flush = () => {
    window.clearTimeout(timer);
    run();
  };
  return d;
}

/**
 * Sizes `canvas` to `box`'s CSS box (whole px) with a backing store at the device's pixel ratio, so that
 * lines stay sharp on high-density screens. Returns the size in CSS px.
 */
export function fitCanvas(canvas: HTMLCanvasElement, box: Element): { width: number; height: number } {
  const r = box.getBoundingClientRect();
  const width = Math.max(0, Math.floor(r.width));
  const height = Math.max(0, Math.floor(r.height));
  const dpr = window.devicePixelRatio || 1;
  canvas.width = Math.round(width * dpr);
  canvas.height = Math.round(height * dpr);
  canvas.style.width = `${width}px`;
  canvas.style.height = `${height}px`;
  return { width, height };
}

/** The 2D context of a canvas sized by fitCanvas, cleared and drawing in CSS px; null without one. */
export function cssContext(canvas: HTMLCanvasElement, width: number, height: number): CanvasRenderingContext2D | null {
  const ctx = canvas.getContext('2d');
  if (!ctx) return null;
  const dpr = window.devicePixelRatio || 1;
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, width, height);
  return ctx;
}
