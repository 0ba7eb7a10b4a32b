// The playback view's keyboard: which key does what (pure, unit-tested), and the help text the view and
// web/README.md show.

import { STEP_LARGE_S, STEP_SMALL_S } from './clock';

export type PlaybackAction =
  | { kind: 'toggle' }
  | { kind: 'step'; seconds: number }
  | { kind: 'faster' }
  | { kind: 'slower' }
  | { kind: 'release' };

export interface KeyLike {
  key: string;
  shiftKey: boolean;
  ctrlKey: boolean;
  metaKey: boolean;
  altKey: boolean;
}

/** The action of a key press, or null when the key is not a playback key. */
export function playbackAction(e: KeyLike): PlaybackAction | null {
  if (e.ctrlKey || e.metaKey || e.altKey) return null;
  switch (e.key) {
    case ' ':
    case 'Spacebar':
      return { kind: 'toggle' };
    case 'ArrowLeft':
      return { kind: 'step', seconds: -(e.shiftKey ? STEP_LARGE_S : STEP_SMALL_S) };
    case 'ArrowRight':
      return { kind: 'step', seconds: e.shiftKey ? STEP_LARGE_S : STEP_SMALL_S };
    case '+':
    case '=':
      return { kind: 'faster' };
    case '-':
    case '_':
      return { kind: 'slower' };
    case 'Escape':
      return { kind: 'release' };
    default:
      return null;
  }
}

/** Whether a key press belongs to the element it happened in (typing, a slider, a list box). */
export function ownsKeys(target: EventTarget | null): boolean {
  if (!(target instanceof HTMLElement)) return false;
  if (target.isContentEditable) return true;
  const tag = target.tagName;
  if (tag === 'TEXTAREA' || tag === 'SELECT') return true;
  if (tag !== 'INPUT') return false;
  const type = (target as HTMLInputElement).type;
  return type !== 'checkbox' && type !== 'radio' && type !== 'button';
}

export const PLAYBACK_KEYS: readonly [string, string][] = [
  ['Space', 'play / pause'],
  ['← / →', '−1 s / +1 s'],
  ['Shift + ← / →', '−1 min / +1 min'],
  ['+ / −', 'faster / slower (0.1×, 1×, 2×, 5×, 10× … 10,000×)'],
  ['Esc', 'stop following the selected flight (again: deselect)'],
  ['click / drag on the time histogram', 'jump / scrub the time cursor'],
  ['click an aircraft', 'select it and follow it'],
];
