#!/usr/bin/env bash
# `trailscope query positions` end to end: a small OpenSky CSV ingested into a scratch store, positions at
# an instant as a table, JSON and GeoJSON, a filter, and the exit codes and messages of bad input.
# Usage: positions_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../support/cli_checks.sh"

# KLM1 flies (52, 4) → (53, 6) over 00:00–00:10, 1000 → 2000 m, track 350 → 10; DLH2 stands at (50, 8).
cat > "$TMP/pos.csv" <<'CSV'
time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude
1514764800,4ca1d0,52,4,200,350,2,KLM1,false,1000
1514765400,4ca1d0,53,6,220,10,,KLM1,false,2000
1514764800,3c6444,50,8,0,0,0,DLH2,true,100
1514766000,3c6444,50,8,0,0,0,DLH2,true,100
CSV
"$BIN" ingest "$TMP/pos.csv" --name pos --data-dir "$TMP/data" --quiet > /dev/null
check "ingest exit" 0 $?
q() { "$BIN" query positions pos --data-dir "$TMP/data" "$@"; }

q --t 2018-01-01T00:05:00Z --json > "$TMP/p.json"
check "json exit" 0 $?
check "json count" 2 "$(json 'd["count"]' < "$TMP/p.json")"
check "json t" 1514765100.0 "$(json 'd["t"]' < "$TMP/p.json")"
check "json KLM1 interpolated" "KLM1 52.5 5.0 1500.0 0.0 None" \
  "$(json '" ".join(str(p[k]) for p in d["positions"] if p["callsign"] == "KLM1" for k in ("callsign", "lat", "lon", "alt_m", "track_deg", "vrate_ms"))' < "$TMP/p.json")"

q --t 1514765100 --geojson > "$TMP/p.geojson"
check "geojson type" FeatureCollection "$(json 'd["type"]' < "$TMP/p.geojson")"
check "geojson KLM1 [lon, lat]" "[5.0, 52.5]" \
  "$(json '[f["geometry"]["coordinates"] for f in d["features"] if f["properties"]["callsign"] == "KLM1"][0]' < "$TMP/p.geojson")"

q --t 1514765100 > "$TMP/p.txt"
check "table exit" 0 $?
contains "table header" "2 flights at 2018-01-01T00:05:00Z" "$TMP/p.txt"
contains "table row" "KLM1" "$TMP/p.txt"
contains "table columns" "speed_ms" "$TMP/p.txt"

check "bbox on the interpolated position" 1 "$(q --t 1514765100 --bbox 4.9,52.4,5.1,52.6 --json | json 'd["count"]')"
check "altitude band in feet" 1 "$(q --t 1514765100 --alt-min 4000 --alt-max 6000 --json | json 'd["count"]')"
check "callsign" DLH2 "$(q --t 1514765100 --callsign dlh --json | json 'd["positions"][0]["callsign"]')"
check "after the last sample" 0 "$(q --t 2018-01-01T01:00:00Z --json | json 'd["count"]')"

q --t soon 2> "$TMP/err" > /dev/null
check "bad t exits 2" 2 $?
check "bad t names t" "trailscope: t: 'soon' is neither Unix seconds nor an ISO 8601 time such as 2018-01-01T06:00:00Z" "$(cat "$TMP/err")"
q --t 1514765100 --t0 1514764800 2> "$TMP/err" > /dev/null
check "t0 exits 2" 2 $?
check "t0 refused" "trailscope: t0 does not apply to positions at an instant: give the instant as t" "$(cat "$TMP/err")"
q 2> "$TMP/err" > /dev/null
rc=$?
check "missing --t fails" 1 "$([ $rc -ne 0 ] && echo 1 || echo 0)"
contains "missing --t is named" "--t" "$TMP/err"
"$BIN" query positions nope --data-dir "$TMP/data" --t 1514765100 2> "$TMP/err" > /dev/null
check "unknown dataset exits 2" 2 $?
"$BIN" query positions --help > "$TMP/help.txt"
contains "help names --t" "--t" "$TMP/help.txt"
contains "help names --geojson" "--geojson" "$TMP/help.txt"

finish
