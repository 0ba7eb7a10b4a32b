#!/usr/bin/env bash
# The bounded load test (`make load`): starts a TrailScope server on 127.0.0.1 with the generated demo
# dataset (`serve --demo`, 20,000 flights, ~17 M points, kept in tests/bench/out/load-data between runs),
# runs tests/bench/load_bench.cpp against it (100 connections of mixed tiles, summaries and flight lists,
# uploads timed to their 202, a health probe, 10 WebSockets, for 60 s), stops the server it started (by
# its PID), writes the records to tests/bench/load_results.jsonl and puts the "Load" section of
# BENCHMARKS.md in place (tests/bench/bench_report.cpp renders it; `make bench` keeps it).
#
#   bash tests/bench/load_test.sh          # or: make load
#
# Environment (all optional):
#   BUILD_DIR=build              CMake build folder (configured here if it is not yet)
#   LOAD_CONNECTIONS=100         HTTP connections        LOAD_SECONDS=60   duration of the load
#   LOAD_WS=10                   WebSocket clients       LOAD_UPLOAD_EVERY_S=5  one upload per interval
#   LOAD_PORT=18580              server port (the next free one from there)
#   LOAD_DEMO_SOURCE=...         vega-datasets' data folder for the demo generator (default:
#                                web/node_modules/vega-datasets/data, from `npm ci` in web/)
#   LOAD_RESULTS=tests/bench/load_results.jsonl   where the records go
#   LOAD_REPORT=BENCHMARKS.md    the report whose Load section is replaced ("" = leave it alone)
#
# Access control: when the binary has the `token` verb, an admin token is created in the data folder
# before the server starts and sent by every client (Authorization: Bearer).
#
# Exit status: non-zero when something fails to run (a build, the server, the load program); the targets
# (0 errors, p99 < 1 s, upload 202 < 1 s, bounded RSS) are reported in BENCHMARKS.md, not enforced here.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$ROOT"
BUILD_DIR=${BUILD_DIR:-build}
OUT=tests/bench/out
DATA_DIR=$OUT/load-data
RESULTS=${LOAD_RESULTS:-tests/bench/load_results.jsonl}
REPORT=${LOAD_REPORT-BENCHMARKS.md}
mkdir -p "$OUT"
LOG=$OUT/load.log
: > "$LOG"

SERVER_PID=
cleanup() {
  local rc=$?
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill -TERM "$SERVER_PID" 2>/dev/null || true
    for _ in $(seq 1 100); do kill -0 "$SERVER_PID" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$SERVER_PID" 2>/dev/null || true
  fi
  [ $rc -ne 0 ] && echo "load_test.sh: FAILED (exit $rc); see $LOG" >&2
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release 2>&1 | tee -a "$LOG" >&2
fi
cmake --build "$BUILD_DIR" -j "$(nproc)" --target trailscope load_bench bench_report 2>&1 | tail -n 3 | tee -a "$LOG" >&2
BIN=$ROOT/$BUILD_DIR/server/trailscope

PORT=${LOAD_PORT:-18580}
for _ in $(seq 1 50); do (exec 3<>"/dev/tcp/127.0.0.1/$PORT") 2>/dev/null || break; PORT=$((PORT + 1)); done

DEMO_ARGS=()
[ -n "${LOAD_DEMO_SOURCE:-}" ] && DEMO_ARGS=(--demo-source "$LOAD_DEMO_SOURCE")
TOKEN_ARGS=()
if "$BIN" token create --help 2>&1 | grep -q -- --role; then
  TOKEN=$("$BIN" token create --data-dir "$DATA_DIR" --name "load-$(date +%s)" --role admin --json |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["token"])')
  TOKEN_ARGS=(--token "$TOKEN")
fi

echo "== server on 127.0.0.1:$PORT (the demo dataset is generated on the first run: a minute or more)" >&2
"$BIN" serve --data-dir "$DATA_DIR" --host 127.0.0.1 --port "$PORT" --web-root /nonexistent --demo \
  "${DEMO_ARGS[@]}" >> "$LOG" 2>&1 &
SERVER_PID=$!
for _ in $(seq 1 6000); do
  curl -fsS -o /dev/null "http://127.0.0.1:$PORT/api/v1/health" 2>/dev/null && break
  kill -0 "$SERVER_PID" 2>/dev/null || { echo "the server exited; see $LOG" >&2; exit 1; }
  sleep 0.1
done

echo "== load: ${LOAD_CONNECTIONS:-100} connections, ${LOAD_WS:-10} WebSockets, ${LOAD_SECONDS:-60} s" >&2
TMP_RESULTS=$OUT/load.jsonl
"$ROOT/$BUILD_DIR/tests/bench/load_bench" --host 127.0.0.1 --port "$PORT" --pid "$SERVER_PID" \
  --connections "${LOAD_CONNECTIONS:-100}" --seconds "${LOAD_SECONDS:-60}" --ws "${LOAD_WS:-10}" \
  --upload-every-s "${LOAD_UPLOAD_EVERY_S:-5}" "${TOKEN_ARGS[@]}" > "$TMP_RESULTS" 2> >(tee -a "$LOG" >&2)

kill -TERM "$SERVER_PID"
for _ in $(seq 1 100); do kill -0 "$SERVER_PID" 2>/dev/null || break; sleep 0.1; done
kill -KILL "$SERVER_PID" 2>/dev/null || true
wait "$SERVER_PID" 2>/dev/null || true
SERVER_PID=

# The machine, the commit and the configuration with the records (bench_report shows them).
python3 - "$TMP_RESULTS" "$RESULTS" <<'EOF'
import json, os, platform, subprocess, sys, time
src, dst = sys.argv[1], sys.argv[2]
def sh(cmd):
    try: return subprocess.run(cmd, shell=True, capture_output=True, text=True).stdout.strip()
    except Exception: return ""
meta = {"bench": "load_meta", "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "cpu": sh("lscpu | sed -n 's/^Model name: *//p' | head -1"), "cores": os.cpu_count(),
        "load_avg": open("/proc/loadavg").read().split()[:3],
        "commit": sh("git rev-parse --short HEAD") + (" + uncommitted changes" if sh("git status --porcelain | head -1") else "")}
with open(dst, "w") as out:
    out.write(json.dumps(meta) + "\n")
    out.write(open(src).read())
EOF
echo "== records: $RESULTS" >&2
if [ -n "$REPORT" ]; then
  "$ROOT/$BUILD_DIR/tests/bench/bench_report" --load-results "$RESULTS" --load-section-only --out "$OUT/load_section.md"
  # The section replaces the one in the report (from its heading to the next "## "), or goes before
  # "## Commands" when the report has none yet.
  python3 - "$REPORT" "$OUT/load_section.md" <<'EOF'
import re, sys
report, section = sys.argv[1], open(sys.argv[2]).read()
text = open(report).read() if __import__("os").path.exists(report) else ""
head = "## Load: mixed traffic"
at = text.find(head)
if at >= 0:
    nxt = text.find("\n## ", at + 1)
    text = text[:at] + section + (text[nxt + 1:] if nxt >= 0 else "")
elif "## Commands" in text:
    at = text.find("## Commands")
    text = text[:at] + section + text[at:]
else:
    text += ("\n" if text else "") + section
open(report, "w").write(text)
EOF
  echo "== $REPORT: Load section updated" >&2
fi
