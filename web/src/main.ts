import './styles.css';
import { App, showFatal } from './app';
import { byId } from './lib/dom';
import { isTrackerHash } from './tracker/route';
import { TrackerView } from './tracker/trackerView';
import { isRunsHash } from './runs/route';
import { RunsView } from './runs/runsView';

// Three views behind one top bar: the flight map dashboard (any hash), the tracker (#tracker…) and the
// runs dashboard (#runs…). Each is built the first time it is shown.
let app: App | null = null;
let tracker: TrackerView | null = null;
let runs: RunsView | null = null;

function route() {
  const isTracker = isTrackerHash(window.location.hash);
  const isRuns = isRunsHash(window.location.hash);
  const view = isTracker ? 'tracker' : isRuns ? 'runs' : 'map';
  byId('app').dataset.view = view;
  for (const tab of document.querySelectorAll<HTMLAnchorElement>('.view-tab')) {
    if (tab.dataset.view === view) tab.setAttribute('aria-current', 'page');
    else tab.removeAttribute('aria-current');
  }
  try {
    if (isTracker) {
      tracker ??= new TrackerView(byId('tracker-root'));
      void tracker.activate(window.location.hash);
    } else if (isRuns) {
      runs ??= new RunsView(byId('runs-root'));
      void runs.activate(window.location.hash);
    } else if (app) {
      app.show();
    } else {
      app = new App();
    }
  } catch (e) {
    console.error(e);
    showFatal(e);
  }
}

window.addEventListener('hashchange', route);
route();
