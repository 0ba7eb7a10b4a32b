import './styles.css';
import { FlightsView } from './flights/flightsView';
import { GazeView } from './gaze/gazeView';
import { byId, mount } from './lib/dom';
import { dashboardOf } from './route';
import { TrackerView } from './tracker/trackerView';
import { RunsView } from './runs/runsView';
import { SessionUi } from './session/sessionUi';

// Four dashboards behind one top bar: the flight map dashboard (flights/, any hash), the tracker
// (tracker/, #tracker…), the runs dashboard (runs/, #runs…) and the gaze dashboard (gaze/, #gaze…). Each
// is built the first time it is shown.
let flights: FlightsView | null = null;
let tracker: TrackerView | null = null;
let runs: RunsView | null = null;
let gaze: GazeView | null = null;

function route() {
  const view = dashboardOf(window.location.hash);
  byId('app').dataset.view = view;
  for (const tab of document.querySelectorAll<HTMLAnchorElement>('.view-tab')) {
    if (tab.dataset.view === view) tab.setAttribute('aria-current', 'page');
    else tab.removeAttribute('aria-current');
  }
  try {
    if (view === 'tracker') {
      tracker ??= new TrackerView(byId('tracker-root'));
      void tracker.activate(window.location.hash);
    } else if (view === 'runs') {
      runs ??= new RunsView(byId('runs-root'));
      void runs.activate(window.location.hash);
    } else if (view === 'gaze') {
      gaze ??= new GazeView(byId('gaze-root'));
      void gaze.activate(window.location.hash);
    } else if (flights) {
      flights.show();
    } else {
      flights = new FlightsView();
    }
  } catch (e) {
    console.error(e);
    showFatal(e);
  }
}

function showFatal(err: unknown) {
  const banner = document.getElementById('banner');
  if (!banner) return;
  mount(banner, `TrailScope failed to start: ${err instanceof Error ? err.message : String(err)}`);
  banner.hidden = false;
}

// Sign-in first (the URL's one-time code becomes a session cookie), so that the dashboards' first requests
// carry it.
const session = new SessionUi(byId('session'));
void session.start().finally(() => {
  window.addEventListener('hashchange', route);
  route();
});
