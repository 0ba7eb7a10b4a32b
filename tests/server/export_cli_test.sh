#!/usr/bin/env bash
# `trailscope export` and `query summary --csv` end to end: a small OpenSky CSV ingested (one flight split at
# a position jump), the exports as GeoJSON and CSV checked by hand, the same bytes as GET .../export and
# GET .../summary?format=csv over a real server (whose export arrives chunked), the 413 of an export over
# max_points, and the exit codes and messages of bad input.
# Usage: export_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
SERVER_PID=
cleanup() { [ -n "$SERVER_PID" ] && kill -9 "$SERVER_PID" 2>/dev/null; rm -rf "$TMP"; }
trap cleanup EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../support/cli_checks.sh"

# KLM1: three samples near Amsterdam, then a jump of 10° north in 60 s confirmed by the sample after it
# (a teleport: split into a second flight).
# DLH2: two samples at Frankfurt. "A,B" is a callsign with a comma (quoted in the CSV).
cat > "$TMP/x.csv" <<'CSV'
time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude
1514764800,4ca1d0,52,4,200,350,2,KLM1,false,1000
1514764860,4ca1d0,52.1,4.1,210,350,,KLM1,false,1500
1514764920,4ca1d0,52.2,4.2,220,350,0,KLM1,false,2000
1514764980,4ca1d0,62.2,4.2,220,350,0,KLM1,false,2000
1514765040,4ca1d0,62.3,4.3,220,350,0,KLM1,false,2000
1514764800,3c6444,50,8,0,0,0,DLH2,true,100
1514765400,3c6444,50,8,0,0,0,DLH2,true,
CSV
"$BIN" ingest "$TMP/x.csv" --name x --data-dir "$TMP/data" --quiet --split-jumps true > "$TMP/ingest.txt"
check "ingest exit" 0 $?
contains "ingest names the split" "1 flights split at jumps" "$TMP/ingest.txt"
e() { "$BIN" export x --data-dir "$TMP/data" "$@"; }

e --format csv > "$TMP/cli.csv"
check "csv exit" 0 $?
check "csv header" "flight_id,icao24,callsign,t,lat,lon,alt_m,speed_ms,track_deg,vrate_ms,on_ground" "$(head -1 "$TMP/cli.csv")"
check "csv rows" 8 "$(wc -l < "$TMP/cli.csv")"
# Flight ids by start time, then icao24: DLH2 (3c6444) is 0, KLM1's legs 1 and 2.
check "csv unknown altitude is empty" "0,3c6444,DLH2,1514765400,50,8,,0,0,0,1" "$(sed -n 3p "$TMP/cli.csv")"
check "csv second leg after the jump" "2,4ca1d0,KLM1,1514764980,62.2,4.2,2000,220,350,0,0" "$(sed -n 7p "$TMP/cli.csv")"
e --format csv --t0 1514764860 --t1 1514764921 --callsign KLM > "$TMP/w.csv"
check "csv window rows" 3 "$(wc -l < "$TMP/w.csv")"
e > "$TMP/cli.geojson"
check "geojson features" 3 "$(json 'len(d["features"])' < "$TMP/cli.geojson")"
check "geojson points" 7 "$(json 'd["points"]' < "$TMP/cli.geojson")"
check "geojson KLM1 first leg" "[[4.0, 52.0, 1000.0], [4.099999904632568, 52.099998474121094, 1500.0], [4.199999809265137, 52.20000076293945, 2000.0]]" \
  "$(json '[f["geometry"]["coordinates"] for f in d["features"] if f["properties"]["callsign"] == "KLM1"][0]' < "$TMP/cli.geojson")"
e -o "$TMP/out.csv" --format csv --json > "$TMP/report.json"
check "--out report" "3 7" "$(json '" ".join(str(d[k]) for k in ("flights", "points"))' < "$TMP/report.json")"
check "--out file equals stdout" same "$(cmp -s "$TMP/out.csv" "$TMP/cli.csv" && echo same || echo differ)"
"$BIN" query summary x --data-dir "$TMP/data" --csv --table top_callsigns > "$TMP/top.csv"
check "summary csv" "callsign,flights,points|KLM1,2,5|DLH2,1,2" "$(paste -sd'|' "$TMP/top.csv")"

e --format kml 2> "$TMP/err" > /dev/null
check "bad format exits 2" 2 $?
check "bad format message" "trailscope: format must be 'geojson' or 'csv', got 'kml'" "$(cat "$TMP/err")"
e --max-points 5 2> "$TMP/err" > /dev/null
check "too many points exits 2" 2 $?
check "too many points message" "trailscope: the window holds 7 points, more than max_points=5: narrow the window or the filters" "$(cat "$TMP/err")"
e --json 2> "$TMP/err" > /dev/null
check "--json without --out exits 2" 2 $?
"$BIN" export --help > "$TMP/help.txt"
for flag in --format --out --max-points --t0 --t1 --bbox --callsign --json; do
  contains "help names $flag" "$flag" "$TMP/help.txt"
done

# The API's bytes are the CLI's: a real server over the same data folder.
use_token "$TMP/data"
start_server "$TMP/data"
curl -s -D "$TMP/h.txt" "$URL/api/v1/datasets/x/export?format=csv" > "$TMP/api.csv"
check "api csv == cli csv" same "$(cmp -s "$TMP/api.csv" "$TMP/cli.csv" && echo same || echo differ)"
contains "api export is chunked" "Transfer-Encoding: chunked" "$TMP/h.txt"
contains "api export is an attachment" 'Content-Disposition: attachment; filename="x-flights.csv"' "$TMP/h.txt"
curl -s "$URL/api/v1/datasets/x/export" > "$TMP/api.geojson"
check "api geojson == cli geojson" same "$(cmp -s "$TMP/api.geojson" "$TMP/cli.geojson" && echo same || echo differ)"
curl -s "$URL/api/v1/datasets/x/summary?format=csv&table=top_callsigns" > "$TMP/api_top.csv"
check "api summary csv == cli's" same "$(cmp -s "$TMP/api_top.csv" "$TMP/top.csv" && echo same || echo differ)"
check "api: too many points" "413 max_points" \
  "$(curl -s -o "$TMP/e.json" -w '%{http_code}' "$URL/api/v1/datasets/x/export?max_points=5") $(json 'd["param"]' < "$TMP/e.json")"
kill -TERM "$SERVER_PID"; wait "$SERVER_PID" 2>/dev/null; SERVER_PID=

finish
