#!/usr/bin/env bash
# `trailscope congestion` end to end: a small OpenSky CSV whose counts are worked out by hand, sectors from a
# GeoJSON file and the grid, the table, JSON and CSV (equal to the API's answer for the same request over a
# real server), the job's events over the WebSocket, and the exit codes and messages of bad input.
# Usage: congestion_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
HERE=$(dirname "${BASH_SOURCE[0]}")
TMP=$(mktemp -d)
SERVER_PID=
cleanup() { [ -n "$SERVER_PID" ] && kill -9 "$SERVER_PID" 2>/dev/null; rm -rf "$TMP"; }
trap cleanup EXIT
source "$HERE/../support/cli_checks.sh"
py() { python3 -c "import json,sys; d=json.load(sys.stdin); $1"; }  # py STATEMENTS < FILE

# AAA1 flies east along 45°N from 0°E to 2°E over 00:00-00:20 at FL350 (10668 m), BBB2 the same at FL200,
# CCC3 along 45.05°N from 0.6°E through 1.0°E (00:10) to 1.4°E (00:20) at FL350.
cat > "$TMP/syn.csv" <<'CSV'
time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude
1514764800,aaaaa1,45.0,0.0,200,90,0,AAA1,false,10668
1514766000,aaaaa1,45.0,2.0,200,90,0,AAA1,false,10668
1514764800,bbbbb2,45.0,0.0,200,90,0,BBB2,false,6096
1514766000,bbbbb2,45.0,2.0,200,90,0,BBB2,false,6096
1514764800,ccccc3,45.05,0.6,200,90,0,CCC3,false,10668
1514765400,ccccc3,45.05,1.0,200,90,0,CCC3,false,10668
1514766000,ccccc3,45.05,1.4,200,90,0,CCC3,false,10668
CSV
# S1: 0.95..1.05°E x 44.9..45.1°N, FL300-FL400, peak 1: AAA1 inside over 570..630 s (between its
# samples), CCC3 over 525..675 s (its 00:10 sample inside), BBB2 below. S2: no traffic.
cat > "$TMP/sectors.geojson" <<'JSON'
{"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"name": "S1", "lower_fl": 300, "upper_fl": 400, "peak": 1},
   "geometry": {"type": "Polygon", "coordinates": [[[0.95, 44.9], [1.05, 44.9], [1.05, 45.1], [0.95, 45.1], [0.95, 44.9]]]}},
  {"type": "Feature", "properties": {"name": "S2", "lower_fl": 0, "upper_fl": 100},
   "geometry": {"type": "Polygon", "coordinates": [[[5, 44], [6, 44], [6, 45], [5, 45], [5, 44]]]}}]}
JSON
"$BIN" ingest "$TMP/syn.csv" --name syn --data-dir "$TMP/data" --quiet > /dev/null
check "ingest exit" 0 $?
c() { "$BIN" congestion syn --data-dir "$TMP/data" --quiet --t0 2018-01-01T00:00:00Z --t1 2018-01-01T00:30:00Z "$@"; }
S1='[v for v in d["counts"]["volumes"] if v["id"] == "S1"][0]'

c --sectors "$TMP/sectors.geojson" --separation --json > "$TMP/c.json"
check "json exit" 0 $?
check "json: S1 occupancy by period (interpolated)" "[8, 9, 10, 11] [1, 2, 2, 1]" \
  "$(json "str($S1[\"occupancy\"][\"step\"]) + \" \" + str($S1[\"occupancy\"][\"count\"])" < "$TMP/c.json")"
check "json: S1 entries" "[0] [2]" \
  "$(json "str($S1[\"entries\"][\"window\"]) + \" \" + str($S1[\"entries\"][\"count\"])" < "$TMP/c.json")"
check "json: one hotspot, periods 9-10, AAA1 and CCC3" "peak 9 10 2 AAA1,CCC3" \
  "$(py 'h = d["counts"]["hotspots"][0]; print(h["kind"], h["first_step"], h["last_step"], h["peak"], ",".join(f["callsign"] for f in h["flights"]))' < "$TMP/c.json")"
check "json: one loss of separation, AAA1/CCC3" "1 AAA1 CCC3" \
  "$(py 'e = d["separation"]["events"]; print(len(e), e[0]["callsign_a"], e[0]["callsign_b"])' < "$TMP/c.json")"
check "json: closest approach ~3 NM at 00:10" "True True" \
  "$(py 'e = d["separation"]["events"][0]["cpa"]; print(abs(e["t"] - 1514765400) < 1, abs(e["horizontal_m"] - 5555.9) < 5)' < "$TMP/c.json")"

c --sectors "$TMP/sectors.geojson" --method samples --json > "$TMP/s.json"
check "samples: only CCC3's sample, in period 10" "[10] [1]" \
  "$(json "str($S1[\"occupancy\"][\"step\"]) + \" \" + str($S1[\"occupancy\"][\"count\"])" < "$TMP/s.json")"

c --sectors "$TMP/sectors.geojson" --csv > "$TMP/c.csv"
check "csv exit" 0 $?
check "csv header" "volume,series,index,start,end,value" "$(head -1 "$TMP/c.csv")"
check "csv: S1 rows (4 occupancy, 1 entries)" 5 "$(grep -c '^S1,' "$TMP/c.csv")"
c --sectors "$TMP/sectors.geojson" --separation --csv --table separation > "$TMP/sep.csv"
check "csv separation: header and one event" 2 "$(wc -l < "$TMP/sep.csv")"

c --sectors "$TMP/sectors.geojson" --separation > "$TMP/c.txt"
check "table exit" 0 $?
contains "table: busiest volumes" "busiest volumes" "$TMP/c.txt"
contains "table: S1 row" "S1" "$TMP/c.txt"
contains "table: hotspots" "hotspots  1" "$TMP/c.txt"
contains "table: separation" "losses of separation  1" "$TMP/c.txt"
contains "table: complexity" "complexity" "$TMP/c.txt"

c --bbox -1,44,3,46 --alt-min 30000 --alt-max 40000 --callsign CCC3 --json > "$TMP/g.json"
check "grid: kind and flights" "grid 1" "$(py 'print(d["counts"]["volumes_kind"], d["counts"]["flights"])' < "$TMP/g.json")"
check "grid: CCC3's cells all in row 405, layer 11" True \
  "$(json 'all(v["id"].startswith("r405") and v["id"].endswith("l11") for v in d["counts"]["volumes"])' < "$TMP/g.json")"

# The progress bar goes to stderr, the answer to stdout.
"$BIN" congestion syn --data-dir "$TMP/data" --t0 1514764800 --t1 1514766600 --json > "$TMP/p.json" 2> "$TMP/p.err"
check "progress run exit" 0 $?
contains "progress bar on stderr" "congestion" "$TMP/p.err"
check "stdout is the JSON" syn "$(json 'd["dataset"]' < "$TMP/p.json")"

# Bad input: exit 2 and the parameter named.
c --sectors "$TMP/sectors.geojson" --bbox 0,44,2,46 2> "$TMP/err" > /dev/null
check "sectors and bbox exit 2" 2 $?
check "sectors and bbox message" "trailscope: --bbox, --alt-min, --alt-max and --alt-unit set the extent of the grid; sectors have their own" "$(cat "$TMP/err")"
c --sectors "$TMP/none.geojson" 2> "$TMP/err" > /dev/null
check "missing sector file exit 2" 2 $?
check "missing sector file message" "trailscope: --sectors: cannot read $TMP/none.geojson" "$(cat "$TMP/err")"
c --method guess 2> "$TMP/err" > /dev/null
check "bad method exit 2" 2 $?
contains "bad method named" "method" "$TMP/err"
c --json --csv 2> "$TMP/err" > /dev/null
check "json and csv exit 2" 2 $?
check "json and csv message" "trailscope: --json and --csv: give one of them" "$(cat "$TMP/err")"
c --compute occupancy,weather 2> "$TMP/err" > /dev/null
check "bad compute exit 2" 2 $?
check "bad compute message" "trailscope: compute: unknown part 'weather' (occupancy, entries, hotspots, complexity or separation)" "$(cat "$TMP/err")"
"$BIN" congestion syn --data-dir "$TMP/data" --quiet --t1 1514766600 2> "$TMP/err" > /dev/null
check "missing t0 exit 2" 2 $?
contains "missing t0 named" "t0" "$TMP/err"
"$BIN" congestion nope --data-dir "$TMP/data" --quiet --t0 1514764800 --t1 1514766600 2> "$TMP/err" > /dev/null
check "unknown dataset exit 2" 2 $?
"$BIN" congestion --help > "$TMP/help.txt"
for flag in --sectors --bbox --alt-min --alt-max --step --duration --method --separation --json --csv --t0 --t1; do
  contains "help names $flag" "$flag" "$TMP/help.txt"
done

# The API's answer to the same request is the CLI's: a real server over the same data folder.
use_token "$TMP/data"
start_server "$TMP/data"
sid=$(curl -s -H 'Content-Type: application/geo+json' --data-binary @"$TMP/sectors.geojson" "$URL/api/v1/sectors?name=test" | json 'd["id"]')
check "api: sectors stored" s1 "$sid"
body='{"dataset":"syn","query":{"t0":"2018-01-01T00:00:00Z","t1":"2018-01-01T00:30:00Z"},"volumes":{"sectors":"'"$sid"'"},"compute":["occupancy","entries","hotspots","complexity","separation"]}'
ws=$(node --experimental-websocket "$HERE/congestion_ws.mjs" "$URL" "$body" 2>/dev/null)
job=$(echo "$ws" | json 'd.get("job")')
check "ws: first event is queued" queued "$(echo "$ws" | json 'd.get("first")')"
check "ws: a running event" True "$(echo "$ws" | json 'd.get("running")')"
check "ws: progress is monotonic" True "$(echo "$ws" | json 'd.get("monotonic")')"
check "ws: last event is done" done "$(echo "$ws" | json 'd.get("last")')"
check "ws: the summary points at the answer" "/api/v1/congestion/$job 1 1" \
  "$(echo "$ws" | py 'print(d["result"]["congestion"], d["result"]["hotspots"], d["result"]["separation_events"])')"
curl -s "$URL/api/v1/congestion/$job" > "$TMP/api.json"
check "api json counts == cli json counts" True \
  "$(python3 -c "import json; a = json.load(open('$TMP/api.json')); b = json.load(open('$TMP/c.json')); print(a['counts'] == b['counts'] and a['separation'] == b['separation'])")"
curl -s "$URL/api/v1/congestion/$job?format=csv" > "$TMP/api.csv"
check "api csv == cli csv" same "$(cmp -s "$TMP/api.csv" "$TMP/c.csv" && echo same || echo differ)"
curl -s "$URL/api/v1/congestion/$job?format=csv&table=separation" > "$TMP/api_sep.csv"
check "api separation csv == cli's" same "$(cmp -s "$TMP/api_sep.csv" "$TMP/sep.csv" && echo same || echo differ)"
check "api: oversized sector upload refused" 413 \
  "$(curl -s -o "$TMP/e.json" -w '%{http_code}' -H 'Content-Length: 20000000' --data-binary 'x' "$URL/api/v1/sectors")"
check "api: oversized sector upload detail" "sector upload exceeds the limit of 16 MiB" "$(json 'd["detail"]' < "$TMP/e.json")"
check "api: too many periods" "413 step" \
  "$(curl -s -o "$TMP/e.json" -w '%{http_code}' -H 'Content-Type: application/json' -d '{"dataset":"syn","query":{"t0":0,"t1":172800},"volumes":{"grid":{}},"step":1}' "$URL/api/v1/congestion") $(json 'd["param"]' < "$TMP/e.json")"
kill -TERM "$SERVER_PID"; wait "$SERVER_PID" 2>/dev/null; SERVER_PID=

finish
