#!/usr/bin/env bash
# TrailScope benchmarks, end to end: builds what it needs, generates the inputs into tests/bench/out/
# (git-ignored), runs the C++ benchmarks, starts a private ClickHouse 18.16 (the peer) and the TrailScope
# server on 127.0.0.1, drives them (sequential HTTP latency, wrk throughput), stops everything it started
# (always: trap), and writes BENCHMARKS.md at the repository root.
#
#   bash tests/bench/run_benchmarks.sh            # or: make bench
#
# Environment (all optional):
#   BUILD_DIR=build            CMake build folder (configured here if it is not yet)
#   BENCH_OUT=tests/bench/out  where inputs, logs and raw results go
#   BENCH_CSV_FLIGHTS=6500     demo flights written as the OpenSky CSV ingest input (≥ 5 M rows)
#   BENCH_FLIGHTS=14000        demo flights for the summary/tile data set (≥ 10 M points)
#   BENCH_TRACKER_FRAMES=1000  frames of each synthetic ToF scenario in the tracker benchmark
#   BENCH_TRACKER_PEER_REPS=3  runs of each OpenCV peer tracker per scenario (CSRT: about a minute each)
#   BENCH_PORT=18480           TrailScope server port;  BENCH_CH_PORT=18123 ClickHouse HTTP port (+1, +2 used)
#   BENCH_QUICK=1              fewer repetitions and smaller data (a smoke run; not for BENCHMARKS.md)
#   BENCH_KEEP=1               keep the generated CSVs and the ClickHouse data folder afterwards
#   BENCH_REPORT=BENCHMARKS.md output file (relative to the repository root; a quick run defaults to
#                              tests/bench/out/BENCHMARKS.quick.md)
#
# Exit status: non-zero only when something fails (a build, a benchmark program, a server that does not
# start). Targets that are missed are reported in BENCHMARKS.md, not turned into a failure; so are
# mismatches between TrailScope and ClickHouse, which are also printed loudly.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$ROOT"
BUILD_DIR=${BUILD_DIR:-build}
OUT=${BENCH_OUT:-tests/bench/out}
PORT=${BENCH_PORT:-18480}
CH_PORT=${BENCH_CH_PORT:-18123}
CSV_FLIGHTS=${BENCH_CSV_FLIGHTS:-6500}
FLIGHTS=${BENCH_FLIGHTS:-14000}
REPORT=${BENCH_REPORT:-BENCHMARKS.md}
# A quick (smoke) run never overwrites the real report unless asked to.
[ "${BENCH_QUICK:-0}" = 1 ] && [ -z "${BENCH_REPORT:-}" ] && REPORT=tests/bench/out/BENCHMARKS.quick.md
SO6=${BENCH_SO6:-$ROOT/../shared/data/flights/traffic_europe_20180101_m3.so6.gz}
SUM_REPS=30 CH_REPS=10 TILE_REPS=15 INGEST_REPS=3 SO6_REPS=5 WRK_SECONDS=5
BUNDLE_REPS=15 BUNDLE_REF_REPS=5 BUNDLE_BIG_REPS=3 BUNDLE_1M=1
if [ "${BENCH_QUICK:-0}" = 1 ]; then
  SUM_REPS=5 CH_REPS=2 TILE_REPS=3 INGEST_REPS=1 SO6_REPS=2 WRK_SECONDS=2
  BUNDLE_REPS=3 BUNDLE_REF_REPS=1 BUNDLE_BIG_REPS=1 BUNDLE_1M=0
  CSV_FLIGHTS=${BENCH_CSV_FLIGHTS:-600} FLIGHTS=${BENCH_FLIGHTS:-1500}
fi
TRACKER_FRAMES=${BENCH_TRACKER_FRAMES:-1000} TRACKER_REPS=3 TRACKER_PEER_REPS=${BENCH_TRACKER_PEER_REPS:-3}
if [ "${BENCH_QUICK:-0}" = 1 ]; then
  TRACKER_FRAMES=${BENCH_TRACKER_FRAMES:-200} TRACKER_REPS=1 TRACKER_PEER_REPS=1
fi

mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
RESULTS=$OUT/results.jsonl
LOG=$OUT/run.log
CMDS=$OUT/commands.txt
META=$OUT/meta.txt
CH_DIR=$OUT/clickhouse
DATA_DIR=$OUT/data
: >"$RESULTS"
: >"$LOG"
: >"$CMDS"
: >"$META"
T_START=$(date +%s)

SERVER_PID=
CH_STARTED=0
cleanup() {
  local rc=$?
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill -TERM "$SERVER_PID" 2>/dev/null || true
    for _ in $(seq 1 50); do kill -0 "$SERVER_PID" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$SERVER_PID" 2>/dev/null || true
  fi
  SERVER_PID=
  if [ "$CH_STARTED" = 1 ]; then bash "$ROOT/tests/bench/clickhouse_ctl.sh" stop "$CH_DIR" || true; CH_STARTED=0; fi
  if [ "${BENCH_KEEP:-0}" != 1 ]; then
    rm -rf "$CH_DIR" "$DATA_DIR" "$OUT"/demo_*.csv* "$OUT"/pocl-cache 2>/dev/null || true
  fi
  if [ $rc -ne 0 ]; then echo "run_benchmarks.sh: FAILED (exit $rc); see $LOG" >&2; fi
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The first port from $1 up (in steps of 10) where nothing listens on $1..$1+$2-1 (127.0.0.1), so that a
# second copy of this script, or someone's ClickHouse, does not make the run fail.
free_port() {
  local p=$1 n=${2:-1} k busy
  for _ in $(seq 1 50); do
    busy=0
    for ((k = 0; k < n; k++)); do
      if (exec 3<>"/dev/tcp/127.0.0.1/$((p + k))") 2>/dev/null; then busy=1; break; fi
    done
    [ $busy = 0 ] && { echo "$p"; return 0; }
    p=$((p + 10))
  done
  echo "no free port near $1" >&2
  return 1
}
# CPU seconds (busy: user, nice, system, irq, softirq) of the whole machine so far, from /proc/stat.
machine_cpu_s() { awk -v hz="$(getconf CLK_TCK)" '/^cpu / { printf "%.2f", ($2 + $3 + $4 + $7 + $8) / hz }' /proc/stat; }
# CPU seconds used by one process so far (utime + stime), 0 when it is gone.
proc_cpu_s() { awk -v hz="$(getconf CLK_TCK)" '{ printf "%.2f", ($14 + $15) / hz }' "/proc/$1/stat" 2>/dev/null || echo 0; }
# CPU seconds of this script's waited-for children (bash's `times`, second line: "XmY.YYYs XmY.YYYs").
# `times` must run in this shell (in a pipeline or $(...) it would describe a fresh subshell): it writes to
# a file, read back by the caller as CHILD_CPU.
children_cpu() {
  times >"$OUT/.times"
  CHILD_CPU=$(tail -1 "$OUT/.times" | awk '{ s = 0; for (i = 1; i <= 2; i++) { split($i, a, "m"); s += a[1] * 60 + a[2] } printf "%.2f", s }')
  rm -f "$OUT/.times"
}
OWN_EXTRA_CPU=0  # CPU of our processes that are not waited-for children (ClickHouse is re-parented to init)
say() { printf '\n== [%4ds] %s\n' "$(($(date +%s) - T_START))" "$*" | tee -a "$LOG" >&2; }
meta() { printf '%s\t%s\n' "$1" "$2" >>"$META"; }
# Records a command line for BENCHMARKS.md: paths relative to the repository root, arguments with
# shell-special characters single-quoted, so that it can be pasted into a shell.
record() {
  local out='' a
  for a in "$@"; do
    a=${a//$OUT/tests/bench/out}
    a=${a//$ROOT\//}
    if [[ $a =~ ^[A-Za-z0-9_./:=,@+%-]+$ ]]; then out+="$a "; else out+="'${a//\'/\'\\\'\'}' "; fi
  done
  printf '%s\n' "${out% }" >>"$CMDS"
}
# Runs a command, records it (for BENCHMARKS.md), appends its stdout (JSON lines) to the results and
# its stderr to the log (and the terminal).
run() {
  record "$@"
  "$@" >>"$RESULTS" 2> >(tee -a "$LOG" >&2)
}
# The same for a command whose stdout is not JSON (the trailscope CLI): everything goes to the log.
run_log() {
  record "$@"
  "$@" 2>&1 | tee -a "$LOG" >&2
}

# ---------------------------------------------------------------------------------------------------
say "build ($BUILD_DIR)"
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release 2>&1 | tee -a "$LOG" >&2
fi
grep -q 'CMAKE_BUILD_TYPE:STRING=Release' "$BUILD_DIR/CMakeCache.txt" ||
  echo "WARNING: $BUILD_DIR is not a Release build; the numbers will not mean much" | tee -a "$LOG" >&2
cmake --build "$BUILD_DIR" -j "$(nproc)" --target trailscope ingest_bench summary_bench tile_bench http_bench bundle_bench projection_bench tracker_bench bench_report \
  2>&1 | tail -n 5 | tee -a "$LOG" >&2
BIN=$ROOT/$BUILD_DIR/server/trailscope
B=$ROOT/$BUILD_DIR/tests/bench
[ -x "$BIN" ] || { echo "missing $BIN" >&2; exit 1; }

if [ ! -f web/node_modules/vega-datasets/data/airports.csv ]; then
  say "web/node_modules missing: npm ci (the demo generator reads vega-datasets)"
  (cd web && npm ci --no-audit --no-fund) 2>&1 | tail -n 3 | tee -a "$LOG" >&2
fi
[ -f "$SO6" ] || { echo "missing the Europe SO6 day: $SO6" >&2; exit 1; }
export TRAILSCOPE_SOURCE=$ROOT
export POCL_CACHE_DIR=$OUT/pocl-cache
rm -rf "$POCL_CACHE_DIR"
mkdir -p "$POCL_CACHE_DIR"
echo "export TRAILSCOPE_SOURCE=\$PWD POCL_CACHE_DIR=\$PWD/tests/bench/out/pocl-cache  # empty at the start" >>"$CMDS"

# ---------------------------------------------------------------------------------------------------
say "machine"
meta date "$(date -u '+%Y-%m-%d %H:%M UTC')"
meta cpu "$(lscpu | sed -n 's/^Model name: *//p' | head -1)"
meta cores "$(nproc)"
meta memory "$(awk '/MemTotal/ {printf "%.1f GiB", $2/1048576}' /proc/meminfo)"
meta os "$(. /etc/os-release && echo "$PRETTY_NAME") / kernel $(uname -r)"
CXX=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$BUILD_DIR/CMakeCache.txt")
meta compiler "$("${CXX:-c++}" --version | head -1), $(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$BUILD_DIR/CMakeCache.txt") build ($BUILD_DIR)"
meta opencl "$(clinfo -l 2>/dev/null | sed -n 's/.*Device #[0-9]*: *//p' | head -1 || true)"
meta clickhouse "$(dpkg-query -W -f='${Version}' clickhouse-server 2>/dev/null || echo 'not installed')"
meta wrk "$(wrk --version 2>&1 | head -1 | cut -d' ' -f1-2 || true)"
meta commit "$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')$( [ -n "$(git -C "$ROOT" status --porcelain 2>/dev/null | head -1)" ] && echo ' + uncommitted changes')"
meta load_start "$(cut -d' ' -f1-3 /proc/loadavg)"
children_cpu
CPU_T0=$(date +%s.%N) CPU_M0=$(machine_cpu_s) CPU_C0=$CHILD_CPU
meta quick "${BENCH_QUICK:-0}"
cat "$META" >&2

# ---------------------------------------------------------------------------------------------------
say "1. ingest"
run "$B/ingest_bench" --file "$SO6" --label so6_europe_day --reps "$SO6_REPS"
run "$B/ingest_bench" --make-csv "$OUT/demo_states.csv" --flights "$CSV_FLIGHTS"
run "$B/ingest_bench" --file "$OUT/demo_states.csv" --label opensky_csv --reps "$INGEST_REPS"
rm -f "$OUT/demo_states.csv"
run "$B/ingest_bench" --make-csv "$OUT/demo_states.csv.gz" --flights "$CSV_FLIGHTS"
run "$B/ingest_bench" --file "$OUT/demo_states.csv.gz" --label opensky_csv_gz --reps "$INGEST_REPS"
rm -f "$OUT/demo_states.csv.gz"

# ---------------------------------------------------------------------------------------------------
say "2. ClickHouse (peer)"
CH=
if command -v clickhouse-server >/dev/null; then
  rm -rf "$CH_DIR"
  CH_PORT=$(free_port "$CH_PORT" 3)
  CH_STARTED=1
  record bash tests/bench/clickhouse_ctl.sh start "$CH_DIR" "$CH_PORT"
  bash tests/bench/clickhouse_ctl.sh start "$CH_DIR" "$CH_PORT"
  CH=http://127.0.0.1:$CH_PORT
  echo "ClickHouse $(dpkg-query -W -f='${Version}' clickhouse-server 2>/dev/null) on $CH (PID $(cat "$CH_DIR/clickhouse.pid"))" | tee -a "$LOG" >&2
else
  echo "clickhouse-server not installed (make deps-bench): the peer comparison is skipped" | tee -a "$LOG" >&2
fi
CH_ARGS=()
[ -n "$CH" ] && CH_ARGS=(--clickhouse "$CH" --ch-reps "$CH_REPS")

say "3. summary over the demo day ($FLIGHTS flights)"
run "$B/summary_bench" --flights "$FLIGHTS" --reps "$SUM_REPS" "${CH_ARGS[@]}"

say "4. density tiles"
run "$B/tile_bench" --so6 "$SO6" --demo-flights "$FLIGHTS" --reps "$TILE_REPS" "${CH_ARGS[@]}"

# --- congestion counts: the grid on the Europe day, and the same occupancy counts in ClickHouse ------
say "4b. congestion counts (occupancy + entries + complexity on the 20 NM grid) and the ClickHouse peer"
cmake --build "$BUILD_DIR" -j "$(nproc)" --target congestion_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
run "$B/congestion_bench" --so6 "$SO6" --reps "${CONGESTION_REPS:-5}" "${CH_ARGS[@]}"

if [ "$CH_STARTED" = 1 ]; then
  OWN_EXTRA_CPU=$(awk -v a="$OWN_EXTRA_CPU" -v b="$(proc_cpu_s "$(cat "$CH_DIR/clickhouse.pid")")" 'BEGIN { printf "%.2f", a + b }')
  record bash tests/bench/clickhouse_ctl.sh stop "$CH_DIR"
  bash tests/bench/clickhouse_ctl.sh stop "$CH_DIR"
  CH_STARTED=0
fi

# --- the ClickHouse store on a local 2 x 2 cluster: its pushed-down reads against ClickHouse's own SQL ---
say "4c. the ClickHouse store (2 shards x 2 replicas): pushed-down reads vs ClickHouse's own SQL for them"
if command -v clickhouse-server >/dev/null && [ -f /usr/share/java/zookeeper.jar ]; then
  BCL_ENV=(CLUSTER_DIR="$OUT/cluster" CLUSTER_PORT="$(free_port 29600 43)" CLUSTER_FRESH=1)
  record env "${BCL_ENV[@]}" bash tests/cluster/cluster.sh up
  BCL_URL=$(env "${BCL_ENV[@]}" bash tests/cluster/cluster.sh up | sed -n 's/^--store //p')
  cmake --build "$BUILD_DIR" -j "$(nproc)" --target clickhouse_store_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
  run "$B/clickhouse_store_bench" --so6 "$SO6" --store "$BCL_URL" --reps "${CH_STORE_REPS:-15}" \
    --scales 1 --demo-scales "${CH_STORE_DEMO_SCALES:-1,8}" --tmp "$OUT/clickhouse_store_bench"
  for f in "$OUT"/cluster/node?/pid "$OUT"/cluster/zk/pid; do  # their CPU is ours, not other people's
    [ -f "$f" ] && OWN_EXTRA_CPU=$(awk -v a="$OWN_EXTRA_CPU" -v b="$(proc_cpu_s "$(cat "$f")")" 'BEGIN { printf "%.2f", a + b }')
  done
  record env "${BCL_ENV[@]}" bash tests/cluster/cluster.sh down
  env "${BCL_ENV[@]}" bash tests/cluster/cluster.sh down
else
  echo "clickhouse-server or zookeeper not installed (make deps-cluster): the ClickHouse store bench is skipped" | tee -a "$LOG" >&2
fi

# ---------------------------------------------------------------------------------------------------
say "5. CUBu bundling (default parameters: 512 px, h = 32, 15 iterations)"
BD=$ROOT/../shared/data/bundling
run "$B/bundle_bench" --graph "$BD/classic/airlines.xml" --label us_airlines --reps "$BUNDLE_REPS" --ref-reps "$BUNDLE_REF_REPS"
run "$B/bundle_bench" --graph "$BD/classic/migrations.xml" --label us_migrations --reps "$BUNDLE_REPS" --ref-reps "$BUNDLE_REF_REPS"
run "$B/bundle_bench" --graph "$BD/epb/airtraffic.json" --label air_traffic --reps "$BUNDLE_BIG_REPS" --ref-reps 1
run "$B/bundle_bench" --graph "$BD/cubu/us_counties_lsp.trl" --label us_counties_lsp --reps "$BUNDLE_BIG_REPS" --ref-reps 1
run "$B/bundle_bench" --so6 "$SO6" --label europe_so6_trails --reps "$BUNDLE_BIG_REPS" --ref-reps 1
run "$B/bundle_bench" --random-edges 100000 --label generated_100k --reps "$BUNDLE_BIG_REPS" --ref-reps 1
if [ "$BUNDLE_1M" = 1 ]; then
  run "$B/bundle_bench" --random-edges 1000000 --label generated_1m --reps 1 --ref-reps 1
fi

# ---------------------------------------------------------------------------------------------------
say "5a. streaming bundling: ~40k trails of a generated US day kept bundled while the clock moves"
cmake --build "$BUILD_DIR" -j "$(nproc)" --target stream_bundle_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
run "$B/stream_bundle_bench" --flights "${STREAM_FLIGHTS:-175000}" --window-s 7200 --step-s 30 --settle 30 \
  --updates "${STREAM_UPDATES:-60}" --backends cpu,opencl --match 1

# ---------------------------------------------------------------------------------------------------
say "5b. projections (PCA, MDS, t-SNE, LAMP at 1k-100k x 50) and the npm peers on the same data"
PROJ_DIR=$OUT/projection
PROJ_SIZES=${PROJ_SIZES:-1000,5000,20000,100000}
PROJ_PEER_SIZES=${PROJ_PEER_SIZES:-1000,5000}
# 95 s per method and size: every method at 100k on the OpenCL path (t-SNE ~90 s by the cost model), the
# slower C++ reference of t-SNE at 100k is skipped and reported so.
run "$B/projection_bench" --data-dir "$PROJ_DIR" --sizes "$PROJ_SIZES" --budget-s 95
if [ ! -d tests/bench/peers/node_modules ]; then
  (cd tests/bench/peers && npm ci --no-audit --no-fund) 2>&1 | tail -n 3 | tee -a "$LOG" >&2
fi
record node tests/bench/projection_peers.mjs --data-dir "$PROJ_DIR" --sizes "$PROJ_PEER_SIZES" --budget-s 300
sed -i '$ s|$|> tests/bench/out/projection/peers.jsonl|' "$CMDS"
node tests/bench/projection_peers.mjs --data-dir "$PROJ_DIR" --sizes "$PROJ_PEER_SIZES" --budget-s 300 \
  >"$PROJ_DIR/peers.jsonl" 2> >(tee -a "$LOG" >&2)
run "$B/projection_bench" --data-dir "$PROJ_DIR" --score-peers "$PROJ_DIR/peers.jsonl"

# ---------------------------------------------------------------------------------------------------
# MIL (--peers csrt,kcf,mil) is left out: about 0.2 s per frame, it would add over half an hour.
say "5c. teat tracker on the synthetic ToF scenarios, and OpenCV's CSRT and KCF trackers (peers) on the same frames"
# First the real depth frames without teats (the Redwood room), each a whole-frame search, beside synthetic
# frames of the same size; last, every scenario on the 20 seeds from 1000 on (robustness; never the seeds used
# while tuning), 1,000 frames each.
run "$B/tracker_bench" --scenarios standard,noisy,occluded,cups-attached,fast-motion --frames "$TRACKER_FRAMES" \
  --seed 1 --reps "$TRACKER_REPS" --peers csrt,kcf --peer-reps "$TRACKER_PEER_REPS" \
  --real "$ROOT/../shared/data/tracker/depth_open3d_rgbd/depth" \
  --robustness-seeds 1000-1019 --robustness-frames "$TRACKER_FRAMES"

# ---------------------------------------------------------------------------------------------------
say "5d. losses of separation: all pairs of the Europe SO6 day (5 NM / 1,000 ft, 2,000 ft above FL410)"
SEP_REPS=5
[ "${BENCH_QUICK:-0}" = 1 ] && SEP_REPS=2
cmake --build "$BUILD_DIR" -j "$(nproc)" --target separation_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
run "$B/separation_bench" --file "$SO6" --reps "$SEP_REPS"

# ---------------------------------------------------------------------------------------------------
say "5e. gaze: ingest rows/s per format, event detection samples/s, kappa against the expert coders"
GAZE_REPS=5
[ "${BENCH_QUICK:-0}" = 1 ] && GAZE_REPS=2
cmake --build "$BUILD_DIR" -j "$(nproc)" --target gaze_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
run "$B/gaze_bench" --gaze-dir "${BENCH_GAZE_DIR:-$ROOT/../shared/data/gaze}" --reps "$GAZE_REPS"
say "5e'. gaze views: a stimulus-space density tile and an AOI query on the Lund data"
cmake --build "$BUILD_DIR" -j "$(nproc)" --target gaze_views_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
run "$B/gaze_views_bench" --gaze-dir "${BENCH_GAZE_DIR:-$ROOT/../shared/data/gaze}" --reps "$((GAZE_REPS * 2))"
say "5f. flow map of the Europe SO6 day end to end (sector fields, evenly spaced streamlines, CUBu, PNG)"
FLOW_REPS=5
[ "${BENCH_QUICK:-0}" = 1 ] && FLOW_REPS=2
cmake --build "$BUILD_DIR" -j "$(nproc)" --target flow_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
run "$B/flow_bench" --file "$SO6" --reps "$FLOW_REPS"
# --- the embedded store at 100 M points: a generated week of dense traffic (~25,000 aircraft in the air) ---
say "5g. the embedded store at 100 M points: a generated week (fleet mode), held as the store holds it, queried"
WEEK_AIRCRAFT=${BENCH_WEEK_AIRCRAFT:-32000} WEEK_DAYS=7 WEEK_REPS=30
[ "${BENCH_QUICK:-0}" = 1 ] && WEEK_AIRCRAFT=${BENCH_WEEK_AIRCRAFT:-2000} WEEK_DAYS=2 WEEK_REPS=5
cmake --build "$BUILD_DIR" -j "$(nproc)" --target week_bench 2>&1 | tail -n 2 | tee -a "$LOG" >&2
run "$B/week_bench" --aircraft "$WEEK_AIRCRAFT" --days "$WEEK_DAYS" --reps "$WEEK_REPS" \
  --host-gib "$(awk '/MemTotal/ { printf "%d", $2 / 1048576 + 0.5 }' /proc/meminfo)"

# ---------------------------------------------------------------------------------------------------
PORT=$(free_port "$PORT" 1)
say "6. the server over loopback (127.0.0.1:$PORT)"
rm -rf "$DATA_DIR"
run_log "$BIN" ingest "$SO6" --data-dir "$DATA_DIR" --name europe --quiet
run_log "$BIN" demo --data-dir "$DATA_DIR" --flights "$FLIGHTS" --name demo
# Access control is on: an admin token for the clients below. http_bench and anim_bench read
# TRAILSCOPE_TOKEN; curl and wrk send it as a header.
TRAILSCOPE_TOKEN=$("$BIN" token create --data-dir "$DATA_DIR" --name bench --role admin --json |
  python3 -c 'import json, sys; print(json.load(sys.stdin)["token"])')
export TRAILSCOPE_TOKEN
AUTH="Authorization: Bearer $TRAILSCOPE_TOKEN"
curl() { command curl -H "$AUTH" "$@"; }
record "$BIN" serve --data-dir "$DATA_DIR" --port "$PORT" --web-root web/dist
sed -i '$ s/$/ \&  # stopped by PID at the end/' "$CMDS"
T0=$(date +%s%N)
"$BIN" serve --data-dir "$DATA_DIR" --port "$PORT" --web-root web/dist >>"$LOG" 2>&1 &
SERVER_PID=$!
for _ in $(seq 1 1200); do
  curl -fsS "http://127.0.0.1:$PORT/api/v1/health" >/dev/null 2>&1 && break
  kill -0 "$SERVER_PID" 2>/dev/null || { echo "the server exited; see $LOG" >&2; exit 1; }
  sleep 0.1
done
curl -fsS "http://127.0.0.1:$PORT/api/v1/health" >/dev/null
echo "{\"bench\":\"server_start\",\"ms\":$((($(date +%s%N) - T0) / 1000000))}" >>"$RESULTS"

BASE=http://127.0.0.1:$PORT
DAY=1704067200  # the demo day (DemoOptions::day_start)
T14=$((DAY + 14 * 3600)) T16=$((DAY + 16 * 3600))
S=/api/v1/datasets/demo/summary
run "$B/http_bench" --base "$BASE" --label summary_whole_day --path "$S" --reps "$SUM_REPS"
run "$B/http_bench" --base "$BASE" --label summary_window_2h --path "$S?t0=$T14&t1=$T16" --reps "$SUM_REPS"
run "$B/http_bench" --base "$BASE" --label summary_bbox_alt --path "$S?bbox=-90,35,-70,45&alt_min=10000&alt_max=30000" --reps "$SUM_REPS"
run "$B/http_bench" --base "$BASE" --label summary_bbox_alt_2h \
  --path "$S?bbox=-90,35,-70,45&alt_min=10000&alt_max=30000&t0=$T14&t1=$T16" --reps "$SUM_REPS"

TILE=/tiles/europe/density/4/8/5.png
# Cold over HTTP: every request a new cache key (t1 after the data: same image, new tile + span key).
run "$B/http_bench" --base "$BASE" --label tile_europe_4_8_5_cold --path "$TILE" --vary t1=1600000000 --reps "$TILE_REPS"
run "$B/http_bench" --base "$BASE" --label tile_europe_4_8_5_warm --path "$TILE" --reps "$SUM_REPS"

# Animation chunks: throughput and scrubs on the Europe day (in process and over HTTP against this server,
# which holds the same day as "europe") and on a generated day of ~25,000 aircraft at once (in process).
# BENCH_ANIM_FLIGHTS (default 216,000: a peak of ~25,000 at once) flights sampled every 30-60 s (~31 M points).
say "6b. animation chunks"
cmake --build "$BUILD_DIR" -j "$(nproc)" --target anim_bench 2>&1 | tail -1 | tee -a "$LOG" >&2
ANIM_FLIGHTS=${BENCH_ANIM_FLIGHTS:-216000} ANIM_SCRUBS=60
[ "${BENCH_QUICK:-0}" = 1 ] && ANIM_FLIGHTS=${BENCH_ANIM_FLIGHTS:-25000} ANIM_SCRUBS=10
run "$B/anim_bench" --so6 "$SO6" --label europe_so6_day --scrubs "$ANIM_SCRUBS" --base "$BASE" --dataset europe
run "$B/anim_bench" --demo-flights "$ANIM_FLIGHTS" --sample-s 30,60 --label demo_${ANIM_FLIGHTS}_flights \
  --scrubs "$ANIM_SCRUBS"

# wrk: a tile already in the server's cache (the request above put it there).
wrk_json() {  # label, then wrk's output on stdin → one JSON line
  awk -v label="$1" '
    function ms(v) { if (v ~ /us$/) return v / 1000; if (v ~ /ms$/) return v + 0; if (v ~ /s$/) return v * 1000; return v }
    /Requests\/sec:/ { rps = $2 }
    /Transfer\/sec:/ { tps = $2 }
    /requests in/ { req = $1 }
    /Non-2xx or 3xx responses:/ { non2xx = $5 }
    /Socket errors:/ { errs = $0; sub(/.*Socket errors: */, "", errs) }
    /^ +50%/ { p50 = ms($2) } /^ +75%/ { p75 = ms($2) } /^ +90%/ { p90 = ms($2) } /^ +99%/ { p99 = ms($2) }
    END {
      printf "{\"bench\":\"wrk\",\"label\":\"%s\",\"requests_per_s\":%s,\"requests\":%s,\"transfer_per_s\":\"%s\",", label, rps + 0, req + 0, tps
      printf "\"latency_p50_ms\":%s,\"latency_p75_ms\":%s,\"latency_p90_ms\":%s,\"latency_p99_ms\":%s,\"non_2xx_3xx\":%d,\"socket_errors\":\"%s\"}\n", p50 + 0, p75 + 0, p90 + 0, p99 + 0, non2xx, errs
    }'
}
if command -v wrk >/dev/null; then
  curl -fsS -o /dev/null "$BASE$TILE"
  ETAG=$(curl -fsS -D - -o /dev/null "$BASE$TILE" | sed -n 's/^[Ee][Tt][Aa][Gg]: *//p' | tr -d '\r')
  record wrk -t2 -c50 -d"${WRK_SECONDS}s" --latency -H "Authorization: Bearer tsk_..." "$BASE$TILE"
  wrk -t2 -c50 -d2s -H "$AUTH" "$BASE$TILE" >>"$LOG" 2>&1  # warm-up
  wrk -t2 -c50 -d"${WRK_SECONDS}s" --latency -H "$AUTH" "$BASE$TILE" 2>>"$LOG" | tee -a "$LOG" | wrk_json tile_cached_200 >>"$RESULTS"
  if [ -n "$ETAG" ]; then
    record wrk -t2 -c50 -d"${WRK_SECONDS}s" --latency -H "If-None-Match: $ETAG" -H "Authorization: Bearer tsk_..." "$BASE$TILE"
    wrk -t2 -c50 -d"${WRK_SECONDS}s" --latency -H "If-None-Match: $ETAG" -H "$AUTH" "$BASE$TILE" 2>>"$LOG" | tee -a "$LOG" |
      wrk_json tile_cached_304 >>"$RESULTS"
  fi
  record wrk -t2 -c50 -d"${WRK_SECONDS}s" --latency "$BASE/api/v1/health"
  wrk -t2 -c50 -d"${WRK_SECONDS}s" --latency "$BASE/api/v1/health" 2>>"$LOG" | tee -a "$LOG" | wrk_json health >>"$RESULTS"
else
  echo "wrk not installed (make deps-test): the throughput test is skipped" | tee -a "$LOG" >&2
fi

kill -TERM "$SERVER_PID" 2>/dev/null || true
for _ in $(seq 1 50); do kill -0 "$SERVER_PID" 2>/dev/null || break; sleep 0.1; done
kill -KILL "$SERVER_PID" 2>/dev/null || true
wait "$SERVER_PID" 2>/dev/null || true  # reaped: its CPU time now counts among our children's
SERVER_PID=

# ---------------------------------------------------------------------------------------------------
# Browser animation: TrailScope's layer vs deck.gl TripsLayer in one headless Chromium (SwiftShader), the
# same seeded trips generated in the page, 120 s tails, at 5k, 25k and 100k aircraft (and the empty map).
ANIM_SIZES=${BENCH_ANIM_SIZES:-5000,25000,100000} ANIM_SECONDS=10
[ "${BENCH_QUICK:-0}" = 1 ] && ANIM_SIZES=${BENCH_ANIM_SIZES:-5000} ANIM_SECONDS=4
say "10. animation in the browser (TrailScope layer vs deck.gl TripsLayer; $ANIM_SIZES aircraft)"
if [ -x "${CHROMIUM:-/usr/bin/chromium}" ]; then
  if [ ! -d tests/bench/peers/node_modules/@deck.gl/geo-layers ] || [ ! -d tests/bench/peers/node_modules/playwright-core ]; then
    (cd tests/bench/peers && npm ci --no-audit --no-fund) 2>&1 | tail -n 3 | tee -a "$LOG" >&2
  fi
  run node tests/bench/anim_browser_bench.mjs --sizes "$ANIM_SIZES" --tail 120 --seconds "$ANIM_SECONDS" \
    --modes empty,trailscope,deckchunks,trips --page "$OUT/anim-page"
else
  echo "chromium not installed (make deps-test): the browser animation benchmark is skipped" | tee -a "$LOG" >&2
fi

# ---------------------------------------------------------------------------------------------------
meta load_end "$(cut -d' ' -f1-3 /proc/loadavg)"
# How much CPU other processes (other people's builds and tests) took while the benchmarks ran: the
# machine's busy CPU time minus ours (children, ClickHouse), as a share of the cores × wall time.
children_cpu
read -r OTHER_S OTHER_PCT < <(awk -v t0="$CPU_T0" -v t1="$(date +%s.%N)" -v m0="$CPU_M0" -v m1="$(machine_cpu_s)" \
  -v c0="$CPU_C0" -v c1="$CHILD_CPU" -v x="$OWN_EXTRA_CPU" -v n="$(nproc)" \
  'BEGIN { o = (m1 - m0) - (c1 - c0) - x; if (o < 0) o = 0; printf "%.1f %.1f\n", o, 100 * o / ((t1 - t0) * n) }')
meta other_cpu_s "$OTHER_S"
meta other_cpu_pct "$OTHER_PCT"
meta duration_s "$(($(date +%s) - T_START))"
say "report → $REPORT"
GPU_ARGS=()
[ -f tests/bench/gpu_h100_bundle.jsonl ] && GPU_ARGS=(--gpu-results tests/bench/gpu_h100_bundle.jsonl)
"$B/bench_report" --results "$RESULTS" --meta "$META" --commands "$CMDS" --out "$ROOT/$REPORT" "${GPU_ARGS[@]}"
echo "done in $(($(date +%s) - T_START)) s; raw results in $RESULTS" >&2
