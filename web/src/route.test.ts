import { describe, expect, it } from 'vitest';
import { dashboardOf, type Dashboard } from './route';

// #tracker… is the tracker's, #runs… the runs dashboard's, #gaze… the gaze dashboard's, any other hash the flight dashboard's.
const CASES: [string, Dashboard][] = [
  ['#tracker', 'tracker'],
  ['#tracker?run=r1&frame=3', 'tracker'],
  ['#runs?sweep=s1', 'runs'],
  ['#runsx', 'map'],
  ['#gaze?g=lund', 'gaze'],
  ['#dataset=europe&value=count', 'map'],
  ['', 'map'],
];

describe('dashboardOf', () => {
  it.each(CASES)('"%s" shows the %s dashboard', (hash, view) => expect(dashboardOf(hash)).toBe(view));
});
