#!/usr/bin/env bash
# End-to-end over loopback: the real binary, real uploads, restarts and a kill in the middle of an ingest.
# Usage: loopback_test.sh TRAILSCOPE_BIN SHARED_DIR
set -uo pipefail
BIN=$(readlink -f "$1")
SHARED=$(readlink -f "$2")
SO6="$SHARED/data/flights/traffic_europe_20180101_m3.so6.gz"
TMP=$(mktemp -d)
source "$(dirname "${BASH_SOURCE[0]}")/../support/cli_checks.sh"  # check, json, start_server, use_token, curl
SERVER_PID=
cleanup() { [ -n "$SERVER_PID" ] && kill -9 "$SERVER_PID" 2>/dev/null; rm -rf "$TMP"; }
trap cleanup EXIT

wait_job() {
  for _ in $(seq 1 600); do
    state=$(curl -s "$URL/api/v1/jobs/$1" | json 'd["state"]')
    case "$state" in done|failed|cancelled) echo "$state"; return;; esac
    sleep 0.1
  done
  echo timeout
}

use_token "$TMP/data"
start_server "$TMP/data"
check "health" ok "$(curl -s "$URL/api/v1/health" | json 'd["status"]')"

# Streamed upload of the real Europe day, ingested as a job.
job=$(curl -s --data-binary @"$SO6" "$URL/api/v1/datasets?name=europe" | json 'd["job"]["id"]')
check "upload job ends done" done "$(wait_job "$job")"
# 11,043 flight ids, split by default between two legs and at teleports (counted in the ingest report).
curl -s "$URL/api/v1/datasets/europe" > "$TMP/europe.json"
EUROPE_FLIGHTS=$(json 'd["flights"]' < "$TMP/europe.json")
check "europe flights" "$EUROPE_FLIGHTS" \
  "$(json '11043 + d["ingest"]["quality"]["jump_splits"]["count"] + d["ingest"]["quality"]["leg_splits"]["count"]' < "$TMP/europe.json")"
check "europe splits between legs" True "$(json 'd["ingest"]["quality"]["leg_splits"]["count"] > 0' < "$TMP/europe.json")"
summary=$(curl -s "$URL/api/v1/datasets/europe/summary?t0=2018-01-01T08:00:00Z&t1=2018-01-01T10:00:00Z&bbox=-5,45,10,55")
check "summary has flights" True "$(echo "$summary" | json 'd["flights"] > 100')"

# Progress over the WebSocket while a second upload is ingested: queued first, monotonic, done last.
ws=$(node --experimental-websocket "$(dirname "$0")/ws_events.mjs" "$URL" "$SO6" europe2 2>/dev/null)
check "ws: first event is queued" queued "$(echo "$ws" | json 'd.get("first")')"
check "ws: a running event" True "$(echo "$ws" | json 'd.get("running")')"
check "ws: progress is monotonic" True "$(echo "$ws" | json 'd.get("monotonic")')"
check "ws: last event is done" done "$(echo "$ws" | json 'd.get("last")')"
check "ws: result names the flights" "$EUROPE_FLIGHTS" "$(echo "$ws" | json 'd.get("flights")')"

# Errors: exact status and the parameter named.
check "bad t0 status" 400 "$(curl -s -o "$TMP/e.json" -w '%{http_code}' "$URL/api/v1/datasets/europe/summary?t0=soon")"
check "bad t0 param" t0 "$(json 'd["param"]' < "$TMP/e.json")"
check "unknown dataset" 404 "$(curl -s -o /dev/null -w '%{http_code}' "$URL/api/v1/datasets/nope/summary")"
check "oversized upload refused" 413 "$(curl -s -o "$TMP/e.json" -w '%{http_code}' -H 'Content-Length: 3000000000' --data-binary 'x' "$URL/api/v1/datasets?name=big")"
check "oversized upload param" body "$(json 'd["param"]' < "$TMP/e.json")"
check "malformed request target" 400 "$(curl -s -g -o /dev/null -w '%{http_code}' "$URL/api/v1/datasets?a=%zz")"

# Bundling: a streamed graph upload, its size limit, a bundle job of it and its image.
AIRLINES="$SHARED/data/bundling/classic/airlines.xml"
graph=$(curl -s --data-binary @"$AIRLINES" "$URL/api/v1/graphs?name=airlines")
check "graph upload: edges" 2101 "$(echo "$graph" | json 'd["edges"]')"
check "oversized graph upload refused" 413 "$(curl -s -o "$TMP/e.json" -w '%{http_code}' -H 'Content-Length: 300000000' --data-binary 'x' "$URL/api/v1/graphs")"
check "oversized graph upload detail" "graph upload exceeds the limit of 256 MiB" "$(json 'd["detail"]' < "$TMP/e.json")"
gid=$(echo "$graph" | json 'd["id"]')
accepted=$(curl -s -H 'Content-Type: application/json' -d '{"source":{"graph":"'"$gid"'"},"params":{"size":256,"iterations":5},"backend":"cpu"}' "$URL/api/v1/bundles")
bundle=$(echo "$accepted" | json 'd["bundle"]')
check "bundle job ends done" done "$(wait_job "$(echo "$accepted" | json 'd["job"]["id"]')")"
check "bundle image" 200 "$(curl -s -o /dev/null -w '%{http_code}' "$URL/api/v1/bundles/$bundle/image.png?width=256")"

# The CLI verb: an image and the figures as JSON; bad input is exit 2 with the parameter named.
"$BIN" bundle "$AIRLINES" -o "$TMP/air.png" --polylines "$TMP/air.bin" --size 256 --iterations 5 --backend cpu --json --quiet > "$TMP/b.json"
check "cli bundle: polylines" 2101 "$(json 'd["polylines"]' < "$TMP/b.json")"
check "cli bundle: png magic" PNG "$(head -c 4 "$TMP/air.png" | tail -c 3)"
check "cli bundle: TSBL magic" TSBL "$(head -c 4 "$TMP/air.bin")"
"$BIN" bundle "$AIRLINES" -o "$TMP/x.png" --h 1 2> "$TMP/err.txt"
check "cli bad parameter exits 2" 2 "$?"
check "cli names the parameter" "trailscope: h must be in [2, 128] px (got 1)" "$(cat "$TMP/err.txt")"

# Depth videos and the live replay: a pack upload, a replay over it, one viewer seeking over the WebSocket.
"$BIN" synth --scenario standard --frames 30 --pack -o "$TMP/clip.tsdv" > /dev/null 2>&1
video=$(curl -s --data-binary @"$TMP/clip.tsdv" "$URL/api/v1/videos?name=clip")
check "video upload: frames" 30 "$(echo "$video" | json 'd["frame_count"]')"
vid=$(echo "$video" | json 'd["id"]')
check "garbage video upload" 415 "$(curl -s -o /dev/null -w '%{http_code}' --data-binary 'junk' "$URL/api/v1/videos")"
check "oversized video upload detail" "video upload exceeds the limit of 2 GiB" "$(curl -s -H 'Content-Length: 3000000000' --data-binary 'x' "$URL/api/v1/videos" | json 'd["detail"]')"
check "depth picture" 200 "$(curl -s -o /dev/null -w '%{http_code}' "$URL/api/v1/videos/$vid/frames/3/depth.png")"
rid=$(curl -s -H 'Content-Type: application/json' -d '{"video":"'"$vid"'"}' "$URL/api/v1/replays" | json 'd["id"]')
rws=$(node --experimental-websocket "$(dirname "$0")/replay_ws.mjs" "$URL" "$rid" 2>/dev/null)
check "replay ws: hello first" hello "$(echo "$rws" | json 'd.get("first")')"
check "replay ws: frame magic" TSRF "$(echo "$rws" | json 'd.get("magic")')"
check "replay ws: depth is a PNG" PNG "$(echo "$rws" | json 'd.get("png")')"
check "replay ws: seek" 5 "$(echo "$rws" | json 'd.get("seeked")')"
check "replay ws: bad op names op" op "$(echo "$rws" | json 'd.get("error_param")')"
for _ in $(seq 1 100); do
  run=$(curl -s "$URL/api/v1/replays/$rid" | json 'd["run"] or ""')
  [ -n "$run" ] && break
  sleep 0.1
done
check "replay run stored" 30 "$(curl -s "$URL/api/v1/runs/$run" | json 'd["summary"]["frames"]')"

# Restart: the dataset is back.
stop_server
start_server "$TMP/data"
check "video survives restart" 30 "$(curl -s "$URL/api/v1/videos/$vid" | json 'd["frame_count"]')"
check "run survives restart" 30 "$(curl -s "$URL/api/v1/runs/$run" | json 'd["summary"]["frames"]')"
check "dataset survives restart" "$EUROPE_FLIGHTS" "$(curl -s "$URL/api/v1/datasets/europe" | json 'd["flights"]')"
check "bundle survives restart" 2101 "$(curl -s "$URL/api/v1/bundles/$bundle" | json 'd["polylines"]')"
check "graph survives restart" 2101 "$(curl -s "$URL/api/v1/graphs/$gid" | json 'd["edges"]')"

# Kill -9 in the middle of an ingest: nothing half-written appears, nothing stored is lost.
zcat "$SO6" > "$TMP/big.so6"; for _ in 1 2 3 4 5 6 7; do zcat "$SO6" | sed 's/ 180101 180101 / 180102 180102 /' >> "$TMP/big.so6"; done
curl -s --data-binary @"$TMP/big.so6" "$URL/api/v1/datasets?name=killed" > /dev/null &
for _ in $(seq 1 100); do
  # Job ids continue across restarts: find the ingest by its dataset.
  st=$(curl -s "$URL/api/v1/jobs" | json '" ".join(j["state"] for j in d["jobs"] if j["dataset"] == "killed")' 2>/dev/null)
  [ "$st" == "running" ] && break
  sleep 0.05
done
kill -9 "$SERVER_PID"; wait "$SERVER_PID" 2>/dev/null; SERVER_PID=
start_server "$TMP/data"
check "killed ingest left no dataset" 404 "$(curl -s -o /dev/null -w '%{http_code}' "$URL/api/v1/datasets/killed")"
check "earlier dataset intact" "$EUROPE_FLIGHTS" "$(curl -s "$URL/api/v1/datasets/europe" | json 'd["flights"]')"
check "no leftovers in tmp/" 0 "$(ls "$TMP/data/tmp" | wc -l)"
check "no leftovers in uploads/" 0 "$(ls "$TMP/data/uploads" | wc -l)"

# Delete.
check "delete" 204 "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$URL/api/v1/datasets/europe")"
check "deleted is gone" 404 "$(curl -s -o /dev/null -w '%{http_code}' "$URL/api/v1/datasets/europe")"
stop_server

finish
