#!/usr/bin/env bash
# Chaos: the server killed with SIGKILL at every write path of its stores (server/src/store/failpoint.hpp
# names them), then restarted. After each kill the store must hold exactly what it held before, byte for
# byte (sha256 of every file), plus the interrupted item only when the kill came after its final rename
# (and then whole: readable through the API), with tmp/ and uploads/ empty and no "*.tmp.*" file left, and
# ids handed out in a 202 before the kill not handed out again.
#
# Usage: chaos_test.sh TRAILSCOPE_BIN
# Small inputs only (a 150,000-row CSV, a 16-edge graph, 6-frame videos): the whole run takes well under a
# minute. Each case: start the server with TRAILSCOPE_FAILPOINT=<point>, send the request that reaches it,
# see the process die by SIGKILL with the failpoint's line in its log, restart it without the failpoint,
# check.
set -uo pipefail
export LC_ALL=C
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
PARALLEL=${CHAOS_PARALLEL:-4}  # cases run at once, each on its own copy of the store
PASS=0 FAIL=0
SERVER_PID=
AUTH=()  # curl arguments that authenticate the requests (none while the server has no access control)
cleanup() { [ -n "$SERVER_PID" ] && kill -9 "$SERVER_PID" 2>/dev/null; rm -rf "$TMP"; }
RUN=$TMP/base  # the folder of the server being driven: its log, pid and exit status
DATA=$RUN/data
mkdir -p "$RUN"
trap cleanup EXIT

check() {  # check NAME EXPECTED ACTUAL
  if [ "$2" == "$3" ]; then PASS=$((PASS + 1)); echo "ok   $1"
  else FAIL=$((FAIL + 1)); echo "FAIL $1: expected '$2', got '$3'"; fi
}
json() { python3 -c "import json,sys; d=json.load(sys.stdin); print($1)"; }

# start [FAILPOINT]: the server on a free port of 127.0.0.1, with the failpoint armed when one is given. A
# small bash between this shell and the server records the server's exit status in $RUN/exit (137: SIGKILL).
start() {
  : > "$RUN/server.log"
  rm -f "$RUN/exit" "$RUN/pid"
  TRAILSCOPE_FAILPOINT=${1:-} bash -c '"$@" & echo $! > "$0/pid"; wait $!; echo $? > "$0/exit"' "$RUN" \
    "$BIN" serve --data-dir "$DATA" --port 0 --host 127.0.0.1 --web-root /nonexistent --backend cpu \
    >> "$RUN/server.log" 2>&1 &
  PORT=
  # Up to 90 s: the server reads every stored dataset before it listens, slow on a loaded CI machine.
  for _ in $(seq 1 3600); do
    PORT=$(grep -oE '127\.0\.0\.1:[0-9]+' "$RUN/server.log" | head -1 | cut -d: -f2)
    [ -n "$PORT" ] && [ -s "$RUN/pid" ] && break
    [ -s "$RUN/exit" ] && break
    sleep 0.025
  done
  SERVER_PID=$(cat "$RUN/pid")
  URL="http://127.0.0.1:$PORT"
}
# Waits up to $1 s for the server to end; prints its exit status, or "alive" (and then kills it).
await_exit() {
  for _ in $(seq 1 $(($1 * 40))); do
    [ -s "$RUN/exit" ] && break
    sleep 0.025
  done
  if [ -s "$RUN/exit" ]; then cat "$RUN/exit"; else echo alive; kill -9 "$SERVER_PID" 2>/dev/null; fi
  SERVER_PID=
}
stop() { kill -TERM "$SERVER_PID"; await_exit 20 > /dev/null; }
c() { curl -s "${AUTH[@]}" "$@"; }
code() { curl -s -o /dev/null -w '%{http_code}' "${AUTH[@]}" "$@"; }
post_json() { c -H 'Content-Type: application/json' -d "$2" "$URL$1"; }
wait_job() {
  local state
  for _ in $(seq 1 600); do
    state=$(c "$URL/api/v1/jobs/$1" | json 'd["state"]' 2>/dev/null)
    case "$state" in done|failed|cancelled) echo "$state"; return;; esac
    sleep 0.05
  done
  echo timeout
}
ids() { c "$URL/api/v1/$1" | json "' '.join(sorted(str(x['id']) for x in d['$2']))"; }

# Every file of the store but tmp/ and uploads/, with its sha256: what "byte-identical" compares. Id
# counters (".last_id", ".last_job_id", ".last_replay_id") are left out: they advance by design, and the
# id checks cover them.
snapshot() {
  (cd "$DATA" && find . \( -path ./tmp -o -path ./uploads \) -prune -o -type f ! -name ".last_*id" -print0 |
    xargs -0 -r sha256sum | LC_ALL=C sort)
}

# ---- inputs ------------------------------------------------------------------------------------------
# OpenSky-style CSV: $1 aircraft, $2 samples each 10 s apart, straight lines (one flight per aircraft).
make_csv() {
  awk -v n="$1" -v m="$2" 'BEGIN {
    print "time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude"
    for (a = 0; a < n; a++)
      for (k = 0; k < m; k++)
        printf "%d,%06x,%.5f,%.5f,200,45,0,TST%d,false,%d\n", 1514764800 + 10 * k, 0xabc000 + a,
          40 + 0.1 * a + 0.0005 * k, 2 + 0.0005 * k, a, 9000 + a
  }'
}
make_csv 2 40 > "$TMP/small.csv"
make_csv 50 3000 > "$TMP/big.csv"  # 150,000 rows: the ingest reports progress mid-parse (every 65,536)
GRAPH='{"nodes": ['
for i in 0 1 2 3; do GRAPH+="{\"id\": \"a$i\", \"x\": 0, \"y\": $((10 * i))}, {\"id\": \"b$i\", \"x\": 100, \"y\": $((10 * i + 5))}, "; done
GRAPH="${GRAPH%, }], \"links\": ["
for i in 0 1 2 3; do for k in 0 1 2 3; do GRAPH+="{\"source\": \"a$i\", \"target\": \"b$k\"}, "; done; done
GRAPH="${GRAPH%, }]}"
echo "$GRAPH" > "$TMP/graph.json"
SECTORS='{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"name": "S1", "lower_fl": 0, "upper_fl": 400}, "geometry": {"type": "Polygon", "coordinates": [[[1, 39], [4, 39], [4, 46], [1, 46], [1, 39]]]}}]}'
echo "$SECTORS" > "$TMP/sectors.geojson"
printf '1,1,10,10,5,5,1,1,1\n2,1,11,10,5,5,1,1,1\n3,1,12,10,5,5,1,1,1\n1,2,40,40,8,8,1,1,1\n2,2,41,41,8,8,1,1,1\n' > "$TMP/gt.txt"
BUNDLE_BODY='{"source": {"graph": "g1"}, "params": {"size": 128, "iterations": 4, "h": 16, "spl": 4}, "backend": "cpu"}'
SYNTH_BODY='{"scenario": "standard", "frames": 6, "seed": 3}'

# ---- the items every case must find unchanged -----------------------------------------------------
# Access control: an admin's token for every request and a reader's, made with the CLI before the first
# start (so the server makes no first token of its own).
TOKEN=$("$BIN" token create --data-dir "$DATA" --name chaos --role admin --json | json 'd["token"]')
READER=$("$BIN" token create --data-dir "$DATA" --name reader --role reader --json | json 'd["token"] + " " + d["id"]')
READER_ID=${READER#* } READER=${READER% *}
AUTH=(-H "Authorization: Bearer $TOKEN")
start
check "baseline: dataset base" done "$(wait_job "$(c --data-binary @"$TMP/small.csv" "$URL/api/v1/datasets?name=base" | json 'd["job"]["id"]')")"
check "baseline: graph g1" g1 "$(c --data-binary @"$TMP/graph.json" "$URL/api/v1/graphs?name=g" | json 'd["id"]')"
r=$(post_json /api/v1/bundles "$BUNDLE_BODY")
check "baseline: bundle b1" "b1 done" "$(echo "$r" | json 'd["bundle"]') $(wait_job "$(echo "$r" | json 'd["job"]["id"]')")"
r=$(post_json /api/v1/videos/synth "$SYNTH_BODY")
check "baseline: video v1" "v1 done" "$(echo "$r" | json 'd["video"]') $(wait_job "$(echo "$r" | json 'd["job"]["id"]')")"
r=$(post_json /api/v1/runs/track '{"video": "v1"}')
check "baseline: track run" done "$(wait_job "$(echo "$r" | json 'd["job"]["id"]')")"
check "baseline: MOT m1" m1 "$(c --data-binary @"$TMP/gt.txt" "$URL/api/v1/mot?kind=gt&name=gt" | json 'd["id"]')"
check "baseline: sectors s1" s1 "$(c -H "Content-Type: application/geo+json" --data-binary @"$TMP/sectors.geojson" "$URL/api/v1/sectors?name=sw" | json 'd["id"]')"
SWEEP_BODY='{"videos": ["v1"], "sweep": {"mode": "grid", "axes": [{"param": "ncc_min", "min": 0.4, "max": 0.6, "steps": 2}]}}'
r=$(post_json /api/v1/sweeps "$SWEEP_BODY")
check "baseline: sweep" done "$(wait_job "$(echo "$r" | json 'd["job"]["id"]')")"
# Two extra items of each deletable kind: one to delete per case, the others must stay.
for name in del1 del2 del3; do
  wait_job "$(c --data-binary @"$TMP/small.csv" "$URL/api/v1/datasets?name=$name" | json 'd["job"]["id"]')" > /dev/null
done
for _ in 1 2 3; do c --data-binary @"$TMP/graph.json" "$URL/api/v1/graphs" > /dev/null; done
for _ in 1 2 3; do c --data-binary @"$TMP/gt.txt" "$URL/api/v1/mot?kind=gt" > /dev/null; done
for _ in 1 2 3; do c -H "Content-Type: application/geo+json" --data-binary @"$TMP/sectors.geojson" "$URL/api/v1/sectors" > /dev/null; done
RUNS_BEFORE=$(ids runs runs)
SWEEPS_BEFORE=$(ids sweeps sweeps)
stop
BASE_SNAPSHOT=$(snapshot)
check "baseline: files on disk" True "$(python3 -c "print($(echo "$BASE_SNAPSHOT" | wc -l) > 40)")"

# ---- one case ----------------------------------------------------------------------------------------
# kill_case NAME FAILPOINT ACTION VERIFY: ACTION (a shell function, run against the armed server) sends the
# request that reaches FAILPOINT; VERIFY (after the restart) checks what the case leaves, and sets GONE
# (files of the baseline that the case may remove: a path prefix, "" for none).
# in_parallel FUNCTION ARGS...: runs a case in the background on a copy of the baseline store, at most
# $PARALLEL at once; its output goes to $TMP/case<n>.out, shown in order at the end.
CASES=0
in_parallel() {
  CASES=$((CASES + 1))
  while [ "$(jobs -rp | wc -l)" -ge "$PARALLEL" ]; do wait -n; done
  (
    RUN=$TMP/case$CASES DATA=$TMP/case$CASES/data SERVER_PID=
    trap '[ -n "$SERVER_PID" ] && kill -9 "$SERVER_PID" 2>/dev/null' EXIT
    mkdir -p "$RUN" && cp -a "$TMP/base/data" "$DATA"
    "$@"
  ) > "$TMP/case$CASES.out" 2>&1 &
}
kill_case() { in_parallel one_case "$@"; }
one_case() {
  local name=$1 point=$2 action=$3 verify=$4
  local before t0=$SECONDS
  before=$(snapshot)
  start "$point"
  "$action" > "$TMP/action.out" 2>&1
  check "$name: killed by SIGKILL" 137 "$(await_exit 30)"
  check "$name: at $point" 1 "$(grep -c "^failpoint ${point%#*}: SIGKILL" "$RUN/server.log")"
  start
  GONE=
  "$verify"
  post_checks "$name" "$before"
  stop
  echo "     ($((SECONDS - t0)) s)"
}
# post_checks NAME SNAPSHOT: what every case checks on the restarted store.
post_checks() {
  local name=$1 before=$2
  # Every file that was there before is there, byte-identical, but those of a deleted item.
  local lost
  lost=$(comm -23 <(echo "$before") <(snapshot) | awk '{print $2}' |
    while read -r f; do [ -n "$GONE" ] && [[ $f == "$GONE"* ]] && continue; echo "$f"; done | tr '\n' ' ')
  check "$name: earlier files byte-identical" "" "$lost"
  check "$name: tmp/ cleared" "" "$(ls -A "$DATA/tmp" 2>/dev/null | tr '\n' ' ')"
  check "$name: uploads/ cleared" "" "$(ls -A "$DATA/uploads" 2>/dev/null | tr '\n' ' ')"
  check "$name: no *.tmp.* files" "" "$(find "$DATA" -name '*.tmp.*' | tr '\n' ' ')"
}
# New files (not in the baseline) under $1: what an interrupted creation left.
new_files() { comm -13 <(echo "$BASE_SNAPSHOT") <(snapshot) | awk '{print $2}' | grep "^\./$1" | tr '\n' ' '; }

# ---- datasets: upload + ingest, delete ----------------------------------------------------------------
up_big() { c --data-binary @"$TMP/big.csv" "$URL/api/v1/datasets?name=crash"; }
dataset_absent() {
  check "  dataset 'crash' absent" 404 "$(code "$URL/api/v1/datasets/crash")"
  check "  datasets listed" "base del1 del2 del3" "$(ids datasets datasets)"
  check "  no new dataset files" "" "$(new_files datasets/)"
}
dataset_whole() {
  check "  dataset 'crash' whole" "50 150000" "$(c "$URL/api/v1/datasets/crash" | json '"%d %d" % (d["flights"], d["points"])')"
  check "  its summary" 150000 "$(c "$URL/api/v1/datasets/crash/summary" | json 'd["points"]')"
  check "  datasets listed" "base crash del1 del2 del3" "$(ids datasets datasets)"
  check "  delete it" 204 "$(code -X DELETE "$URL/api/v1/datasets/crash")"
}
kill_case "ingest mid-parse" "job.progress:ingest" up_big dataset_absent
kill_case "ingest staged" store.stage up_big dataset_absent
kill_case "ingest mid-write" store.write.column up_big dataset_absent
kill_case "ingest before manifest" store.write.before_manifest up_big dataset_absent
kill_case "ingest before rename" store.publish.before_rename up_big dataset_absent
kill_case "ingest after rename" store.publish.after_rename up_big dataset_whole

# A kill while the body is still streaming in (no failpoint: the test kills it), the "early" case.
upload_mid_body() {
start
c --limit-rate 2M --data-binary @"$TMP/big.csv" "$URL/api/v1/datasets?name=crash" > /dev/null 2>&1 &
CURL_PID=$!
for _ in $(seq 1 100); do [ -n "$(ls -A "$DATA/uploads")" ] && break; sleep 0.02; done
check "upload mid-body: partial upload on disk" 1 "$(ls -A "$DATA/uploads" | wc -l)"
kill -9 "$SERVER_PID"
check "upload mid-body: killed" 137 "$(await_exit 10)"
wait "$CURL_PID" 2>/dev/null
start
dataset_absent
check "upload mid-body: uploads/ cleared" "" "$(ls -A "$DATA/uploads")"
check "upload mid-body: earlier files byte-identical" "" "$(comm -23 <(echo "$BASE_SNAPSHOT") <(snapshot) | tr '\n' ' ')"
stop
}
in_parallel upload_mid_body

del_dataset() { code -X DELETE "$URL/api/v1/datasets/del1"; }
dataset_deleted() {
  check "  dataset del1 gone" 404 "$(code "$URL/api/v1/datasets/del1")"
  check "  datasets listed" "base del2 del3" "$(ids datasets datasets)"
  check "  del2 still answers" 80 "$(c "$URL/api/v1/datasets/del2" | json 'd["points"]')"
  GONE=./datasets/del1/
}
kill_case "dataset delete after rename" store.remove.after_rename del_dataset dataset_deleted

# ---- graphs: upload, delete ----------------------------------------------------------------------------
up_graph() { c --data-binary @"$TMP/graph.json" "$URL/api/v1/graphs?name=crash"; }
graph_absent() {
  check "  graphs listed" "g1 g2 g3 g4" "$(ids graphs graphs)"
  check "  no new graph files" "" "$(new_files graphs/)"
}
graph_whole() {
  check "  graphs listed" "g1 g2 g3 g4 g5" "$(ids graphs graphs)"
  check "  g5 whole" "crash 16" "$(c "$URL/api/v1/graphs/g5" | json '"%s %d" % (d["name"], d["edges"])')"
  r=$(post_json /api/v1/bundles "${BUNDLE_BODY/g1/g5}")  # reads every column of g5
  check "  g5 bundles" done "$(wait_job "$(echo "$r" | json 'd["job"]["id"]')")"
  check "  delete its bundle" 204 "$(code -X DELETE "$URL/api/v1/bundles/$(echo "$r" | json 'd["bundle"]')")"
  check "  delete g5" 204 "$(code -X DELETE "$URL/api/v1/graphs/g5")"
}
kill_case "graph staged" store.stage up_graph graph_absent
kill_case "graph mid-write" store.write.column up_graph graph_absent
kill_case "graph before manifest" store.write.before_manifest up_graph graph_absent
kill_case "graph before rename" store.publish.before_rename up_graph graph_absent
kill_case "graph after rename" store.publish.after_rename up_graph graph_whole
del_graph() { code -X DELETE "$URL/api/v1/graphs/g2"; }
graph_deleted() {
  check "  graphs listed" "g1 g3 g4" "$(ids graphs graphs)"
  GONE=./graphs/g2/
}
kill_case "graph delete after rename" store.remove.after_rename del_graph graph_deleted

# ---- bundles (a job) -------------------------------------------------------------------------------
BUNDLE_ID= BUNDLE_JOB=
bundle_job() {
  r=$(post_json /api/v1/bundles "$BUNDLE_BODY")
  BUNDLE_ID=$(echo "$r" | json 'd["bundle"]') BUNDLE_JOB=$(echo "$r" | json 'd["job"]["id"]')
}
fresh_ids_bundle() {  # a new bundle job after the restart: neither its bundle id nor its job id is reused
  r=$(post_json /api/v1/bundles "$BUNDLE_BODY")
  local b j
  b=$(echo "$r" | json 'd["bundle"]') j=$(echo "$r" | json 'd["job"]["id"]')
  check "  new bundle id differs from the lost one" True "$([ -n "$b" ] && [ "$b" != "$BUNDLE_ID" ] && echo True || echo "$b")"
  check "  new job id differs from the lost one" True "$([ -n "$j" ] && [ "$j" != "$BUNDLE_JOB" ] && echo True || echo "$j")"
  wait_job "$j" > /dev/null
  code -X DELETE "$URL/api/v1/bundles/$b" > /dev/null
}
bundle_absent() {
  # A kill on the job's thread can come before the I/O thread has sent the 202: then no id was handed out.
  [ -z "$BUNDLE_ID" ] && echo "     (killed before the 202 was sent: no bundle id to compare)"
  check "  bundles listed" b1 "$(ids bundles bundles)"
  check "  no new bundle files" "" "$(new_files bundles/)"
  fresh_ids_bundle
}
bundle_whole() {
  check "  bundles listed" "b1 $BUNDLE_ID" "$(ids bundles bundles)"
  check "  its image" 200 "$(code "$URL/api/v1/bundles/$BUNDLE_ID/image.png?width=64")"
  fresh_ids_bundle
  check "  delete it" 204 "$(code -X DELETE "$URL/api/v1/bundles/$BUNDLE_ID")"
}
kill_case "bundle mid-job" "job.progress:bundle" bundle_job bundle_absent
kill_case "bundle mid-write" store.write.column bundle_job bundle_absent
kill_case "bundle before rename" store.publish.before_rename bundle_job bundle_absent
kill_case "bundle after rename" store.publish.after_rename bundle_job bundle_whole
del_bundle() { code -X DELETE "$URL/api/v1/bundles/b1"; }
bundle_deleted() {
  check "  bundles listed" "" "$(ids bundles bundles)"
  GONE=./bundles/b1/
}

# ---- videos (synthetic: a job) ------------------------------------------------------------------------
VIDEO_ID= VIDEO_JOB=
synth_job() {
  r=$(post_json /api/v1/videos/synth "$SYNTH_BODY")
  VIDEO_ID=$(echo "$r" | json 'd["video"]') VIDEO_JOB=$(echo "$r" | json 'd["job"]["id"]')
}
fresh_ids_video() {
  r=$(post_json /api/v1/videos/synth "$SYNTH_BODY")
  local v j
  v=$(echo "$r" | json 'd["video"]') j=$(echo "$r" | json 'd["job"]["id"]')
  check "  new video id differs from the lost one" True "$([ -n "$v" ] && [ "$v" != "$VIDEO_ID" ] && echo True || echo "$v")"
  check "  new job id differs from the lost one" True "$([ -n "$j" ] && [ "$j" != "$VIDEO_JOB" ] && echo True || echo "$j")"
  wait_job "$j" > /dev/null
  code -X DELETE "$URL/api/v1/videos/$v" > /dev/null
}
video_absent() {
  [ -z "$VIDEO_ID" ] && echo "     (killed before the 202 was sent: no video id to compare)"
  check "  videos listed" v1 "$(ids videos videos)"
  check "  no new video files" "" "$(new_files videos/)"
  fresh_ids_video
}
video_whole() {
  check "  videos listed" "v1 $VIDEO_ID" "$(ids videos videos)"
  check "  its last frame" 200 "$(code "$URL/api/v1/videos/$VIDEO_ID/frames/5/depth.png")"
  fresh_ids_video
  check "  delete it" 204 "$(code -X DELETE "$URL/api/v1/videos/$VIDEO_ID")"
}
kill_case "synth mid-job" "job.progress:synth" synth_job video_absent
kill_case "synth staged" store.stage synth_job video_absent
kill_case "synth before meta" store.write.before_manifest synth_job video_absent
kill_case "synth before rename" store.publish.before_rename synth_job video_absent
kill_case "synth after rename" store.publish.after_rename synth_job video_whole

# ---- runs (a track job) and MOT files: payload + row --------------------------------------------------
track_job() { post_json /api/v1/runs/track '{"video": "v1"}'; }
run_absent() {
  check "  runs listed" "$RUNS_BEFORE" "$(ids runs runs)"
  check "  no new run files" "" "$(new_files runs/)"
}
kill_case "track mid-job" "job.progress:track" track_job run_absent
kill_case "run payload written, row not" store.row.before_row track_job run_absent
kill_case "run row before rename" store.replace.before_rename:.json track_job run_absent
del_run() { code -X DELETE "$URL/api/v1/runs/r1"; }
run_deleted() {
  check "  runs listed" "$(echo "$RUNS_BEFORE" | sed 's/^r1 //')" "$(ids runs runs)"
  check "  its log gone" "" "$(ls "$DATA/runs" | grep '^r1\.')"
  GONE=./runs/r1.
}
kill_case "run delete between row and payload" store.row.remove.after_row del_run run_deleted

up_mot() { c --data-binary @"$TMP/gt.txt" "$URL/api/v1/mot?kind=gt&name=crash"; }
mot_absent() {
  check "  MOT files listed" "m1 m2 m3 m4" "$(ids mot files)"
  check "  no new MOT files" "" "$(new_files mot/)"
}
kill_case "MOT payload before rename" store.replace.before_rename:.txt up_mot mot_absent
kill_case "MOT payload written, row not" store.row.before_row up_mot mot_absent
kill_case "MOT row before rename" store.replace.before_rename:.json up_mot mot_absent
del_mot() { code -X DELETE "$URL/api/v1/mot/m2"; }
mot_deleted() {
  check "  MOT files listed" "m1 m3 m4" "$(ids mot files)"
  check "  its payload gone" "" "$(ls "$DATA/mot" | grep '^m2\.')"
  GONE=./mot/m2.
}
kill_case "MOT delete between row and payload" store.row.remove.after_row del_mot mot_deleted

# ---- sector sets ------------------------------------------------------------------------------------
up_sectors() { c -H "Content-Type: application/geo+json" --data-binary @"$TMP/sectors.geojson" "$URL/api/v1/sectors?name=crash"; }
sectors_absent() {
  check "  sector sets listed" "s1 s2 s3 s4" "$(ids sectors sectors)"
  check "  no new sector files" "" "$(new_files sectors/)"
}
sectors_whole() {
  check "  sector sets listed" "s1 s2 s3 s4 s5" "$(ids sectors sectors)"
  check "  its GeoJSON as uploaded" "$(json 'json.dumps(d, sort_keys=True)' < "$TMP/sectors.geojson")" \
    "$(c "$URL/api/v1/sectors/s5" | json 'json.dumps(d, sort_keys=True)')"
  check "  delete it" 204 "$(code -X DELETE "$URL/api/v1/sectors/s5")"
}
kill_case "sectors staged" store.stage up_sectors sectors_absent
kill_case "sectors GeoJSON before rename" store.replace.before_rename:.geojson up_sectors sectors_absent
kill_case "sectors before manifest" store.write.before_manifest up_sectors sectors_absent
kill_case "sectors before rename" store.publish.before_rename up_sectors sectors_absent
kill_case "sectors after rename" store.publish.after_rename up_sectors sectors_whole
del_sectors() { code -X DELETE "$URL/api/v1/sectors/s2"; }
sectors_deleted() {
  check "  sector sets listed" "s1 s3 s4" "$(ids sectors sectors)"
  GONE=./sectors/s2/
}
kill_case "sectors delete after rename" store.remove.after_rename del_sectors sectors_deleted

# ---- sweeps: a record rewritten as its runs arrive -----------------------------------------------
sweep_job() { post_json /api/v1/sweeps "$SWEEP_BODY"; }
sweep_absent() {
  check "  sweeps listed" "$SWEEPS_BEFORE" "$(ids sweeps sweeps)"
  check "  no new sweep files" "" "$(new_files sweeps/)"
  check "  runs listed" "$RUNS_BEFORE" "$(ids runs runs)"
}
# Killed after its record and first run: the record is whole and says "interrupted"; each run it lists
# exists.
sweep_interrupted() {
  local s
  s=$(ls "$DATA/sweeps" | grep -v -x -F -f <(echo "$SWEEPS_BEFORE" | tr ' ' '\n' | sed 's/$/.json/') | sed 's/\.json$//')
  check "  one new sweep record" 1 "$(echo "$s" | grep -c .)"
  check "  it is interrupted" interrupted "$(c "$URL/api/v1/sweeps/$s" | json 'd["state"]')"
  for run in $(c "$URL/api/v1/sweeps/$s" | json "' '.join(d['runs'])"); do
    check "  its run $run exists" 200 "$(code "$URL/api/v1/runs/$run")"
  done
}
kill_case "sweep record before rename" "store.replace.before_rename:.json#1" sweep_job sweep_absent
kill_case "sweep mid-job" "job.progress:sweep" sweep_job sweep_interrupted

kill_case "bundle delete after rename" store.remove.after_rename del_bundle bundle_deleted

# ---- tokens.json: written by `trailscope token create|revoke` (atomically, under a file lock) ---------
# token_case NAME FAILPOINT VERIFY TOKEN-ARGS...: the CLI killed at FAILPOINT, then the server started on
# the store and VERIFY run.
token_case() { in_parallel one_token_case "$@"; }
one_token_case() {
  local name=$1 point=$2 verify=$3 before
  shift 3
  before=$(snapshot)
  TRAILSCOPE_FAILPOINT=$point "$BIN" token "$@" --data-dir "$DATA" > "$RUN/cli.out" 2> "$RUN/cli.err"
  check "$name: CLI killed by SIGKILL" 137 "$?"
  check "$name: at $point" 1 "$(grep -c "^failpoint $point: SIGKILL" "$RUN/cli.err")"
  start
  GONE=
  "$verify"
  post_checks "$name" "$before"
  check "$name: tokens.json readable by its owner only" 600 "$(stat -c %a "$DATA/tokens.json")"
  check "$name: the admin's token still works" 200 "$(code "$URL/api/v1/datasets")"
  stop
}
token_names() { "$BIN" token list --data-dir "$DATA" --json | json "' '.join(sorted(t['name'] for t in d))"; }
tokens_unchanged() {
  check "  tokens listed" "chaos reader" "$(token_names)"
  check "  the reader's token works" 200 "$(curl -s -o /dev/null -w '%{http_code}' -H "Authorization: Bearer $READER" "$URL/api/v1/datasets")"
}
token_created() {
  check "  tokens listed" "chaos crash reader" "$(token_names)"
  GONE=./tokens.json
}
token_revoked() {
  check "  tokens listed" chaos "$(token_names)"
  check "  the reader's token refused" 401 "$(curl -s -o /dev/null -w '%{http_code}' -H "Authorization: Bearer $READER" "$URL/api/v1/datasets")"
  GONE=./tokens.json
}
token_case "token create before rename" store.replace.before_rename:.json tokens_unchanged create --name crash --role writer
token_case "token create after rename" store.replace.after_rename:.json token_created create --name crash --role writer
token_case "token revoke before rename" store.replace.before_rename:.json tokens_unchanged revoke "$READER_ID"
token_case "token revoke after rename" store.replace.after_rename:.json token_revoked revoke "$READER_ID"

wait
for i in $(seq 1 "$CASES"); do cat "$TMP/case$i.out"; done
PASS=$((PASS + $(cat "$TMP"/case*.out | grep -c '^ok')))
FAIL=$((FAIL + $(cat "$TMP"/case*.out | grep -c '^FAIL')))
echo "$PASS passed, $FAIL failed"
[ "$FAIL" -eq 0 ]
