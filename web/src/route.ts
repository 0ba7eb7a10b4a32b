// Which dashboard a URL hash shows: "#tracker…" the tracker (tracker/route.ts), "#runs…" the runs
// dashboard (runs/route.ts), "#gaze…" the gaze dashboard (gaze/route.ts), any other hash the flight map
// dashboard, whose hash is its own query string.

import { isGazeHash } from './gaze/route';
import { isRunsHash } from './runs/route';
import { isTrackerHash } from './tracker/route';

/** The `data-view` of the top bar's tabs and of `#app`. */
export type Dashboard = 'map' | 'tracker' | 'runs' | 'gaze';

export function dashboardOf(hash: string): Dashboard {
  return isTrackerHash(hash) ? 'tracker' : isRunsHash(hash) ? 'runs' : isGazeHash(hash) ? 'gaze' : 'map';
}
