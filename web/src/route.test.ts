import { describe, expect, it } from 'vitest';
import { dashboardOf } from './route';

describe('dashboardOf', () => {
  it('gives #tracker… to the tracker, #runs… to the runs dashboard and any other hash to the flights', () => {
    expect(dashboardOf('#tracker')).toBe('tracker');
    expect(dashboardOf('#tracker?run=r1&frame=3')).toBe('tracker');
    expect(dashboardOf('#runs?sweep=s1')).toBe('runs');
    expect(dashboardOf('#runsx')).toBe('map');
    expect(dashboardOf('#dataset=europe&value=count')).toBe('map');
    expect(dashboardOf('')).toBe('map');
  });
});
