#!/usr/bin/env bash
# Browser test of the TrailScope dashboard against a real server over loopback.
#   1. a temporary data dir, 2. `trailscope ingest` of the Europe SO6 day as "europe",
#   3. `trailscope serve` on a free port (127.0.0.1 only), 4. the Playwright test(s), 5. the server is always stopped.
# Environment: TRAILSCOPE_BIN (default build/server/trailscope), TRAILSCOPE_SHARED (default ../shared),
#              CHROMIUM (default /usr/bin/chromium), E2E_KEEP=1 keeps the temp dir.
# Prints "N passed, M failed" last; exits non-zero on any failure.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
BIN="${TRAILSCOPE_BIN:-build/server/trailscope}"
SHARED="${TRAILSCOPE_SHARED:-../shared}"
DATA="$SHARED/data/flights/traffic_europe_20180101_m3.so6.gz"

die() { echo "run.sh: $*" >&2; echo "0 passed, 1 failed"; exit 1; }
[ -x "$BIN" ] || die "$BIN is missing: build the server first (or set TRAILSCOPE_BIN)"
[ -f "$DATA" ] || die "$DATA is missing (set TRAILSCOPE_SHARED to the shared folder)"

# The front-end: rebuild when web/dist is missing or older than its sources.
if [ ! -f web/dist/index.html ] || [ -n "$(find web/src web/index.html web/vite.config.ts -newer web/dist/index.html -print -quit)" ]; then
  echo "run.sh: building web/dist"
  [ -d web/node_modules ] || npm ci --prefix web --no-audit --no-fund
  build_log="$(npm run --prefix web build 2>&1)" || { echo "$build_log" >&2; die "web build failed"; }
fi
[ -d tests/e2e/node_modules/playwright-core ] || npm ci --prefix tests/e2e --no-audit --no-fund

TMP="$(mktemp -d -t trailscope-e2e.XXXXXX)"
SERVER_PID=""
cleanup() {
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill "$SERVER_PID" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$SERVER_PID" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$SERVER_PID" 2>/dev/null || true
  fi
  if [ "${E2E_KEEP:-0}" = 1 ]; then echo "run.sh: kept $TMP"; else rm -rf "$TMP"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "run.sh: ingest $DATA"
"$BIN" ingest "$DATA" --data-dir "$TMP/data" --name europe >"$TMP/ingest.log" 2>&1 || {
  tail -n 20 "$TMP/ingest.log" >&2
  die "ingest failed"
}

PORT="$(node -e 'const s=require("net").createServer().listen(0,"127.0.0.1",()=>{console.log(s.address().port);s.close()})')"
"$BIN" serve --data-dir "$TMP/data" --port "$PORT" --host 127.0.0.1 --web-root web/dist >"$TMP/server.log" 2>&1 &
SERVER_PID=$!

BASE_URL="http://127.0.0.1:$PORT"
for i in $(seq 150); do
  if curl -fsS "$BASE_URL/api/v1/health" >/dev/null 2>&1; then break; fi
  kill -0 "$SERVER_PID" 2>/dev/null || { tail -n 20 "$TMP/server.log" >&2; die "server exited"; }
  [ "$i" = 150 ] && { tail -n 20 "$TMP/server.log" >&2; die "server not healthy after 15 s"; }
  sleep 0.1
done
echo "run.sh: server up at $BASE_URL (pid $SERVER_PID)"

status=0
BASE_URL="$BASE_URL" DATASET=europe node tests/e2e/dashboard.test.mjs || status=$?
if [ "$status" != 0 ]; then
  echo "run.sh: server log (tail):" >&2
  tail -n 30 "$TMP/server.log" >&2
fi
exit "$status"
