#!/usr/bin/env bash
# Browser tests of the TrailScope dashboards against real servers over loopback.
#   1. a temporary data dir, 2. `trailscope ingest` of the Europe SO6 day as "europe",
#   3. `trailscope serve` on a free port (127.0.0.1 only), 4. the flight dashboard test (dashboard.test.mjs)
#      , the playback test (animation.test.mjs) and the congestion panel test (congestion.test.mjs) on that
#      server, and the animation chunks against the positions endpoint (web/src/**/*.e2e.ts, vitest),
#   5. a second server on its own data dir with `--demo` (the synthetic tracker videos) and the tracker
#      dashboard test (tracker.test.mjs), 6. a third server on its own empty data dir and the runs
#      dashboard test (runs.test.mjs: it makes short synthetic videos and a 200-run sweep through the API),
#   7. a fourth server on its own empty data dir and the gaze dashboard test (gaze.test.mjs: it uploads a
#      Lund 2013 recording and its stimulus image through the page),
#   8. the servers are always stopped.
# Environment: TRAILSCOPE_BIN (default build/server/trailscope), TRAILSCOPE_SHARED (default ../shared),
#              CHROMIUM (default /usr/bin/chromium), E2E_KEEP=1 keeps the temp dir,
#              E2E_ONLY=dashboard|animation|congestion|flow|tracker|runs|gaze runs one of the tests; RUNS_SAMPLES, RUNS_FRAMES
#              and RUNS_SCENARIOS size the runs test's sweep (default 100 points × standard, fast-motion
#              videos of 64 frames).
# Prints "N passed, M failed" last; exits non-zero on any failure.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
BIN="${TRAILSCOPE_BIN:-build/server/trailscope}"
SHARED="${TRAILSCOPE_SHARED:-../shared}"
DATA="$SHARED/data/flights/traffic_europe_20180101_m3.so6.gz"

die() { echo "run.sh: $*" >&2; echo "0 passed, 1 failed"; exit 1; }
[ -x "$BIN" ] || die "$BIN is missing: build the server first (or set TRAILSCOPE_BIN)"
[ "${E2E_ONLY:-}" = tracker ] || [ "${E2E_ONLY:-}" = runs ] || [ "${E2E_ONLY:-}" = gaze ] || [ -f "$DATA" ] || die "$DATA is missing (set TRAILSCOPE_SHARED to the shared folder)"

# The front-end: rebuild when web/dist is missing or older than its sources.
if [ ! -f web/dist/index.html ] || [ -n "$(find web/src web/index.html web/vite.config.ts -newer web/dist/index.html -print -quit)" ]; then
  echo "run.sh: building web/dist"
  [ -d web/node_modules ] || npm ci --prefix web --no-audit --no-fund
  build_log="$(npm run --prefix web build 2>&1)" || { echo "$build_log" >&2; die "web build failed"; }
fi
[ -d tests/e2e/node_modules/playwright-core ] || npm ci --prefix tests/e2e --no-audit --no-fund
# `serve --demo` reads the demo routes from web/node_modules/vega-datasets.
[ -d web/node_modules/vega-datasets ] || npm ci --prefix web --no-audit --no-fund

ONLY="${E2E_ONLY:-}"
TMP="$(mktemp -d -t trailscope-e2e.XXXXXX)"
SERVER_PIDS=()
stop_server() {
  local pid="$1"
  if kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  fi
}
cleanup() {
  for pid in "${SERVER_PIDS[@]}"; do stop_server "$pid"; done
  if [ "${E2E_KEEP:-0}" = 1 ]; then echo "run.sh: kept $TMP"; else rm -rf "$TMP"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# start_server NAME DATA_DIR [serve flags...]: serves on a free loopback port; sets BASE_URL and SERVER_LOG.
start_server() {
  local name="$1" data="$2"
  shift 2
  local port pid i
  port="$(node -e 'const s=require("net").createServer().listen(0,"127.0.0.1",()=>{console.log(s.address().port);s.close()})')"
  SERVER_LOG="$TMP/server-$name.log"
  # Access control is on: an admin token for the tests (harness.mjs signs the browser in with it).
  TRAILSCOPE_TOKEN="$("$BIN" token create --data-dir "$data" --name e2e --role admin --json |
    node -e 'let s="";process.stdin.on("data",(d)=>s+=d).on("end",()=>console.log(JSON.parse(s).token))')" ||
    die "token create failed"
  export TRAILSCOPE_TOKEN
  "$BIN" serve --data-dir "$data" --port "$port" --host 127.0.0.1 --web-root web/dist "$@" >"$SERVER_LOG" 2>&1 &
  pid=$!
  SERVER_PIDS+=("$pid")
  BASE_URL="http://127.0.0.1:$port"
  for i in $(seq 300); do
    if curl -fsS "$BASE_URL/api/v1/health" >/dev/null 2>&1; then break; fi
    kill -0 "$pid" 2>/dev/null || { tail -n 20 "$SERVER_LOG" >&2; die "server ($name) exited"; }
    [ "$i" = 300 ] && { tail -n 20 "$SERVER_LOG" >&2; die "server ($name) not healthy after 30 s"; }
    sleep 0.1
  done
  # The one-time sign-in URL it printed (dashboard.test.mjs signs a browser in with it).
  LOGIN_URL="$(grep -oE 'http://[^ ]+/\?login=[0-9a-f]+' "$SERVER_LOG" | head -1)"
  echo "run.sh: $name server up at $BASE_URL (pid $pid)"
}

status=0
run_test() {
  local file="$1"
  shift
  local rc=0
  env BASE_URL="$BASE_URL" "$@" node "tests/e2e/$file" || rc=$?
  if [ "$rc" != 0 ]; then
    status=$rc
    echo "run.sh: server log (tail):" >&2
    tail -n 30 "$SERVER_LOG" >&2
  fi
}

if [ -z "$ONLY" ] || [ "$ONLY" = dashboard ] || [ "$ONLY" = animation ] || [ "$ONLY" = congestion ] || [ "$ONLY" = flow ]; then
  echo "run.sh: ingest $DATA"
  "$BIN" ingest "$DATA" --data-dir "$TMP/data" --name europe >"$TMP/ingest.log" 2>&1 || {
    tail -n 20 "$TMP/ingest.log" >&2
    die "ingest failed"
  }
  start_server flights "$TMP/data"
  [ "$ONLY" = animation ] || [ "$ONLY" = congestion ] || [ "$ONLY" = flow ] || run_test dashboard.test.mjs DATASET=europe LOGIN_URL="$LOGIN_URL"
  [ "$ONLY" = dashboard ] || [ "$ONLY" = congestion ] || [ "$ONLY" = flow ] || run_test animation.test.mjs DATASET=europe
  [ "$ONLY" = dashboard ] || [ "$ONLY" = animation ] || [ "$ONLY" = flow ] || run_test congestion.test.mjs DATASET=europe
  [ -n "$ONLY" ] && [ "$ONLY" != flow ] || run_test flow.test.mjs DATASET=europe
  if [ "$ONLY" != congestion ] && [ "$ONLY" != flow ]; then
    # The animation chunks of the same server against its positions endpoint: the browser's decoder and
    # interpolation (web/src/flights/animation/*.e2e.ts, run by vitest in Node).
    echo "run.sh: animation chunks vs positions (web/src/**/*.e2e.ts)"
    anim_rc=0
    (cd web && TRAILSCOPE_E2E=1 TRAILSCOPE_URL="$BASE_URL" DATASET=europe npx vitest run) || anim_rc=$?
    [ "$anim_rc" = 0 ] || status=$anim_rc
  fi
fi

if [ -z "$ONLY" ] || [ "$ONLY" = tracker ]; then
  # Its own server and data dir: --demo adds the synthetic videos (standard, cups-attached) and a small
  # flight data set, which the flight test's server must not see.
  start_server tracker "$TMP/tracker-data" --demo --demo-flights 200
  run_test tracker.test.mjs TRACKER_VIDEO=cups-attached
fi

if [ -z "$ONLY" ] || [ "$ONLY" = runs ]; then
  # Its own server and empty data dir: the test makes its videos and its sweep, so the sweep's runs are
  # the only runs there.
  start_server runs "$TMP/runs-data"
  run_test runs.test.mjs
fi

if [ -z "$ONLY" ] || [ "$ONLY" = gaze ]; then
  # Its own server and empty data dir: the test uploads its gaze file, so it is the only one listed.
  start_server gaze "$TMP/gaze-data"
  run_test gaze.test.mjs TRAILSCOPE_SHARED="$SHARED"
fi
exit "$status"
